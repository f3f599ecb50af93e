// Scene::reuseBvhOf: consecutive scenes (a frame sequence, an interactive session's edits) build
// only the BVHs of what changed. Shapes are matched by name and compared by a fingerprint of what
// their BVH is built from (points, indices, sphere centre and radius, motion steps), so a change a
// host does not announce is still caught. Materials, normals and uvs are not BVH inputs: shading
// reads them from the new scene's own shapes.
#include <algorithm>
#include <cstring>
#include <set>
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

void Scene::reuseBvhOf(const Scene& previous, BvhReuse reuse) {
    if (committed_) throw std::logic_error("reuseBvhOf: the scene is committed already");
    if (!previous.committed_ || &previous == this) return;  // nothing built to take
    // A BVH can only be instanced within its own device; nothing of this scene's is built yet.
    device_ = previous.device_;
    device_->reporter = this;
    previous_ = std::make_unique<Previous>();
    previous_->topFingerprints = previous.topFingerprints_;
    previous_->staticBvh = previous.staticBvh_;
    previous_->topLevel = previous.topLevelAsBvh();
    previous_->masks = reuse == BvhReuse::Edits;
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
    bvh->spheres = sphereStore_;
    bvh->rtc = rtcNewScene(device_->device);
    rtcSetSceneBuildQuality(bvh->rtc, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(bvh->rtc, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);  // masks (buildStaticBvh)
    size_t builtBefore = stats_.primitivesBuilt;
    std::vector<int> geomToShape;
    for (int s : shapes) {
        size_t before = stats_.primitivesBuilt;
        buildShapeGeometry(bvh->rtc, geomToShape, s);
        bvh->names.push_back(shapes_[s].name);
        bvh->fingerprints.push_back(fingerprints[s]);
        bvh->geometryPrimitives.push_back(stats_.primitivesBuilt - before);
        bvh->geometryBounds.push_back(shapeBounds(shapes_[s]));
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

    // The previous static BVH (or the previous scene's top level, when it held shapes alone),
    // kept while it holds only shapes this scene has as they were; or, for edits, with those it
    // no longer has so (moved, edited, hidden, removed) masked: hits on them are skipped
    // (Scene::trace), and the shapes that changed are built in the top level. So an edit builds
    // only what it changed, until the masked primitives pass kMaskedShare of the BVH's.
    if (const std::shared_ptr<const Bvh>& base = previous_->staticBvh ? previous_->staticBvh : previous_->topLevel) {
        std::map<std::string, int> staticByName;
        for (int i : top)
            if (isStatic(i)) staticByName[shapes_[i].name] = i;
        std::vector<int> toShape(base->names.size(), -1);
        size_t masked = 0;
        bool anyKept = false;
        for (size_t g = 0; g < base->names.size(); ++g) {
            auto it = staticByName.find(base->names[g]);
            if (it != staticByName.end() && fingerprints[it->second] == base->fingerprints[g]) {
                toShape[g] = it->second;
                anyKept = true;
            } else {
                masked += base->geometryPrimitives[g];
            }
        }
        if (anyKept && double(masked) <= (previous_->masks ? kMaskedShare * double(base->primitives) : 0.0)) {
            staticBvh_ = base;
            staticBvhToShape_ = toShape;
            if (masked > 0) {
                staticMasked_.assign(toShape.size(), 0);
                for (size_t g = 0; g < toShape.size(); ++g)
                    if (toShape[g] < 0) staticMasked_[g] = 1, maskedBounds_.push_back(base->geometryBounds[g]);
                // Shadow rays test these bounds before they take the filter; past a few, their union.
                constexpr size_t kMaskedBoundsTested = 8;
                if (maskedBounds_.size() > kMaskedBoundsTested) {
                    Bounds all;
                    for (const Bounds& b : maskedBounds_) all.lo = vmin(all.lo, b.lo), all.hi = vmax(all.hi, b.hi);
                    maskedBounds_ = {all};
                }
                // Padded well past the float error of a hit on their surfaces: a miss of the box
                // must be a miss of the shape.
                for (Bounds& b : maskedBounds_) {
                    Vec3 pad(1e-4f * (maxComponent(vmax(vmax(b.lo, -b.lo), vmax(b.hi, -b.hi))) + maxComponent(b.hi - b.lo)));
                    b.lo = b.lo - pad, b.hi = b.hi + pad;
                }
            }
            stats_.primitivesReused += base->primitives - masked;
            stats_.primitivesMasked = masked;
            return shapesOutside(top, toShape);
        }
    }
    // Else a new static BVH of the shapes unchanged since the previous scene (built once, then
    // kept while they stay so). Spheres the top level tests beside its BVH (chooseDirectSpheres)
    // stay out of it.
    const bool spheresBeside = spheresBesideBvh(top);
    std::vector<int> members;
    for (int i : top) {
        auto it = previous_->topFingerprints.find(shapes_[i].name);
        if (isStatic(i) && !(spheresBeside && isStaticSphere(i)) && it != previous_->topFingerprints.end() &&
            it->second == fingerprints[i])
            members.push_back(i);
    }
    if (members.empty()) return top;
    staticBvh_ = shapesBvh(members, fingerprints, nullptr);
    staticBvhToShape_ = members;
    return shapesOutside(top, members);
}

// The shapes of `top` that are not in `inStatic` (shape indices; -1 entries are ignored): those
// the top level builds beside a static BVH.
std::vector<int> Scene::shapesOutside(const std::vector<int>& top, const std::vector<int>& inStatic) const {
    std::vector<bool> member(shapes_.size(), false);
    for (int i : inStatic)
        if (i >= 0) member[size_t(i)] = true;
    std::vector<int> loose;
    for (int i : top)
        if (!member[size_t(i)]) loose.push_back(i);
    return loose;
}

void Scene::growByShape(const Shape& shape, Vec3& lo, Vec3& hi) {
    if (shape.isSphere) {  // as its geometry bounds it: centre -+ radius
        lo = vmin(lo, shape.center - Vec3(shape.radius));
        hi = vmax(hi, shape.center + Vec3(shape.radius));
        return;
    }
    for (uint32_t index : shape.indices) {  // the triangles' corners, not every point
        lo = vmin(lo, shape.positions[index]);
        hi = vmax(hi, shape.positions[index]);
    }
}

std::shared_ptr<const Scene::Bvh> Scene::topLevelAsBvh() const {
    // Only a top level of static shapes with names of their own: an instance in it would be an
    // instance within an instance (Embree here allows one level), and a name must find its shape.
    if (!instances_.empty() || staticBvh_) return nullptr;
    auto bvh = std::make_shared<Bvh>();
    std::set<std::string> names;
    for (int shape : topGeomToShape_) {
        if (shape < 0) return nullptr;
        const Shape& s = shapes_[size_t(shape)];
        // topFingerprints_ holds the static shapes with a name of their own.
        auto fingerprint = topFingerprints_.find(s.name);
        if (fingerprint == topFingerprints_.end() || !names.insert(s.name).second) return nullptr;
        bvh->names.push_back(s.name);
        bvh->fingerprints.push_back(fingerprint->second);
        bvh->geometryPrimitives.push_back(s.isSphere ? 1 : s.indices.size() / 3);
        bvh->primitives += bvh->geometryPrimitives.back();
        bvh->geometryBounds.push_back(shapeBounds(s));
    }
    rtcRetainScene(top_);
    bvh->rtc = top_;
    bvh->spheres = sphereStore_;
    return bvh;
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
