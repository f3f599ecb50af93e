#pragma once
#include "../integrator.h"
#include "lighting.h"

namespace gi {

// Traces through stochastic-presence surfaces (cut-outs) to the first surface that stops the ray.
Intersection intersectVisible(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats, bool cameraRay);

class PathIntegrator : public Integrator {
public:
    PathIntegrator(int paths, int pathDepth, int rayDepth, int rouletteDepth);
    Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs) const override;
    // One path from an already shaded first vertex (shared with the irradiance-cache record sampler).
    Color continuePath(const Scene& scene, ShadingPoint sp, Sampler& sampler, RayStats& stats) const;

private:
    int paths_, pathDepth_, rayDepth_, rouletteDepth_;
};

}  // namespace gi
