#include "ray_benchmark.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <ctime>
#include <vector>

#include "embree_ray.h"
#include "sampler.h"
#include "sampling.h"

namespace gi {

namespace {
double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct PoolRay {
    Vec3 o, d;
};

// Rays are generated before the clock starts, so the figure is Embree's traversal and nothing of
// ours. A pool of 2^20 rays (24 MB) is cycled through for longer runs: large enough that the
// rays do not repeat within a batch, small enough not to disturb the peak-memory figures.
std::vector<PoolRay> makeRayPool(const Scene& scene, uint64_t rays, uint32_t seed) {
    Vec3 lo = scene.boundsMin(), extent = scene.boundsMax() - scene.boundsMin();
    std::vector<PoolRay> pool(std::min<uint64_t>(rays, uint64_t(1) << 20));
    tbb::parallel_for(size_t(0), pool.size(), size_t(4096), [&](size_t i) {
        Sampler sampler(seed);
        sampler.startStream(0, uint32_t(i));
        Vec2 u = sampler.get2D();
        pool[i].o = lo + extent * Vec3(u.x, u.y, sampler.get1D());
        pool[i].d = sampleUniformSphere(sampler.get2D());
    });
    return pool;
}
}  // namespace

RayBenchmarkResult castIncoherentRays(const Scene& scene, uint64_t rays, uint32_t seed, int threads) {
    RTCScene rtc = scene.embreeScene();
    constexpr uint64_t kBatch = 4096;
    uint64_t batches = (rays + kBatch - 1) / kBatch;
    tbb::enumerable_thread_specific<uint64_t> hits(0);
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    std::vector<PoolRay> pool;
    arena.execute([&] { pool = makeRayPool(scene, rays, seed); });
    if (pool.empty()) return RayBenchmarkResult();
    double cpuStart = processCpuSeconds();
    auto start = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(uint64_t(0), batches, [&](uint64_t batch) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            uint64_t& h = hits.local();
            uint64_t end = std::min(rays, (batch + 1) * kBatch);
            for (uint64_t i = batch * kBatch; i < end; ++i) {
                const PoolRay& r = pool[i % pool.size()];
                RTCRayHit rh = toEmbreeRayHit(r.o, r.d, 0, kInf);
                rtcIntersect1(rtc, &context, &rh);
                h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        });
    });
    RayBenchmarkResult r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.cpuSeconds = processCpuSeconds() - cpuStart;
    r.rays = rays;
    for (uint64_t h : hits) r.hits += h;
    return r;
}

RenderReplayResult replayRenderRays(const Scene& scene, RenderSettings settings) {
    RenderReplayResult result;
    settings.recordRays = nullptr;
    {
        Renderer renderer(scene, settings);
        double cpuStart = processCpuSeconds();
        renderer.render();
        result.render.cpuSeconds = processCpuSeconds() - cpuStart;
        result.render.seconds = renderer.stats().renderSeconds;
        result.render.rays = renderer.stats().rays;
    }
    std::vector<RecordedRay> rays;
    settings.recordRays = &rays;
    {
        Renderer renderer(scene, settings);
        renderer.render();
    }
    RTCScene rtc = scene.embreeScene();
    constexpr size_t kBatch = 4096;
    tbb::enumerable_thread_specific<uint64_t> hits(0);
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    double cpuStart = processCpuSeconds();
    auto start = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(size_t(0), (rays.size() + kBatch - 1) / kBatch, [&](size_t batch) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            uint64_t& h = hits.local();
            for (size_t i = batch * kBatch, end = std::min(rays.size(), i + kBatch); i < end; ++i) {
                const RecordedRay& r = rays[i];
                if (r.occlusion) {
                    RTCRay ray = toEmbreeRay(r.o, r.d, r.tMin, r.tMax, r.time);
                    rtcOccluded1(rtc, &context, &ray);
                    h += ray.tfar < 0;
                } else {
                    RTCRayHit rh = toEmbreeRayHit(r.o, r.d, r.tMin, r.tMax, r.time);
                    rtcIntersect1(rtc, &context, &rh);
                    h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                }
            }
        });
    });
    result.replay.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.replay.cpuSeconds = processCpuSeconds() - cpuStart;
    result.replay.rays = rays.size();
    for (uint64_t h : hits) result.replay.hits += h;
    return result;
}

}  // namespace gi
