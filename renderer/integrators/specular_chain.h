// The shading points at which the ray tracer (DirectIntegrator) asks for indirect light: the
// first non-specular hit of a camera ray and of every specular branch below it, up to
// rayDepth. The cache passes visit exactly these, so the render finds records where it looks.
#pragma once
#include "lighting.h"
#include "path.h"

namespace gi {

// Calls visit(shadingPoint) for each such point, in a fixed (depth-first, branch) order.
template <class Visit>
void forEachDiffuseHit(const Scene& scene, const Ray& ray, Sampler& sampler, RayStats& stats, int rayDepth,
                       Visit&& visit, int specularDepth = 0) {
    Intersection hit = intersectVisible(scene, ray, sampler, stats, specularDepth == 0);
    if (hit.kind != Intersection::Kind::Surface) return;
    ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
    if (sp.bsdf.hasNonDelta()) visit(sp);
    if (specularDepth >= rayDepth) return;
    BsdfSample branches[3];
    int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
    for (int i = 0; i < n; ++i)
        forEachDiffuseHit(scene, spawnRay(sp.si, sp.frame.toWorld(branches[i].wi)), sampler, stats, rayDepth, visit,
                          specularDepth + 1);
}

// The normal of the hemisphere a record at sp integrates over: the shading normal, on the side
// the ray arrived from (makeShadingPoint leaves transmissive surfaces unflipped).
inline Vec3 recordNormal(const ShadingPoint& sp) { return dot(sp.frame.n, sp.wo) < 0 ? -sp.frame.n : sp.frame.n; }

}  // namespace gi
