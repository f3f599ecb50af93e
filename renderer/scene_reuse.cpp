// Scene::reuseBvhOf: consecutive scenes (a frame sequence, an interactive session's edits) build
// only the BVHs of what changed. Shapes are matched by name and compared by a fingerprint of what
// their BVH is built from (points, indices, sphere centre and radius, motion steps), so a change a
// host does not announce is still caught. Materials, normals and uvs are not BVH inputs: shading
// reads them from the new scene's own shapes.
#include <cstring>
#include <stdexcept>

#include "scene_bvh.h"

namespace gi {

namespace {

// A 64-bit hash of raw bytes: tells an edited shape from an unedited one (not cryptographic).
class Hasher {
public:
    void add(uint64_t v) {
        h_ ^= v * 0x9E3779B97F4A7C15ull;
        h_ = ((h_ << 27) | (h_ >> 37)) * 0xBF58476D1CE4E5B9ull + 0x94D049BB133111EBull;
    }
    void bytes(const void* data, size_t size) {
        add(size);
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (; size >= 8; p += 8, size -= 8) {
            uint64_t word;
            std::memcpy(&word, p, 8);
            add(word);
        }
        uint64_t tail = 0;
        if (size) std::memcpy(&tail, p, size);
        add(tail);
    }
    template <class T>
    void vector(const std::vector<T>& v) {
        bytes(v.data(), v.size() * sizeof(T));
    }
    uint64_t value() const { return h_; }

private:
    uint64_t h_ = 0x243F6A8885A308D3ull;
};

}  // namespace

Scene::EmbreeDevice::EmbreeDevice() {
    device = rtcNewDevice(nullptr);
    auto warnScene = [](void* userPtr, RTCError code, const char* message) {
        const Scene* scene = static_cast<EmbreeDevice*>(userPtr)->reporter.load();
        if (scene) scene->warn("Embree error " + std::to_string(int(code)) + ": " + (message ? message : ""));
    };
    rtcSetDeviceErrorFunction(device, warnScene, this);
}

RTCDevice Scene::embreeDevice() const { return device_->device; }

uint64_t Scene::fingerprint(const Shape& s) {
    Hasher h;
    h.add(s.isSphere);
    h.vector(s.positions);
    h.vector(s.indices);
    h.bytes(&s.center, sizeof s.center);
    h.bytes(&s.radius, sizeof s.radius);
    h.add(s.stepPositions.size());
    for (const std::vector<Vec3>& step : s.stepPositions) h.vector(step);
    h.vector(s.stepCenters);
    h.vector(s.stepRadii);
    return h.value();
}

void Scene::reuseBvhOf(const Scene& previous) {
    if (committed_) throw std::logic_error("reuseBvhOf: the scene is committed already");
    if (!previous.committed_ || &previous == this) return;  // nothing built to take
    // A BVH can only be instanced within its own device; nothing of this scene's is built yet.
    device_ = previous.device_;
    device_->reporter = this;
    previous_ = std::make_unique<Previous>();
    previous_->topFingerprints = previous.topFingerprints_;
    previous_->staticBvh = previous.staticBvh_;
    std::map<std::string, int> uses;
    for (const Prototype& p : previous.prototypes_) uses[p.name]++;
    for (const Prototype& p : previous.prototypes_)
        if (uses[p.name] == 1 && p.bvh) previous_->prototypes[p.name] = p.bvh;
}

std::shared_ptr<const Scene::Bvh> Scene::shapesBvh(const std::vector<int>& shapes,
                                                   const std::vector<uint64_t>& fingerprints,
                                                   const std::shared_ptr<const Bvh>& previous) {
    if (previous && previous->names.size() == shapes.size()) {
        bool same = true;
        for (size_t i = 0; i < shapes.size() && same; ++i)
            same = previous->names[i] == shapes_[shapes[i]].name && previous->fingerprints[i] == fingerprints[shapes[i]];
        if (same) {
            stats_.primitivesReused += previous->primitives;
            return previous;
        }
    }
    auto bvh = std::make_shared<Bvh>();
    bvh->rtc = rtcNewScene(device_->device);
    rtcSetSceneBuildQuality(bvh->rtc, RTC_BUILD_QUALITY_HIGH);
    size_t builtBefore = stats_.primitivesBuilt;
    std::vector<int> geomToShape;
    for (int s : shapes) {
        buildShapeGeometry(bvh->rtc, geomToShape, s);
        bvh->names.push_back(shapes_[s].name);
        bvh->fingerprints.push_back(fingerprints[s]);
    }
    // Embree numbers a new scene's geometries 0, 1, ... in attach order: geometry id i is shapes[i].
    if (geomToShape != shapes) throw std::logic_error("Embree geometry ids out of attach order");
    rtcCommitScene(bvh->rtc);
    bvh->primitives = stats_.primitivesBuilt - builtBefore;
    return bvh;
}

std::vector<int> Scene::buildStaticBvh(const std::vector<uint64_t>& fingerprints) {
    std::vector<int> top;
    std::map<std::string, int> uses;
    for (size_t i = 0; i < shapes_.size(); ++i)
        if (shapes_[i].prototype < 0) top.push_back(int(i)), uses[shapes_[i].name]++;
    auto isStatic = [&](int i) {
        const Shape& s = shapes_[i];
        return uses[s.name] == 1 && s.stepPositions.empty() && s.stepCenters.empty();
    };
    for (int i : top)
        if (isStatic(i)) topFingerprints_[shapes_[i].name] = fingerprints[i];
    if (!previous_) return top;  // a scene built alone: every shape in the top level, as always

    std::map<std::string, int> unchanged;  // by name
    for (int i : top) {
        auto it = previous_->topFingerprints.find(shapes_[i].name);
        if (isStatic(i) && it != previous_->topFingerprints.end() && it->second == fingerprints[i])
            unchanged[shapes_[i].name] = i;
    }
    if (unchanged.empty()) return top;
    // The previous static BVH while all of its shapes are here unchanged; else a new one of the
    // shapes unchanged since the previous scene (built once, then kept while they stay so).
    std::vector<int> members;
    if (const std::shared_ptr<const Bvh>& previous = previous_->staticBvh) {
        for (const std::string& name : previous->names) {
            auto it = unchanged.find(name);
            if (it == unchanged.end()) {
                members.clear();
                break;
            }
            members.push_back(it->second);
        }
    }
    if (members.empty())
        for (int i : top)
            if (unchanged.count(shapes_[i].name)) members.push_back(i);
    staticBvh_ = shapesBvh(members, fingerprints, previous_->staticBvh);
    staticBvhToShape_ = members;
    std::vector<bool> inStatic(shapes_.size(), false);
    for (int i : members) inStatic[size_t(i)] = true;
    std::vector<int> loose;
    for (int i : top)
        if (!inStatic[size_t(i)]) loose.push_back(i);
    return loose;
}

void Scene::countShapes() {
    for (const Shape& s : shapes_) {
        if (s.isSphere)
            stats_.spheres++;
        else
            stats_.triangles += s.indices.size() / 3;
        if (!s.stepPositions.empty() || !s.stepCenters.empty()) stats_.movingShapes++;
    }
}

}  // namespace gi
