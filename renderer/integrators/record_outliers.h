// Irradiance records robust to outliers (issue 15). A record's hemisphere paths now and then
// find a rare, very bright path - through the window glass to the sun, a 0.53-degree disc whose
// radiance is 10^5 times the sky's - and its estimate jumps by orders of magnitude; the cache
// then spreads that one path over the record's whole radius as a splotch. Each record's samples
// are clamped to kOutlierFactor times the mean of its samples without the brightest ones
// (the top kOutlierShare, at least one): a statistic that one spike cannot move. Light that a
// record sees in more than that share of its directions (a window, a sunlit patch) is never
// touched; what is cut is light that a record of M N paths cannot estimate anyway (expected
// hits per record far below one), so the cache loses little energy and no longer blotches.
#pragma once
#include <algorithm>
#include <vector>

#include "../math.h"

namespace gi {

inline constexpr float kOutlierFactor = 256;
inline constexpr float kOutlierShare = 0.02f;

// Clamps samples (in place) whose luminance exceeds the threshold, keeping their hue; returns
// how many were clamped.
inline int clampRecordOutliers(std::vector<Color>& samples) {
    const size_t n = samples.size();
    if (n < 8) return 0;
    std::vector<float> y(n);
    for (size_t i = 0; i < n; ++i) y[i] = luminance(samples[i]);
    size_t top = std::max<size_t>(1, size_t(kOutlierShare * float(n)));
    std::nth_element(y.begin(), y.begin() + (n - top), y.end());
    double kept = 0;
    for (size_t i = 0; i < n - top; ++i) kept += y[i];
    float threshold = kOutlierFactor * float(kept / double(n - top));
    if (!(threshold > 0)) return 0;  // a dark record: nothing to compare a bright path with
    int clamped = 0;
    for (Color& c : samples) {
        float l = luminance(c);
        if (l > threshold) {
            c = c * (threshold / l);
            ++clamped;
        }
    }
    return clamped;
}

}  // namespace gi
