// Irradiance records robust to outliers (issue 15). A record's hemisphere paths now and then
// find a rare, very bright path - through the window glass to the sun, a 0.53-degree disc whose
// radiance is 10^5 times the sky's - and its estimate jumps by orders of magnitude; the cache
// then spreads that one path over the record's whole radius as a splotch. No sample may add more
// than kOutlierContribution times the record's robust mean (the mean of its samples without the
// brightest ones, the top kOutlierShare, at least one: a statistic that one spike cannot move)
// to an estimate of N samples, so each is clamped at kOutlierContribution N times that mean.
// Light that a record sees in more than that share of its directions (a window, a sunlit patch)
// is never touched; what is cut is light that a record of N paths cannot estimate anyway
// (expected hits per record far below one). The bound grows with N, so a record refined with
// more paths (record_refinement.h) keeps more of it and converges: at a fixed 256x a record of
// 1728 paths cut the sky through a window in the sky-lit room's corners into dark blotches (the
// mean 0.989 of the path tracer's, 0.999 with the bound growing). kOutlierContribution is 4096x
// the robust mean at the thesis's 108 paths: with the records refined, 256x there cut Sibenik's
// caches 2-4% dark (sun and sky through the glass; irradiance, adaptive and photon cache 0.952,
// 0.925, 0.964 of the reference, 0.973, 0.961, 1.000 at 4096x, FLIP and outlier blocks no worse)
// and bought nothing on the sunlit room, the sky-lit room or Sponza (outlier blocks and means the
// same at both factors).
#pragma once
#include <algorithm>
#include <vector>

#include "../math.h"

namespace gi {

inline constexpr float kOutlierContribution = 4096.0f / 108;
inline constexpr float kOutlierShare = 0.02f;

// Clamps samples (in place) whose luminance exceeds the threshold for a record of `recordSamples`
// samples in all (these and those it already had; at least samples.size()), keeping their hue;
// returns how many were clamped.
inline int clampRecordOutliers(std::vector<Color>& samples, size_t recordSamples = 0) {
    const size_t n = samples.size();
    if (n < 8) return 0;
    std::vector<float> y(n);
    for (size_t i = 0; i < n; ++i) y[i] = luminance(samples[i]);
    size_t top = std::max<size_t>(1, size_t(kOutlierShare * float(n)));
    std::nth_element(y.begin(), y.begin() + (n - top), y.end());
    double kept = 0;
    for (size_t i = 0; i < n - top; ++i) kept += y[i];
    float threshold = kOutlierContribution * float(std::max(n, recordSamples)) * float(kept / double(n - top));
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

// The same for samples whose light came partly from a caustic map: the paths' own parts are
// clamped, the map's parts (a density estimate, not a rare path) are added back untouched. The clamp
// cut the sunlit patches that window glass throws on Sibenik's floor, which a record's paths reach
// in few of their directions: the adaptive cache read 0.93 of the reference with its caustic map,
// 0.96 without the map at all; the plain cache 0.995 with this.
inline int clampRecordOutliers(std::vector<Color>& samples, const std::vector<Color>& fromCausticMap,
                               size_t recordSamples) {
    int clamped = clampRecordOutliers(samples, recordSamples);
    for (size_t i = 0; i < samples.size(); ++i) samples[i] += fromCausticMap[i];
    return clamped;
}

}  // namespace gi
