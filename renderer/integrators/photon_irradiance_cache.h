// Photon mapping with an irradiance cache (thesis 2.4.7, 3.3.4). The ray tracer's emission,
// direct light and specular recursion (DirectIntegrator); caustics from the caustic map at
// every non-specular point; and indirect diffuse light interpolated from an irradiance cache
// (irradiance_cache.h, Tabellion-Lamorlette weights) whose records are the global photon
// map's irradiance estimate: "the photon map is used in place of the irradiance cache, and
// only where there are not enough photons to estimate the irradiance is it computed, by path
// tracing" (2.4.7). A record needs at least half of gatherPhotons within maxGatherRadius, and
// the photons must cover their disc (no edge, corner or thin column under it: the estimate would
// read dark); elsewhere it is a path-traced record (paths, pathDepth; path_traced_record.h).
//
// The global map holds only photons that have bounced off a non-specular surface: direct
// light comes from light sampling and caustics from the caustic map, so path-traced records
// leave caustic paths out as well (unless there is no caustic map).
//
// A photon record reuses its estimate over half the gather disc's radius (divided by the
// accuracy k), clamped to [minSpacing, maxSpacing] pixels: the estimate is already an
// average over that disc. It has no gradients: its neighbours differ only in photon noise.
//
// The cache is filled before the render, coarse to fine over the pixel centres
// (progressive_fill.h), in an order fixed by the pixels; a render-time lookup that finds no
// record computes one for that sample alone without storing it, so the image does not depend
// on thread timing. Before the next pass those records join the cache (render_time_records.h) and,
// unless refineRecords is off, the path-traced records take more paths (record_refinement.h)
// while further batches of global photons join the map (photon_maps.h's addPhotonBatch) and the
// photon records are estimated again from k B^(2/3) photons after B batches: a fixed map kept its
// photon noise in the records however long the render ran (Cornell box, photon records of 20 000
// photons: indirect e^2 0.0075 fixed, 0.00042 after 87 batches at 256 spp).
#pragma once
#include <atomic>

#include "direct.h"
#include "irradiance_cache.h"
#include "path_traced_record.h"
#include "photon_maps.h"
#include "pixel_footprint.h"
#include "record_refinement.h"
#include "render_time_records.h"

namespace gi {

struct PhotonIrradianceCacheSettings {
    PhotonMapSettings photons;
    RecordSettings record;  // the path-traced fallback records, and the spacing limits of all records
    int lightSamples = 1;
    bool refineRecords = true;  // more paths for the path-traced records between passes (record_refinement.h)
};

class PhotonMapIrradianceCacheIntegrator : public DirectIntegrator {
public:
    explicit PhotonMapIrradianceCacheIntegrator(const PhotonIrradianceCacheSettings& settings);
    void preprocess(const PreprocessContext& context) override;
    void beginPass(const PreprocessContext& context, int firstSample, int count) override;
    std::map<std::string, double> statistics() const override;

    const PhotonMaps& maps() const { return maps_; }
    const IrradianceCache& cache() const { return cache_; }

protected:
    Color indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats) const override;

private:
    struct Counters {
        std::atomic<uint64_t> photonRecords{0}, pathTracedRecords{0}, pathTracedRays{0};
        std::atomic<uint64_t> nanoseconds{0};  // thread-time of records computed in the passes
    };
    // A record site and the surface it lies on (for the photon map's visibility guard).
    struct Site {
        RecordSite record;
        uint32_t surface;
    };
    Site siteOf(const ShadingPoint& sp) const;
    // The global map's irradiance at a record site on `surface` from recordPhotons_ photons;
    // false where too few photons cover the disc for a photon record (the site is path traced).
    bool photonIrradiance(const Scene& scene, const RecordSite& site, uint32_t surface, PhotonEstimate* estimate) const;
    // From the photon map where it has enough photons, by path tracing elsewhere.
    IrradianceRecord computeRecord(const Scene& scene, const Site& site, RayStats& stats, Counters& counters) const;
    // The cache's interpolation (2.31) over the records valid at the site that it can see: a
    // record from another surface counts only with a clear line between the two (the
    // visibility guard of photon_map.h), so that no record reaches through a thin wall to
    // the floor on its other side, however small the wall's distance or large the record.
    bool interpolate(const Scene& scene, const Site& site, bool relaxed, Color* E) const;
    void fillFromPixelCentres(const PreprocessContext& context);
    // More photons between passes (photon_maps.h's addPhotonBatch) and the photon records
    // re-estimated from them.
    void addPhotonBatches(const PreprocessContext& context);

    PhotonIrradianceCacheSettings settings_;
    std::unique_ptr<PathTracedRecordSampler> recordSampler_;  // made once the caustic map is known
    IrradianceCache cache_;
    std::vector<uint32_t> recordSurfaces_;  // per record id, the surface it lies on
    PhotonMaps maps_;
    PixelFootprint footprint_;
    uint32_t seed_ = 0;
    int recordPhotons_ = 0;  // k of the photon records' estimates
    double fillSeconds_ = 0;
    Counters preprocessRecords_;
    std::unique_ptr<RecordRefinement> refinement_;  // made with the record sampler
    mutable Counters renderRecords_;
    mutable RenderTimeRecords renderTimeRecords_;  // computed in this pass, inserted before the next
    uint64_t adoptedRecords_ = 0;
    mutable std::atomic<uint64_t> lookups_{0};
};

}  // namespace gi
