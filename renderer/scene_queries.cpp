// The Scene's ray queries: closest hits (trace, then finish into a SurfaceInteraction), shadow
// rays, the analytic lights tested beside the surface BVH, and the masks that hide shapes of a
// kept BVH (scene_reuse.cpp). scene.cpp builds what these query.
#include <algorithm>
#include <cmath>

#include "embree_ray.h"
#include "scene.h"
#include "scene_bvh.h"
#include "sphere_geometry.h"

namespace gi {

namespace {

// Perturbs the shading normal n by a tangent-space normal map. The tangent frame follows the
// triangle's texture parametrisation (T along +u, B along +v, MikkTSpace's convention for
// OpenGL-style maps), made orthonormal around n. Triangles without a usable parametrisation keep n.
Vec3 applyNormalMap(const Material& material, Vec2 uv, Vec3 n, Vec3 e1, Vec3 e2, Vec2 duv1, Vec2 duv2) {
    float det = duv1.x * duv2.y - duv1.y * duv2.x;
    if (!(std::fabs(det) > 1e-20f)) return n;
    float r = 1 / det;
    Vec3 dpdu = (e1 * duv2.y - e2 * duv1.y) * r;
    Vec3 dpdv = (e2 * duv1.x - e1 * duv2.x) * r;
    Vec3 t = dpdu - n * dot(n, dpdu);
    if (!(lengthSquared(t) > 1e-30f) || !isFinite(t)) return n;
    t = normalize(t);
    Vec3 b = cross(n, t);
    if (dot(b, dpdv) < 0) b = -b;  // mirrored uvs
    Vec3 m = material.tangentNormal(uv);
    Vec3 perturbed = t * m.x + b * m.y + n * m.z;
    return lengthSquared(perturbed) > 0 && isFinite(perturbed) ? normalize(perturbed) : n;
}

}  // namespace

void Scene::makeInteraction(const Ray& ray, const PendingHit& pending, SurfaceInteraction& si) const {
    const RTCRayHit& rh = pending.rh;
    const RTCHit& h = rh.hit;
    const int shapeId = pending.shape;
    const Instance* inst = pending.instance >= 0 ? &instances_[size_t(pending.instance)] : nullptr;
    if (inst) si.instanceId = uint32_t(pending.instance);
    const Shape& s = shapes_[shapeId];
    // The geometry the ray hit: moving shapes and instances where they are at the ray's time.
    const Mat4 toWorld = !inst ? Mat4() : inst->stepToWorld.empty() ? inst->toWorld : atTime(inst->stepToWorld, ray.time);
    si.time = ray.time;
    si.t = rh.ray.tfar;
    si.p = ray.o + ray.d * si.t;
    si.coneWidth = ray.coneWidth + ray.coneSpread * si.t;
    si.coneSpread = ray.coneSpread;
    si.primId = h.primID;
    si.shapeId = uint32_t(shapeId);
    si.material = materials_[s.material].get();
    si.doubleSided = s.doubleSided;
    // A cone's width in uv units (only where textures read it): world units times the uv
    // parameterisation's density, which an instance's transform divides by its scale.
    const bool footprint = si.coneWidth > 0 && si.material->texturedBsdf();
    const float worldPerObject = footprint && inst ? float(std::cbrt(std::fabs(toWorld.det3()))) : 1.0f;
    Vec3 ng, ns;
    if (s.isSphere) {
        Vec3 center = s.stepCenters.empty() ? s.center : atTime(s.stepCenters, ray.time);
        float radius = s.stepRadii.empty() ? s.radius : atTime(s.stepRadii, ray.time);
        Vec3 local = inst ? Vec3(0.0f) : si.p - center;
        if (inst) {
            Mat4 inv;
            toWorld.inverse(inv);
            local = inv.point(si.p) - center;
        }
        Vec3 n = normalize(local);
        ng = ns = n;
        si.uv = Vec2(0.5f + std::atan2(n.z, n.x) / (2 * kPi), std::acos(std::clamp(n.y, -1.0f, 1.0f)) / kPi);
        // u spans the equator's 2 pi r, v a meridian's pi r: their geometric mean.
        if (footprint) si.uvFootprint = si.coneWidth / (worldPerObject * kPi * std::sqrt(2.0f) * radius);
        // Re-project onto the sphere: removes the intersection's float error along the ray.
        Vec3 surface = center + n * radius;
        si.p = inst ? toWorld.point(surface) : surface;
    } else {
        uint32_t i0 = s.indices[3 * h.primID], i1 = s.indices[3 * h.primID + 1], i2 = s.indices[3 * h.primID + 2];
        float b1 = h.u, b2 = h.v, b0 = 1 - b1 - b2;
        const bool moving = !s.stepPositions.empty();
        const Vec3 p0 = moving ? atTime(s.stepPositions, ray.time, i0) : s.positions[i0];
        const Vec3 p1 = moving ? atTime(s.stepPositions, ray.time, i1) : s.positions[i1];
        const Vec3 p2 = moving ? atTime(s.stepPositions, ray.time, i2) : s.positions[i2];
        const Vec3 areaNormal = cross(p1 - p0, p2 - p0);
        ng = normalize(areaNormal);
        Vec3 objectP = p0 * b0 + p1 * b1 + p2 * b2;
        si.p = inst ? toWorld.point(objectP) : objectP;
        ns = ng;
        if (!s.normals.empty()) {
            auto normal = [&](uint32_t i) { return s.stepNormals.empty() ? s.normals[i] : atTime(s.stepNormals, ray.time, i); };
            Vec3 n = normal(i0) * b0 + normal(i1) * b1 + normal(i2) * b2;
            if (lengthSquared(n) > 1e-12f) ns = normalize(n);
        }
        if (!s.uvs.empty()) {
            si.uv = s.uvs[i0] * b0 + s.uvs[i1] * b1 + s.uvs[i2] * b2;
            const Vec2 duv1 = s.uvs[i1] - s.uvs[i0], duv2 = s.uvs[i2] - s.uvs[i0];
            if (footprint) {
                // The triangle's uv area over its area: squared uv units per square world unit.
                const float density = std::fabs(duv1.x * duv2.y - duv1.y * duv2.x) / length(areaNormal);
                si.uvFootprint = std::isfinite(density) ? si.coneWidth * std::sqrt(density) / worldPerObject : 0.0f;
            }
            if (si.material->hasNormalMap())
                ns = applyNormalMap(*si.material, si.uv, ns, p1 - p0, p2 - p0, duv1, duv2);
        }
        if (si.material->isEmissive()) {
            if (!inst && s.lightOffset >= 0) si.emissiveLight = s.lightOffset + int(h.primID);
            if (inst && inst->lightOffset >= 0) {
                auto it = prototypes_[inst->prototype].relativeLightOffset.find(shapeId);
                if (it != prototypes_[inst->prototype].relativeLightOffset.end())
                    si.emissiveLight = inst->lightOffset + it->second + int(h.primID);
            }
        }
    }
    if (inst) {
        ng = normalize(toWorld.normal(ng));
        ns = normalize(toWorld.normal(ns));
        if (toWorld.det3() < 0) {  // mirroring flips the winding
            ng = -ng;
            ns = -ns;
        }
    }
    if (dot(ns, ng) < 0) ns = -ns;  // keep authored normals on the geometric side's hemisphere
    si.ng = ng;
    si.ns = ns;
}

namespace {
// Up to this many analytic lights are tested one by one after the surface BVH; more (a church's
// windows, a stadium's lamps) get a BVH of their own, so a ray's cost does not grow with them.
constexpr size_t kLinearLightTests = 4;

struct LightIntersectContext {
    RTCIntersectContext embree;  // first: Embree hands the callback this pointer
    bool cameraRay;
};
}  // namespace

void Scene::buildLightBvh() {
    if (analyticLights_.size() <= kLinearLightTests) return;
    lightBvh_ = rtcNewScene(device_->device);
    RTCGeometry g = rtcNewGeometry(device_->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(analyticLights_.size()));
    rtcSetGeometryUserData(g, this);
    rtcSetGeometryBoundsFunction(
        g,
        [](const RTCBoundsFunctionArguments* args) {
            const Scene* scene = static_cast<const Scene*>(args->geometryUserPtr);
            Vec3 lo, hi;
            scene->lights_[scene->analyticLights_[args->primID]]->shapeBounds(&lo, &hi);
            // Flat lights have flat boxes: pad them by their coordinates' float error.
            Vec3 pad(pointErrorBound(lo) + pointErrorBound(hi));
            lo = lo - pad;
            hi = hi + pad;
            *args->bounds_o = RTCBounds{lo.x, lo.y, lo.z, 0, hi.x, hi.y, hi.z, 0};
        },
        nullptr);
    rtcSetGeometryIntersectFunction(g, intersectLightPrimitive);
    rtcCommitGeometry(g);
    rtcAttachGeometry(lightBvh_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(lightBvh_);
}

void Scene::intersectLightPrimitive(const RTCIntersectFunctionNArguments* args) {
    // Only rtcIntersect1 reaches this scene: one ray, laid out as an RTCRayHit.
    if (!args->valid[0]) return;
    const Scene* scene = static_cast<const Scene*>(args->geometryUserPtr);
    const Light& light = *scene->lights_[scene->analyticLights_[args->primID]];
    if (reinterpret_cast<const LightIntersectContext*>(args->context)->cameraRay && !light.visibleToCamera) return;
    RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    Ray ray{{rh->ray.org_x, rh->ray.org_y, rh->ray.org_z}, {rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z},
            rh->ray.tnear, rh->ray.tfar, rh->ray.time};
    float t = light.intersect(ray);
    if (t < rh->ray.tfar) {
        rh->ray.tfar = t;
        rh->hit.geomID = args->geomID;
        rh->hit.primID = args->primID;
    }
}

void Scene::intersectAnalyticLights(const Ray& ray, bool cameraRay, Intersection& result) const {
    if (lightBvh_) {
        LightIntersectContext context;
        rtcInitIntersectContext(&context.embree);
        context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        context.cameraRay = cameraRay;
        RTCRayHit rh = toEmbreeRayHit(ray.o, ray.d, ray.tMin, result.t, ray.time);  // moving lights: where at its time
        rtcIntersect1(lightBvh_, &context.embree, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
        result.kind = Intersection::Kind::Light;
        result.light = analyticLights_[rh.hit.primID];
        result.t = rh.ray.tfar;
        return;
    }
    Ray lightRay = ray;
    lightRay.tMax = result.t;
    for (int i : analyticLights_) {
        if (cameraRay && !lights_[i]->visibleToCamera) continue;
        float t = lights_[i]->intersect(lightRay);
        if (t < lightRay.tMax) {
            lightRay.tMax = t;
            result.kind = Intersection::Kind::Light;
            result.light = i;
            result.t = t;
        }
    }
}

void Scene::initMaskContext(MaskContext& context, bool skipsMasked) const {
    rtcInitIntersectContext(&context.embree);
    context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    if (skipsMasked) context.embree.filter = skipMasked;
    context.scene = this;
}

bool Scene::mayHitMasked(const Vec3& origin, const Vec3& dir, float distance) const {
    for (const Bounds& b : maskedBounds_) {
        // Slabs; a NaN from 0 * inf (a ray in a slab's plane) keeps the interval as it is.
        float t0 = 0, t1 = distance;
        for (int a = 0; a < 3; ++a) {
            float inv = 1 / dir[a], near = (b.lo[a] - origin[a]) * inv, far = (b.hi[a] - origin[a]) * inv;
            if (near > far) std::swap(near, far);
            t0 = near > t0 ? near : t0;
            t1 = far < t1 ? far : t1;
        }
        if (t0 <= t1 * (1 + 1e-5f)) return true;
    }
    return false;
}

void Scene::skipMasked(const RTCFilterFunctionNArguments* args) {
    const Scene* scene = reinterpret_cast<const MaskContext*>(args->context)->scene;
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] && RTCHitN_instID(args->hit, args->N, i, 0) == scene->staticBvhGeom_ &&
            scene->staticMasked_[RTCHitN_geomID(args->hit, args->N, i)])
            args->valid[i] = 0;
}

Intersection Scene::intersect(const Ray& ray, RayStats& stats, bool cameraRay) const {
    return finish(ray, trace(ray, stats, cameraRay));
}

Scene::PendingHit Scene::trace(const Ray& ray, RayStats& stats, bool cameraRay) const {
    ++stats.rays;
    PendingHit pending;
    // A NaN ray (from a broken camera or a numerical accident upstream) hits nothing: Embree's
    // behaviour on it is undefined (its debug builds assert).
    if (!embreeValid(ray.o) || !embreeValid(ray.d) || std::isnan(ray.tMin) || std::isnan(ray.tMax)) return pending;
    if (stats.record) stats.record->push_back({ray.o, ray.d, ray.tMin, ray.tMax, false, ray.time, cameraRay});
    // A ray that may meet masked shapes skips them by Embree's filter; only those rays pay for it.
    MaskContext context;
    initMaskContext(context, !staticMasked_.empty() && mayHitMasked(ray.o, ray.d, ray.tMax));
    RTCRayHit& rh = pending.rh;
    rh = toEmbreeRayHit(ray.o, ray.d, ray.tMin, ray.tMax, ray.time);
    // The direct spheres first: a hit on one shortens the ray Embree traverses.
    const int sphere = nearestDirectSphere(ray.o, ray.d, ray.tMin, &rh.ray.tfar);
    rtcIntersect1(top_, &context.embree, &rh);
    Intersection& result = pending.hit;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        result.kind = Intersection::Kind::Surface;
        result.t = rh.ray.tfar;
        pending.shape = hitShape(rh.hit, &pending.instance);
        const Shape& s = shapes_[pending.shape];
        if (!s.isSphere) __builtin_prefetch(&s.indices[3 * size_t(rh.hit.primID)]);
    } else if (sphere >= 0) {
        result.kind = Intersection::Kind::Surface;
        result.t = rh.ray.tfar;
        rh.hit.primID = 0;
        pending.shape = sphere;
    }
    // Area lights are analytic: tested after the surface BVH, up to the surface hit.
    intersectAnalyticLights(ray, cameraRay, result);
    return pending;
}

void Scene::prefetchSurface(const PendingHit& pending) const {
    if (pending.hit.kind != Intersection::Kind::Surface) return;
    const Shape& s = shapes_[pending.shape];
    if (s.isSphere || !s.stepPositions.empty()) return;
    const uint32_t* corner = &s.indices[3 * size_t(pending.rh.hit.primID)];
    for (int k = 0; k < 3; ++k) {
        __builtin_prefetch(&s.positions[corner[k]]);
        if (!s.normals.empty()) __builtin_prefetch(&s.normals[corner[k]]);
        if (!s.uvs.empty()) __builtin_prefetch(&s.uvs[corner[k]]);
    }
}

Intersection Scene::finish(const Ray& ray, const PendingHit& pending) const {
    Intersection result = pending.hit;
    if (result.kind == Intersection::Kind::Surface) makeInteraction(ray, pending, result.si);
    return result;
}

int Scene::nearestDirectSphere(const Vec3& o, const Vec3& d, float tMin, float* tMax) const {
    int nearest = -1;
    for (const DirectSphere& s : directSpheres_) {
        float crossing[2];
        if (!sphereCrossings(s.sphere, o, d, crossing[0], crossing[1])) continue;
        for (float t : crossing)  // the nearer first; the farther when the ray starts past it (inside)
            if (t > tMin && t < *tMax) {
                *tMax = t;
                nearest = s.shape;
                break;
            }
    }
    return nearest;
}

bool Scene::directSphereBlocks(const Vec3& o, const Vec3& d, float distance) const {
    for (const DirectSphere& s : directSpheres_) {
        float t0, t1;
        if (sphereCrossings(s.sphere, o, d, t0, t1) && ((t0 > 0 && t0 < distance) || (t1 > 0 && t1 < distance)))
            return true;
    }
    return false;
}

int Scene::hitShape(const RTCHit& h, int* instance) const {
    if (h.instID[0] == RTC_INVALID_GEOMETRY_ID) return topGeomToShape_[h.geomID];
    if (h.instID[0] == staticBvhGeom_) return staticBvhToShape_[h.geomID];
    *instance = -topGeomToShape_[h.instID[0]] - 1;
    return prototypes_[instances_[size_t(*instance)].prototype].geomToShape[h.geomID];
}

bool Scene::occluded(const Vec3& origin, const Vec3& dir, float distance, RayStats& stats, float time) const {
    ++stats.rays;
    if (!embreeValid(origin) || !embreeValid(dir) || std::isnan(distance)) return true;  // no light along a NaN ray
    if (stats.record) stats.record->push_back({origin, dir, 0, distance, true, time});
    MaskContext context;
    initMaskContext(context, !staticMasked_.empty() && mayHitMasked(origin, dir, distance));
    if (directSphereBlocks(origin, dir, distance)) return true;
    RTCRay r = toEmbreeRay(origin, dir, 0, distance, time);
    rtcOccluded1(top_, &context.embree, &r);
    return r.tfar < 0;  // Embree sets tfar to -inf on a hit
}

bool Scene::visible(const SurfaceInteraction& si, const Vec3& wi, float distance, RayStats& stats) const {
    Vec3 o = offsetRayOrigin(si.p, si.ng, wi);
    // Stop short of the sampled point by its own float error too (an emissive triangle is in the BVH).
    float d = std::isfinite(distance)
                  ? distance * (1 - 1e-4f) - length(o - si.p) - 4 * pointErrorBound(si.p + wi * distance)
                  : kInf;
    if (std::isfinite(d) && d <= 0) return true;
    return !occluded(o, wi, d, stats, si.time);
}

}  // namespace gi
