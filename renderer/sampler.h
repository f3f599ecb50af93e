// Deterministic low-discrepancy sampler: Owen-scrambled, shuffled 2D Sobol points padded across
// dimension pairs (Burley 2020, "Practical Hash-based Owen Scrambling"). Every pair of
// dimensions is an independently scrambled (0,2)-sequence, so any sample count is well
// stratified and a progressive render can stop after any pass. Depends only on
// (pixel, sample index, dimension, seed), never on thread timing.
#pragma once
#include <cstdint>

#include "math.h"
#include "sampler_batch.h"

namespace gi {

inline uint32_t reverseBits(uint32_t x) {
    x = __builtin_bswap32(x);  // reverses the bytes; then the bits within each byte
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
}

// reverseBits of both halves at once, and the halves swapped: reverseBits(lo) << 32 | reverseBits(hi).
inline uint64_t reverseBits64(uint64_t x) {
    x = __builtin_bswap64(x);
    x = ((x >> 1) & 0x5555555555555555ull) | ((x & 0x5555555555555555ull) << 1);
    x = ((x >> 2) & 0x3333333333333333ull) | ((x & 0x3333333333333333ull) << 2);
    return ((x >> 4) & 0x0F0F0F0F0F0F0F0Full) | ((x & 0x0F0F0F0F0F0F0F0Full) << 4);
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

// Sobol's second dimension is linear over GF(2) in the index bits, so it is evaluated a byte
// at a time from four 256-entry tables instead of a loop over all 32 bits. The tables hold the
// bit-reversed values: the Owen scramble works on reversed bits, so this saves a reversal.
struct SobolDimension1Tables {
    uint32_t table[4][256];
    constexpr SobolDimension1Tables() : table() {
        uint32_t direction[32] = {};
        uint32_t v = 1u << 31;
        for (int bit = 0; bit < 32; ++bit, v ^= v >> 1) {
            uint32_t reversed = 0;
            for (int b = 0; b < 32; ++b) reversed |= ((v >> b) & 1u) << (31 - b);
            direction[bit] = reversed;
        }
        for (int byte = 0; byte < 4; ++byte)
            for (uint32_t value = 0; value < 256; ++value) {
                uint32_t r = 0;
                for (int bit = 0; bit < 8; ++bit)
                    if (value & (1u << bit)) r ^= direction[byte * 8 + bit];
                table[byte][value] = r;
            }
    }
};
inline constexpr SobolDimension1Tables kSobolDimension1{};

// reverseBits(Sobol dimension 1 of index).
inline uint32_t sobolDimension1Reversed(uint32_t index) {
    return kSobolDimension1.table[0][index & 0xff] ^ kSobolDimension1.table[1][(index >> 8) & 0xff] ^
           kSobolDimension1.table[2][(index >> 16) & 0xff] ^ kSobolDimension1.table[3][index >> 24];
}

inline float uintToUnitFloat(uint32_t x) { return std::min(float(x >> 8) * 0x1p-24f, 0.99999994f); }

class Sampler {
public:
    Sampler(uint32_t seed) : seed_(seed) {}

    // Starts the stream for one camera sample of one pixel.
    void start(int px, int py, uint32_t sampleIndex) {
        pixelHash_ = hashCombine(hashCombine(seed_, uint32_t(px)), uint32_t(py));
        sampleIndex_ = sampleIndex;
        reversedIndex_ = reverseBits(sampleIndex);
        dimension_ = 0;
        batchEnd_ = 0;
    }

    Vec2 get2D() {
#if defined(__AVX2__)
        // Pairs come eight at a time (sampler_batch.h), the same values as one at a time.
        if (dimension_ >= batchEnd_) {  // dimension_ only grows from start's 0
            batchStart_ = dimension_;
            batchEnd_ = dimension_ + sampler_batch::kPairs;
            sampler_batch::pairs(pixelHash_, reversedIndex_, batchStart_, batch_);
        }
        return batch_[dimension_++ - batchStart_];
#else
        return pairAt(dimension_++);
#endif
    }
    float get1D() { return get2D().x; }
    // The time within the shutter (0 = open, 1 = close) of this camera sample or photon: a
    // dimension of its own, outside the sequence get2D walks, so that drawing it shifts no other
    // dimension and a scene where nothing moves renders bit-identically with or without a shutter.
    float shutterTime() const { return pairAt(kShutterDimension).x; }
    uint32_t sampleIndex() const { return sampleIndex_; }  // the camera sample (or stream index) started

    // An independent stream for work that is not per pixel (photons, cache records).
    void startStream(uint32_t stream, uint32_t index) {
        pixelHash_ = hashCombine(hashCombine(seed_, 0xa511e9b3u), stream);
        sampleIndex_ = index;
        reversedIndex_ = reverseBits(index);
        dimension_ = 0;
        batchEnd_ = 0;
    }

    // The pair of `dimension` in the current sample, one at a time (get2D's reference).
    Vec2 pairAt(uint32_t dimension) const {
        uint32_t pairSeed = hashCombine(pixelHash_, dimension);
        // The pair's shuffled index: the index Owen-scrambled (a Laine-Karras permutation of its
        // reversed bits). Each coordinate is then the scramble of Sobol's point at that index, whose
        // own two reversals cancel against the index's: scrambled in reversed form, reversed once.
        uint32_t index = reverseBits(laineKarrasPermutation(reversedIndex_, pairSeed));
        // Per-coordinate seeds from the pair's hash by odd multipliers: distinct, and cheaper than rehashing.
        uint32_t x = laineKarrasPermutation(index, pairSeed * 0x68bc21ebu);
        uint32_t y = laineKarrasPermutation(sobolDimension1Reversed(index), pairSeed * 0x02e5be93u);
        // Both coordinates' bits reversed in one 64-bit reversal (12% less time per pair than two).
        uint64_t reversed = reverseBits64(uint64_t(y) << 32 | x);
        return {uintToUnitFloat(uint32_t(reversed >> 32)), uintToUnitFloat(uint32_t(reversed))};
    }

private:
    // Far beyond any path's dimension count (paths stop at kDepthCap bounces of a few pairs each).
    static constexpr uint32_t kShutterDimension = 0x5bd1e995u;

    uint32_t seed_;
    uint32_t pixelHash_ = 0;
    uint32_t sampleIndex_ = 0;
    uint32_t reversedIndex_ = 0;  // reverseBits(sampleIndex_), the scramble's input for every pair
    uint32_t dimension_ = 0;
    // get2D's pairs of dimensions [batchStart_, batchEnd_) of the current sample (none after start).
    uint32_t batchStart_ = 0, batchEnd_ = 0;
    Vec2 batch_[sampler_batch::kPairs];
};

}  // namespace gi
