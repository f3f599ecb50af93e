// Embree on its own: casts incoherent closest-hit rays (uniform origins in the scene's bounding
// box, uniform directions, generated before timing starts) on all threads, as the baseline for
// the renderer's rays/s.
#pragma once
#include <cstdint>

#include "scene.h"

namespace gi {

struct RayBenchmarkResult {
    uint64_t rays = 0;
    uint64_t hits = 0;
    double seconds = 0;
    double cpuSeconds = 0;  // CPU time of the whole process over the timed casting
    double raysPerSecond() const { return seconds > 0 ? rays / seconds : 0; }
};

RayBenchmarkResult castIncoherentRays(const Scene& scene, uint64_t rays, uint32_t seed, int threads);

}  // namespace gi
