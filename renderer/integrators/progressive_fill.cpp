#include "progressive_fill.h"

#include <tbb/parallel_for.h>

#include <chrono>

namespace gi {

PixelPhases::PixelPhases(int width, int height, float maxSpacing) : width_(width), height_(height) {
    coarsest_ = 1;
    levels_ = 0;
    while (coarsest_ * 2 <= std::max(1.0f, maxSpacing) && coarsest_ < (1 << 14)) {
        coarsest_ *= 2;
        ++levels_;
    }
}

int PixelPhases::phaseOf(int x, int y) const {
    // The coarsest grid step dividing both coordinates (0 is divisible by every step).
    int step = coarsest_;
    while (step > 1 && (x % step != 0 || y % step != 0)) step /= 2;
    if (step == coarsest_) return 0;
    int level = 0;  // 0 for the first level below the coarsest grid
    for (int s = coarsest_ / 2; s > step; s /= 2) ++level;
    bool oddX = (x / step) % 2 != 0, oddY = (y / step) % 2 != 0;
    int subGrid = oddX && !oddY ? 0 : (!oddX && oddY ? 1 : 2);
    return 1 + 3 * level + subGrid;
}

std::vector<std::vector<uint32_t>> PixelPhases::pixelsByPhase() const {
    std::vector<std::vector<uint32_t>> phases(count());
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) phases[phaseOf(x, y)].push_back(uint32_t(y) * uint32_t(width_) + uint32_t(x));
    return phases;
}

std::vector<uint32_t> addMissingRecords(const Scene& scene, const IrradianceRecordSampler& sampler, uint32_t seed,
                                        const std::vector<RecordSite>& sites, IrradianceCache& cache,
                                        RecordCounters& counters) {
    // Coverage against the cache as it was when the phase began: a fixed state, so the
    // answer does not depend on which thread looks first.
    std::vector<uint8_t> missing(sites.size(), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, sites.size(), 64), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) missing[i] = !cache.covers(sites[i].p, sites[i].n);
    });
    std::vector<size_t> wanted;
    for (size_t i = 0; i < sites.size(); ++i)
        if (missing[i]) wanted.push_back(i);

    std::vector<IrradianceRecord> records(wanted.size());
    tbb::parallel_for(size_t(0), wanted.size(), [&](size_t i) {
        auto start = std::chrono::steady_clock::now();
        const RecordSite& site = sites[wanted[i]];
        RayStats stats;
        records[i] = sampler.sample(scene, site, seed, IrradianceRecordSampler::streamKey(site), stats);
        auto nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start);
        counters.nanoseconds.fetch_add(uint64_t(nanoseconds.count()), std::memory_order_relaxed);
        counters.rays.fetch_add(stats.rays, std::memory_order_relaxed);
    });
    std::vector<uint32_t> ids;
    ids.reserve(records.size());
    for (const IrradianceRecord& r : records) ids.push_back(cache.insert(r));
    counters.records.fetch_add(records.size(), std::memory_order_relaxed);
    return ids;
}

}  // namespace gi
