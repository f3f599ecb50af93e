// Unidirectional path tracing with next-event estimation, multiple importance sampling
// (power heuristic) and Russian roulette (thesis 2.4.4). `paths` independent paths continue
// from each camera sample's first hit; `pathDepth` bounds the scattering vertices of a path
// and `rayDepth` its specular (delta) vertices.
#include "path.h"

#include "lighting.h"
#include "photon_map.h"
#include "../ray_cone.h"

namespace gi {

PathIntegrator::PathIntegrator(int paths, int pathDepth, int rayDepth, int rouletteDepth)
    : paths_(std::max(1, paths)), pathDepth_(pathDepth), rayDepth_(rayDepth), rouletteDepth_(rouletteDepth) {}

Intersection intersectVisible(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats, bool cameraRay) {
    return intersectVisible(scene, ray, scene.trace(ray, stats, cameraRay), sampler, stats, cameraRay);
}

Intersection intersectVisible(const Scene& scene, Ray ray, const Scene::PendingHit& first, Sampler& sampler,
                              RayStats& stats, bool cameraRay) {
    Intersection hit = scene.finish(ray, first);
    // Stochastic presence ("presence" opacity, cut-outs): pass through with probability 1 - opacity.
    for (int layers = 0; layers < 64; ++layers) {
        if (layers > 0) hit = scene.intersect(ray, stats, cameraRay);
        if (hit.kind != Intersection::Kind::Surface || !hit.si.material->hasPresence()) return hit;
        float presence = hit.si.material->presence(hit.si.uv);
        if (presence >= 1 || sampler.get1D() < presence) return hit;
        ray.o = offsetRayOrigin(hit.si.p, hit.si.ng, ray.d);
        if (std::isfinite(ray.tMax)) ray.tMax -= hit.t;
    }
    return Intersection();
}

Color PathIntegrator::Li(const Ray& ray, const Scene& scene, Sampler& sampler, RayStats& stats,
                         SampleAovs* aovs) const {
    Intersection hit = intersectVisible(scene, ray, sampler, stats, true);
    if (hit.kind == Intersection::Kind::None) return escapedRadiance(scene, ray, 0, true, true);
    Color L = emittedOnHit(scene, hit, ray, ray.o, 0, true);
    if (hit.kind == Intersection::Kind::Light) return L;
    ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
    recordAovs(aovs, sp, hit.t);
    if (pathDepth_ <= 0) return L;
    Color sum(0.0f);
    for (int i = 0; i < paths_; ++i) sum += continuePath(scene, sp, sampler, stats);
    return L + sum / float(paths_);
}

Color PathIntegrator::continuePath(const Scene& scene, ShadingPoint sp, Sampler& sampler, RayStats& stats,
                                   const CausticPhotons* caustics, Color* causticPart) const {
    Color L(0.0f), beta(1.0f);
    int vertices = 1, specularVertices = 0;
    for (;;) {
        // Four sample pairs per vertex: the light point, (light choice, BSDF lobe), the BSDF
        // direction and Russian roulette.
        Vec2 uLight = sampler.get2D(), uChoice = sampler.get2D();
        const bool readsCaustics = caustics && sp.bsdf.hasNonDelta() && sampler.get1D() < caustics->readShare;
        BsdfSample bs = sp.bsdf.sample(sp.woLocal, uChoice.y, sampler.get2D());
        // The vertex's light sample and caustic read, added before what the next hit emits (the
        // sums' order kept): the shadow ray is traced after the next ray, while the next hit's
        // triangle data is on its way from memory (Scene::trace).
        const Color vertexBeta = beta;
        auto addVertexLight = [&](const DirectLightSample& direct) {
            L += vertexBeta * resolveDirectLight(scene, sp, direct, stats);
            if (!readsCaustics) return;
            Color caustic = vertexBeta *
                            caustics->map->radiance(sp, scene, caustics->photons, caustics->maxRadius, caustics->coneFilter)
                                .value /
                            caustics->readShare;
            L += caustic;
            if (causticPart) *causticPart += caustic;
        };
        bool goesOn = bs.valid && !(bs.delta && depthLimitReached(specularVertices++, rayDepth_, stats));
        if (goesOn) {
            beta *= bs.weight;
            goesOn = isFinite(beta) && !isBlack(beta);
        }
        if (!goesOn) {
            addVertexLight(prepareDirectLight(scene, sp, uLight, uChoice.x, true));
            break;
        }
        // Every vertex before a specular bounce read the caustic map, so a light found through
        // it is a caustic already counted there (a dome is not in the map).
        const bool lightsAreCaustics = caustics && bs.delta;
        Vec3 wi = sp.frame.toWorld(bs.wi);
        Ray next = spawnRay(sp.si, wi);
        continueCone(next, sp.si, bs);
        Scene::PendingHit pending = scene.trace(next, stats, false);
        DirectLightSample direct = prepareDirectLight(scene, sp, uLight, uChoice.x, true);
        scene.prefetchSurface(pending);  // the indices have had the light sample's time to arrive
        addVertexLight(direct);
        Intersection hit = intersectVisible(scene, next, pending, sampler, stats, false);
        if (hit.kind == Intersection::Kind::None) {
            L += beta * (lightsAreCaustics ? domeRadiance(scene, next) : escapedRadiance(scene, next, bs.pdf, bs.delta, false));
            break;
        }
        // An emissive surface that is no light emits no photons: always counted.
        if (!lightsAreCaustics || (hit.kind == Intersection::Kind::Surface && hit.si.emissiveLight < 0))
            L += beta * emittedOnHit(scene, hit, next, sp.si.p, bs.pdf, bs.delta);
        if (hit.kind == Intersection::Kind::Light || depthLimitReached(vertices, pathDepth_, stats)) break;
        ++vertices;
        makeShadingPoint(hit.si, -wi, sp);
        if (vertices > rouletteDepth_) {
            float q = std::max(0.05f, 1 - maxComponent(beta));
            if (sampler.get1D() < q) break;
            beta = beta / (1 - q);
        }
    }
    return L;
}

}  // namespace gi
