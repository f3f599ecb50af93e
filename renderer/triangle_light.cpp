// Emissive triangles as lights: still ones, and those of meshes or instances that move during the
// shutter (motion.h).
#include <algorithm>
#include <array>

#include "area_light.h"
#include "material.h"
#include "motion.h"

namespace gi {

namespace {

class TriangleLight : public AreaLight {
public:
    // L: the radiance at the centroid, for the light's power and its photons (the material's
    // emission there unless given).
    TriangleLight(const Vec3 p[3], const Vec2 uv[3], const Material* m, bool twoSided, Color L)
        : material_(m), twoSided_(twoSided) {
        for (int i = 0; i < 3; ++i) {
            p_[i] = p[i];
            uv_[i] = uv[i];
        }
        Vec3 c = cross(p[1] - p[0], p[2] - p[0]);
        area_ = 0.5f * length(c);
        n_ = normalize(c);
        L_ = L;
    }
    static Color centroidEmission(const Vec2 uv[3], const Material* m) {
        return m->emission(Vec2((uv[0].x + uv[1].x + uv[2].x) / 3, (uv[0].y + uv[1].y + uv[2].y) / 3));
    }
    SurfacePoint samplePoint(Vec2 u) const override {
        Vec2 b = sampleUniformTriangle(u);
        return {p_[0] * b.x + p_[1] * b.y + p_[2] * (1 - b.x - b.y), n_};
    }
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        LightSample ls;
        if (!(area_ > 0)) return ls;  // a moving triangle can collapse at some instant
        Vec2 b = sampleUniformTriangle(u);
        Vec3 p = p_[0] * b.x + p_[1] * b.y + p_[2] * (1 - b.x - b.y);
        Vec3 d = p - ref;
        float dist = length(d);
        if (!(dist > 0)) return ls;
        ls.wi = d / dist;
        ls.distance = dist;
        float cosLight = dot(-ls.wi, n_);
        if (cosLight <= 0 && !twoSided_) return ls;
        ls.pdf = areaToSolidAngle(1 / area_, dist, cosLight);
        Vec2 uv = uv_[0] * b.x + uv_[1] * b.y + uv_[2] * (1 - b.x - b.y);
        ls.Li = ls.pdf > 0 ? material_->emission(uv) : Color(0);
        return ls;
    }
    float area() const override { return area_; }
    bool twoSided() const override { return twoSided_; }
    bool extent(Vec3* lo, Vec3* hi) const override {
        *lo = vmin(p_[0], vmin(p_[1], p_[2]));
        *hi = vmax(p_[0], vmax(p_[1], p_[2]));
        return true;
    }
    Vec3 normalCone(float* cosThetaO) const override {
        *cosThetaO = 1;
        return n_;
    }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        return area_ > 0 ? areaToSolidAngle(1 / area_, t, dot(-wi, n_)) : 0.0f;
    }
    Color radiance(const Vec3& wi, float time) const override { return L_; }  // hits use the material directly

private:
    Vec3 p_[3], n_;
    Vec2 uv_[3];
    const Material* material_;
    bool twoSided_;
    float area_;
};

// An emissive triangle that moves during the shutter: of a mesh whose points or transform move
// (top-level meshes hold world-space points per step), or of a prototype seen through a moving
// instance. At a time it is where Embree's motion geometry puts it: its points at that time placed
// by its transform at that time, each interpolated linearly between its own steps. Next-event
// estimation at a path's time and the pdf a BSDF-sampled hit is weighted with therefore see the
// triangle the ray hits, and its photons leave it where it is at their time.
class MovingTriangleLight final : public Light {
public:
    MovingTriangleLight(std::vector<std::array<Vec3, 3>> points, std::vector<Mat4> toWorld, const Vec2 uv[3],
                        const Material* m, bool twoSided)
        : points_(std::move(points)), toWorld_(std::move(toWorld)), material_(m), twoSided_(twoSided) {
        std::copy_n(uv, 3, uv_);
        L_ = TriangleLight::centroidEmission(uv, m);
    }

    TriangleLight at(float time) const {
        std::array<Vec3, 3> p = points_[0];
        if (points_.size() > 1) {
            TimeSegment s = timeSegment(time, points_.size());
            for (int k = 0; k < 3; ++k) p[k] = lerp(points_[size_t(s.index)][k], points_[size_t(s.index) + 1][k], s.fraction);
        }
        if (!toWorld_.empty()) {
            Mat4 m = atTime(toWorld_, time);
            for (Vec3& v : p) v = m.point(v);
        }
        return TriangleLight(p.data(), uv_, material_, twoSided_, L_);
    }
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override { return at(time).sample(ref, u, time); }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        return at(time).pdf(ref, wi, t, time);
    }
    Color radiance(const Vec3&, float) const override { return L_; }
    // A point at time t is a point of the steps' points placed by a blend of the steps' transforms:
    // a convex combination of every step's points placed by every step's transform, so their box
    // holds it. Its normal turns, so the cone is every direction.
    bool emissionBounds(LightBounds* b) const override {
        Vec3 lo(kInf), hi(-kInf);
        std::vector<Mat4> transforms = toWorld_.empty() ? std::vector<Mat4>{Mat4()} : toWorld_;
        for (const Mat4& m : transforms)
            for (const std::array<Vec3, 3>& step : points_)
                for (const Vec3& v : step) {
                    Vec3 w = toWorld_.empty() ? v : m.point(v);
                    lo = vmin(lo, w), hi = vmax(hi, w);
                }
        b->lo = lo, b->hi = hi;
        b->phi = luminance(power(bounds_));
        b->w = Vec3(0, 0, 1);
        b->cosThetaO = -1;
        b->cosThetaE = 0;
        b->twoSided = twoSided_;
        return b->phi > 0;
    }
    // Averaged over the finer of the two step grids: what the triangle emits over the shutter.
    Color power(const SceneBounds& bounds) const override {
        size_t n = std::max(points_.size(), toWorld_.size());
        if (n < 2) return at(0).power(bounds);
        Color sum(0.0f);
        for (size_t i = 0; i < n; ++i) sum += at(float(i) / float(n - 1)).power(bounds);
        return sum / float(n);
    }
    PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds& bounds, float time) const override {
        TriangleLight there = at(time);
        if (!(there.area() > 0)) {  // collapsed at this instant: no flux
            PhotonEmission none;
            none.ray.o = there.samplePoint(uPos).p;
            none.ray.d = Vec3(0, 0, 1);
            none.power = Color(0.0f);
            return none;
        }
        return there.emit(uPos, uDir, bounds, time);
    }

private:
    std::vector<std::array<Vec3, 3>> points_;  // per step of its own motion (one when it has none)
    std::vector<Mat4> toWorld_;                // per step of its instance's motion, one, or none (world points)
    Vec2 uv_[3];
    const Material* material_;
    bool twoSided_;
    Color L_;
};

}  // namespace

std::unique_ptr<Light> createTriangleLight(const Vec3 p[3], const Vec2 uv[3], const Material* material,
                                           bool doubleSided, const std::string& name) {
    auto light = std::make_unique<TriangleLight>(p, uv, material, doubleSided, TriangleLight::centroidEmission(uv, material));
    light->name = name;
    return light;
}

std::unique_ptr<Light> createMovingTriangleLight(std::vector<std::array<Vec3, 3>> points, std::vector<Mat4> toWorld,
                                                 const Vec2 uv[3], const Material* material, bool doubleSided,
                                                 const std::string& name) {
    auto light = std::make_unique<MovingTriangleLight>(std::move(points), std::move(toWorld), uv, material, doubleSided);
    light->name = name;
    return light;
}

}  // namespace gi
