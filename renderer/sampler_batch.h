// Eight consecutive dimension pairs of one sample of the Sampler's sequence at once, in AVX2
// (sampler.h). Bit for bit the scalar Sampler::pairAt: the same hash, Laine-Karras permutations,
// bit reversals and Sobol dimension, eight lanes per instruction. A path vertex draws four or five
// pairs, each of which costs the scalar code about 15 ns; the batch of eight costs about 23.
#pragma once
#include <cstdint>

#include "math.h"

namespace gi::sampler_batch {
constexpr int kPairs = 8;
}

#if defined(__AVX2__)
#include <immintrin.h>

namespace gi::sampler_batch {

inline __m256i laineKarras(__m256i x, __m256i seed) {
    x = _mm256_add_epi32(x, seed);
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x6c50b47cu))));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0xb82f1e52u))));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0xc7afe638u))));
    x = _mm256_xor_si256(x, _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x8d22f6e6u))));
    return x;
}

// reverseBits per lane: the bytes swapped, then each byte's nibbles reversed by table.
inline __m256i reverseBits(__m256i x) {
    const __m256i byteSwap = _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,  //
                                              3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12);
    const __m256i nibble = _mm256_setr_epi8(0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15,  //
                                            0, 8, 4, 12, 2, 10, 6, 14, 1, 9, 5, 13, 3, 11, 7, 15);
    const __m256i low = _mm256_set1_epi8(0x0f);
    x = _mm256_shuffle_epi8(x, byteSwap);
    __m256i lo = _mm256_shuffle_epi8(nibble, _mm256_and_si256(x, low));
    __m256i hi = _mm256_shuffle_epi8(nibble, _mm256_and_si256(_mm256_srli_epi16(x, 4), low));
    return _mm256_or_si256(_mm256_slli_epi16(lo, 4), hi);
}

// hashCombine(seed, v) per lane.
inline __m256i hashCombine(uint32_t seed, __m256i v) {
    __m256i x = _mm256_add_epi32(v, _mm256_set1_epi32(int(0x9e3779b9u + (seed << 6) + (seed >> 2))));
    x = _mm256_xor_si256(x, _mm256_set1_epi32(int(seed)));
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x7feb352du)));
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = _mm256_mullo_epi32(x, _mm256_set1_epi32(int(0x846ca68bu)));
    return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}

// sobolDimension1Reversed per lane. That dimension's generator matrix is Pascal's triangle mod 2,
// the fifth Kronecker power of [[1,1],[0,1]] (Lucas's theorem), so it is applied as five
// shift-and-mask steps, one per bit of the bit position.
inline __m256i sobolDimension1Reversed(__m256i v) {
    v = _mm256_xor_si256(v, _mm256_and_si256(_mm256_srli_epi32(v, 1), _mm256_set1_epi32(0x55555555)));
    v = _mm256_xor_si256(v, _mm256_and_si256(_mm256_srli_epi32(v, 2), _mm256_set1_epi32(0x33333333)));
    v = _mm256_xor_si256(v, _mm256_and_si256(_mm256_srli_epi32(v, 4), _mm256_set1_epi32(0x0f0f0f0f)));
    v = _mm256_xor_si256(v, _mm256_and_si256(_mm256_srli_epi32(v, 8), _mm256_set1_epi32(0x00ff00ff)));
    return _mm256_xor_si256(v, _mm256_srli_epi32(v, 16));
}

// uintToUnitFloat per lane.
inline __m256 toUnitFloat(__m256i x) {
    __m256 f = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(x, 8)), _mm256_set1_ps(0x1p-24f));
    return _mm256_min_ps(f, _mm256_set1_ps(0.99999994f));
}

// The pairs of dimensions first .. first + 7 of the sample whose pixel hash and reversed index
// are given (Sampler::pairAt), into out[0..7].
inline void pairs(uint32_t pixelHash, uint32_t reversedIndex, uint32_t first, Vec2* out) {
    static_assert(sizeof(Vec2) == 2 * sizeof(float));
    const __m256i dimensions = _mm256_add_epi32(_mm256_set1_epi32(int(first)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i pairSeed = hashCombine(pixelHash, dimensions);
    const __m256i index = reverseBits(laineKarras(_mm256_set1_epi32(int(reversedIndex)), pairSeed));
    const __m256i x = laineKarras(index, _mm256_mullo_epi32(pairSeed, _mm256_set1_epi32(int(0x68bc21ebu))));
    const __m256i y = laineKarras(sobolDimension1Reversed(index),
                                  _mm256_mullo_epi32(pairSeed, _mm256_set1_epi32(int(0x02e5be93u))));
    const __m256 fx = toUnitFloat(reverseBits(x)), fy = toUnitFloat(reverseBits(y));
    // (x0 y0 x1 y1 | x4 y4 x5 y5) and (x2 y2 x3 y3 | x6 y6 x7 y7), then their halves in order.
    const __m256 lo = _mm256_unpacklo_ps(fx, fy), hi = _mm256_unpackhi_ps(fx, fy);
    float* f = reinterpret_cast<float*>(out);
    _mm256_storeu_ps(f, _mm256_permute2f128_ps(lo, hi, 0x20));
    _mm256_storeu_ps(f + 8, _mm256_permute2f128_ps(lo, hi, 0x31));
}

}  // namespace gi::sampler_batch
#endif
