#include "direct.h"

#include "path.h"

namespace gi {

DirectIntegrator::DirectIntegrator(int rayDepth, int lightSamples)
    : rayDepth_(rayDepth), lightSamples_(std::max(1, lightSamples)) {}

Color DirectIntegrator::Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats,
                           SampleAovs* aovs) const {
    return trace(ray, scene, sampler, stats, aovs, 0, true);
}

Color DirectIntegrator::trace(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats,
                              SampleAovs* aovs, int specularDepth, bool cameraRay) const {
    Intersection hit = intersectVisible(scene, ray, sampler, stats, cameraRay);
    // Only camera rays and specular branches get here, so emitters count in full (no MIS).
    if (hit.kind == Intersection::Kind::None) return escapedRadiance(scene, ray, 0, true, cameraRay);
    Color L = emittedOnHit(scene, hit, ray, ray.o, 0, true);
    if (hit.kind == Intersection::Kind::Light) return L;
    ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
    recordAovs(aovs, sp, hit.t);
    if (sp.bsdf.hasNonDelta()) {
        Color direct(0.0f);
        for (int i = 0; i < lightSamples_; ++i) direct += sampleDirectLight(scene, sp, sampler, stats, false);
        L += direct / float(lightSamples_);
        L += indirect(scene, sp, sampler, stats);
    }
    if (specularDepth < rayDepth_) {
        BsdfSample branches[3];
        int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
        for (int i = 0; i < n; ++i) {
            Ray next = spawnRay(sp.si, sp.frame.toWorld(branches[i].wi));
            L += branches[i].weight * trace(next, scene, sampler, stats, nullptr, specularDepth + 1, false);
        }
    }
    return L;
}

}  // namespace gi
