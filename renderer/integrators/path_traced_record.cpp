#include "path_traced_record.h"

#include "record_outliers.h"

namespace gi {

PathTracedRecordSampler::PathTracedRecordSampler(const RecordSettings& settings, const CausticPhotons& caustics)
    : settings_(settings),
      layout_(HemisphereLayout::forPaths(settings.paths)),
      // The continuation starts at the record path's second vertex, so it gets one vertex less.
      continuation_(1, continuationDepth(settings.pathDepth), settings.rayDepth, std::max(0, settings.rouletteDepth - 1)),
      caustics_(caustics) {}

Color PathTracedRecordSampler::bouncedRadiance(const Scene& scene, const SurfaceInteraction& origin, const Vec3& wi,
                                               Sampler& sampler, RayStats& stats, float* distance,
                                               Color* causticPart) const {
    Ray ray = spawnRay(origin, wi);
    Color weight(1.0f);
    *distance = kInf;
    for (int specularVertices = 0;; ++specularVertices) {
        Intersection hit = intersectVisible(scene, ray, sampler, stats, false);
        if (specularVertices == 0 && hit.kind != Intersection::Kind::None) *distance = hit.t;
        // A light reached directly is direct light (light sampling), through specular
        // surfaces a caustic (the caustic map), but for the sky: the map leaves domes out.
        if (hit.kind == Intersection::Kind::None && specularVertices > 0) return weight * domeRadiance(scene, ray);
        if (hit.kind != Intersection::Kind::Surface) return Color(0.0f);
        const SurfaceInteraction& si = hit.si;
        Color L(0.0f);
        // An emissive surface that is not a light is sampled by nothing else.
        if (si.emissiveLight < 0 && si.material->isEmissive() && (si.doubleSided || dot(ray.d, si.ng) < 0))
            L += si.material->emission(si.uv);
        ShadingPoint sp = makeShadingPoint(si, -ray.d);
        if (sp.bsdf.hasNonDelta() || !caustics_.map) {
            Color caustic(0.0f);
            L += continuation_.continuePath(scene, sp, sampler, stats, caustics_.map ? &caustics_ : nullptr, &caustic);
            *causticPart += weight * caustic;
            return weight * L;
        }
        // A purely specular surface: follow one branch, picked by its weight, and see whether
        // the path finds a non-specular surface before it finds light.
        if (depthLimitReached(specularVertices, settings_.rayDepth, stats)) return weight * L;
        float uLobe = sampler.get1D();
        BsdfSample bs = sp.bsdf.sample(sp.woLocal, uLobe, sampler.get2D());
        if (!bs.valid) return weight * L;
        weight *= bs.weight;
        if (!isFinite(weight) || isBlack(weight)) return Color(0.0f);
        ray = spawnRay(sp.si, sp.frame.toWorld(bs.wi));
    }
}

IrradianceRecord PathTracedRecordSampler::sample(const Scene& scene, const RecordSite& site, uint32_t seed,
                                                 uint32_t streamKey, RayStats& stats, uint32_t samplesBefore) const {
    const int M = layout_.polar, N = layout_.azimuthal;
    Frame frame(site.n);
    SurfaceInteraction origin;
    origin.ng = site.ng;
    const float rMinus = std::max(settings_.minSpacing * site.footprint, 1e-6f * (1 + length(site.p)));
    const float rPlus = std::max(settings_.maxSpacing, settings_.minSpacing) * site.footprint;
    Sampler sampler(seed);
    std::vector<Color> samples(size_t(M * N), Color(0.0f)), fromCausticMap(samples.size(), Color(0.0f));
    float minDistance = kInf;
    for (int j = 0; j < M; ++j)
        for (int k = 0; k < N; ++k) {
            sampler.startStream(streamKey, uint32_t(j * N + k));
            Vec2 u = sampler.get2D();
            // Cosine-weighted within the cell: sin^2(theta) uniform over [j/M, (j+1)/M).
            float sin2 = (j + u.x) / M, sinTheta = std::sqrt(sin2), cosTheta = safeSqrt(1 - sin2);
            float phi = 2 * kPi * (k + u.y) / N;
            Vec3 wi = frame.toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
            float distance;
            origin.p = recordRayOrigin(site, wi);
            Color caustic(0.0f);
            Color L = bouncedRadiance(scene, origin, wi, sampler, stats, &distance, &caustic);
            if (isFinite(L) && isFinite(caustic)) {  // one broken path must not poison a region
                samples[size_t(j * N + k)] = vmax(L - caustic, Color(0.0f));
                fromCausticMap[size_t(j * N + k)] = vmax(caustic, Color(0.0f));
            }
            minDistance = std::min(minDistance, std::max(distance, rMinus));
        }
    outliersClamped_.fetch_add(uint64_t(clampRecordOutliers(samples, fromCausticMap, samplesBefore + samples.size())), std::memory_order_relaxed);
    Color sum(0.0f);
    for (const Color& l : samples) sum += l;
    IrradianceRecord record;
    record.p = site.p;
    record.n = site.n;
    record.footprint = site.footprint;
    record.ng = site.ng;
    record.wo = site.wo;
    record.samples = uint32_t(M * N);
    record.E = sum * (kPi / float(M * N));  // cosine-weighted estimator
    record.minDistance = minDistance;
    float radius = 0.5f * minDistance / settings_.accuracy;
    record.radius = std::isfinite(radius) ? std::clamp(radius, rMinus, std::max(rMinus, rPlus)) : std::max(rMinus, rPlus);
    return record;
}

}  // namespace gi
