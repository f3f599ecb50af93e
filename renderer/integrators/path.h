#pragma once
#include "../integrator.h"
#include "lighting.h"

namespace gi {

class PhotonMap;

// A caustic photon map read along a continued path: at each vertex that is not purely specular,
// the light that reached it from a light through specular surfaces alone (L S+ D), which the
// map holds. A light the path reaches through a specular bounce is then not counted again, but
// for the domes: the map leaves them out (PhotonMapSettings::causticMapLeavesOutDomes), and a
// BSDF-sampled ray finds the sky through glass well. Each vertex reads the map with probability
// readShare, weighted by its inverse: a k-nearest search costs more than the rest of a vertex.
struct CausticPhotons {
    const PhotonMap* map = nullptr;
    int photons = 0;
    float maxRadius = 0;
    float coneFilter = 0;
    float readShare = 1;
};

// Traces through stochastic-presence surfaces (cut-outs) to the first surface that stops the ray.
Intersection intersectVisible(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats, bool cameraRay);
// The same from the ray's first hit, already traced (Scene::trace).
Intersection intersectVisible(const Scene& scene, Ray ray, const Scene::PendingHit& first, Sampler& sampler,
                              RayStats& stats, bool cameraRay);

class PathIntegrator : public Integrator {
public:
    PathIntegrator(int paths, int pathDepth, int rayDepth, int rouletteDepth);
    Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs) const override;
    // One path from an already shaded first vertex (shared with the irradiance-cache record
    // samplers); with `caustics`, caustic light comes from that map (see CausticPhotons), and
    // `causticPart` (when given) gets the share of the result read from it.
    Color continuePath(const Scene& scene, ShadingPoint sp, Sampler& sampler, RayStats& stats,
                       const CausticPhotons* caustics = nullptr, Color* causticPart = nullptr) const;

private:
    int paths_, pathDepth_, rayDepth_, rouletteDepth_;
};

}  // namespace gi
