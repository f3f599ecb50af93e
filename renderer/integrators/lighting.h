// Shared light-transport pieces: next-event estimation with MIS, emission picked up by a
// BSDF-sampled ray, shading frames and first-hit AOVs.
#pragma once
#include "../integrator.h"

namespace gi {

// A shading point ready for BSDF queries: local frame around the shading normal, flipped to
// the side the ray came from for two-sided opaque surfaces.
struct ShadingPoint {
    SurfaceInteraction si;
    Bsdf bsdf;
    Frame frame;
    Vec3 wo;       // world, towards the previous vertex
    Vec3 woLocal;  // in `frame`
};

ShadingPoint makeShadingPoint(const SurfaceInteraction& si, const Vec3& wo);
// The same into `sp`, every field overwritten: a path's loop reuses its point, where a returned
// copy, read back in wide moves from the narrower stores just made, stalls on store forwarding.
void makeShadingPoint(const SurfaceInteraction& si, const Vec3& wo, ShadingPoint& sp);

// Direct light at a shading point from one light chosen by power, MIS-weighted against BSDF
// sampling when `mis` is set (pure light sampling otherwise).
Color sampleDirectLight(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats, bool mis);
// The same with the caller's samples: uLight picks the point on the light, uSelect the light.
Color sampleDirectLight(const Scene& scene, const ShadingPoint& sp, Vec2 uLight, float uSelect, RayStats& stats,
                        bool mis);

// sampleDirectLight in two halves, so that a path can trace its next ray between them while the
// shadow ray waits: the light sample and the BSDF's value, then the shadow ray and the weight.
struct DirectLightSample {
    LightSample light;
    Color f;              // BSDF value times the cosine; black: nothing to test
    Vec3 wiLocal;
    float pmf = 0;
    bool mis = false;
};
DirectLightSample prepareDirectLight(const Scene& scene, const ShadingPoint& sp, Vec2 uLight, float uSelect, bool mis);
Color resolveDirectLight(const Scene& scene, const ShadingPoint& sp, const DirectLightSample& sample, RayStats& stats);

// Radiance from an emitter reached by a BSDF-sampled ray, MIS-weighted against light sampling.
// prevPdf: BSDF pdf of the sampled direction; prevDelta: it came from a delta lobe (no MIS).
Color emittedOnHit(const Scene& scene, const Intersection& hit, const Ray& ray, const Vec3& prevPoint,
                   float prevPdf, bool prevDelta);
// Radiance of infinite lights along an escaping ray, MIS-weighted likewise.
Color escapedRadiance(const Scene& scene, const Ray& ray, float prevPdf, bool prevDelta, bool cameraRay);
// What the dome lights (Light::isDome) send along a ray that leaves the scene.
Color domeRadiance(const Scene& scene, const Ray& ray);

void recordAovs(SampleAovs* aovs, const ShadingPoint& sp, float depth);

// Spawns a ray leaving a surface in direction d.
inline Ray spawnRay(const SurfaceInteraction& si, const Vec3& d) {
    Ray r;
    r.o = offsetRayOrigin(si.p, si.ng, d);
    r.d = d;
    r.tMin = 0;
    r.tMax = kInf;
    r.time = si.time;  // a path (and each of its shadow rays) sees the scene at one instant
    return r;
}

}  // namespace gi
