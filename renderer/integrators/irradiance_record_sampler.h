// Computes irradiance-cache records (thesis 2.4.5, 3.3.1): path tracing over a hemisphere
// stratified into M x N cells of equal projected area, the cell layout that the Ward & Heckbert
// gradients (2.29, 2.30) are defined on.
#pragma once
#include <atomic>
#include "irradiance_record.h"
#include "path.h"

namespace gi {

// M polar x N azimuthal cells; N close to pi M (Ward & Heckbert's proportion), M N = paths
// whenever `paths` has a divisor near sqrt(paths / pi).
struct HemisphereLayout {
    int polar = 1, azimuthal = 1;
    static HemisphereLayout forPaths(int paths);
    int cells() const { return polar * azimuthal; }
};

// Where a record is wanted: position, geometric normal (for the ray offset), the normal of the
// hemisphere, the direction towards the viewer, and the world-space size of a pixel there.
struct RecordSite {
    Vec3 p, ng, n, wo;
    float footprint = 0;
};

// Where a record's ray in direction wi leaves from: a hair off the site towards the viewer. A
// site exactly on a crease or a mesh edge (a floor's edge under a wall) lies on the other
// surface's plane too, where the ray offset along its own normal would let half the hemisphere
// slip under that surface; whatever the viewer sees the site from is open space next to every
// surface there. Twice the point's error bound clears that plane (spawnRay then adds one along
// the normal); 16 times it put the origin 1.5 units off the wall at 10^5 and darkened the caches
// by up to 16% (tests/python/test_stress.py, test_scale_and_offset_do_not_change_the_image).
// A ray below the site's geometric plane (a shading normal tilts the hemisphere past it) leaves
// from the site itself and crosses the surface there, as the path tracer's BSDF-sampled ray
// does: from the lifted origin it hit the site's own surface from the front and brought its lit
// radiance back, 2-6% too much light on Sponza's smooth-shaded arcades.
inline Vec3 recordRayOrigin(const RecordSite& site, const Vec3& wi) {
    if (dot(wi, site.ng) < 0) return site.p;
    return site.p + site.wo * (1e-3f * site.footprint + pointErrorBound(site.p));
}

// The site a path-traced record was computed at.
inline RecordSite recordSite(const IrradianceRecord& record) {
    return RecordSite{record.p, record.ng, record.n, record.wo, record.footprint};
}

// A record's path reads the caustic map at a vertex one time in four (weighted by four): on
// Sibenik with portals, reading it at every vertex made the photon cache's records cost more than 5 s.
inline constexpr float kRecordCausticShare = 0.25f;

struct RecordSettings {
    int paths = 108;        // M N hemisphere rays
    int pathDepth = kDepthCap;  // scattering vertices of a record's paths, counting the record's own
    int rayDepth = kDepthCap;   // specular vertices of those paths
    int rouletteDepth = 3;  // vertices before Russian roulette
    float accuracy = 1;     // k of 2.32
    float minSpacing = 1.5f, maxSpacing = 10;  // record radius bounds, in pixels
};

// Depth of the path that continues a record's path from its second vertex: one less, except
// that the safety cap stays the cap.
inline int continuationDepth(int pathDepth) { return pathDepth >= kDepthCap ? kDepthCap : std::max(0, pathDepth - 1); }

class IrradianceRecordSampler {
public:
    explicit IrradianceRecordSampler(const RecordSettings& settings);

    // False when the paths are too short to carry any light that has bounced (pathDepth < 2).
    bool gathersLight() const { return settings_.pathDepth >= 2; }
    const HemisphereLayout& layout() const { return layout_; }
    const RecordSettings& settings() const { return settings_; }
    // Hemisphere samples clamped as outliers (record_outliers.h) so far.
    uint64_t outliersClamped() const { return outliersClamped_.load(std::memory_order_relaxed); }

    // Samples the hemisphere above `site`. The random numbers come from stream `streamKey` of
    // a sampler seeded with `seed`, cell c using the stream's sample c, so a record depends on
    // (seed, key, site) only. `samplesBefore`: the samples the record already has, when these
    // are to be added to it (record_refinement.h); they set the outlier bound (record_outliers.h).
    IrradianceRecord sample(const Scene& scene, const RecordSite& site, uint32_t seed, uint32_t streamKey,
                            RayStats& stats, uint32_t samplesBefore = 0) const;

    // A stream key from a site's position and normal bits: the same site always gets the same
    // random numbers, whichever pass or thread computes it. Round r > 0 of a refined record
    // (record_refinement.h) takes the key of (site, r).
    static uint32_t streamKey(const RecordSite& site, uint32_t round = 0);

    // With a caustic map (the pixels read it), caustic light is the map's along the whole path, as
    // in the photon cache's path-traced records (path_traced_record.h): a path that reaches a light
    // through specular surfaces alone is left out, later non-specular vertices read the map. Domes
    // stay the paths' (the map leaves them out). Set before the first record.
    void readCaustics(const CausticPhotons& caustics) { caustics_ = caustics; }

private:
    // Radiance arriving at the site from direction wi that has bounced at least once: the
    // direct light that the ray tracer adds by light sampling is left out. Sets the hit distance,
    // and adds to causticPart what of it the caustic map gave.
    Color bouncedRadiance(const Scene& scene, const SurfaceInteraction& origin, const Vec3& wi, Sampler& sampler,
                          RayStats& stats, float* distance, Color* causticPart) const;

    RecordSettings settings_;
    HemisphereLayout layout_;
    mutable std::atomic<uint64_t> outliersClamped_{0};
    PathIntegrator continuation_;  // paths from a hemisphere ray's first hit onwards
    CausticPhotons caustics_;      // map null: every path counts
};

}  // namespace gi
