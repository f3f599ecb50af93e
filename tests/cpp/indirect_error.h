// The error of an integrator's indirect light against a path-traced reference, less the
// reference's own noise: what the convergence tests of the caches and photon maps measure.
//
// An integrator's indirect light is its image minus the `direct` image of the same seed and light
// samples: the ray tracer's part (emission, direct light, specular recursion) draws the same random
// numbers in both, so its noise, common to every integrator, cancels. The reference's indirect light
// is the path tracer's image minus a many-sample `direct` image, each from two independent halves,
// whose difference gives the reference's own variance. Errors are taken over the 4 x 4 pixel
// blocks' luminance: a block mean's noise is close to normal where single pixels are heavy-tailed.
#pragma once
#include <vector>

#include "renderer/math.h"

namespace gi::test {

inline std::vector<double> blockLuminance(const std::vector<float>& rgb, int size) {
    std::vector<double> blocks;
    for (int by = 0; by + 4 <= size; by += 4)
        for (int bx = 0; bx + 4 <= size; bx += 4) {
            double sum = 0;
            for (int y = by; y < by + 4; ++y)
                for (int x = bx; x < bx + 4; ++x) {
                    const float* p = &rgb[3 * (size_t(y) * size + x)];
                    sum += luminance(Color(p[0], p[1], p[2]));
                }
            blocks.push_back(sum / 16);
        }
    return blocks;
}

struct IndirectReference {
    std::vector<double> blocks;  // the reference's indirect light per block
    double variance = 0;         // of a block of it, from its halves: difference^2 / 4, averaged
    double mean = 0;             // of the blocks
};

// From block luminances of two independent path-traced halves and two `direct` halves.
inline IndirectReference indirectReference(const std::vector<double> path[2], const std::vector<double> direct[2]) {
    IndirectReference r;
    const size_t n = path[0].size();
    for (size_t b = 0; b < n; ++b) {
        r.blocks.push_back((path[0][b] + path[1][b]) / 2 - (direct[0][b] + direct[1][b]) / 2);
        double dp = path[0][b] - path[1][b], dd = direct[0][b] - direct[1][b];
        r.variance += (dp * dp + dd * dd) / 4 / double(n);
        r.mean += r.blocks.back() / double(n);
    }
    return r;
}

struct IndirectError {
    double e2;    // mean squared block error less the reference's variance, over the reference's mean^2
    double mean;  // indirect mean over the reference's
};

// `image` and `direct`: block luminances of an integrator's render and the same seed's `direct`.
inline IndirectError indirectError(const std::vector<double>& image, const std::vector<double>& direct,
                                   const IndirectReference& reference) {
    const size_t n = image.size();
    double squared = 0, sum = 0;
    for (size_t i = 0; i < n; ++i) {
        double indirect = image[i] - direct[i], d = indirect - reference.blocks[i];
        squared += d * d / double(n);
        sum += indirect / double(n);
    }
    return {(squared - reference.variance) / (reference.mean * reference.mean), sum / reference.mean};
}

}  // namespace gi::test
