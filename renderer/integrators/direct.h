// The ray tracer the irradiance-caching integrators build on (thesis 3.3.1): emission, direct
// light by light sampling at every non-specular hit, and recursion into every specular
// (delta) branch for the first kSplitDepth specular vertices, one branch picked by weight
// deeper, up to `rayDepth` (specular_chain.h). Indirect diffuse light is left to `indirect()`, which the
// plain ray tracer leaves at zero.
#pragma once
#include "../integrator.h"
#include "lighting.h"

namespace gi {

class DirectIntegrator : public Integrator {
public:
    DirectIntegrator(int rayDepth, int lightSamples);
    Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs) const override;

protected:
    // Indirect light reflected at a non-specular shading point (e.g. from an irradiance cache).
    virtual Color indirect(const Scene&, const ShadingPoint&, Sampler&, RayStats&) const { return Color(0.0f); }
    Color trace(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs,
                int specularDepth, bool cameraRay) const;

    int rayDepth_, lightSamples_;
};

}  // namespace gi
