// The fallback records of photon mapping with an irradiance cache (thesis 2.4.7: "only where
// there are not enough photons to estimate the irradiance is it computed, by path tracing").
//
// The hemisphere is sampled in the M x N cells of the irradiance cache's record sampler
// (irradiance_record_sampler.h). With a caustic map, which supplies caustics at every shading
// point, caustic light is the map's along the whole path: a path that reaches a light through
// specular surfaces alone (L S+ D at the record, a caustic there) is left out, and every later
// non-specular vertex reads the map for the light focused onto it (the sun through window glass
// onto a floor lights the room from there). Domes are the exception (CausticPhotons): the map
// leaves them out, and the records carry the sky through glass. (The cache's own sampler counts
// every path: it serves integrators without a caustic map.) Without gradients, as in Ward's
// original cache: validity from the T&L radius of the nearest hit, like the photon records.
#pragma once
#include "irradiance_record.h"
#include "irradiance_record_sampler.h"
#include "path.h"

namespace gi {

class PathTracedRecordSampler {
public:
    // caustics.map: the caustic map, or null when there is none (then every path counts).
    PathTracedRecordSampler(const RecordSettings& settings, const CausticPhotons& caustics);

    // A record for `site` from stream `streamKey` of a sampler seeded with `seed`: cell c uses
    // the stream's sample c, so a record depends on (seed, key, site) only. `samplesBefore` as
    // in IrradianceRecordSampler::sample.
    IrradianceRecord sample(const Scene& scene, const RecordSite& site, uint32_t seed, uint32_t streamKey,
                            RayStats& stats, uint32_t samplesBefore = 0) const;
    // Hemisphere samples clamped as outliers (record_outliers.h) so far.
    uint64_t outliersClamped() const { return outliersClamped_.load(std::memory_order_relaxed); }

private:
    // Radiance arriving from direction wi that has bounced off a non-specular surface at least
    // once (or, without a caustic map, off any surface); sets the first hit's distance, and adds to
    // causticPart what of it the caustic map gave.
    Color bouncedRadiance(const Scene& scene, const SurfaceInteraction& origin, const Vec3& wi, Sampler& sampler,
                          RayStats& stats, float* distance, Color* causticPart) const;

    RecordSettings settings_;
    HemisphereLayout layout_;
    PathIntegrator continuation_;
    CausticPhotons caustics_;
    mutable std::atomic<uint64_t> outliersClamped_{0};
};

}  // namespace gi
