// Static spheres as Embree user geometry: an exact ray-sphere test of our own. Embree 3.13's
// sphere points (RTC_GEOMETRY_TYPE_SPHERE_POINT) cost each ray about 46 ns on the Cornell box's
// one sphere, more than its ten quads together (bench/peers.py --tracing-only, one thread: 9.3 M
// rays per second with it, 16.2 M without); this geometry 30-37 ns (10.1-10.9 M, runs apart), and the path
// tracer's Cornell box about 5% less time. Moving spheres keep Embree's, which interpolates their
// time steps.
#pragma once
#include <embree3/rtcore.h>

#include <deque>
#include <memory>

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

// A committed user geometry of one sphere, its data appended to `store`.
RTCGeometry newSphereGeometry(RTCDevice device, SphereStore& store, const Vec3& center, float radius);

}  // namespace gi
