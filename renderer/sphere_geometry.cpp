#include "sphere_geometry.h"

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace gi {

namespace {
// One lane of a ray packet as a single ray: the context's filter (Scene::skipMasked) sees each
// candidate hit on its own.
RTCRay laneRay(RTCRayN* rays, unsigned n, unsigned i) {
    RTCRay r;
    r.org_x = RTCRayN_org_x(rays, n, i), r.org_y = RTCRayN_org_y(rays, n, i), r.org_z = RTCRayN_org_z(rays, n, i);
    r.dir_x = RTCRayN_dir_x(rays, n, i), r.dir_y = RTCRayN_dir_y(rays, n, i), r.dir_z = RTCRayN_dir_z(rays, n, i);
    r.tnear = RTCRayN_tnear(rays, n, i), r.tfar = RTCRayN_tfar(rays, n, i);
    r.time = RTCRayN_time(rays, n, i), r.mask = RTCRayN_mask(rays, n, i);
    r.id = RTCRayN_id(rays, n, i), r.flags = RTCRayN_flags(rays, n, i);
    return r;
}

// The nearest of the lane's crossings in (tnear, tfar) that the context's filter accepts
// (Scene::skipMasked: a masked shape's hits are refused, and then its far crossing is tried too):
// its distance and hit record; false if none.
template <typename Args>
bool acceptedCrossing(const Args* args, RTCRay ray, float& t, RTCHit& hit) {
    const SphereData& s = *static_cast<const SphereData*>(args->geometryUserPtr);
    const Vec3 o(ray.org_x, ray.org_y, ray.org_z), d(ray.dir_x, ray.dir_y, ray.dir_z);
    float crossing[2];
    if (!sphereCrossings(s, o, d, crossing[0], crossing[1])) return false;
    const float tfar = ray.tfar;
    for (float candidate : crossing) {
        if (!(candidate > ray.tnear && candidate < tfar)) continue;
        const Vec3 ng = o + d * candidate - s.center;
        hit.Ng_x = ng.x, hit.Ng_y = ng.y, hit.Ng_z = ng.z;
        hit.u = hit.v = 0;
        hit.primID = args->primID, hit.geomID = args->geomID;
        hit.instID[0] = args->context->instID[0];
        if (args->context->filter) {  // the geometry has no filter of its own
            ray.tfar = candidate;     // the filter sees the candidate's distance, as with Embree's geometries
            int valid = -1;
            RTCFilterFunctionNArguments filter{&valid, args->geometryUserPtr, args->context,
                                               reinterpret_cast<RTCRayN*>(&ray), reinterpret_cast<RTCHitN*>(&hit), 1};
            if constexpr (std::is_same_v<Args, RTCIntersectFunctionNArguments>)
                rtcFilterIntersection(args, &filter);
            else
                rtcFilterOcclusion(args, &filter);
            if (!valid) continue;
        }
        t = candidate;
        return true;
    }
    return false;
}

void intersectSphere(const RTCIntersectFunctionNArguments* args) {
    const unsigned n = args->N;
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, n);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, n);
    for (unsigned i = 0; i < n; ++i) {
        float t;
        RTCHit hit;
        if (!args->valid[i] || !acceptedCrossing(args, laneRay(rays, n, i), t, hit)) continue;
        RTCRayN_tfar(rays, n, i) = t;
        RTCHitN_Ng_x(hits, n, i) = hit.Ng_x, RTCHitN_Ng_y(hits, n, i) = hit.Ng_y, RTCHitN_Ng_z(hits, n, i) = hit.Ng_z;
        RTCHitN_u(hits, n, i) = 0, RTCHitN_v(hits, n, i) = 0;
        RTCHitN_primID(hits, n, i) = hit.primID, RTCHitN_geomID(hits, n, i) = hit.geomID;
        RTCHitN_instID(hits, n, i, 0) = hit.instID[0];
    }
}

void occludedBySphere(const RTCOccludedFunctionNArguments* args) {
    for (unsigned i = 0; i < args->N; ++i) {
        float t;
        RTCHit hit;
        if (args->valid[i] && acceptedCrossing(args, laneRay(args->ray, args->N, i), t, hit))
            RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();  // Embree's "occluded"
    }
}
}  // namespace

RTCGeometry newSphereGeometry(RTCDevice device, SphereStore& store, const Vec3& center, float radius) {
    store.push_back({center, radius});
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryUserData(g, &store.back());
    rtcSetGeometryBoundsFunction(
        g,
        [](const RTCBoundsFunctionArguments* args) {
            const SphereData& s = *static_cast<const SphereData*>(args->geometryUserPtr);
            *args->bounds_o = RTCBounds{s.center.x - s.radius, s.center.y - s.radius, s.center.z - s.radius, 0,
                                        s.center.x + s.radius, s.center.y + s.radius, s.center.z + s.radius, 0};
        },
        nullptr);
    rtcSetGeometryIntersectFunction(g, intersectSphere);
    rtcSetGeometryOccludedFunction(g, occludedBySphere);
    return g;
}

}  // namespace gi
