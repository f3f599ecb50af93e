// Photon mapping with final gathering (thesis 2.4.7, 3.3.5). The ray tracer's emission,
// direct light by light sampling and specular recursion (DirectIntegrator), and at every
// non-specular point it reaches:
// - caustics, read from the caustic map (L S+ D paths, which light sampling cannot find);
// - indirect light, from finalGatherSamples rays distributed by the BSDF (cosine-distributed
//   on a Lambertian surface) that read the global map's radiance estimate where they land.
//   A gather ray that meets a specular surface continues through it, finalGatherDepth
//   vertices at most; emitters it meets add nothing, since light sampling (direct) and the
//   caustic map (through specular surfaces) already count them.
//
// By default a gather ray's hit adds its direct light by light sampling (one shadow ray) and reads
// only the photons that have bounced from the map: a k-nearest disc that reaches past a thin or
// curved surface (a column) reads too dark, and direct light is most of what it would read
// (Sponza under sun and sky at 128x96: 0.87 of the path tracer with all light from the map, 0.91
// with direct light sampled, 0.93 with 4 million photons). gatherDirectLight = 0 is the thesis's
// final gather (the `thesis` presets).
//
// By default a gather ray path-traces one vertex past its hit before it reads the map
// (gatherBounces = 1: light sampling with MIS there, and the BSDF choosing the way on), as
// production final gatherers do ("secondary bounces"): the map then holds light that has bounced
// at least twice, about the albedo times less of the image, and its density-estimation bias with
// it (Sponza under sun and sky, 80x60: 0.915 of the path tracer with the map at the gather hit,
// 0.963 one vertex on, 0.975 two on).
//
// The estimate a gather ray reads is precomputed (Christensen 2000): the global map's
// irradiance at every 4th photon (fewer beyond a million photons; photon_maps.h), so a gather
// costs one nearest-photon search instead of a k-nearest one (a k = 50 search visits some 240
// photons: ten times the work). What it returns is the diffuse reflection, reflectance / pi
// * E, at the gather point; a glossy lobe there reflects nothing into the gather (the final
// gather's usual approximation, second-order since it is one bounce away from the camera).
#pragma once
#include <atomic>

#include "direct.h"
#include "photon_maps.h"

namespace gi {

struct PhotonFinalGatherSettings {
    PhotonMapSettings photons;
    int finalGatherSamples = 16;  // thesis table 4.3
    int finalGatherDepth = kDepthCap;
    // Direct light at a gather ray's hit by light sampling, the photon map giving only what has
    // bounced (caustics and indirect light); off: all of it from the photon map (the thesis).
    bool gatherDirectLight = true;
    // Vertices a gather ray path-traces past its hit (light sampling with MIS, BSDF sampling)
    // before it reads the photon map: each multiplies the map's share of the image, and so its
    // density-estimation bias, by about the albedo. 0: the map at the gather hit (the thesis).
    int gatherBounces = 1;
    int rayDepth = kDepthCap;
    int lightSamples = 1;
};

class PhotonMapFinalGatherIntegrator : public DirectIntegrator {
public:
    explicit PhotonMapFinalGatherIntegrator(const PhotonFinalGatherSettings& settings);
    void preprocess(const PreprocessContext& context) override;
    std::map<std::string, double> statistics() const override;
    const PhotonMaps& maps() const { return maps_; }

protected:
    Color indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats) const override;

private:
    // Radiance arriving back along `ray` from the global map, through at most
    // finalGatherDepth - vertex specular vertices.
    Color gatherRay(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats, int vertex) const;

    PhotonFinalGatherSettings settings_;
    PhotonMaps maps_;
    mutable std::atomic<uint64_t> gatherRays_{0}, lookups_{0}, fallbackLookups_{0};
};

}  // namespace gi
