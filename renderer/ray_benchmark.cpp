#include "ray_benchmark.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

#include "embree_ray.h"
#include "sampler.h"
#include "sampling.h"

namespace gi {

RayBenchmarkResult castIncoherentRays(const Scene& scene, uint64_t rays, uint32_t seed, int threads) {
    Vec3 lo = scene.boundsMin(), extent = scene.boundsMax() - scene.boundsMin();
    RTCScene rtc = scene.embreeScene();
    constexpr uint64_t kBatch = 4096;
    uint64_t batches = (rays + kBatch - 1) / kBatch;
    tbb::enumerable_thread_specific<uint64_t> hits(0);
    auto start = std::chrono::steady_clock::now();
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(uint64_t(0), batches, [&](uint64_t batch) {
            Sampler sampler(seed);
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            uint64_t& h = hits.local();
            uint64_t end = std::min(rays, (batch + 1) * kBatch);
            for (uint64_t i = batch * kBatch; i < end; ++i) {
                sampler.startStream(uint32_t(batch), uint32_t(i));
                Vec2 u = sampler.get2D();
                Vec3 o = lo + extent * Vec3(u.x, u.y, sampler.get1D());
                Vec3 d = sampleUniformSphere(sampler.get2D());
                RTCRayHit rh = toEmbreeRayHit(o, d, 0, kInf);
                rtcIntersect1(rtc, &context, &rh);
                h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        });
    });
    RayBenchmarkResult r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.rays = rays;
    for (uint64_t h : hits) r.hits += h;
    return r;
}

}  // namespace gi
