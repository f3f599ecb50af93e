// Motion blur: geometry given at evenly spaced steps over the camera's shutter interval, which
// Embree's multi-segment motion geometry interpolates linearly at each ray's time (0 = shutter
// open, 1 = shutter close). The helpers here interpolate exactly as Embree does, so the shading
// point, normals and instance transforms at a hit belong to the geometry the ray hit.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

#include "math.h"

namespace gi {

// At most this many steps per shape: the loaders sample at the authored time samples inside the
// shutter, and a finer grid than that adds memory without changing linear segments.
inline constexpr size_t kMaxMotionSteps = 64;

// What moves during the shutter, at `count()` evenly spaced steps (step 0 at shutter open, the last
// at shutter close). Empty: nothing moves.
struct MotionSteps {
    std::vector<std::vector<Vec3>> points;  // deformation: per step, one per position; empty: none
    std::vector<Mat4> transforms;           // transform motion: per step; empty: the static transform
    size_t count() const { return std::max(points.size(), transforms.size()); }
    bool empty() const { return count() < 2; }
};

// Embree's time segment (getTimeSegment in its sources): the segment `time` falls in among
// steps - 1 segments, and the fraction within it.
struct TimeSegment {
    int index = 0;
    float fraction = 0;
};
inline TimeSegment timeSegment(float time, size_t steps) {
    if (steps < 2) return {};
    float segments = float(steps - 1);
    float scaled = time * segments;
    float index = std::clamp(std::floor(scaled), 0.0f, segments - 1);
    return {int(index), scaled - index};
}

// A value of `steps` (one per time step) at `time`.
inline Vec3 atTime(const std::vector<Vec3>& steps, float time) {
    TimeSegment s = timeSegment(time, steps.size());
    if (steps.size() < 2) return steps.empty() ? Vec3(0.0f) : steps[0];
    return lerp(steps[s.index], steps[s.index + 1], s.fraction);
}

inline float atTime(const std::vector<float>& steps, float time) {
    if (steps.size() < 2) return steps.empty() ? 0.0f : steps[0];
    TimeSegment s = timeSegment(time, steps.size());
    return steps[s.index] * (1 - s.fraction) + steps[s.index + 1] * s.fraction;
}

// Vertex `i` of a moving mesh (one vertex array per time step) at `time`.
inline Vec3 atTime(const std::vector<std::vector<Vec3>>& steps, float time, uint32_t i) {
    TimeSegment s = timeSegment(time, steps.size());
    if (steps.size() < 2) return steps.empty() ? Vec3(0.0f) : steps[0][i];
    return lerp(steps[s.index][i], steps[s.index + 1][i], s.fraction);
}

// An instance transform at `time`: Embree interpolates the matrices of RTC_FORMAT_FLOAT4X4 linearly.
inline Mat4 atTime(const std::vector<Mat4>& steps, float time) {
    if (steps.size() < 2) return steps.empty() ? Mat4() : steps[0];
    TimeSegment s = timeSegment(time, steps.size());
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r.m[i][j] = steps[s.index].m[i][j] * (1 - s.fraction) + steps[s.index + 1].m[i][j] * s.fraction;
    return r;
}

// A host's motion samples (Hydra's SampleTransform / SamplePrimvar: increasing times relative to
// the frame, the shutter's boundaries among them) onto the evenly spaced steps the renderer takes:
// the sample times themselves when evenly spaced, otherwise a grid as fine as their closest pair
// (at most kMaxMotionSteps); the same rule as the USD loader's (python/gi/motion.py step_times).
inline std::vector<float> evenStepTimes(std::vector<float> times) {
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    if (times.size() < 2 || !std::isfinite(times.front()) || !std::isfinite(times.back())) return {};
    float closest = times.back() - times.front();
    for (size_t i = 1; i < times.size(); ++i) closest = std::min(closest, times[i] - times[i - 1]);
    float span = times.back() - times.front();
    // Clamped as a float: a ratio beyond size_t's range must not be converted.
    size_t segments = size_t(std::clamp(std::ceil(span / closest - 1e-4f), 1.0f, float(kMaxMotionSteps - 1)));
    std::vector<float> grid(segments + 1);
    for (size_t i = 0; i <= segments; ++i) grid[i] = times.front() + span * float(i) / float(segments);
    grid.back() = times.back();
    return grid;
}

// The steps over a shutter [open, close] (times relative to the frame) of motion sampled at the
// times of each of `series` (a host samples over a wider interval than one camera's shutter):
// the shutter's ends and the samples strictly inside it, through evenStepTimes. Empty when the
// shutter does not open.
inline std::vector<float> shutterStepTimes(float open, float close,
                                           std::initializer_list<const std::vector<float>*> series) {
    if (!(close > open)) return {};
    std::vector<float> times{open, close};
    for (const std::vector<float>* s : series)
        if (s)
            for (float t : *s)
                if (t > open && t < close) times.push_back(t);
    return evenStepTimes(std::move(times));
}

// The value at `t` of samples at increasing `times`, interpolated linearly by lerp(a, b, fraction)
// (held before the first and after the last).
template <typename T, typename Lerp>
T sampleAt(const std::vector<float>& times, const std::vector<T>& values, float t, Lerp lerp) {
    if (times.size() < 2 || t <= times.front()) return values.front();
    if (t >= times.back()) return values.back();
    size_t i = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin());
    float fraction = (t - times[i - 1]) / (times[i] - times[i - 1]);
    return lerp(values[i - 1], values[i], fraction);
}

}  // namespace gi
