#include "record_refinement.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>

namespace gi {

void RecordRefinement::beforePass(const PreprocessContext& context, uint64_t fillRays, IrradianceCache& cache,
                                  const Sample& sample) {
    if (fillRays + counters_.rays.load() >= context.passRays) return;
    // Weights as in the header: a record's radius in pixels, the square root of the pixels it serves.
    std::vector<uint32_t> refinable;
    std::vector<float> share;
    double weights = 0;
    for (uint32_t id = 0; id < cache.size(); ++id) {
        const IrradianceRecord& record = cache.record(id);
        if (record.samples == 0) continue;
        refinable.push_back(id);
        float pixels = record.footprint > 0 ? record.influenceRadius() / record.footprint : 1.0f;
        share.push_back(std::clamp(pixels, 1.0f, kMaxRecordWeight));
        weights += share.back();
    }
    if (refinable.empty()) return;
    for (float& s : share) s = float(s * double(share.size()) / weights);  // mean 1: a level is a round each
    const double deadline = context.deadline > 0 ? steadySeconds() + 0.5 * context.secondsLeft() : 0;
    while (fillRays + counters_.rays.load() < context.passRays) {
        ++level_;
        std::atomic<bool> cut{false};
        tbb::parallel_for(tbb::blocked_range<size_t>(0, refinable.size(), 8), [&](const tbb::blocked_range<size_t>& range) {
            auto start = std::chrono::steady_clock::now();
            RayStats stats;
            uint64_t refined = 0;
            for (size_t i = range.begin(); i < range.end() && !cut; ++i) {
                uint32_t target = 1 + uint32_t(float(level_) * share[i]);
                while (cache.record(refinable[i]).samples / cellsPerRound_ < target) {
                    if (context.cancelled() || (deadline > 0 && steadySeconds() >= deadline)) {
                        cut = true;
                        break;
                    }
                    const IrradianceRecord& record = cache.record(refinable[i]);
                    RecordSite site = recordSite(record);
                    uint32_t round = record.samples / cellsPerRound_;
                    cache.addSamples(refinable[i], sample(site, IrradianceRecordSampler::streamKey(site, round),
                                                          record.samples, stats));
                    ++refined;
                }
            }
            auto nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start);
            counters_.nanoseconds.fetch_add(uint64_t(nanoseconds.count()), std::memory_order_relaxed);
            counters_.rays.fetch_add(stats.rays, std::memory_order_relaxed);
            counters_.records.fetch_add(refined, std::memory_order_relaxed);
        });
        if (cut) break;
        ++rounds_;
    }
}

double RecordRefinement::meanSamples(const IrradianceCache& cache) {
    double samples = 0, records = 0;
    for (uint32_t id = 0; id < cache.size(); ++id)
        if (cache.record(id).samples > 0) {
            samples += cache.record(id).samples;
            ++records;
        }
    return records > 0 ? samples / records : 0.0;
}

size_t RecordRefinement::pathTracedCount(const IrradianceCache& cache) {
    size_t count = 0;
    for (uint32_t id = 0; id < cache.size(); ++id) count += cache.record(id).samples > 0;
    return count;
}

}  // namespace gi
