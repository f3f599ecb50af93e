// Conversions between the renderer's Ray and Embree's ray structures.
#pragma once
#include <embree3/rtcore.h>

#include <limits>

#include "math.h"

namespace gi {

// Embree accepts only coordinates of magnitude below ~1.8e18 (its FLT_LARGE); beyond that, or
// with a NaN, its behaviour is undefined (debug builds assert).
constexpr float kMaxEmbreeCoordinate = 1e18f;
inline bool embreeValid(const Vec3& v) {
    return std::fabs(v.x) < kMaxEmbreeCoordinate && std::fabs(v.y) < kMaxEmbreeCoordinate &&
           std::fabs(v.z) < kMaxEmbreeCoordinate;  // false for NaN too
}

inline RTCRay toEmbreeRay(const Vec3& o, const Vec3& d, float tMin, float tMax, float time = 0) {
    RTCRay r;
    r.org_x = o.x, r.org_y = o.y, r.org_z = o.z;
    r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
    r.tnear = tMin;
    r.tfar = std::isfinite(tMax) ? tMax : std::numeric_limits<float>::max();
    r.time = time;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    return r;
}

inline RTCRayHit toEmbreeRayHit(const Vec3& o, const Vec3& d, float tMin, float tMax, float time = 0) {
    RTCRayHit rh;
    rh.ray = toEmbreeRay(o, d, tMin, tMax, time);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace gi
