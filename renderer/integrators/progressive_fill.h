// The first, coarse-to-fine pass that fills the irradiance cache before the render, so that
// the render only reads it (issue 4: results must not depend on thread timing).
//
// Pixels are visited in phases: every S-th pixel of every S-th row first (S the largest
// power of two not above the maximum record spacing), then, level by level, the pixels
// halfway between, in three interleaved sub-grids (right, below, diagonal) down to every
// pixel. Within a phase the sites the cache does not cover yet get records computed in
// parallel, which are then inserted in pixel order; the next phase sees them. Sites of one
// phase are at least two grid steps apart, so few records of a phase overlap.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "irradiance_cache.h"
#include "irradiance_record_sampler.h"

namespace gi {

class PixelPhases {
public:
    PixelPhases(int width, int height, float maxSpacing);
    int count() const { return 1 + 3 * levels_; }
    int width() const { return width_; }
    // The phase pixel (x, y) belongs to, in [0, count()).
    int phaseOf(int x, int y) const;
    // Every phase's pixel indices (y * width + x), each in scanline order.
    std::vector<std::vector<uint32_t>> pixelsByPhase() const;

private:
    int width_, height_, coarsest_, levels_;
};

// Thread-seconds and counts of record computation, shared by preprocess and render.
struct RecordCounters {
    std::atomic<uint64_t> records{0}, nanoseconds{0}, rays{0};
};

// Computes, in parallel, a record for each site the cache does not cover, then inserts them
// in the order of `sites`. Returns the new records' ids.
std::vector<uint32_t> addMissingRecords(const Scene& scene, const IrradianceRecordSampler& sampler, uint32_t seed,
                                        const std::vector<RecordSite>& sites, IrradianceCache& cache,
                                        RecordCounters& counters);

}  // namespace gi
