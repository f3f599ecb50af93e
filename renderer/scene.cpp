#include "scene.h"

#include "embree_ray.h"
#include "scene_bvh.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <numeric>
#include <sstream>

namespace gi {

namespace {

bool isSimilarity(const Mat4& m) {
    Vec3 a = m.vector(Vec3(1, 0, 0)), b = m.vector(Vec3(0, 1, 0)), c = m.vector(Vec3(0, 0, 1));
    float la = length(a), lb = length(b), lc = length(c);
    float tol = 1e-4f * std::max(la, std::max(lb, lc));
    return std::fabs(la - lb) < tol && std::fabs(la - lc) < tol && std::fabs(dot(a, b)) < tol * la &&
           std::fabs(dot(a, c)) < tol * la && std::fabs(dot(b, c)) < tol * lb;
}

// The indices 0..count-1 in order of nameOf(index), insertion order among equal names. Hosts
// add lights and shapes in their own order (the USD loader in stage order, hdGi in Hydra's path
// order); the scene's lights follow their names, so that every choice made by light index (light
// selection, photon emission with its pilot and guide) is the same whichever host built the
// scene (issue 18).
template <typename NameOf>
std::vector<int> orderedByName(size_t count, NameOf nameOf) {
    std::vector<int> order(count);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return nameOf(a) < nameOf(b); });
    return order;
}

}  // namespace

Scene::Scene() : device_(std::make_shared<EmbreeDevice>()) { device_->reporter = this; }

std::string Scene::indexedName(const std::string& base, size_t index, size_t count) {
    std::string digits = std::to_string(index);
    const size_t width = std::to_string(std::max<size_t>(count, 1) - 1).size();
    if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
    return base + "[" + digits + "]";
}

Scene::~Scene() {
    if (top_) rtcReleaseScene(top_);
    if (lightBvh_) rtcReleaseScene(lightBvh_);
    const Scene* self = this;
    device_->reporter.compare_exchange_strong(self, nullptr);  // a later scene may report there now
}

void Scene::warn(const std::string& message) const {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    warnings_.push_back(message);
}

std::vector<std::string> Scene::warnings() const {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    return warnings_;
}

size_t Scene::warningCount() const {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    return warnings_.size();
}

void Scene::dropWarningsAfter(size_t count) const {
    std::lock_guard<std::mutex> lock(warningsMutex_);
    if (warnings_.size() > count) warnings_.resize(count);
}

int Scene::addMaterial(const MaterialDesc& desc) {
    materialDescs_.push_back(desc);
    return int(materialDescs_.size()) - 1;
}

int Scene::defaultMaterial() {
    if (defaultMaterial_ < 0) {
        MaterialDesc d;
        d.name = "<default grey diffuse>";
        d.useSpecularWorkflow = true;
        defaultMaterial_ = addMaterial(d);
    }
    return defaultMaterial_;
}

int Scene::addPrototype(const std::string& name) {
    Prototype prototype;
    prototype.name = name;
    prototypes_.push_back(std::move(prototype));
    return int(prototypes_.size()) - 1;
}

int Scene::addMesh(const std::string& name, std::vector<Vec3> positions, std::vector<uint32_t> indices,
                   std::vector<Vec3> normals, std::vector<Vec2> uvs, int material, const Mat4* transform,
                   bool doubleSided, int prototype, const MotionSteps& motion) {
    if (prototype >= int(prototypes_.size())) {
        warn("mesh " + name + ": unknown prototype " + std::to_string(prototype) + "; ignored");
        return -1;
    }
    if (transform && !transform->isFinite()) {
        warn("mesh " + name + ": NaN or Inf in its transform; ignored");
        return -1;
    }
    if (material < 0 || material >= int(materialDescs_.size())) material = defaultMaterial();
    if (!normals.empty() && normals.size() != positions.size()) {
        warn("mesh " + name + ": " + std::to_string(normals.size()) + " normals for " +
             std::to_string(positions.size()) + " points; normals ignored");
        normals.clear();
    }
    if (!uvs.empty() && uvs.size() != positions.size()) {
        warn("mesh " + name + ": st has the wrong length; ignored");
        uvs.clear();
    }
    size_t badNormals = 0, badUvs = 0;
    for (Vec3& n : normals)
        if (!isFinite(n) || !(lengthSquared(n) >= 1e-12f)) {
            n = Vec3(0.0f);  // shading falls back to the geometric normal
            ++badNormals;
        }
    std::vector<Mat4> stepTransforms;
    std::vector<std::vector<Vec3>> stepPositions = meshMotion(name, positions, transform, prototype, motion, stepTransforms);
    std::vector<std::vector<Vec3>> stepNormals;
    if (!normals.empty() && !stepTransforms.empty())
        for (const Mat4& m : stepTransforms) {
            std::vector<Vec3> step = normals;
            for (Vec3& n : step)
                if (lengthSquared(n) > 0) n = normalize(m.normal(n));
            stepNormals.push_back(std::move(step));
        }
    // Bake the transform into top-level meshes; prototypes keep object space.
    if (!stepPositions.empty()) {
        positions = stepPositions[0];
        if (!stepNormals.empty()) normals = stepNormals[0];
        else if (transform && prototype < 0)
            for (Vec3& n : normals)
                if (lengthSquared(n) > 0) n = normalize(transform->normal(n));
    } else if (transform && prototype < 0) {
        for (Vec3& p : positions) p = transform->point(p);
        for (Vec3& n : normals)
            if (lengthSquared(n) > 0) n = normalize(transform->normal(n));
    }
    for (Vec2& uv : uvs)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
            uv = Vec2(0, 0);
            ++badUvs;
        }
    // Keep only triangles with valid indices, finite points and non-zero area.
    std::vector<uint32_t> kept;
    kept.reserve(indices.size());
    size_t outOfRange = 0, nonFinite = 0, degenerate = 0;
    for (size_t i = 0; i + 2 < indices.size(); i += 3) {
        uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
        if (a >= positions.size() || b >= positions.size() || c >= positions.size()) {
            ++outOfRange;
            continue;
        }
        if (!embreeValid(positions[a]) || !embreeValid(positions[b]) || !embreeValid(positions[c])) {
            ++nonFinite;
            continue;
        }
        Vec3 cr = cross(positions[b] - positions[a], positions[c] - positions[a]);
        if (!(lengthSquared(cr) > 0)) {
            ++degenerate;
            continue;
        }
        kept.insert(kept.end(), {a, b, c});
    }
    auto report = [&](size_t count, const char* what) {
        if (count) warn("mesh " + name + ": " + std::to_string(count) + " " + what);
    };
    report(outOfRange, "triangles with out-of-range indices dropped");
    report(nonFinite, "triangles with NaN, Inf or out-of-range (beyond 1e18) points dropped");
    report(degenerate, "degenerate (zero-area) triangles dropped");
    report(badNormals, "NaN or zero normals replaced by the geometric normal");
    report(badUvs, "NaN st values set to 0");
    if (indices.size() % 3) warn("mesh " + name + ": index count is not a multiple of 3; the rest is ignored");
    if (kept.empty()) {
        warn("mesh " + name + ": no valid triangles; ignored");
        return -1;
    }
    for (size_t step = 1; step < stepPositions.size(); ++step)
        for (uint32_t i : kept)
            if (!embreeValid(stepPositions[step][i])) {
                warn("mesh " + name + ": NaN, Inf or out-of-range points at motion step " + std::to_string(step) +
                     "; rendered without motion blur");
                stepPositions.clear();
                stepNormals.clear();
                break;
            }
    for (Vec3& p : positions)
        if (!embreeValid(p)) p = Vec3(0.0f);  // unreferenced now; keep Embree's bounds finite
    for (auto& step : stepPositions)
        for (Vec3& p : step)
            if (!embreeValid(p)) p = Vec3(0.0f);
    Shape s;
    s.name = name;
    s.positions = std::move(positions);
    s.normals = std::move(normals);
    s.uvs = std::move(uvs);
    s.indices = std::move(kept);
    s.stepPositions = std::move(stepPositions);
    s.stepNormals = std::move(stepNormals);
    s.material = material;
    s.doubleSided = doubleSided;
    s.prototype = prototype;
    shapes_.push_back(std::move(s));
    int id = int(shapes_.size()) - 1;
    if (prototype >= 0) prototypes_[prototype].shapes.push_back(id);
    return id;
}

int Scene::addSphere(const std::string& name, Vec3 center, float radius, int material, const Mat4* transform,
                     int prototype, const MotionSteps& motion) {
    if (!isFinite(center) || !std::isfinite(radius) || !(radius > 0) || (transform && !transform->isFinite())) {
        warn("sphere " + name + ": NaN, Inf or non-positive radius; ignored");
        return -1;
    }
    if (material < 0 || material >= int(materialDescs_.size())) material = defaultMaterial();
    if (!motion.points.empty()) warn("sphere " + name + ": point motion does not apply to a sphere; ignored");
    std::vector<Mat4> steps;
    if (!motion.transforms.empty() && prototype >= 0)
        warn("sphere " + name + ": transform motion inside a prototype is ignored (its instances' motion applies)");
    else
        steps = transformMotion("sphere " + name, motion);
    bool round = !transform || isSimilarity(*transform);
    for (const Mat4& m : steps) round = round && isSimilarity(m);
    if ((transform || !steps.empty()) && prototype < 0 && !round) {
        // Embree spheres are round: an ellipsoid is a unit sphere under an instance transform.
        int proto = addPrototype(name);
        int id = addSphere(name, center, radius, material, nullptr, proto);
        MotionSteps instanceMotion;
        instanceMotion.transforms = steps;
        addInstance(proto, steps.empty() ? *transform : steps[0], name, instanceMotion);
        return id;
    }
    Shape s;
    s.name = name;
    s.isSphere = true;
    s.center = center;
    s.radius = radius;
    if (transform && prototype < 0) {
        s.center = transform->point(center);
        s.radius = radius * std::cbrt(std::fabs(float(transform->det3())));
    }
    for (const Mat4& m : steps) {
        s.stepCenters.push_back(m.point(center));
        s.stepRadii.push_back(radius * std::cbrt(std::fabs(float(m.det3()))));
    }
    if (!steps.empty()) s.center = s.stepCenters[0], s.radius = s.stepRadii[0];
    for (size_t i = 0; i < std::max<size_t>(1, steps.size()); ++i) {
        Vec3 c = steps.empty() ? s.center : s.stepCenters[i];
        float r = steps.empty() ? s.radius : s.stepRadii[i];
        if (!embreeValid(c) || !(r < kMaxEmbreeCoordinate)) {
            warn("sphere " + name + ": beyond the renderer's range (coordinates or radius above 1e18); ignored");
            return -1;
        }
    }
    s.material = material;
    s.prototype = prototype;
    shapes_.push_back(s);
    int id = int(shapes_.size()) - 1;
    if (prototype >= 0) prototypes_[prototype].shapes.push_back(id);
    return id;
}

int Scene::addInstance(int prototype, const Mat4& transform, const std::string& name, const MotionSteps& motion) {
    if (prototype < 0 || prototype >= int(prototypes_.size())) {
        warn("instance " + name + ": unknown prototype; ignored");
        return -1;
    }
    Mat4 inv;
    if (!transform.isFinite() || !transform.inverse(inv)) {
        warn("instance " + name + ": NaN, Inf or singular transform; ignored");
        return -1;
    }
    if (!motion.points.empty()) warn("instance " + name + ": point motion does not apply to an instance; ignored");
    std::vector<Mat4> steps = transformMotion("instance " + name, motion);
    instances_.push_back(Instance{name, prototype, steps.empty() ? transform : steps[0], steps});
    return int(instances_.size()) - 1;
}

int Scene::addLight(const LightDesc& desc) {
    lightDescs_.push_back(desc);
    return int(lightDescs_.size()) - 1;
}

std::shared_ptr<Image> Scene::loadImage(const std::string& file, const std::string& colorSpace, std::string& error,
                                        bool* first) {
    std::string key = file + "|" + colorSpace;
    auto it = imageCache_.find(key);
    *first = it == imageCache_.end();
    if (!*first) return it->second;
    std::shared_ptr<Image> image;
    bool read = true;
    if (sharedImages_) image = sharedImages_->get(file, colorSpace, error, &read);
    else if (!std::filesystem::exists(file)) error = "file not found";
    else image = Image::load(file, colorSpace, error);
    if (image && read) stats_.texturesRead++;
    if (image) {
        stats_.textureBytes += image->memoryBytes();
        stats_.textures++;
    }
    return imageCache_.emplace(key, image).first->second;
}

Texture Scene::loadTexture(const TextureDesc& desc, const std::string& materialName, const std::string& input) {
    Texture t;
    t.desc = desc;
    if (isUdimPath(desc.file)) {
        // Tiles that are not there are normal (a UDIM set covers the tiles its mesh uses); one that
        // is there and cannot be read is a problem.
        t.udimTiles.resize(kUdimTiles);
        for (int i = 0; i < kUdimTiles; ++i) {
            std::string tile = udimTilePath(desc.file, kUdimFirstTile + i);
            if (!std::filesystem::exists(tile)) continue;
            std::string tileError;
            bool first = false;
            t.udimTiles[size_t(i)] = loadImage(tile, desc.sourceColorSpace, tileError, &first);
            if (!t.udimTiles[size_t(i)] && first)
                warn("material " + materialName + ": " + input + " texture " + tile + ": " + tileError +
                     "; its tile reads the fallback");
            if (!t.image) t.image = t.udimTiles[size_t(i)];
        }
        if (!t.image) {
            t.udimTiles.clear();
            if (imageCache_.emplace(desc.file + "|" + desc.sourceColorSpace, nullptr).second)  // once per pattern
                warn("material " + materialName + ": " + input + " texture " + desc.file +
                     ": no UDIM tile (1001-1100) found; using the constant value");
        }
    } else {
        std::string error;
        bool first = false;
        t.image = loadImage(desc.file, desc.sourceColorSpace, error, &first);
        if (!t.image && first)  // once per file, as it is read once
            warn("material " + materialName + ": " + input + " texture " + desc.file + ": " + error +
                 "; using the constant value");
    }
    if (t.image) t.prepare();
    return t;
}

void Scene::bindMaterials() {
    // Textures are read only for materials some geometry uses.
    std::vector<bool> used(materialDescs_.size(), false);
    for (const Shape& s : shapes_) used[s.material] = true;
    materials_.clear();
    for (size_t i = 0; i < materialDescs_.size(); ++i) {
        const MaterialDesc& d = materialDescs_[i];
        Material::TextureBinder binder = [&](const TextureDesc& t, const std::string& input) {
            return used[i] ? loadTexture(t, d.name, input) : Texture();
        };
        materials_.push_back(std::make_unique<Material>(d, binder));
        if (used[i] && !materials_.back()->repairedInputs().empty()) {
            std::string inputs;
            for (const std::string& input : materials_.back()->repairedInputs())
                inputs += (inputs.empty() ? "" : ", ") + input;
            warn("material " + d.name + ": NaN, Inf or out-of-range " + inputs + " replaced by defaults");
        }
        if (used[i] && materials_.back()->isSpecular()) hasSpecular_ = true;
    }
}

void Scene::buildShapeGeometry(RTCScene target, std::vector<int>& geomToShape, int shapeId) {
    const Shape& s = shapes_[shapeId];
    RTCGeometry g;
    // Moving shapes get one vertex buffer per time step (Embree's multi-segment motion blur).
    const size_t steps = s.isSphere ? s.stepCenters.size() : s.stepPositions.size();
    if (s.isSphere && !steps) {
        g = newSphereGeometry(device_->device, *sphereStore_, s.center, s.radius);
    } else if (s.isSphere) {
        g = rtcNewGeometry(device_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        if (steps) rtcSetGeometryTimeStepCount(g, unsigned(steps));
        for (size_t step = 0; step < std::max<size_t>(1, steps); ++step) {
            Vec3 c = steps ? s.stepCenters[step] : s.center;
            float* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, unsigned(step),
                                                                   RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
            v[0] = c.x, v[1] = c.y, v[2] = c.z, v[3] = steps ? s.stepRadii[step] : s.radius;
        }
    } else {
        g = rtcNewGeometry(device_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        if (steps) rtcSetGeometryTimeStepCount(g, unsigned(steps));
        for (size_t step = 0; step < std::max<size_t>(1, steps); ++step) {
            const std::vector<Vec3>& points = steps ? s.stepPositions[step] : s.positions;
            float* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, unsigned(step),
                                                                   RTC_FORMAT_FLOAT3, 3 * sizeof(float), points.size()));
            for (size_t i = 0; i < points.size(); ++i)
                v[3 * i] = points[i].x, v[3 * i + 1] = points[i].y, v[3 * i + 2] = points[i].z;
        }
        size_t triangles = s.indices.size() / 3;
        uint32_t* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(uint32_t), triangles));
        std::copy(s.indices.begin(), s.indices.end(), idx);
    }
    stats_.primitivesBuilt += s.isSphere ? 1 : s.indices.size() / 3;
    rtcCommitGeometry(g);
    unsigned geomId = rtcAttachGeometry(target, g);
    rtcReleaseGeometry(g);
    if (geomToShape.size() <= geomId) geomToShape.resize(geomId + 1, -1);
    geomToShape[geomId] = shapeId;
}

bool Scene::isStaticSphere(int shape) const {
    return shapes_[size_t(shape)].isSphere && shapes_[size_t(shape)].stepCenters.empty();
}

bool Scene::spheresBesideBvh(const std::vector<int>& shapes) const {
    return size_t(std::count_if(shapes.begin(), shapes.end(), [&](int i) { return isStaticSphere(i); })) <=
           kDirectSpheres;
}

void Scene::chooseDirectSpheres(std::vector<int>& top) {
    if (!spheresBesideBvh(top)) return;
    for (int i : top)
        if (isStaticSphere(i)) directSpheres_.push_back({SphereData{shapes_[size_t(i)].center, shapes_[size_t(i)].radius}, i});
    top.erase(std::remove_if(top.begin(), top.end(), [&](int i) { return isStaticSphere(i); }), top.end());
}

void Scene::commit() {
    if (committed_) return;
    auto start = std::chrono::steady_clock::now();
    bindMaterials();
    countShapes();
    std::vector<uint64_t> fingerprints(shapes_.size());
    for (size_t i = 0; i < shapes_.size(); ++i) fingerprints[i] = fingerprint(shapes_[i]);
    top_ = rtcNewScene(device_->device);
    rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(top_, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);  // the next scene may mask it (topLevelAsBvh)
    std::vector<int> topShapes = buildStaticBvh(fingerprints);
    chooseDirectSpheres(topShapes);
    for (int i : topShapes) buildShapeGeometry(top_, topGeomToShape_, i);
    std::map<std::string, int> prototypeUses;
    for (const Prototype& p : prototypes_) prototypeUses[p.name]++;
    for (Prototype& p : prototypes_) {
        std::shared_ptr<const Bvh> previous;
        if (previous_ && prototypeUses[p.name] == 1) {
            auto it = previous_->prototypes.find(p.name);
            if (it != previous_->prototypes.end()) previous = it->second;
        }
        p.bvh = shapesBvh(p.shapes, fingerprints, previous);
        p.rtc = p.bvh->rtc;
        p.geomToShape = p.shapes;
        for (int s : p.shapes)
            if (materials_[shapes_[s].material]->isEmissive()) p.emissive = true;
    }
    for (size_t i = 0; i < instances_.size(); ++i) {
        const Instance& inst = instances_[i];
        RTCGeometry g = rtcNewGeometry(device_->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, prototypes_[inst.prototype].rtc);
        // Embree's column-major layout of M^T is exactly USD's row-major M. A moving instance
        // gets one transform per time step (linearly interpolated, as motion.h's atTime).
        const size_t steps = inst.stepToWorld.size();
        if (steps) {
            rtcSetGeometryTimeStepCount(g, unsigned(steps));
            stats_.movingInstances++;
        }
        for (size_t step = 0; step < std::max<size_t>(1, steps); ++step) {
            const Mat4& toWorld = steps ? inst.stepToWorld[step] : inst.toWorld;
            float m[16];
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) m[r * 4 + c] = float(toWorld.m[r][c]);
            rtcSetGeometryTransform(g, unsigned(step), RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, m);
        }
        rtcCommitGeometry(g);
        unsigned geomId = rtcAttachGeometry(top_, g);
        rtcReleaseGeometry(g);
        if (topGeomToShape_.size() <= geomId) topGeomToShape_.resize(geomId + 1, -1);
        topGeomToShape_[geomId] = -int(i) - 1;
    }
    // With motion, bounds over the whole shutter: the union of the linear bounds at open and at
    // close. Without, the scene's bounds (so that a scene where nothing moves is unchanged).
    auto topBounds = [&](Vec3& lo, Vec3& hi) {
        RTCBounds b;
        rtcGetSceneBounds(top_, &b);
        lo = Vec3(b.lower_x, b.lower_y, b.lower_z), hi = Vec3(b.upper_x, b.upper_y, b.upper_z);
        if (hasMotion()) {
            RTCLinearBounds linear;
            rtcGetSceneLinearBounds(top_, &linear);
            lo = vmin(Vec3(linear.bounds0.lower_x, linear.bounds0.lower_y, linear.bounds0.lower_z),
                      Vec3(linear.bounds1.lower_x, linear.bounds1.lower_y, linear.bounds1.lower_z));
            hi = vmax(Vec3(linear.bounds0.upper_x, linear.bounds0.upper_y, linear.bounds0.upper_z),
                      Vec3(linear.bounds1.upper_x, linear.bounds1.upper_y, linear.bounds1.upper_z));
        }
    };
    Vec3 lo(kInf), hi(-kInf);
    if (staticBvh_) {
        // A static BVH with masks bounds shapes this scene does not have: the scene's bounds are
        // those of the rest and of the shapes it keeps there, as the scene built alone has them.
        if (!staticMasked_.empty()) {
            rtcCommitScene(top_);
            topBounds(lo, hi);
            for (int shape : staticBvhToShape_)
                if (shape >= 0) growByShape(shapes_[size_t(shape)], lo, hi);
        }
        // Identity-instanced: its hits are the top level's (hitShape).
        RTCGeometry g = rtcNewGeometry(device_->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, staticBvh_->rtc);
        const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, identity);
        rtcCommitGeometry(g);
        staticBvhGeom_ = rtcAttachGeometry(top_, g);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(top_);
    stats_.instances = instances_.size();
    stats_.prototypes = prototypes_.size();
    if (staticMasked_.empty()) topBounds(lo, hi);
    for (const DirectSphere& s : directSpheres_) growByShape(shapes_[size_t(s.shape)], lo, hi);  // not in top_
    if (isFinite(lo) && isFinite(hi) && hi.x >= lo.x) {
        boundsMin_ = lo;
        boundsMax_ = hi;
        bounds_.center = (lo + hi) * 0.5f;
        bounds_.radius = std::max(1e-3f, length(hi - lo) * 0.5f);
    }
    buildLights();
    stats_.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    committed_ = true;
}

void Scene::buildLights() {
    std::vector<Portal> portals;
    bool hasDome = false;
    for (const LightDesc& d : lightDescs_) hasDome = hasDome || d.kind == "dome";
    const std::vector<int> descOrder =
        orderedByName(lightDescs_.size(), [&](int i) -> const std::string& { return lightDescs_[size_t(i)].name; });
    for (int i : descOrder) {
        const LightDesc& d = lightDescs_[size_t(i)];
        if (d.kind != "portal") continue;
        Portal portal;
        if (!hasDome) warn("portal " + d.name + ": no dome light to guide; ignored");
        else if (makePortal(*this, d, portal)) portals.push_back(portal);
    }
    for (int i : descOrder) {
        if (lightDescs_[size_t(i)].kind == "portal") continue;
        LightDesc d = lightDescs_[size_t(i)];
        d.motionTransforms = transformMotion("light " + d.name, MotionSteps{{}, d.motionTransforms});
        if (!d.motionTransforms.empty() && !lightKindMoves(d.kind)) {
            warn("light " + d.name + ": a " + d.kind + " light's motion during the shutter is not blurred; it shines "
                 "as at the frame");
            d.motionTransforms.clear();
        }
        std::string warning;
        auto light = createLight(d, warning);
        if (light && !d.motionTransforms.empty()) stats_.movingLights++;
        if (!warning.empty()) warn(warning);
        if (light) lights_.push_back(std::move(light));
    }
    // A shape's emissive triangles as lights: placed by `toWorld` (an instance's, at the frame) or in
    // world space; moving ones (the shape's own steps, or `stepToWorld`, an instance's) where they
    // are at each ray's time, as Embree's motion geometry has them.
    auto addTriangles = [&](const Shape& s, const Mat4* toWorld, const std::vector<Mat4>& stepToWorld) {
        const Material* m = materials_[s.material].get();
        const bool moving = !s.stepPositions.empty() || !stepToWorld.empty();
        int first = int(lights_.size());
        for (size_t t = 0; t + 2 < s.indices.size(); t += 3) {
            Vec3 p[3];
            Vec2 uv[3];
            for (int k = 0; k < 3; ++k) {
                uint32_t i = s.indices[t + k];
                p[k] = toWorld ? toWorld->point(s.positions[i]) : s.positions[i];
                uv[k] = s.uvs.empty() ? Vec2(0, 0) : s.uvs[i];
            }
            if (moving) {
                std::vector<std::array<Vec3, 3>> points;
                if (s.stepPositions.empty()) points.push_back({s.positions[s.indices[t]], s.positions[s.indices[t + 1]], s.positions[s.indices[t + 2]]});
                for (const std::vector<Vec3>& step : s.stepPositions)
                    points.push_back({step[s.indices[t]], step[s.indices[t + 1]], step[s.indices[t + 2]]});
                std::vector<Mat4> placed = !stepToWorld.empty() ? stepToWorld : toWorld ? std::vector<Mat4>{*toWorld} : std::vector<Mat4>{};
                lights_.push_back(createMovingTriangleLight(std::move(points), std::move(placed), uv, m, s.doubleSided, s.name));
            } else {
                lights_.push_back(createTriangleLight(p, uv, m, s.doubleSided, s.name));
            }
            stats_.emissiveTriangles++;
        }
        return first;
    };
    auto shapeName = [&](int i) -> const std::string& { return shapes_[size_t(i)].name; };
    for (int i : orderedByName(shapes_.size(), shapeName)) {
        Shape& s = shapes_[size_t(i)];
        if (s.prototype < 0 && !s.isSphere && materials_[s.material]->isEmissive())
            s.lightOffset = addTriangles(s, nullptr, {});
    }
    for (const Shape& s : shapes_)
        if (s.isSphere && materials_[s.material]->isEmissive())
            warn("sphere " + s.name + ": emissive spheres are lit only when hit, not sampled as lights");
    for (int i : orderedByName(instances_.size(), [&](int i) -> const std::string& { return instances_[size_t(i)].name; })) {
        Instance& inst = instances_[size_t(i)];
        const Prototype& p = prototypes_[inst.prototype];
        if (!p.emissive) continue;
        inst.lightOffset = int(lights_.size());
        for (int k : orderedByName(p.shapes.size(), [&](int k) -> const std::string& { return shapeName(p.shapes[size_t(k)]); })) {
            int sid = p.shapes[size_t(k)];
            if (!shapes_[sid].isSphere && materials_[shapes_[sid].material]->isEmissive())
                prototypes_[inst.prototype].relativeLightOffset[sid] =
                    addTriangles(shapes_[sid], &inst.toWorld, inst.stepToWorld) - inst.lightOffset;
        }
    }
    if (!portals.empty()) {
        stats_.portals = portals.size();
        auto set = std::make_shared<const PortalSet>(std::move(portals));
        for (auto& light : lights_)
            if (light->isInfinite()) light->setPortals(set);
    }
    std::vector<float> power;
    Vec3 lo = boundsMin_, hi = boundsMax_;  // the geometry's and the bounded lights' (photonBounds)
    bool grew = false;
    for (size_t i = 0; i < lights_.size(); ++i) {
        lights_[i]->preprocess(bounds_);
        power.push_back(luminance(lights_[i]->power(bounds_)));
        if (lights_[i]->isInfinite()) infiniteLights_.push_back(int(i));
        Vec3 a, b;
        if (!lights_[i]->shapeBounds(&a, &b)) continue;
        analyticLights_.push_back(int(i));
        if (!isFinite(a) || !isFinite(b)) continue;
        grew = grew || a.x < lo.x || a.y < lo.y || a.z < lo.z || b.x > hi.x || b.y > hi.y || b.z > hi.z;
        lo = vmin(lo, a), hi = vmax(hi, b);
    }
    photonBounds_ = bounds_;
    if (grew) {
        photonBounds_.center = (lo + hi) * 0.5f;
        photonBounds_.radius = std::max(1e-3f, length(hi - lo) * 0.5f);
    }
    buildLightBvh();
    std::vector<const Light*> lights;
    for (const auto& light : lights_) lights.push_back(light.get());
    lightSampler_ = LightSampler(lights, power);
    stats_.lights = lights_.size();
    // A scene that emits nothing renders black: say so, or the user is left to guess (an OBJ whose
    // light material is missing from its .mtl; a stage whose lights are deactivated).
    if (lights_.empty() && !std::any_of(shapes_.begin(), shapes_.end(), [&](const Shape& s) {
            return materials_[size_t(s.material)]->isEmissive();
        }))
        warn("no lights and no emissive surfaces: every image of this scene is black");
}

}  // namespace gi
