#include "irradiance_record_sampler.h"

#include "record_outliers.h"

#include <bit>
#include <vector>

namespace gi {

HemisphereLayout HemisphereLayout::forPaths(int paths) {
    paths = std::max(1, paths);
    double ideal = std::sqrt(paths / double(kPi));
    int best = 0;
    double bestDistance = 0;
    for (int m = 1; m <= paths; ++m) {
        if (paths % m != 0 || m < ideal / 2 || m > ideal * 2) continue;
        double distance = std::fabs(std::log(m / ideal));
        if (best == 0 || distance < bestDistance) best = m, bestDistance = distance;
    }
    HemisphereLayout layout;
    if (best > 0) {
        layout.polar = best;
        layout.azimuthal = paths / best;
    } else {  // no divisor near the ideal proportion (e.g. a prime): about `paths` cells
        layout.polar = std::max(1, int(std::lround(ideal)));
        layout.azimuthal = std::max(1, int(std::lround(double(paths) / layout.polar)));
    }
    return layout;
}

IrradianceRecordSampler::IrradianceRecordSampler(const RecordSettings& settings)
    : settings_(settings),
      layout_(HemisphereLayout::forPaths(settings.paths)),
      // The continuation starts at the record path's second vertex, so it gets one vertex less.
      continuation_(1, continuationDepth(settings.pathDepth), settings.rayDepth, std::max(0, settings.rouletteDepth - 1)) {}

uint32_t IrradianceRecordSampler::streamKey(const RecordSite& site, uint32_t round) {
    uint32_t h = 0x1c0ffee5u;
    for (float v : {site.p.x, site.p.y, site.p.z, site.n.x, site.n.y, site.n.z}) h = hashCombine(h, std::bit_cast<uint32_t>(v));
    return round == 0 ? h : hashCombine(h, round);
}

Color IrradianceRecordSampler::bouncedRadiance(const Scene& scene, const SurfaceInteraction& origin, const Vec3& wi,
                                               Sampler& sampler, RayStats& stats, float* distance,
                                               Color* causticPart) const {
    Ray ray = spawnRay(origin, wi);
    Intersection hit = intersectVisible(scene, ray, sampler, stats, false);
    if (hit.kind == Intersection::Kind::None) {
        *distance = kInf;
        return Color(0.0f);  // infinite lights: direct light, sampled by the ray tracer
    }
    if (hit.kind == Intersection::Kind::Light) {
        *distance = hit.t;
        return Color(0.0f);  // a light's own surface: direct light as well
    }
    const SurfaceInteraction& si = hit.si;
    *distance = length(si.p - origin.p);
    Color L(0.0f);
    // An emissive surface the light sampler does not know (no light index) is not direct light
    // for the ray tracer, so the cache must gather it.
    if (si.emissiveLight < 0 && si.material->isEmissive() && (si.doubleSided || dot(wi, si.ng) < 0))
        L += si.material->emission(si.uv);
    // Everything that leaves the hit point by reflection: its direct light and further bounces.
    L += continuation_.continuePath(scene, makeShadingPoint(si, -wi), sampler, stats, caustics_.map ? &caustics_ : nullptr,
                                    causticPart);
    return L;
}

IrradianceRecord IrradianceRecordSampler::sample(const Scene& scene, const RecordSite& site, uint32_t seed,
                                                 uint32_t streamKey, RayStats& stats, uint32_t samplesBefore) const {
    const int M = layout_.polar, N = layout_.azimuthal, cells = M * N;
    Frame frame(site.n);
    SurfaceInteraction origin;
    origin.ng = site.ng;
    std::vector<Color> L(cells, Color(0.0f)), causticL(cells, Color(0.0f));
    std::vector<float> R(cells, kInf);
    Sampler sampler(seed);
    // Distances below this are treated as this: a hit at ~0 distance (a crease) must not
    // turn into an infinite gradient or a zero radius.
    const float rMinus = std::max(settings_.minSpacing * site.footprint, 1e-6f * (1 + length(site.p)));

    IrradianceRecord record;
    record.p = site.p;
    record.n = site.n;
    record.footprint = site.footprint;
    record.ng = site.ng;
    record.wo = site.wo;
    record.samples = uint32_t(cells);
    Color sum(0.0f);
    double inverseDistanceSum = 0;
    float minDistance = kInf;
    for (int j = 0; j < M; ++j)
        for (int k = 0; k < N; ++k) {
            int c = j * N + k;
            sampler.startStream(streamKey, uint32_t(c));
            Vec2 u = sampler.get2D();
            // Cosine-weighted within the cell: sin^2(theta) uniform over [j/M, (j+1)/M).
            float sin2 = (j + u.x) / M, sinTheta = std::sqrt(sin2), cosTheta = safeSqrt(1 - sin2);
            float phi = 2 * kPi * (k + u.y) / N;
            Vec3 wi = frame.toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
            float distance;
            origin.p = recordRayOrigin(site, wi);
            Color caustic(0.0f);
            Color Li = bouncedRadiance(scene, origin, wi, sampler, stats, &distance, &caustic);
            if (!isFinite(Li) || !isFinite(caustic)) Li = caustic = Color(0.0f);  // one broken path must not poison a region
            L[c] = vmax(Li - caustic, Color(0.0f));
            causticL[c] = vmax(caustic, Color(0.0f));
            if (std::isfinite(distance)) {
                R[c] = std::max(distance, rMinus);
                inverseDistanceSum += 1.0 / R[c];
                minDistance = std::min(minDistance, R[c]);
            }
        }
    outliersClamped_.fetch_add(uint64_t(clampRecordOutliers(L, causticL, samplesBefore + size_t(cells))),
                               std::memory_order_relaxed);
    for (const Color& l : L) sum += l;
    const float cellWeight = kPi / cells;  // cosine-weighted estimator: E = pi / (M N) sum L
    record.E = sum * cellWeight;
    record.harmonicMeanDistance = inverseDistanceSum > 0 ? float(cells / inverseDistanceSum) : kInf;
    record.minDistance = minDistance;

    // Rotation gradient (2.29), evaluated at cell centres so that tan(theta) stays bounded by
    // sqrt(2M - 1) however close to the horizon a sample fell.
    Vec3 rotation[3], translation[3];
    for (int k = 0; k < N; ++k) {
        float phiCentre = 2 * kPi * (k + 0.5f) / N;
        Vec3 v(-std::sin(phiCentre), std::cos(phiCentre), 0);  // direction phi_k + pi/2
        Color tanSum(0.0f);
        for (int j = 0; j < M; ++j) tanSum += L[j * N + k] * std::sqrt((j + 0.5f) / (M - j - 0.5f));
        for (int ch = 0; ch < 3; ++ch) rotation[ch] += v * (tanSum[ch] * cellWeight);
    }
    // Translation gradient (2.30): how the cell boundaries sweep over nearer or farther
    // surfaces as the point moves; the nearer of two neighbouring hits decides.
    for (int k = 0; k < N; ++k) {
        int previousK = (k + N - 1) % N;
        float phiCentre = 2 * kPi * (k + 0.5f) / N, phiBoundary = 2 * kPi * k / N;
        Vec3 u(std::cos(phiCentre), std::sin(phiCentre), 0);        // u_k
        Vec3 v(-std::sin(phiBoundary), std::cos(phiBoundary), 0);  // v_k-: direction phi_k- + pi/2
        Color polar(0.0f), azimuthal(0.0f);
        for (int j = 1; j < M; ++j) {
            float sinMinus = std::sqrt(float(j) / M), cos2Minus = 1 - float(j) / M;
            float r = std::min(R[j * N + k], R[(j - 1) * N + k]);
            if (std::isfinite(r)) polar += (L[j * N + k] - L[(j - 1) * N + k]) * (sinMinus * cos2Minus / r);
        }
        for (int j = 0; j < M; ++j) {
            float sinMinus = std::sqrt(float(j) / M), sinPlus = std::sqrt(float(j + 1) / M);
            float r = std::min(R[j * N + k], R[j * N + previousK]);
            if (std::isfinite(r)) azimuthal += (L[j * N + k] - L[j * N + previousK]) * ((sinPlus - sinMinus) / r);
        }
        for (int ch = 0; ch < 3; ++ch) translation[ch] += u * (2 * kPi / N * polar[ch]) + v * azimuthal[ch];
    }
    for (int ch = 0; ch < 3; ++ch) {
        record.rotationGradient[ch] = frame.toWorld(rotation[ch]);
        record.translationGradient[ch] = frame.toWorld(translation[ch]);
    }

    // Validity radius: 2.33's max(min(R_i / 2, R+), R-) / k, with R_i the nearest hit, R+- = k
    // times the spacing limits in pixels (so the radius lies between those spacings whatever
    // k is), and Krivanek's gradient limit: no farther than the translation gradient takes
    // Y(E) to zero.
    const float rPlus = std::max(settings_.maxSpacing, settings_.minSpacing) * site.footprint;
    float radius = 0.5f * minDistance / settings_.accuracy;
    Vec3 luminanceGradient = translation[0] * 0.2126f + translation[1] * 0.7152f + translation[2] * 0.0722f;
    float gradientLength = length(luminanceGradient);
    if (gradientLength > 0) radius = std::min(radius, luminance(record.E) / gradientLength);
    if (!std::isfinite(radius)) radius = rPlus;
    record.radius = std::max(std::min(radius, rPlus), rMinus);

    // sigma of the stratified estimate, from differences of azimuthal neighbours (each
    // difference^2 / 2 estimates a cell's variance); unstratified when there is one column.
    double variance = 0;
    if (N > 1) {
        for (int j = 0; j < M; ++j)
            for (int k = 0; k < N; ++k) {
                double d = luminance(L[j * N + k]) - luminance(L[j * N + (k + 1) % N]);
                variance += 0.5 * d * d;
            }
    } else if (cells > 1) {
        double mean = luminance(sum) / cells, squares = 0;
        for (const Color& l : L) squares += (luminance(l) - mean) * (luminance(l) - mean);
        variance = squares * cells / (cells - 1);
    }
    record.sigma = cellWeight * float(std::sqrt(variance));
    return record;
}

}  // namespace gi
