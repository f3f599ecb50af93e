// GGX (Trowbridge-Reitz) microfacet distribution with Smith masking and visible-normal
// sampling (Heitz 2018), and the exact dielectric Fresnel term. Local frame: normal = +z.
#pragma once
#include "math.h"

namespace gi {

inline float cosTheta(const Vec3& w) { return w.z; }
inline float absCosTheta(const Vec3& w) { return std::fabs(w.z); }
inline bool sameHemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + n * (2 * dot(wo, n)); }

// Refracts wi about n (in the same hemisphere as wi); eta = eta_transmitted / eta_incident
// relative to n's side. Returns false on total internal reflection.
inline bool refract(const Vec3& wi, Vec3 n, float eta, float* etap, Vec3* wt) {
    float cosi = dot(n, wi);
    if (cosi < 0) {
        eta = 1 / eta;
        cosi = -cosi;
        n = -n;
    }
    float sin2i = std::max(0.0f, 1 - cosi * cosi);
    float sin2t = sin2i / (eta * eta);
    if (sin2t >= 1) return false;
    float cost = safeSqrt(1 - sin2t);
    *wt = -wi / eta + n * (cosi / eta - cost);
    if (etap) *etap = eta;
    return true;
}

// Unpolarised Fresnel reflectance of a dielectric interface; cosi < 0 means from inside.
inline float fresnelDielectric(float cosi, float eta) {
    cosi = std::clamp(cosi, -1.0f, 1.0f);
    if (cosi < 0) {
        eta = 1 / eta;
        cosi = -cosi;
    }
    float sin2t = (1 - cosi * cosi) / (eta * eta);
    if (sin2t >= 1) return 1;
    float cost = safeSqrt(1 - sin2t);
    float rParallel = (eta * cosi - cost) / (eta * cosi + cost);
    float rPerpendicular = (cosi - eta * cost) / (cosi + eta * cost);
    return (rParallel * rParallel + rPerpendicular * rPerpendicular) / 2;
}

inline Color fresnelSchlick(const Color& f0, float f90, float cosTheta) {
    float m = clamp01(1 - cosTheta);
    float m5 = (m * m) * (m * m) * m;
    return f0 + (Color(f90) - f0) * m5;
}

class GGX {
public:
    // Below this alpha the surface is treated as perfectly smooth (a delta lobe).
    static constexpr float kSmoothAlpha = 1e-3f;
    explicit GGX(float alpha) : alpha_(std::max(alpha, 1e-4f)) {}
    float alpha() const { return alpha_; }
    bool smooth() const { return alpha_ < kSmoothAlpha; }

    float D(const Vec3& wm) const {
        float c2 = wm.z * wm.z;
        if (c2 <= 0) return 0;
        float a2 = alpha_ * alpha_;
        float d = c2 * (a2 - 1) + 1;
        return a2 / (kPi * d * d);
    }
    float lambda(const Vec3& w) const {
        float c2 = w.z * w.z;
        if (c2 <= 0) return 1e8f;  // exactly grazing: fully masked
        float tan2 = std::max(0.0f, 1 - c2) / c2;
        return (std::sqrt(1 + alpha_ * alpha_ * tan2) - 1) / 2;
    }
    float G1(const Vec3& w) const { return 1 / (1 + lambda(w)); }
    float G(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }
    // |cos theta| * lambda(w), without the division by cos theta: alpha/2 at exactly grazing
    // instead of a capped 1e8 * an underflowed cosine (no cancellation either when alpha is small).
    float cosLambda(const Vec3& w) const {
        float c = absCosTheta(w), s2 = std::max(0.0f, 1 - c * c), a2s2 = alpha_ * alpha_ * s2;
        return a2s2 / (2 * (std::sqrt(c * c + a2s2) + c));
    }
    // G(wo, wi) / (|cos wo| |cos wi|), the factor of every microfacet BSDF: finite as either
    // cosine goes to 0 (denormal directions made f = G / (4 cos cos) an Inf before).
    float GOverCosines(const Vec3& wo, const Vec3& wi) const {
        float co = absCosTheta(wo), ci = absCosTheta(wi);
        float d = co * ci + ci * cosLambda(wo) + co * cosLambda(wi);
        // f itself is unbounded when both directions graze (f cos is not): capped so that f stays
        // a finite float even for denormal cosines.
        return d > 0 ? std::min(1 / d, 1e20f) : 0;
    }
    // Density of visible normals for direction wo: G1(wo) / cos * D * |wo.wm|, stably.
    float visibleD(const Vec3& wo, const Vec3& wm) const {
        float d = absCosTheta(wo) + cosLambda(wo);
        return absCosTheta(wo) > 0 && d > 0 ? D(wm) * absDot(wo, wm) / d : 0;
    }
    float pdf(const Vec3& wo, const Vec3& wm) const { return visibleD(wo, wm); }

    Vec3 sampleVisibleNormal(Vec3 wo, Vec2 u) const {
        bool flip = wo.z < 0;
        if (flip) wo = -wo;
        Vec3 wh = normalize(Vec3(alpha_ * wo.x, alpha_ * wo.y, wo.z));
        Vec3 t1 = wh.z < 0.99999f ? normalize(cross(Vec3(0, 0, 1), wh)) : Vec3(1, 0, 0);
        Vec3 t2 = cross(wh, t1);
        float r = std::sqrt(u.x), phi = 2 * kPi * u.y;
        float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
        float s = 0.5f * (1 + wh.z);
        p2 = (1 - s) * safeSqrt(1 - p1 * p1) + s * p2;
        Vec3 nh = t1 * p1 + t2 * p2 + wh * safeSqrt(1 - p1 * p1 - p2 * p2);
        Vec3 wm = normalize(Vec3(alpha_ * nh.x, alpha_ * nh.y, std::max(1e-6f, nh.z)));
        return flip ? -wm : wm;
    }

private:
    float alpha_;
};

}  // namespace gi
