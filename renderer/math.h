// Small vector and matrix types. Single precision for geometry and radiance; double for
// transforms so that scenes far from the origin keep their precision until baked.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace gi {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Vec2 {
    float x = 0, y = 0;
    Vec2() = default;
    Vec2(float x_, float y_) : x(x_), y(y_) {}
    Vec2 operator+(Vec2 b) const { return {x + b.x, y + b.y}; }
    Vec2 operator-(Vec2 b) const { return {x - b.x, y - b.y}; }
    Vec2 operator*(float s) const { return {x * s, y * s}; }
};

struct Vec3 {
    float x = 0, y = 0, z = 0;
    Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr Vec3(float s) : x(s), y(s), z(s) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator+(const Vec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
    Vec3 operator-(const Vec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
    Vec3 operator*(const Vec3& b) const { return {x * b.x, y * b.y, z * b.z}; }
    Vec3 operator/(const Vec3& b) const { return {x / b.x, y / b.y, z / b.z}; }
    Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(float s) const { float r = 1.0f / s; return {x * r, y * r, z * r}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& b) { x += b.x; y += b.y; z += b.z; return *this; }
    Vec3& operator*=(const Vec3& b) { x *= b.x; y *= b.y; z *= b.z; return *this; }
    Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
};
inline Vec3 operator*(float s, const Vec3& v) { return v * s; }

using Color = Vec3;  // linear Rec.709 RGB

inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float absDot(const Vec3& a, const Vec3& b) { return std::fabs(dot(a, b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline float lengthSquared(const Vec3& v) { return dot(v, v); }
inline Vec3 normalize(const Vec3& v) {
    float l = length(v);
    return l > 0 ? v / l : Vec3(0, 0, 1);
}
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float maxComponent(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float luminance(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool isFinite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool isBlack(const Color& c) { return c.x <= 0 && c.y <= 0 && c.z <= 0; }
inline Vec3 lerp(const Vec3& a, const Vec3& b, float t) { return a * (1 - t) + b * t; }
inline float clamp01(float v) { return std::min(1.0f, std::max(0.0f, v)); }
inline float safeSqrt(float v) { return std::sqrt(std::max(0.0f, v)); }

// An orthonormal basis around a unit normal (Duff et al. 2017, branchless).
// The angle between unit vectors, accurate near 0 and pi (unlike acos of the dot product).
inline float angleBetween(const Vec3& a, const Vec3& b) {
    if (dot(a, b) < 0) return kPi - 2 * std::asin(std::min(1.0f, length(a + b) / 2));
    return 2 * std::asin(std::min(1.0f, length(b - a) / 2));
}

struct Frame {
    Vec3 s, t, n;
    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    explicit Frame(const Vec3& normal) : n(normal) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = Vec3(b, sign + n.y * n.y * a, -n.y);
    }
    Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Affine 4x4 in USD's convention: row vectors, p' = p * M, translation in row 3.
struct Mat4 {
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    static Mat4 identity() { return Mat4(); }
    static Mat4 fromRowMajor(const double* v) {
        Mat4 r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) r.m[i][j] = v[i * 4 + j];
        return r;
    }
    Vec3 point(const Vec3& p) const {
        double x = p.x * m[0][0] + p.y * m[1][0] + p.z * m[2][0] + m[3][0];
        double y = p.x * m[0][1] + p.y * m[1][1] + p.z * m[2][1] + m[3][1];
        double z = p.x * m[0][2] + p.y * m[1][2] + p.z * m[2][2] + m[3][2];
        return {float(x), float(y), float(z)};
    }
    Vec3 vector(const Vec3& v) const {
        return {float(v.x * m[0][0] + v.y * m[1][0] + v.z * m[2][0]),
                float(v.x * m[0][1] + v.y * m[1][1] + v.z * m[2][1]),
                float(v.x * m[0][2] + v.y * m[1][2] + v.z * m[2][2])};
    }
    Mat4 operator*(const Mat4& b) const {
        Mat4 r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
                r.m[i][j] = s;
            }
        return r;
    }
    double det3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    bool isFinite() const {
        for (auto& row : m)
            for (double v : row)
                if (!std::isfinite(v)) return false;
        return true;
    }
    // Inverse of the affine part; returns false if singular.
    bool inverse(Mat4& out) const;  // affine matrices only (the last column is ignored)
    // Normals transform by the inverse transpose of the linear part.
    Vec3 normal(const Vec3& n) const;
};

inline bool Mat4::inverse(Mat4& out) const {
    double d = det3();
    if (!(std::fabs(d) > 1e-300) || !std::isfinite(d)) return false;
    double id = 1.0 / d;
    Mat4 r;
    r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    for (int j = 0; j < 3; ++j)
        r.m[3][j] = -(m[3][0] * r.m[0][j] + m[3][1] * r.m[1][j] + m[3][2] * r.m[2][j]);
    r.m[0][3] = r.m[1][3] = r.m[2][3] = 0;
    r.m[3][3] = 1;
    out = r;
    return true;
}

inline Vec3 Mat4::normal(const Vec3& n) const {
    Mat4 inv;
    if (!inverse(inv)) return n;
    // Row-vector convention: n' = n * (M^-1)^T, i.e. column j of inv dotted with n.
    return {float(n.x * inv.m[0][0] + n.y * inv.m[0][1] + n.z * inv.m[0][2]),
            float(n.x * inv.m[1][0] + n.y * inv.m[1][1] + n.z * inv.m[1][2]),
            float(n.x * inv.m[2][0] + n.y * inv.m[2][1] + n.z * inv.m[2][2])};
}

struct Ray {
    Vec3 o, d;
    float tMin = 0, tMax = kInf;
    float time = 0;  // within the camera's shutter: 0 = open, 1 = close (motion.h)
    // A ray cone: its width at `o` and its growth per unit of distance (radians), which size
    // the footprint a hit's textures are read over (SurfaceInteraction::uvFootprint). 0: the
    // textures' finest level, as for camera rays.
    float coneWidth = 0, coneSpread = 0;
};

// Offsets a ray origin off a surface along the geometric normal, scaled with the magnitude
// of the position so that far-from-origin scenes do not self-intersect (pbrt's error-bound
// idea, with a conservative constant instead of tracked bounds).
// How far a computed surface point may be from the true surface: a hit point reconstructed from
// barycentrics (or re-projected onto a sphere) is good to a few float ulps of its largest
// coordinate, so 8 ulps (2^-20 relative) clear it; the absolute term covers points near the
// origin on larger triangles. Scenes far from the origin (10^5) get offsets of ~0.1 unit, not the
// whole units a fixed relative 1e-5 gave; scenes at 10^-3 scale stay well above 1e-7.
inline float pointErrorBound(const Vec3& p) {
    float magnitude = std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z)));
    return magnitude * 0x1p-20f + 1e-7f;
}

inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& ng, const Vec3& dir) {
    Vec3 offset = ng * pointErrorBound(p);
    return dot(dir, ng) < 0 ? p - offset : p + offset;
}

}  // namespace gi
