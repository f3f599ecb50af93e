// Progressive refinement of an irradiance cache's path-traced records (issue 15).
//
// A record of M N hemisphere paths carries its noise into every pixel it serves, and no number
// of camera samples averages that out: a cache filled once stops converging however long the
// render runs (on the sky-lit room the irradiance cache's blotches kept its FLIP at 0.10 after
// 5 s, twice the path tracer's). So before each of the render's passes every path-traced record
// takes further rounds of M N paths (round r from the stream of (site, r)), merged into its
// irradiance, gradients and sigma; its position, radius and octree entry stay. Rounds are added
// while the records' rays (the fill's and the rounds') are fewer than the rays the passes have
// traced, so about half the work goes to each and both the records' noise and the pixels' fall as
// the render goes on. They are shared by the pixels a record serves: the image's squared error
// from the records, sum over records of (pixels served) sigma^2 / samples, is least for a given
// number of samples when each record's samples grow as the square root of its pixels: its radius
// in pixels (1 to kMaxRecordWeight). So the adaptive cache's many small records near creases take
// fewer rounds than the wide ones on open walls, whose noise spreads into blotches (sky-lit room,
// 160x120, 5 s, seeds 1-3: FLIP of the irradiance cache 0.054-0.058 with every record refined
// alike, 0.049-0.051 weighted; adaptive cache 0.062-0.065 and 0.056). A record's outlier bound
// grows with its samples (record_outliers.h), so the clamp's bias falls too. Passes double in size,
// so the image is mostly the latest passes, rendered with the most refined records.
//
// Rays are counted, not timed: a render of a fixed sample count is deterministic. Under a time
// limit a round stops once half the time left before the pass's deadline is spent (the pass
// keeps the other half); records it did not reach keep the samples they have.
#pragma once
#include <cstdint>
#include <functional>

#include "../integrator.h"
#include "irradiance_cache.h"
#include "irradiance_record_sampler.h"
#include "progressive_fill.h"

namespace gi {

// A record's weight, its radius in pixels, is capped at this.
inline constexpr float kMaxRecordWeight = 64.0f;

class RecordRefinement {
public:
    // More samples for the record at `site`: from stream `streamKey`, `samplesBefore` being the
    // samples the record already has (the samplers' sample()).
    using Sample = std::function<IrradianceRecord(const RecordSite& site, uint32_t streamKey, uint32_t samplesBefore,
                                                  RayStats& stats)>;

    // cellsPerRound: the samples of one round (the sampler's M N).
    explicit RecordRefinement(int cellsPerRound) : cellsPerRound_(uint32_t(std::max(1, cellsPerRound))) {}

    // Refines the cache's path-traced records (samples > 0) until they have traced as many rays
    // as the passes (context.passRays); `fillRays` are the rays the fill spent on them.
    void beforePass(const PreprocessContext& context, uint64_t fillRays, IrradianceCache& cache, const Sample& sample);

    int rounds() const { return rounds_; }
    const RecordCounters& counters() const { return counters_; }  // records = record-rounds added
    // Mean samples of the cache's path-traced records (0 without any).
    static double meanSamples(const IrradianceCache& cache);
    // How many of the cache's records are path-traced (refinable).
    static size_t pathTracedCount(const IrradianceCache& cache);

private:
    uint32_t cellsPerRound_;
    int rounds_ = 0;    // levels reached
    uint32_t level_ = 0;  // a record's rounds are 1 + level x its share
    RecordCounters counters_;
};

}  // namespace gi
