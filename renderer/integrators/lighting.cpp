#include "lighting.h"

namespace gi {

ShadingPoint makeShadingPoint(const SurfaceInteraction& si, const Vec3& wo) {
    ShadingPoint sp;
    makeShadingPoint(si, wo, sp);
    return sp;
}

void makeShadingPoint(const SurfaceInteraction& si, const Vec3& wo, ShadingPoint& sp) {
    sp.si = si;
    sp.wo = wo;
    sp.bsdf = si.material->bsdf(si.uv, si.uvFootprint);
    if (!sp.bsdf.transmits() && dot(wo, si.ng) < 0) {
        // Opaque surfaces reflect on the side the ray arrived from.
        sp.si.ng = -si.ng;
        sp.si.ns = -si.ns;
    }
    Vec3 n = sp.si.ns;
    // An interpolated normal can face away from a view the geometry faces: use the true normal.
    if (!sp.bsdf.transmits() && dot(wo, n) <= 0) n = sp.si.ng;
    sp.frame = Frame(n);
    sp.woLocal = sp.frame.toLocal(wo);
}

Color sampleDirectLight(const Scene& scene, const ShadingPoint& sp, Sampler& sampler, RayStats& stats, bool mis) {
    Vec2 uLight = sampler.get2D();
    float uSelect = sampler.get1D();
    return sampleDirectLight(scene, sp, uLight, uSelect, stats, mis);
}

Color sampleDirectLight(const Scene& scene, const ShadingPoint& sp, Vec2 uLight, float uSelect, RayStats& stats,
                        bool mis) {
    return resolveDirectLight(scene, sp, prepareDirectLight(scene, sp, uLight, uSelect, mis), stats);
}

DirectLightSample prepareDirectLight(const Scene& scene, const ShadingPoint& sp, Vec2 uLight, float uSelect, bool mis) {
    DirectLightSample d;  // f black: nothing to test
    if (scene.lights().empty() || !sp.bsdf.hasNonDelta()) return d;
    int index = scene.lightSampler().sample(sp.si.p, uSelect, &d.pmf);
    if (index < 0) return d;  // no light can reach this point
    const Light& light = *scene.lights()[index];
    d.light = light.sample(sp.si.p, uLight, sp.si.time);  // where it is at the path's time
    if (!(d.light.pdf > 0) || isBlack(d.light.Li)) return d;
    d.wiLocal = sp.frame.toLocal(d.light.wi);
    d.f = sp.bsdf.eval(sp.woLocal, d.wiLocal) * absCosTheta(d.wiLocal);
    d.mis = mis;
    return d;
}

Color resolveDirectLight(const Scene& scene, const ShadingPoint& sp, const DirectLightSample& d, RayStats& stats) {
    if (isBlack(d.f)) return Color(0.0f);
    const LightSample& ls = d.light;
    if (!scene.visible(sp.si, ls.wi, ls.distance, stats)) return Color(0.0f);
    if (ls.delta) return d.f * ls.Li / d.pmf;
    float lightPdf = d.pmf * ls.pdf;
    float weight = d.mis ? powerHeuristic(lightPdf, sp.bsdf.pdf(sp.woLocal, d.wiLocal)) : 1.0f;
    return d.f * ls.Li * (weight / lightPdf);
}

Color emittedOnHit(const Scene& scene, const Intersection& hit, const Ray& ray, const Vec3& prevPoint,
                   float prevPdf, bool prevDelta) {
    if (hit.kind == Intersection::Kind::Light) {
        const Light& light = *scene.lights()[hit.light];
        Color Le = light.radiance(ray.d, ray.time);
        if (prevDelta || isBlack(Le)) return Le;
        float lightPdf = scene.lightPmf(prevPoint, hit.light) * light.pdf(prevPoint, ray.d, hit.t, ray.time);
        return Le * powerHeuristic(prevPdf, lightPdf);
    }
    const SurfaceInteraction& si = hit.si;
    if (!si.material->isEmissive()) return Color(0.0f);
    if (!si.doubleSided && dot(ray.d, si.ng) > 0) return Color(0.0f);  // back of a one-sided emitter
    Color Le = si.material->emission(si.uv);
    if (prevDelta || si.emissiveLight < 0) return Le;
    float lightPdf = scene.lightPmf(prevPoint, si.emissiveLight) *
                     scene.lights()[si.emissiveLight]->pdf(prevPoint, ray.d, length(si.p - prevPoint), ray.time);
    return Le * powerHeuristic(prevPdf, lightPdf);
}

Color escapedRadiance(const Scene& scene, const Ray& ray, float prevPdf, bool prevDelta, bool cameraRay) {
    Color L(0.0f);
    for (int index : scene.infiniteLights()) {
        const Light& light = *scene.lights()[index];
        if (cameraRay && !light.visibleToCamera) continue;
        Color Le = light.radiance(ray.d, ray.time);
        if (isBlack(Le)) continue;
        if (prevDelta) {
            L += Le;
            continue;
        }
        float lightPdf = scene.lightPmf(ray.o, index) * light.pdf(ray.o, ray.d, kInf, ray.time);
        L += Le * powerHeuristic(prevPdf, lightPdf);
    }
    return L;
}

Color domeRadiance(const Scene& scene, const Ray& ray) {
    Color L(0.0f);
    for (int index : scene.infiniteLights())
        if (scene.lights()[size_t(index)]->isDome()) L += scene.lights()[size_t(index)]->radiance(ray.d, ray.time);
    return L;
}

void recordAovs(SampleAovs* aovs, const ShadingPoint& sp, float depth) {
    if (!aovs || aovs->hit) return;
    aovs->hit = true;
    aovs->depth = depth;
    aovs->normal = sp.si.ns;
    aovs->albedo = sp.bsdf.albedo();
    aovs->shapeId = int32_t(sp.si.shapeId);
    aovs->instanceId = sp.si.instanceId == 0xffffffffu ? -1 : int32_t(sp.si.instanceId);
}

}  // namespace gi
