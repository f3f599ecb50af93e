// One irradiance-cache record (thesis 2.4.5): the indirect irradiance at a point, the distances
// its hemisphere rays travelled, and its rotation and translation gradients (Ward & Heckbert
// 1992; formulas 2.29-2.30). Validity and weight follow Tabellion & Lamorlette (2.32-2.35), and
// a record is extrapolated to a nearby point with both gradients (2.31).
#pragma once
#include "../math.h"

namespace gi {

// cos(alpha+) with alpha+ = 10 degrees: the normal deviation at which epsilon_n reaches 1 (2.34).
inline constexpr float kMaxRecordAngleCos = 0.98480775301f;

struct IrradianceRecord {
    Vec3 p;  // position
    Vec3 n;  // unit normal, on the side the record's hemisphere was sampled
    Color E;  // indirect irradiance
    // Per colour channel, dE/d(rotation vector) and dE/d(position); both world space, the
    // translation gradient lying in the record's tangent plane.
    Vec3 rotationGradient[3];
    Vec3 translationGradient[3];
    float harmonicMeanDistance = kInf;  // of the hemisphere rays' hits (Ward's R_i)
    float minDistance = kInf;           // nearest hit (Tabellion & Lamorlette's R_i)
    // Where epsilon_p (2.33) reaches 1/k: R_i/2 clamped to [R-, R+], divided by the accuracy k.
    float radius = 0;
    float radiusFactor = 1;  // a_i of adaptive refinement (2.36): only ever shrinks
    float sigma = 0;         // standard deviation of the estimate of Y(E), for 2.38
    float footprint = 0;     // world size of a pixel at the record
    // Where its hemisphere rays leave from (RecordSite's ng and wo, with p, n and footprint
    // above), and how many it has averaged: record_refinement.h adds more. 0 for a record that
    // is not path traced (a photon estimate), which is never refined.
    Vec3 ng, wo;
    uint32_t samples = 0;

    float influenceRadius() const { return radius * radiusFactor; }

    // 2.32-2.35: w = 1 - k max(eps_p, eps_n); zero or less where the record does not apply.
    // The radius already holds 1/k. A `relaxed` lookup (the render's fallback for a sample
    // that fell between the records of neighbouring pixel centres) reaches one pixel farther
    // and accepts twice the normal deviation; it does not scale the radius, which would let
    // large, distant records leak across an occluder they never saw.
    float weight(const Vec3& point, const Vec3& normal, float accuracy, bool relaxed = false) const {
        float r = influenceRadius() + (relaxed ? footprint : 0.0f);
        if (!(r > 0)) return 0;
        Vec3 d = point - p;
        float distance2 = lengthSquared(d);
        if (distance2 >= r * r) return 0;
        float cosine = dot(normal, n);
        // Beyond 60 degrees a first-order rotation extrapolation means nothing, whatever k is;
        // this also rejects flipped normals (the other side of a surface).
        if (cosine <= 0.5f) return 0;
        // Ward's "in front" test: a record lying in front of the point's tangent plane sees
        // surfaces the point may not (a crease), so it does not apply there.
        if (dot(d, normal + n) < -0.1f * r) return 0;
        float epsP = std::sqrt(distance2) / r;
        float epsN = (relaxed ? 0.5f : 1.0f) * accuracy * safeSqrt(1 - cosine) / std::sqrt(1 - kMaxRecordAngleCos);
        return 1 - std::max(epsP, epsN);
    }

    // 2.31's bracket: E_i + (n_i x n) . grad_r E_i + (P - P_i) . grad_t E_i, kept non-negative so
    // that a steep gradient far from its record cannot produce a black (or negative) value.
    Color extrapolate(const Vec3& point, const Vec3& normal) const {
        Vec3 rotation = cross(n, normal), translation = point - p;
        Color result;
        for (int c = 0; c < 3; ++c)
            result[c] = std::max(0.0f, E[c] + dot(rotation, rotationGradient[c]) +
                                           dot(translation, translationGradient[c]));
        return result;
    }
};

}  // namespace gi
