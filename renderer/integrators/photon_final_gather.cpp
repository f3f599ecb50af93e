#include "photon_final_gather.h"

#include "disc_area.h"
#include "path.h"
#include "specular_chain.h"
#include "../ray_cone.h"

namespace gi {

namespace {
constexpr float kBounceCausticShare = 0.25f;
}  // namespace

PhotonMapFinalGatherIntegrator::PhotonMapFinalGatherIntegrator(const PhotonFinalGatherSettings& settings)
    : DirectIntegrator(settings.rayDepth, settings.lightSamples), settings_(settings) {
    settings_.photons.globalKeepsDirectAndCaustic = true;
    settings_.photons.globalLeavesOutDirect = settings.gatherDirectLight;
    settings_.photons.precomputeIrradiance = true;
    settings_.photons.rayDepth = settings.rayDepth;
    settings_.photons.causticMapLeavesOutDomes = true;
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
        L += maps_.caustic.radiance(sp, scene, k, maps_.causticRadius, kCausticConeFilter).value;
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
        continueCone(ray, sp.si, bs);
        gathered += bs.weight * gatherRay(scene, ray, sampler, stats, 1);
    }
    gatherRays_.fetch_add(uint64_t(samples), std::memory_order_relaxed);
    return L + gathered / float(samples);
}

Color PhotonMapFinalGatherIntegrator::gatherRay(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats,
                                                int vertex) const {
    Color L(0.0f), weight(1.0f);
    int bounces = 0;  // path-traced vertices past the gather hit (gatherBounces of them, then the map)
    // An emitter this path reaches is its to count only when a path-traced vertex's non-specular
    // sample found it (MIS against that vertex's light sample); through specular surfaces, the
    // caustic map read at the vertex before them counts it. MIS needs that sample's pdf and point.
    // A dome this path reaches right after a specular bounce (through glass) is its to count
    // whatever came before: the caustic map leaves domes out.
    bool countsEmitters = false, afterSpecular = false;
    float prevPdf = 0;
    Vec3 prevPoint;
    for (;; ++vertex) {
        Intersection hit = intersectVisible(scene, ray, sampler, stats, false);
        if (afterSpecular && hit.kind == Intersection::Kind::None) return L + weight * domeRadiance(scene, ray);
        if (countsEmitters) {
            if (hit.kind == Intersection::Kind::None) return L + weight * escapedRadiance(scene, ray, prevPdf, false, false);
            L += weight * emittedOnHit(scene, hit, ray, prevPoint, prevPdf, false);
        }
        if (hit.kind != Intersection::Kind::Surface) return L;  // lights: direct light or caustics
        const SurfaceInteraction& si = hit.si;
        // An emissive surface that is not a light (an emissive sphere) is sampled by nothing
        // else, so the gather ray collects it.
        if (!countsEmitters && si.emissiveLight < 0 && si.material->isEmissive() &&
            (si.doubleSided || dot(ray.d, si.ng) < 0))
            L += weight * si.material->emission(si.uv);
        ShadingPoint sp = makeShadingPoint(si, -ray.d);
        if (bounces < settings_.gatherBounces) {
            // A path-traced bounce: light-sampled with MIS, the BSDF choosing the way on.
            ++bounces;
            if (sp.bsdf.hasNonDelta()) {
                L += weight * sampleDirectLight(scene, sp, sampler, stats, true);
                // Light focused here through glass or off a mirror (L S+ D), which neither light
                // sampling nor the BSDF's way on can find: the caustic map's, as at the shading point.
                // Read by one gather ray in kBounceCausticShare, weighted by its inverse (the same
                // mean): a pixel's gather rays average it, and each read is a k-nearest search
                // that cost more than the rest of the bounce (Cornell box: 2.0 of 3.7 s).
                if (!maps_.caustic.empty() && sampler.get1D() < kBounceCausticShare) {
                    L += weight * maps_.caustic.radiance(sp, scene, settings_.photons.gatherPhotons, maps_.causticRadius,
                                                         kCausticConeFilter).value / kBounceCausticShare;
                    lookups_.fetch_add(1, std::memory_order_relaxed);
                }
            }
            if (depthLimitReached(vertex, settings_.finalGatherDepth, stats)) return L;
            float uLobe = sampler.get1D();
            BsdfSample bs = sp.bsdf.sample(sp.woLocal, uLobe, sampler.get2D());
            if (!bs.valid) return L;
            weight *= bs.weight;
            if (!isFinite(weight) || isBlack(weight)) return L;
            countsEmitters = !bs.delta;
            afterSpecular = bs.delta;
            prevPdf = bs.pdf, prevPoint = sp.si.p;
            ray = spawnRay(sp.si, sp.frame.toWorld(bs.wi));
            continueCone(ray, sp.si, bs);
            continue;
        }
        if (settings_.gatherDirectLight && sp.bsdf.hasNonDelta())
            L += weight * sampleDirectLight(scene, sp, sampler, stats, false);
        // The map's irradiance is reflected by the Lambertian lobe; a glossy lobe's share (a
        // near-mirror's, nearly all of it) is traced on below. Without the shadow ray the map
        // holds the direct light too, which the traced lobe would miss: the thesis's set-up reads
        // the Lambertian reflectance alone, as it did.
        const bool traceGlossy = settings_.gatherDirectLight && sp.bsdf.hasGlossy();
        Color reflectance = traceGlossy ? sp.bsdf.diffuseLobe(sp.woLocal) * kPi : sp.bsdf.diffuseReflectance();
        if (!isBlack(reflectance)) {
            PhotonLookup at = PhotonLookup::at(sp, scene);
            Photon nearest;
            Color E;
            if (maps_.irradiance.nearest(at, maps_.gatherRadius, &nearest)) {
                E = nearest.power;
            } else {
                // No precomputed photon near enough where photons are sparse (4 times sparser
                // than the global map's): the global map's own estimate, rather than darkness.
                int k = settings_.photons.gatherPhotons;
                E = overSurfaceInDisc(maps_.global.irradiance(at, k, maps_.gatherRadius), k, at, sampler, stats);
                fallbackLookups_.fetch_add(1, std::memory_order_relaxed);
            }
            L += weight * reflectance * E * kInvPi;
            lookups_.fetch_add(1, std::memory_order_relaxed);
        }
        // Continue through one specular branch, picked in proportion to its weight.
        BsdfSample branches[3];
        int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
        if (n == 0 && traceGlossy) {
            // The glossy lobes' light from other surfaces, as DirectIntegrator::glossyIndirect
            // traces it; its next hit reads the map in turn. Emitters it reaches were the shadow
            // ray's (through specular surfaces: the map's caustics).
            if (depthLimitReached(vertex, settings_.finalGatherDepth, stats)) return L;
            float uLobe = sampler.get1D();
            Vec2 u = sampler.get2D();
            float uSurvive = sampler.get1D();
            Vec3 wi;
            Color w;
            if (!sampleGlossyBranch(sp, uLobe, u, uSurvive, &wi, &w)) return L;
            weight *= w;
            countsEmitters = false;
            afterSpecular = false;
            ray = spawnRay(sp.si, wi);
            continue;
        }
        if (n == 0 || depthLimitReached(vertex, settings_.finalGatherDepth, stats)) return L;
        if (!followDeltaBranch(sp, branches, n, sampler.get1D(), weight, ray)) return L;
        countsEmitters = false;
        afterSpecular = true;
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
