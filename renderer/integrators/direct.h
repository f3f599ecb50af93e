// The ray tracer the irradiance-caching integrators build on (thesis 3.3.1): emission, direct
// light by light sampling at every non-specular hit, and recursion into every specular
// (delta) branch for the first kSplitDepth specular vertices, one branch picked by weight
// deeper, up to `rayDepth` (specular_chain.h). Indirect diffuse light is left to `indirect()`, which the
// plain ray tracer leaves at zero, and integrators that set tracesGlossy_ trace the indirect light
// of glossy lobes (glossyIndirect): the thesis's scenes are Lambertian, but on Sponza's floor
// (roughness 0.35, specular 0.04, seen at grazing angles) the caches read 25% dark without it.
#pragma once
#include "../integrator.h"
#include "lighting.h"

namespace gi {

// Which emitters a ray counts where it reaches them.
enum class BranchEmitters { All, DomesOnly, None };

class DirectIntegrator : public Integrator {
public:
    DirectIntegrator(int rayDepth, int lightSamples);
    Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs) const override;

protected:
    // Indirect light reflected at a non-specular shading point (e.g. from an irradiance cache).
    virtual Color indirect(const Scene&, const ShadingPoint&, Sampler&, RayStats&) const { return Color(0.0f); }
    // first: the emitters the ray itself counts where it reaches them (none for a glossy ray,
    // whose lights the light sampling at its origin counted already); later: those its specular
    // branches count.
    Color trace(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats, SampleAovs* aovs,
                int specularDepth, bool cameraRay, BranchEmitters first = BranchEmitters::All,
                BranchEmitters later = BranchEmitters::All) const;
    // The light that sp's glossy lobes (rough specular, clearcoat, rough glass: Bsdf::hasGlossy)
    // reflect from other surfaces, for integrators whose indirect() covers only the Lambertian
    // lobe: one ray sampled from the BSDF, weighted by its lobes other than the Lambertian one,
    // traced on as a specular branch is, continued with Russian roulette on that weight.
    Color glossyIndirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats,
                         int specularDepth) const;
    // The way on of such a ray from uniform numbers (lobe, direction, survival): false where
    // Russian roulette or a delta lobe ends it, else its world direction and weight (the BSDF
    // less its Lambertian lobe, cos / pdf, over the survival probability).
    static bool sampleGlossyBranch(const ShadingPoint& sp, float uLobe, Vec2 u, float uSurvive, Vec3* wi,
                                   Color* weight);

    int rayDepth_, lightSamples_;
    bool tracesGlossy_ = false;  // glossyIndirect at every non-specular hit
    // The emitters a glossy ray counts through specular surfaces (L S+ G E): those the
    // integrator's photon estimates at the glossy point leave out (a caustic map read through
    // the whole BSDF there has them: counted again, they were counted twice).
    BranchEmitters glossyBranchEmitters_ = BranchEmitters::All;
};

}  // namespace gi
