// Static spheres: an exact ray-sphere test of our own, as Embree user geometry or, for the few
// spheres of a scene's top level, tested beside its BVH (Scene::directSpheres_). Embree 3.13's
// sphere points (RTC_GEOMETRY_TYPE_SPHERE_POINT) cost each ray about 46 ns on the Cornell box's
// one sphere, more than its ten quads together (bench/peers.py --tracing-only, one thread: 9.3 M
// rays per second with it, 16.2 M without); this geometry 30-37 ns (10.1-10.9 M, runs apart), and
// the path tracer's Cornell box about 5% less time. Moving spheres keep Embree's, which
// interpolates their time steps.
#pragma once
#include <embree3/rtcore.h>

#include <cmath>
#include <deque>
#include <memory>
#include <utility>

#include "math.h"

namespace gi {

struct SphereData {
    Vec3 center;
    float radius;
};
// The spheres' centres and radii at stable addresses (the geometries' user data). Shared by every
// Embree scene that holds one of their geometries: the Scene's top level and its BVHs that later
// scenes keep (Scene::Bvh).
using SphereStore = std::deque<SphereData>;

// The ray's two crossings with the sphere, nearer first; false when it passes by. The quadratic's
// robust form (Haines et al., "Precision Improvements for Ray/Sphere Intersection", Ray Tracing
// Gems ch. 7): the discriminant from the closest approach, and no cancellation in the roots.
inline bool sphereCrossings(const SphereData& s, const Vec3& o, const Vec3& d, float& t0, float& t1) {
    const Vec3 f = o - s.center;
    const float a = dot(d, d), b = -dot(f, d);
    const Vec3 closest = f + d * (b / a);
    const float r2 = s.radius * s.radius, discriminant = r2 - dot(closest, closest);
    if (!(discriminant >= 0)) return false;  // also false for a NaN
    const float q = b + std::copysign(std::sqrt(a * discriminant), b);
    t0 = (dot(f, f) - r2) / q;
    t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    return true;
}

// A committed user geometry of one sphere, its data appended to `store`.
RTCGeometry newSphereGeometry(RTCDevice device, SphereStore& store, const Vec3& center, float radius);

}  // namespace gi
