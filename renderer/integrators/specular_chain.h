// The shading points at which the ray tracer (DirectIntegrator) asks for indirect light: the
// first non-specular hit of a camera ray and of every specular branch below it, up to
// rayDepth. The cache passes visit exactly these, so the render finds records where it looks.
#pragma once
#include "lighting.h"
#include "path.h"

#include <algorithm>

namespace gi {

// Specular branches are all followed (Whitted's ray tracer) for the first kSplitDepth specular
// vertices; deeper, one branch is followed, picked in proportion to its weight, so a path
// through many glass surfaces costs one ray per vertex instead of 2^depth.
inline constexpr int kSplitDepth = 5;

// Picks one of n delta branches with probability max(w_i) / max(1, sum_j max(w_j)): when the
// weights sum below 1 the path may end instead (Russian roulette). Returns the branch, or -1
// when the path ends, and its weight divided by the probability of picking it.
inline int pickDeltaBranch(const BsdfSample* branches, int n, float u, Color* weight) {
    float total = 0;
    for (int i = 0; i < n; ++i) total += maxComponent(branches[i].weight);
    if (!(total > 0)) return -1;
    float scale = std::max(1.0f, total);
    u *= scale;
    for (int i = 0; i < n; ++i) {
        float w = maxComponent(branches[i].weight);
        if (u < w || (i == n - 1 && total >= 1)) {
            *weight = branches[i].weight * (scale / w);
            return i;
        }
        u -= w;
    }
    return -1;
}

// Continues a path through one of sp's n delta branches, picked by pickDeltaBranch: multiplies
// `weight` by its weight over its probability and points `ray` along it. False when the path ends
// there (roulette, or a weight that is no longer finite and positive).
inline bool followDeltaBranch(const ShadingPoint& sp, const BsdfSample* branches, int n, float u, Color& weight,
                              Ray& ray) {
    Color picked;
    int pick = pickDeltaBranch(branches, n, u, &picked);
    if (pick < 0) return false;
    weight *= picked;
    if (!isFinite(weight) || isBlack(weight)) return false;
    ray = spawnRay(sp.si, sp.frame.toWorld(branches[pick].wi));
    return true;
}

// Calls visit(shadingPoint) for each such point, in a fixed (depth-first, branch) order.
template <class Visit>
void forEachDiffuseHit(const Scene& scene, Ray ray, Sampler& sampler, RayStats& stats, int rayDepth,
                       Visit&& visit, int specularDepth = 0) {
    for (;; ++specularDepth) {
        Intersection hit = intersectVisible(scene, ray, sampler, stats, specularDepth == 0);
        if (hit.kind != Intersection::Kind::Surface) return;
        ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
        if (sp.bsdf.hasNonDelta()) visit(sp);
        BsdfSample branches[3];
        int n = sp.bsdf.deltaBranches(sp.woLocal, branches);
        if (n == 0 || depthLimitReached(specularDepth, rayDepth, stats)) return;
        if (specularDepth < kSplitDepth) {
            for (int i = 0; i < n; ++i)
                forEachDiffuseHit(scene, spawnRay(sp.si, sp.frame.toWorld(branches[i].wi)), sampler, stats, rayDepth,
                                  visit, specularDepth + 1);
            return;
        }
        Color weight(1.0f);
        if (!followDeltaBranch(sp, branches, n, sampler.get1D(), weight, ray)) return;
    }
}

// The normal of the hemisphere a record at sp integrates over: the shading normal, on the side
// the ray arrived from (makeShadingPoint leaves transmissive surfaces unflipped).
inline Vec3 recordNormal(const ShadingPoint& sp) { return dot(sp.frame.n, sp.wo) < 0 ? -sp.frame.n : sp.frame.n; }

}  // namespace gi
