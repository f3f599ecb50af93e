#include "photon_final_gather.h"

#include "path.h"
#include "specular_chain.h"

namespace gi {

PhotonMapFinalGatherIntegrator::PhotonMapFinalGatherIntegrator(const PhotonFinalGatherSettings& settings)
    : DirectIntegrator(settings.rayDepth, settings.lightSamples), settings_(settings) {
    settings_.photons.globalKeepsDirectAndCaustic = true;
    settings_.photons.globalLeavesOutDirect = settings.gatherDirectLight;
    settings_.photons.precomputeIrradiance = true;
    settings_.photons.rayDepth = settings.rayDepth;
}

void PhotonMapFinalGatherIntegrator::preprocess(const PreprocessContext& context) {
    buildPhotonMaps(context, settings_.photons, maps_);
    if (maps_.global.empty() && settings_.finalGatherSamples > 0 && settings_.photons.photons > 0)
        context.scene.warn("photonMapFinalGather: the global photon map is empty, so final gathering finds no "
                           "indirect light; the image has direct light and caustics only");
}

Color PhotonMapFinalGatherIntegrator::indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler,
                                               RayStats& stats) const {
    const int k = settings_.photons.gatherPhotons;
    Color L(0.0f);
    if (!maps_.caustic.empty()) {
        L += maps_.caustic.radiance(sp, scene, k, maps_.gatherRadius, kCausticConeFilter).value;
        lookups_.fetch_add(1, std::memory_order_relaxed);
    }
    const int samples = settings_.finalGatherSamples;
    if (maps_.global.empty() || samples <= 0) return L;
    Color gathered(0.0f);
    for (int i = 0; i < samples; ++i) {
        float uLobe = sampler.get1D();
        BsdfSample bs = sp.bsdf.sample(sp.woLocal, uLobe, sampler.get2D());
        // Delta lobes are the ray tracer's specular recursion; the non-delta estimate stays
        // unbiased because bs.pdf counts the probability of having picked a non-delta lobe.
        if (!bs.valid || bs.delta) continue;
        Ray ray = spawnRay(sp.si, sp.frame.toWorld(bs.wi));
        gathered += bs.weight * gatherRay(scene, ray, sampler, stats, 1);
    }
    gatherRays_.fetch_add(uint64_t(samples), std::memory_order_relaxed);
    return L + gathered / float(samples);
}

Color PhotonMapFinalGatherIntegrator::gatherRay(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats,
                                                int vertex) const {
    Color L(0.0f), weight(1.0f);
    for (;; ++vertex) {
        Intersection hit = intersectVisible(scene, ray, sampler, stats, false);
        if (hit.kind != Intersection::Kind::Surface) return L;  // lights: direct light or caustics
        const SurfaceInteraction& si = hit.si;
        // An emissive surface that is not a light (an emissive sphere) is sampled by nothing
        // else, so the gather ray collects it.
        if (si.emissiveLight < 0 && si.material->isEmissive() && (si.doubleSided || dot(ray.d, si.ng) < 0))
            L += weight * si.material->emission(si.uv);
        ShadingPoint sp = makeShadingPoint(si, -ray.d);
        if (settings_.gatherDirectLight && sp.bsdf.hasNonDelta())
            L += weight * sampleDirectLight(scene, sp, sampler, stats, false);
        Color reflectance = sp.bsdf.diffuseReflectance();
        if (!isBlack(reflectance)) {
            PhotonLookup at = PhotonLookup::at(sp, scene);
            Photon nearest;
            Color E;
            if (maps_.irradiance.nearest(at, maps_.gatherRadius, &nearest)) {
                E = nearest.power;
            } else {
                // No precomputed photon near enough where photons are sparse (4 times sparser
                // than the global map's): the global map's own estimate, rather than darkness.
                E = maps_.global.irradiance(at, settings_.photons.gatherPhotons, maps_.gatherRadius).value;
                fallbackLookups_.fetch_add(1, std::memory_order_relaxed);
            }
            L += weight * reflectance * E * kInvPi;
            lookups_.fetch_add(1, std::memory_order_relaxed);
        }
        // Continue through one specular branch, picked in proportion to its weight.
        BsdfSample branches[3];
        int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
        if (n == 0 || depthLimitReached(vertex, settings_.finalGatherDepth, stats)) return L;
        if (!followDeltaBranch(sp, branches, n, sampler.get1D(), weight, ray)) return L;
    }
}

std::map<std::string, double> PhotonMapFinalGatherIntegrator::statistics() const {
    std::map<std::string, double> stats = maps_.statistics;
    stats["finalGatherRays"] = double(gatherRays_.load());
    stats["photonLookups"] = double(lookups_.load());
    stats["globalMapFallbackLookups"] = double(fallbackLookups_.load());
    return stats;
}

}  // namespace gi
