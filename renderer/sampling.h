// Warping functions from [0,1)^2 to directions and shapes, and MIS weights.
#pragma once
#include <vector>

#include "math.h"

namespace gi {

inline Vec2 sampleConcentricDisk(Vec2 u) {
    float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    float r, theta;
    if (std::fabs(ox) > std::fabs(oy)) {
        r = ox;
        theta = (kPi / 4) * (oy / ox);
    } else {
        r = oy;
        theta = kPi / 2 - (kPi / 4) * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}

inline Vec3 sampleCosineHemisphere(Vec2 u) {
    Vec2 d = sampleConcentricDisk(u);
    return {d.x, d.y, safeSqrt(1 - d.x * d.x - d.y * d.y)};
}
inline float cosineHemispherePdf(float cosTheta) { return std::max(0.0f, cosTheta) * kInvPi; }

inline Vec3 sampleUniformSphere(Vec2 u) {
    float z = 1 - 2 * u.x;
    float r = safeSqrt(1 - z * z);
    float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformSpherePdf() { return 1.0f / (4 * kPi); }

// Uniform direction in the cone around +z with cos(half angle) = cosMax.
inline Vec3 sampleUniformCone(Vec2 u, float cosMax) {
    float cosTheta = (1 - u.x) + u.x * cosMax;
    float sinTheta = safeSqrt(1 - cosTheta * cosTheta);
    float phi = u.y * 2 * kPi;
    return {std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta};
}
inline float uniformConePdf(float cosMax) { return 1 / (2 * kPi * (1 - cosMax)); }
// The same for a cone given by sin^2 of its half-angle: stays finite when the cone is narrower than
// float precision around 1 (a tiny light far away, where 1 - cosMax rounds to 0).
inline float uniformConePdfFromSin2(float sin2) {
    float oneMinusCos = sin2 / (1 + safeSqrt(1 - sin2));
    return oneMinusCos > 0 ? 1 / (2 * kPi * oneMinusCos) : 0.0f;
}

// Barycentrics uniform over a triangle (Heitz's low-distortion mapping).
inline Vec2 sampleUniformTriangle(Vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

// A rectangle (corner s, perpendicular edges ex, ey) as seen from p: the spherical rectangle of
// Urena, Fajardo and King (2013), sampled uniformly in solid angle (pbrt-v4's
// SampleSphericalRectangle). solidAngle is 0 when p lies in the rectangle's plane.
struct SphericalRectangle {
    SphericalRectangle(const Vec3& p, const Vec3& s, const Vec3& ex, const Vec3& ey);
    // The point on the rectangle a uniform direction hits.
    Vec3 sample(Vec2 u) const;
    float solidAngle = 0;

private:
    Vec3 p_, x_, y_, z_;  // z_ points from p towards the rectangle's plane
    float x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0, z0_ = 0, b0_ = 0, b1_ = 0, g0g1_ = 0, g2g3_ = 0;
};

inline float powerHeuristic(float pdfA, float pdfB) {
    float a = pdfA * pdfA, b = pdfB * pdfB;
    if (std::isinf(a)) return 1;
    return a + b > 0 ? a / (a + b) : 0;
}

// A discrete distribution proportional to non-negative weights (light selection, the rows
// and columns of an environment map). Falls back to uniform when all weights are zero.
class Distribution1D {
public:
    Distribution1D() = default;
    Distribution1D(const float* weights, int n);
    // Index drawn with probability pmf(index); `remapped` is u rescaled to [0,1) inside the bin.
    int sample(float u, float* pmf, float* remapped = nullptr) const;
    float pmf(int i) const { return total_ > 0 ? func_[i] / total_ : 0; }
    float total() const { return total_; }
    int size() const { return int(func_.size()); }
    float func(int i) const { return func_[i]; }

private:
    std::vector<float> func_, cdf_;
    float total_ = 0;
};

}  // namespace gi
