// An area light that moves during the shutter (a UsdLux light whose transform is animated across
// it): its kind's light at evenly spaced steps (motion.h), the first at shutter open and the last
// at close, interpolated linearly at a ray's time as Embree interpolates moving geometry (centres,
// corners, edges, radii and radiance; normals interpolated and normalised). Camera rays, the
// light samples of their paths (next-event estimation at the path's time) and the pdf a
// BSDF-sampled ray that hits the light is weighted with all see the light at one time, so MIS
// stays consistent; photons leave it from where it is at their time. Bounds (light selection,
// the light BVH) hold every step, so they hold the light at every time between (linear
// interpolation stays in the steps' convex hull).
#pragma once
#include <utility>
#include <vector>

#include "light.h"
#include "light_sampler.h"
#include "motion.h"

namespace gi {

// `Kind` (a rect, disk, sphere or cylinder light) provides Kind::between(a, b, fraction): the
// light between two of its steps.
template <typename Kind>
class MovingLight final : public Light {
public:
    explicit MovingLight(std::vector<Kind> steps) : steps_(std::move(steps)) {}

    // The light where it is at `time` (0 = shutter open, 1 = close).
    Kind at(float time) const {
        TimeSegment s = timeSegment(time, steps_.size());
        return Kind::between(steps_[size_t(s.index)], steps_[size_t(s.index) + 1], s.fraction);
    }
    LightSample sample(const Vec3& ref, Vec2 u, float time) const override { return at(time).sample(ref, u, time); }
    float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const override {
        return at(time).pdf(ref, wi, t, time);
    }
    Color radiance(const Vec3& wi, float time) const override { return at(time).radiance(wi, time); }
    float intersect(const Ray& r) const override { return at(r.time).intersect(r); }
    bool shapeBounds(Vec3* lo, Vec3* hi) const override {
        for (size_t i = 0; i < steps_.size(); ++i) {
            Vec3 stepLo, stepHi;
            if (!steps_[i].shapeBounds(&stepLo, &stepHi)) return false;
            *lo = i == 0 ? stepLo : vmin(*lo, stepLo);
            *hi = i == 0 ? stepHi : vmax(*hi, stepHi);
        }
        return true;
    }
    bool emissionBounds(LightBounds* b) const override {
        LightBounds all;
        for (const Kind& step : steps_) {
            LightBounds stepBounds;
            if (!step.emissionBounds(&stepBounds)) return false;
            all = unionOf(all, stepBounds);  // boxes and the cone of normals of every step
        }
        all.phi = luminance(power(bounds_));  // one light's power, not the steps' sum
        *b = all;
        return all.phi > 0;
    }
    // Averaged over the steps: what the light emits over the shutter (a rigid motion keeps it).
    Color power(const SceneBounds& bounds) const override {
        Color sum(0.0f);
        for (const Kind& step : steps_) sum += step.power(bounds);
        return sum / float(steps_.size());
    }
    PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds& bounds, float time) const override {
        return at(time).emit(uPos, uDir, bounds, time);
    }
    void preprocess(const SceneBounds& bounds) override {
        Light::preprocess(bounds);
        for (Kind& step : steps_) step.preprocess(bounds);
    }

private:
    std::vector<Kind> steps_;
};

}  // namespace gi
