#include <gtest/gtest.h>

#include <set>

#include "renderer/sampler.h"
#include "renderer/sampling.h"

using namespace gi;

// Each 2D dimension pair is a (0,2)-sequence: the first 2^k points of a pixel put exactly one
// point in every elementary interval of area 2^-k (checked here for the 4x4 strata of 16 points).
TEST(Sampler, FirstSixteenSamplesStratifyEveryDimensionPair) {
    Sampler sampler(42);
    for (int dimensionPair = 0; dimensionPair < 6; ++dimensionPair) {
        std::set<int> cells;
        for (uint32_t i = 0; i < 16; ++i) {
            sampler.start(3, 5, i);
            Vec2 u;
            for (int d = 0; d <= dimensionPair; ++d) u = sampler.get2D();
            ASSERT_GE(u.x, 0);
            ASSERT_LT(u.x, 1);
            cells.insert(int(u.x * 4) * 4 + int(u.y * 4));
        }
        EXPECT_EQ(cells.size(), 16u) << "dimension pair " << dimensionPair;
    }
}

TEST(Sampler, PixelsAndSeedsDecorrelate) {
    Sampler a(1), b(1), c(2);
    a.start(0, 0, 0);
    b.start(1, 0, 0);
    c.start(0, 0, 0);
    Vec2 ua = a.get2D(), ub = b.get2D(), uc = c.get2D();
    EXPECT_NE(ua.x, ub.x);
    EXPECT_NE(ua.x, uc.x);
}

TEST(Sampler, MeanOfManySamplesIsOneHalf) {
    Sampler s(3);
    double sum = 0;
    const int n = 4096;
    for (int i = 0; i < n; ++i) {
        s.start(7, 9, uint32_t(i));
        s.get2D();
        sum += s.get2D().y;
    }
    EXPECT_NEAR(sum / n, 0.5, 1e-3);
}

TEST(Distribution1D, SamplesInProportionAndIgnoresBadWeights) {
    float w[] = {1, 0, 3, std::nanf(""), -2};
    Distribution1D d(w, 5);
    EXPECT_FLOAT_EQ(d.pmf(0), 0.25f);
    EXPECT_FLOAT_EQ(d.pmf(2), 0.75f);
    EXPECT_FLOAT_EQ(d.pmf(3), 0.0f);
    float pmf;
    EXPECT_EQ(d.sample(0.1f, &pmf), 0);
    EXPECT_EQ(d.sample(0.5f, &pmf), 2);
    EXPECT_FLOAT_EQ(pmf, 0.75f);
    float zeros[] = {0, 0};
    Distribution1D uniform(zeros, 2);
    EXPECT_FLOAT_EQ(uniform.pmf(1), 0.5f);
}

TEST(Warps, CosineHemisphereIsNormalisedAndUpward) {
    Sampler s(5);
    for (uint32_t i = 0; i < 256; ++i) {
        s.start(0, 0, i);
        Vec3 d = sampleCosineHemisphere(s.get2D());
        EXPECT_NEAR(length(d), 1.0f, 1e-5f);
        EXPECT_GE(d.z, 0.0f);
    }
}

// get2D's pairs come eight at a time where the CPU has AVX2 (sampler_batch.h): the same values as
// one at a time, across camera samples, streams and the shutter's own dimension.
TEST(Sampler, PairsInBatchesAreThePairsOneAtATime) {
    uint32_t state = 12345;
    auto next = [&] { return state = hashCombine(state, 0x2545f491u); };
    for (int trial = 0; trial < 5000; ++trial) {
        Sampler batched(next());
        if (trial % 2) batched.startStream(next(), next());
        else batched.start(int(next() % 4096), int(next() % 4096), next());
        const Sampler reference = batched;
        const int pairs = int(next() % 40);
        for (int k = 0; k < pairs; ++k) {
            Vec2 u = batched.get2D(), v = reference.pairAt(uint32_t(k));
            ASSERT_EQ(u.x, v.x) << "trial " << trial << ", pair " << k;
            ASSERT_EQ(u.y, v.y) << "trial " << trial << ", pair " << k;
        }
        EXPECT_EQ(batched.shutterTime(), reference.shutterTime());
    }
}
