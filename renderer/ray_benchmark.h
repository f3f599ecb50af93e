// Embree on its own: casts incoherent closest-hit rays (uniform origins in the scene's bounding
// box, uniform directions, generated before timing starts) on all threads, as the baseline for
// the renderer's rays/s.
#pragma once
#include <cstdint>

#include "render.h"
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

// Embree's share of a render: renders once timed, once recording its rays (the same rays, since
// renders are deterministic), then casts the recorded rays through Embree alone (closest hit or
// occlusion, as the renderer did) on the same threads. replay.seconds / render.seconds is the
// share of the render's time that is Embree's; 1 would mean the renderer costs nothing else.
//
// How the recorded rays are cast: one at a time in the render's order (what the renderer does),
// or in wavefront order (a wave's paths' first rays, then their second rays, ..., shadow rays
// apart), one at a time or as Embree's 8-wide packets. The wavefront replays measure what a
// renderer tracing whole waves of paths could gain in Embree, before writing one.
enum class RayReplay { RenderOrder, Wavefront, WavefrontPackets8 };
struct RenderReplayResult {
    RayBenchmarkResult render, replay;
};
RenderReplayResult replayRenderRays(const Scene& scene, RenderSettings settings,
                                    RayReplay replay = RayReplay::RenderOrder);

}  // namespace gi
