// The finite area emitters' shared machinery (light.cpp's rect, disk, sphere and cylinder lights,
// triangle_light.cpp's emissive triangles): uniform-area sampling and photon emission.
#pragma once
#include <cmath>

#include "light.h"

namespace gi {

// Solid-angle pdf of a point sampled uniformly by area.
inline float areaToSolidAngle(float areaPdf, float distance, float cosAtLight) {
    float c = std::fabs(cosAtLight);
    return c > 1e-8f ? areaPdf * distance * distance / c : 0.0f;
}

// An emitter with an area: samples it uniformly by area and emits photons from it with a cosine lobe.
class AreaLight : public Light {
public:
    struct SurfacePoint {
        Vec3 p, n;  // n: the emitting side
    };
    virtual SurfacePoint samplePoint(Vec2 u) const = 0;
    virtual float area() const = 0;
    virtual bool twoSided() const { return false; }
    virtual Color radianceAt(const SurfacePoint&) const { return L_; }
    // The box holding the emitting surface, and the cone of its normals (cosine -1: all ways).
    virtual bool extent(Vec3* lo, Vec3* hi) const { return shapeBounds(lo, hi); }
    virtual Vec3 normalCone(float* cosThetaO) const {
        *cosThetaO = -1;
        return Vec3(0, 0, 1);
    }
    bool emissionBounds(LightBounds* b) const override {
        if (!extent(&b->lo, &b->hi)) return false;
        b->phi = luminance(power(bounds_));
        b->w = normalCone(&b->cosThetaO);
        b->cosThetaE = 0;  // each point emits over its hemisphere
        b->twoSided = twoSided();
        return b->phi > 0;
    }

    LightSample sample(const Vec3& ref, Vec2 u, float time) const override {
        SurfacePoint s = samplePoint(u);
        Vec3 d = s.p - ref;
        float dist = length(d);
        LightSample ls;
        if (!(dist > 0)) return ls;
        ls.wi = d / dist;
        ls.distance = dist;
        float cosLight = dot(-ls.wi, s.n);
        if (cosLight <= 0 && !twoSided()) return ls;
        ls.pdf = areaToSolidAngle(1 / area(), dist, cosLight);
        ls.Li = ls.pdf > 0 ? radianceAt(s) : Color(0);
        return ls;
    }
    PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds&, float) const override {
        SurfacePoint s = samplePoint(uPos);
        Vec3 local = sampleCosineHemisphere(uDir);
        Vec3 n = s.n;
        if (twoSided() && uDir.x < 0.5f) {  // reuse the bit: pick a side
            n = -n;
            local = sampleCosineHemisphere(Vec2(uDir.x * 2, uDir.y));
        } else if (twoSided()) {
            local = sampleCosineHemisphere(Vec2((uDir.x - 0.5f) * 2, uDir.y));
        }
        Frame f(n);
        PhotonEmission e;
        e.ray.o = offsetRayOrigin(s.p, n, n);
        e.ray.d = f.toWorld(local);
        // flux = L * cos / (pdf_area * pdf_dir) = L * A * pi (* 2 for two sides)
        e.power = radianceAt(s) * (area() * kPi * (twoSided() ? 2.0f : 1.0f));
        return e;
    }
    Color power(const SceneBounds&) const override { return L_ * (area() * kPi * (twoSided() ? 2.0f : 1.0f)); }

protected:
    Color L_;
};

}  // namespace gi
