// Irradiance caching (thesis 2.4.5, 3.3.1): the ray tracer's emission, direct light and
// specular recursion, with indirect diffuse light interpolated from a cache of irradiance
// records: indirect radiance = diffuse reflectance / pi * E_indirect.
//
// preprocess() fills the cache in a coarse-to-fine pass over the pixel centres
// (progressive_fill.h); the render then only reads it. A render-time lookup that finds no
// valid record (a jittered sample between covered pixel centres, a point on a curved
// surface whose normal turned past alpha+) first retries with the limits relaxed by a pixel
// and a doubled angle, and failing that computes a record for that sample alone, without
// storing it: every thread sees the same cache, so the image does not depend on thread timing.
// Before the next pass those records join the cache (render_time_records.h), and the records take
// more paths (record_refinement.h) unless refineRecords is off.
//
// Caustics: the records' paths find a light through glass or off a mirror only by chance - the sun
// through a window pane, a 0.53-degree disc, about once in 10^5 bounces - so the thesis's cache
// misses light that reaches a room only through glass (the sunlit glazed room read 0.63 of its
// reference). Where the scene has specular surfaces and a light that is not a dome, a caustic map
// (photon_maps.h, Jensen's L S+ D photons) carries that light, as in the photon cache: the pixels
// read it at every non-specular hit and the records' paths along their way
// (IrradianceRecordSampler::readCaustics). causticPhotons 0 leaves it out, as the thesis does.
#pragma once
#include <atomic>

#include "direct.h"
#include "irradiance_cache.h"
#include "irradiance_record_sampler.h"
#include "photon_maps.h"
#include "pixel_footprint.h"
#include "progressive_fill.h"
#include "record_refinement.h"
#include "render_time_records.h"

namespace gi {

struct IrradianceCacheSettings {
    RecordSettings record;
    int lightSamples = 1;
    bool refineRecords = true;  // record_refinement.h; the thesis's cache is fixed after the fill
    double causticPhotons = 500000;  // emitted for the caustic map; 0: none
    int gatherPhotons = 50;          // k of its density estimates
};

class IrradianceCacheIntegrator : public DirectIntegrator {
public:
    explicit IrradianceCacheIntegrator(const IrradianceCacheSettings& settings);
    void preprocess(const PreprocessContext& context) override;
    void beginPass(const PreprocessContext& context, int firstSample, int count) override;
    std::map<std::string, double> statistics() const override;

    const IrradianceCache& cache() const { return cache_; }
    const IrradianceRecordSampler& recordSampler() const { return recordSampler_; }
    // Where the record serving shading point sp would be computed.
    RecordSite siteOf(const ShadingPoint& sp) const;

protected:
    Color indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats) const override;

    // Empties the cache and takes the view, seed and scene extent from the context.
    void beginPreprocess(const PreprocessContext& context);
    // The caustic map, where the scene can focus light and causticPhotons > 0; the records read it.
    void buildCausticMap(const PreprocessContext& context);
    // Fills the cache from the pixel centres' shading points, coarse to fine.
    void fillFromPixelCentres(const PreprocessContext& context);
    // The camera ray through a pixel's centre; the sampler is set to that pixel's fill stream.
    Ray pixelCentreRay(const PreprocessContext& context, uint32_t pixel, Sampler& sampler) const;

    IrradianceCacheSettings settings_;
    PhotonMaps maps_;  // the caustic map alone, or nothing
    IrradianceRecordSampler recordSampler_;
    IrradianceCache cache_;
    PixelFootprint footprint_;
    uint32_t seed_ = 0;
    double preprocessSeconds_ = 0;
    RecordCounters preprocessRecords_;
    RecordRefinement refinement_;

    // Render-time counters (the render runs on many threads through const Li).
    mutable RecordCounters renderRecords_;
    mutable RenderTimeRecords renderTimeRecords_;  // computed in this pass, inserted before the next
    uint64_t adoptedRecords_ = 0;
    mutable std::atomic<uint64_t> lookups_{0}, relaxedLookups_{0}, interpolationNanoseconds_{0};
};

}  // namespace gi
