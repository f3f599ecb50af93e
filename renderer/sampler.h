// Deterministic low-discrepancy sampler: Owen-scrambled, shuffled 2D Sobol points padded across
// dimension pairs (Burley 2020, "Practical Hash-based Owen Scrambling"). Every pair of
// dimensions is an independently scrambled (0,2)-sequence, so any sample count is well
// stratified and a progressive render can stop after any pass. Depends only on
// (pixel, sample index, dimension, seed), never on thread timing.
#pragma once
#include <cstdint>

#include "math.h"

namespace gi {

inline uint32_t reverseBits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

inline uint32_t hashCombine(uint32_t seed, uint32_t v) {
    // A 32-bit finaliser (lowbias32 by Chris Wellons) over a golden-ratio combination.
    uint32_t x = seed ^ (v + 0x9e3779b9u + (seed << 6) + (seed >> 2));
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

inline uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
    return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

inline uint32_t sobolDimension1(uint32_t index) {
    uint32_t v = 1u << 31, r = 0;
    for (; index; index >>= 1, v ^= v >> 1)
        if (index & 1) r ^= v;
    return r;
}

inline float uintToUnitFloat(uint32_t x) { return std::min(float(x >> 8) * 0x1p-24f, 0.99999994f); }

class Sampler {
public:
    Sampler(uint32_t seed) : seed_(seed) {}

    // Starts the stream for one camera sample of one pixel.
    void start(int px, int py, uint32_t sampleIndex) {
        pixelHash_ = hashCombine(hashCombine(seed_, uint32_t(px)), uint32_t(py));
        sampleIndex_ = sampleIndex;
        dimension_ = 0;
    }

    Vec2 get2D() {
        uint32_t pairSeed = hashCombine(pixelHash_, dimension_++);
        uint32_t index = nestedUniformScramble(sampleIndex_, pairSeed);
        uint32_t x = nestedUniformScramble(reverseBits(index), hashCombine(pairSeed, 0x68bc21ebu));
        uint32_t y = nestedUniformScramble(sobolDimension1(index), hashCombine(pairSeed, 0x02e5be93u));
        return {uintToUnitFloat(x), uintToUnitFloat(y)};
    }
    float get1D() { return get2D().x; }

    // An independent stream for work that is not per pixel (photons, cache records).
    void startStream(uint32_t stream, uint32_t index) {
        pixelHash_ = hashCombine(hashCombine(seed_, 0xa511e9b3u), stream);
        sampleIndex_ = index;
        dimension_ = 0;
    }

private:
    uint32_t seed_;
    uint32_t pixelHash_ = 0;
    uint32_t sampleIndex_ = 0;
    uint32_t dimension_ = 0;
};

}  // namespace gi
