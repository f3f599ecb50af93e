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

// One lane of an 8-wide packet set from a single ray (toEmbreeRayHit's fields, so both follow one rule).
inline void setPacketLane(RTCRayHit8& packet, int lane, const RTCRayHit& rh) {
    packet.ray.org_x[lane] = rh.ray.org_x, packet.ray.org_y[lane] = rh.ray.org_y, packet.ray.org_z[lane] = rh.ray.org_z;
    packet.ray.dir_x[lane] = rh.ray.dir_x, packet.ray.dir_y[lane] = rh.ray.dir_y, packet.ray.dir_z[lane] = rh.ray.dir_z;
    packet.ray.tnear[lane] = rh.ray.tnear;
    packet.ray.tfar[lane] = rh.ray.tfar;
    packet.ray.time[lane] = rh.ray.time;
    packet.ray.mask[lane] = rh.ray.mask;
    packet.ray.id[lane] = rh.ray.id;
    packet.ray.flags[lane] = rh.ray.flags;
    packet.hit.geomID[lane] = rh.hit.geomID;
    packet.hit.instID[0][lane] = rh.hit.instID[0];
}

}  // namespace gi
