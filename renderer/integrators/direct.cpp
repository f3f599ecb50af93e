#include "direct.h"

#include "path.h"
#include "specular_chain.h"

namespace gi {

DirectIntegrator::DirectIntegrator(int rayDepth, int lightSamples)
    : rayDepth_(rayDepth), lightSamples_(std::max(1, lightSamples)) {}

Color DirectIntegrator::Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats,
                           SampleAovs* aovs) const {
    return trace(ray, scene, sampler, stats, aovs, 0, true);
}

Color DirectIntegrator::trace(const Ray& cameraOrBranch, const Scene& scene, Sampler& sampler, RayStats& stats,
                              SampleAovs* aovs, int specularDepth, bool cameraRay, BranchEmitters first,
                              BranchEmitters later) const {
    Ray ray = cameraOrBranch;
    Color L(0.0f), weight(1.0f);
    BranchEmitters emitters = first;
    for (;; ++specularDepth, cameraRay = false, aovs = nullptr, emitters = later) {
        Intersection hit = intersectVisible(scene, ray, sampler, stats, cameraRay);
        // Only camera rays and specular branches get here, so emitters count in full (no MIS).
        if (hit.kind == Intersection::Kind::None) {
            if (emitters == BranchEmitters::All) return L + weight * escapedRadiance(scene, ray, 0, true, cameraRay);
            return emitters == BranchEmitters::DomesOnly ? L + weight * domeRadiance(scene, ray) : L;
        }
        if (emitters == BranchEmitters::All) L += weight * emittedOnHit(scene, hit, ray, ray.o, 0, true);
        if (hit.kind == Intersection::Kind::Light) return L;
        ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
        recordAovs(aovs, sp, hit.t);
        if (sp.bsdf.hasNonDelta()) {
            Color direct(0.0f);
            for (int i = 0; i < lightSamples_; ++i) direct += sampleDirectLight(scene, sp, sampler, stats, false);
            L += weight * (direct / float(lightSamples_) + indirect(scene, sp, sampler, stats));
            if (tracesGlossy_ && sp.bsdf.hasGlossy()) L += weight * glossyIndirect(scene, sp, sampler, stats, specularDepth);
        }
        BsdfSample branches[3];
        int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
        if (n == 0 || depthLimitReached(specularDepth, rayDepth_, stats)) return L;
        if (specularDepth < kSplitDepth) {  // every branch (specular_chain.h)
            for (int i = 0; i < n; ++i) {
                Ray next = spawnRay(sp.si, sp.frame.toWorld(branches[i].wi));
                L += weight * branches[i].weight *
                     trace(next, scene, sampler, stats, nullptr, specularDepth + 1, false, later, later);
            }
            return L;
        }
        if (!followDeltaBranch(sp, branches, n, sampler.get1D(), weight, ray)) return L;
    }
}

Color DirectIntegrator::glossyIndirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats,
                                       int specularDepth) const {
    float uLobe = sampler.get1D();
    Vec2 u = sampler.get2D();
    float uSurvive = sampler.get1D();
    if (depthLimitReached(specularDepth, rayDepth_, stats)) return Color(0.0f);
    Vec3 wi;
    Color weight;
    if (!sampleGlossyBranch(sp, uLobe, u, uSurvive, &wi, &weight)) return Color(0.0f);
    return weight * trace(spawnRay(sp.si, wi), scene, sampler, stats, nullptr, specularDepth + 1, false,
                          BranchEmitters::None, glossyBranchEmitters_);
}

bool DirectIntegrator::sampleGlossyBranch(const ShadingPoint& sp, float uLobe, Vec2 u, float uSurvive, Vec3* wi,
                                          Color* weight) {
    BsdfSample s = sp.bsdf.sample(sp.woLocal, uLobe, u);
    if (!s.valid || s.delta || !(s.pdf > 0)) return false;  // delta lobes are the branches'
    // The sampled direction's f without the Lambertian lobe, which indirect() covers.
    Color f = sp.bsdf.eval(sp.woLocal, s.wi);
    if (s.wi.z > 0) f = f - sp.bsdf.diffuseLobe(sp.woLocal);
    Color w = vmax(f, Color(0.0f)) * (std::abs(s.wi.z) / s.pdf);
    float survive = std::min(1.0f, maxComponent(w));
    if (!(survive > 0) || !isFinite(w) || uSurvive >= survive) return false;
    *wi = sp.frame.toWorld(s.wi);
    *weight = w / survive;
    return true;
}

}  // namespace gi
