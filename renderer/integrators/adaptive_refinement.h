// Adaptive refinement of an irradiance cache (Krivanek et al. 2006, thesis 2.4.5 formulas
// 2.36-2.39 and 3.3.2), run over the shading points of a first pass.
//
// The thesis processes a queue one point at a time. Here the queue is processed in rounds,
// in parallel, against the cache as it stood when the round began:
//   1. every queued point gathers its valid records; a point with none is uncovered; at a
//      point with two or more, each record that is discernible from the others (2.38) gets
//      a proposed radius factor that just excludes the point (2.39);
//   2. each record takes the smallest factor proposed for it (a minimum: the same whatever
//      order the proposals arrived in);
//   3. uncovered points get new records, coarse to fine over their pixels as in the first
//      fill (progressive_fill.h), inserted in point order;
//   4. the points within a changed record's former radius, or a new record's radius, form
//      the next round's queue.
// It stops when a round changes nothing (or after `maxRounds`): a record is never removed
// from the point it was computed at, so a point gets at most one record of its own, and
// radii only shrink. A change propagates one ring of neighbours per round, so rounds are
// many (about a hundred at 1024x768) but those after the first few are small. Memory beyond
// the points themselves is a few bytes a point (queue, flags) and a float per record.
#pragma once
#include <atomic>

#include "irradiance_cache.h"
#include "irradiance_record_sampler.h"
#include "pixel_footprint.h"
#include "point_index.h"
#include "progressive_fill.h"
#include "shading_point_store.h"

namespace gi {

struct AdaptiveRefinementSettings {
    float threshold = 0.02f;  // 2.38's relative luminance difference (2%: not perceptible)
    int maxRounds = 1000;  // a safety net: the refinement terminates on its own (see examine())
};

struct RefinementStatistics {
    int rounds = 0;
    uint64_t pointVisits = 0;     // points processed, over all rounds
    uint64_t shrinks = 0;         // radius factors reduced
    uint64_t newRecords = 0;      // records created by the refinement (after the first fill)
    size_t indexBytes = 0;        // the point index
    bool converged = false;
};

class AdaptiveRefinement {
public:
    AdaptiveRefinement(const Scene& scene, const IrradianceRecordSampler& sampler, uint32_t seed,
                       const PixelFootprint& footprint, PixelPhases phases, const ShadingPointStore& points,
                       IrradianceCache& cache, RecordCounters& counters);

    // Records for the given points (indices, ascending) that the cache does not cover, coarse
    // to fine over their pixels. Returns the new records' ids.
    // Stops between phases once steadySeconds() passes `deadline` (0 = none).
    std::vector<uint32_t> cover(const std::vector<uint32_t>& pointIds, double deadline = 0);
    // The refinement queue, starting from every point. Stops between rounds when cancelled or
    // once steadySeconds() passes `deadline` (0 = none).
    RefinementStatistics refine(const AdaptiveRefinementSettings& settings, const std::atomic<bool>* cancel,
                                double deadline = 0);

private:
    // Step 1 for one point: marks it uncovered, or proposes factors for discernible records.
    void examine(uint32_t point, float threshold, std::vector<IrradianceCache::Contribution>& scratch,
                 std::vector<float>& proposals, uint8_t& uncovered) const;
    // Step 4: the points inside any of the spheres, ascending.
    std::vector<uint32_t> pointsWithin(const std::vector<std::pair<Vec3, float>>& spheres) const;

    const Scene& scene_;
    const IrradianceRecordSampler& sampler_;
    uint32_t seed_;
    const PixelFootprint& footprint_;
    PixelPhases phases_;
    const ShadingPointStore& points_;
    IrradianceCache& cache_;
    RecordCounters& counters_;
    PointIndex index_;
};

}  // namespace gi
