#include "ray_benchmark.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <ctime>
#include <limits>
#include <tuple>
#include <algorithm>
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
    // (parallel_for's three-index form takes a step, not a grain: a blocked range, so that every ray is made.)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pool.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
        Sampler sampler(seed);
        for (size_t i = range.begin(); i < range.end(); ++i) {
            sampler.startStream(0, uint32_t(i));
            Vec2 u = sampler.get2D();
            pool[i].o = lo + extent * Vec3(u.x, u.y, sampler.get1D());
            pool[i].d = sampleUniformSphere(sampler.get2D());
        }
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
                const bool sphere = scene.nearestDirectSphere(r.o, r.d, 0, &rh.ray.tfar) >= 0;  // as Scene::trace
                rtcIntersect1(rtc, &context, &rh);
                h += sphere || rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
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

namespace {
// The recorded rays in wavefront order: waves of kWavePaths consecutive paths (a camera ray
// starts a path), within a wave all closest-hit rays by their index along the path (every path's
// first, then every path's second, ...), then the shadow rays the same way.
std::vector<RecordedRay> wavefrontOrder(const std::vector<RecordedRay>& rays) {
    constexpr uint32_t kWavePaths = 1024;
    struct Key {
        uint32_t wave;
        bool occlusion;
        uint32_t step, path;
        size_t index;
    };
    std::vector<Key> keys;
    keys.reserve(rays.size());
    uint32_t path = 0, steps[2] = {0, 0};
    for (size_t i = 0; i < rays.size(); ++i) {
        if (rays[i].camera && i > 0) path++, steps[0] = steps[1] = 0;
        bool occlusion = rays[i].occlusion;
        keys.push_back({path / kWavePaths, occlusion, steps[occlusion]++, path, i});
    }
    // (path, kind, step) names one ray: the keys are distinct, so any sort gives this order.
    std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
        return std::tie(a.wave, a.occlusion, a.step, a.path) < std::tie(b.wave, b.occlusion, b.step, b.path);
    });
    std::vector<RecordedRay> ordered;
    ordered.reserve(rays.size());
    for (const Key& k : keys) ordered.push_back(rays[k.index]);
    return ordered;
}

// Casts rays[begin, end) as 8-wide packets of consecutive rays of one kind (a kind change or the
// end leaves lanes off). Returns the hits.
uint64_t castPackets8(const Scene& scene, RTCScene rtc, RTCIntersectContext& context,
                      const std::vector<RecordedRay>& rays, size_t begin, size_t end) {
    uint64_t hits = 0;
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    bool sphere[8];
    for (size_t i = begin; i < end;) {
        const bool occlusion = rays[i].occlusion;
        int lanes = 0;
        for (; lanes < 8 && i < end && rays[i].occlusion == occlusion; ++lanes, ++i) {
            const RecordedRay& r = rays[i];
            RTCRayHit single = toEmbreeRayHit(r.o, r.d, r.tMin, r.tMax, r.time);
            // The direct spheres as Scene::trace and Scene::occluded test them, lane by lane.
            sphere[lanes] = occlusion ? scene.directSphereBlocks(r.o, r.d, single.ray.tfar)
                                      : scene.nearestDirectSphere(r.o, r.d, r.tMin, &single.ray.tfar) >= 0;
            setPacketLane(rh, lanes, single);
            valid[lanes] = occlusion && sphere[lanes] ? 0 : -1;  // blocked: not cast, as in Scene::occluded
        }
        for (int k = lanes; k < 8; ++k) valid[k] = 0;
        if (occlusion) {
            rtcOccluded8(valid, rtc, &context, &rh.ray);
            for (int k = 0; k < lanes; ++k) hits += sphere[k] || rh.ray.tfar[k] < 0;
        } else {
            rtcIntersect8(valid, rtc, &context, &rh);
            for (int k = 0; k < lanes; ++k) hits += sphere[k] || rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

uint64_t castOneByOne(const Scene& scene, RTCScene rtc, RTCIntersectContext& context,
                      const std::vector<RecordedRay>& rays, size_t begin, size_t end) {
    uint64_t hits = 0;
    for (size_t i = begin; i < end; ++i) {
        const RecordedRay& r = rays[i];
        if (r.occlusion) {
            RTCRay ray = toEmbreeRay(r.o, r.d, r.tMin, r.tMax, r.time);
            if (scene.directSphereBlocks(r.o, r.d, ray.tfar)) {  // blocked: not cast, as in Scene::occluded
                ++hits;
                continue;
            }
            rtcOccluded1(rtc, &context, &ray);
            hits += ray.tfar < 0;
        } else {
            RTCRayHit rh = toEmbreeRayHit(r.o, r.d, r.tMin, r.tMax, r.time);
            const bool sphere = scene.nearestDirectSphere(r.o, r.d, r.tMin, &rh.ray.tfar) >= 0;  // as Scene::trace
            rtcIntersect1(rtc, &context, &rh);
            hits += sphere || rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}
}  // namespace

RenderReplayResult replayRenderRays(const Scene& scene, RenderSettings settings, RayReplay replay) {
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
    if (replay != RayReplay::RenderOrder) rays = wavefrontOrder(rays);
    RTCScene rtc = scene.embreeScene();
    // Batches are whole waves' worth of rays, so packets rarely straddle two waves.
    constexpr size_t kBatch = 8192;
    tbb::enumerable_thread_specific<uint64_t> hits(0);
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    double cpuStart = processCpuSeconds();
    auto start = std::chrono::steady_clock::now();
    arena.execute([&] {
        tbb::parallel_for(size_t(0), (rays.size() + kBatch - 1) / kBatch, [&](size_t batch) {
            RTCIntersectContext context;
            rtcInitIntersectContext(&context);
            context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            size_t begin = batch * kBatch, end = std::min(rays.size(), begin + kBatch);
            hits.local() += replay == RayReplay::WavefrontPackets8 ? castPackets8(scene, rtc, context, rays, begin, end)
                                                                    : castOneByOne(scene, rtc, context, rays, begin, end);
        });
    });
    result.replay.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.replay.cpuSeconds = processCpuSeconds() - cpuStart;
    result.replay.rays = rays.size();
    for (uint64_t h : hits) result.replay.hits += h;
    return result;
}

}  // namespace gi
