// Integrator "auto": the prediction from pilot images (auto_select.h), on synthetic pilots whose
// noise and bias are known, and the renderer's resolution of "auto" into one technique.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <random>

#include "renderer/auto_select.h"
#include "renderer/integrators/progressive_photon_map.h"
#include "renderer/render.h"
#include "scenes.h"

namespace gi {
namespace {

using test::addIcosphere;
using test::buildFloorUnderRectLight;
using test::lambert;

constexpr int kPilotWidth = 64, kPilotHeight = 32, kPilotPixels = kPilotWidth * kPilotHeight;
constexpr double kTruth = 100;  // every pixel's true value, in sRGB codes

double srgbCodeOf(double linear) {
    double x = std::clamp(linear, 0.0, 1.0);
    return 255 * (x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
}
double linearOf(double code) {
    double v = code / 255;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}
// d code / d linear at `code`: the delta method's slope.
double slopeAt(double code) {
    double x = linearOf(code);
    return 255 * 1.055 / 2.4 * std::pow(x, 1 / 2.4 - 1);
}

// kAutoPilotBatches batches whose every value is linear(kTruth + bias) + N(0, (sigma / f')^2): a
// noise of sigma codes to first order, each batch rendered in `seconds`.
AutoPilot syntheticPilot(const std::string& integrator, double bias, double sigma, double seconds, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma / slopeAt(kTruth + bias));
    AutoPilot pilot;
    pilot.integrator = integrator;
    pilot.width = kPilotWidth;
    pilot.height = kPilotHeight;
    pilot.batches.resize(kAutoPilotBatches);
    for (auto& batch : pilot.batches) {
        batch.resize(kPilotPixels * 3);
        for (float& v : batch) v = float(linearOf(kTruth + bias) + noise(rng));
    }
    pilot.batchSamples.assign(kAutoPilotBatches, 1.0);  // one sample per pixel in `seconds`
    pilot.steadySecondsPerSample = seconds / kPilotPixels;
    pilot.complete = true;
    return pilot;
}

// As syntheticPilot, but from two caches of kAutoPilotBatches / 2 batches each: every value of a
// cache is off by its own N(0, cacheSigma^2) codes, shared by the cache's batches, and value i by
// `bias(i)` codes (the technique's fixed error: the same in both caches).
template <class Bias>
AutoPilot twoCachePilot(const std::string& integrator, Bias bias, double sigma, double cacheSigma, double seconds,
                        uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    AutoPilot pilot = syntheticPilot(integrator, 0, sigma, seconds, seed);
    std::vector<double> offset(kPilotPixels * 3);
    for (size_t k = 0; k < pilot.batches.size(); ++k) {
        if (k % (kAutoPilotBatches / 2) == 0)
            for (size_t i = 0; i < offset.size(); ++i) offset[i] = bias(i) + cacheSigma * gauss(rng);
        for (size_t i = 0; i < offset.size(); ++i) {
            double code = kTruth + offset[i];
            pilot.batches[k][i] = float(linearOf(code) + sigma / slopeAt(code) * gauss(rng));
        }
    }
    pilot.firstCacheBatches = kAutoPilotBatches / 2;
    return pilot;
}

const AutoPrediction& prediction(const AutoChoice& choice, const std::string& integrator) {
    for (const AutoPrediction& p : choice.predictions)
        if (p.integrator == integrator) return p;
    throw std::runtime_error("no prediction for " + integrator);
}

// Noise and bias estimates: a path tracer of sigma 2 codes per batch and a cache of bias 5,
// sigma 2. n = 2048 * 3 values, K = 8 batches. To first order noise(1) is the values' mean sample
// variance over K - 1 = 7 degrees of freedom, relative standard error sqrt(2 / (7 n)) = 0.7%; the
// second-order terms (f''/f' = -4.6 per linear unit at code 100, sigma 0.0054 linear) are below
// 0.1%: 4 sigma and those, 3%. The cache's bias estimate mean((f(M) - f(R))^2) - Var(R) - noise(1/K)
// with f(M) - f(R) = 5 + d, d ~ N(0, 4/8 + 4/8): each term's variance is 4 * 25 * 1 + 2 * 1^2 =
// 102, so the mean's standard error is sqrt(102 / n) = 0.13 codes^2: 4 sigma is 0.52.
TEST(Auto, EstimatesNoiseAndBiasOfSyntheticPilots) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 2, 0.1, 1),
                                     syntheticPilot("irradianceCache", 5, 2, 0.1, 2)};
    // The final render: 4x the pilot's pixels in 4 s, so 10x a batch's 0.1 s per pixel (r = 0.1).
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    const AutoPrediction& path = prediction(choice, "path");
    const AutoPrediction& cache = prediction(choice, "irradianceCache");
    EXPECT_NEAR(path.noise, 4, 0.03 * 4);
    EXPECT_NEAR(cache.noise, 4, 0.03 * 4);
    EXPECT_NEAR(cache.bias, 25, 0.52);
    EXPECT_LT(path.bias, 0.52);  // it is the reference here: nothing but noise
    EXPECT_EQ(path.batches, kAutoPilotBatches);
    // Small noise scales as the samples: noise(r) = r noise(1), to the second-order terms above.
    EXPECT_NEAR(predictedNoise(pilots[0], 0.1), 0.1 * path.noise, 0.001 * path.noise);
    // Consistent: bias * min(1, K r) + noise(r); a cache: bias + noise(r).
    EXPECT_NEAR(path.predictedRmse * path.predictedRmse,
                path.bias * std::min(1.0, kAutoPilotBatches * 0.1) + predictedNoise(pilots[0], 0.1), 1e-9);
    EXPECT_NEAR(cache.predictedRmse * cache.predictedRmse, cache.bias + predictedNoise(pilots[1], 0.1),
                1e-9);
    EXPECT_EQ(choice.integrator, "path");
}

// The heavy tail that a few small pilot images miss (fireflies: a caustic through glass): every
// sample is 0.1 + N(0, 0.05^2) linear, and one in 500 is a firefly of 20. Batches of 16 samples
// clamp a firefly (20 / 16 > 1) to code 255; a render of 256 does not (20 / 256 = 0.08), so its
// error is the firefly's full size, and the pilot's codes scaled by 1/time predict about a fifth of
// it. The prediction from linear values must reach the render's true error, here simulated: 256
// samples of the same law per value. The firefly term dominates both; the pilot sees 6144 * 8 *
// (1 - (1 - 1/500)^16) = 1570 fireflies, so its estimate's relative standard error is
// 1 / sqrt(1570) = 2.5% (4 sigma: 10%), and the truth's (6144 values) about 2%: the prediction
// must be at least 0.85 of the truth. It may be pessimistic (the point f is taken at, the
// others' mean, is noisy, and f is concave), but by less than 2x.
TEST(Auto, PredictsTheErrorOfHeavyTailedNoise) {
    constexpr int kBatchSamples = 16, kRenderSamples = 256, kValues = kPilotPixels * 3;
    constexpr double kBase = 0.1, kSigma = 0.05, kFirefly = 20, kFireflyOdds = 1.0 / 500;
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, 1.0);
    // The mean of `samples` samples of the law above.
    auto pixel = [&](int samples) {
        std::binomial_distribution<int> fireflies(samples, kFireflyOdds);
        return kBase + kSigma / std::sqrt(double(samples)) * gauss(rng) + kFirefly * fireflies(rng) / samples;
    };
    AutoPilot pilot;
    pilot.width = kPilotWidth;
    pilot.height = kPilotHeight;
    pilot.batches.assign(kAutoPilotBatches, std::vector<float>(kValues));
    for (auto& batch : pilot.batches)
        for (float& v : batch) v = float(pixel(kBatchSamples));
    const auto& batches = pilot.batches;
    const double truthCode = srgbCodeOf(kBase + kFirefly * kFireflyOdds);
    double trueMse = 0, pilotCodesMse = 0;
    for (int i = 0; i < kValues; ++i) {
        double e = srgbCodeOf(pixel(kRenderSamples)) - truthCode;
        trueMse += e * e / kValues;
        double d = srgbCodeOf(batches[0][size_t(i)]) - srgbCodeOf(batches[1][size_t(i)]);
        pilotCodesMse += d * d / 2 / kValues;
    }
    const double q = double(kBatchSamples) / kRenderSamples;
    double predicted = predictedNoise(pilot, q);
    EXPECT_GE(predicted, 0.85 * trueMse);
    EXPECT_LE(predicted, 2.0 * trueMse);
    EXPECT_LT(pilotCodesMse * q, 0.5 * trueMse);  // the scene is one that codes scaled by time miss
}

// The choice as the budget grows: a path tracer of sigma 20 per batch (its MSE 400 r to first
// order) against a cache of bias b, sigma 2 (MSE b^2 + 4 r). The cache's bias estimate now has R's
// noise in it: f(M) - f(R) = b + d, d ~ N(0, 400/8 + 4/8), so its standard error is
// sqrt((4 b^2 50.5 + 2 50.5^2) / n): 1.3 for b = 3 and 1.6 for b = 5; the path tracer's noise at
// sigma 20 (0.054 linear at code 100) is f'' -> up to 5% above first order: the choices below hold
// within 4 sigma of both.
TEST(Auto, ChoosesTheCacheAtShortBudgetsAndThePathTracerAtLongOnes) {
    // 4 s, r = 0.1: the path tracer 40 (its margin: 32), the cache 9 + 0.4 (at most 15.6).
    std::vector<AutoPilot> shortRun = {syntheticPilot("path", 0, 20, 0.1, 3),
                                       syntheticPilot("irradianceCache", 3, 2, 0.1, 4)};
    EXPECT_EQ(predictFromPilots(shortRun, kPilotPixels, 4.0 * kPilotPixels, 4.0).integrator, "irradianceCache");
    // 40 s, r = 0.01: the path tracer 4 (margin 3.2), the cache 25 + 0.04 (at least 18.6).
    std::vector<AutoPilot> longRun = {syntheticPilot("path", 0, 20, 0.1, 5),
                                      syntheticPilot("irradianceCache", 5, 2, 0.1, 6)};
    AutoChoice choice = predictFromPilots(longRun, kPilotPixels, 4.0 * kPilotPixels, 40.0);
    EXPECT_EQ(choice.integrator, "path");
    // sqrt(400 * 0.01) = 2 (its bias term: R's noise, 50 * 0.08, removed within 1.6 * 0.08);
    // noise 2.7% (4 sigma of its estimate) and up to 5% of second order in MSE: 5% in RMSE.
    EXPECT_NEAR(prediction(choice, "path").predictedRmse, 2.0, 0.1);
}

TEST(Auto, LeavesOutIncompletePilotsAndFallsBackOnThePathTracer) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 20, 0.1, 5), AutoPilot{"photonMapFinalGather"}};
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_EQ(choice.integrator, "path");
    EXPECT_FALSE(prediction(choice, "photonMapFinalGather").complete);
    EXPECT_NE(choice.summary().find("photonMapFinalGather (no pilot in time: 0 of 8 batches"), std::string::npos);
    // Not even the path tracer's pilot: nothing to compare, the unbiased technique.
    EXPECT_EQ(predictFromPilots({AutoPilot{"path"}}, kPilotPixels, 4.0 * kPilotPixels, 4.0).integrator, "path");
}

// A consistent technique brighter than the path tracer where the path tracer misses light (its
// pilot has low noise but is 30 codes dark): the consistent estimators' inverse-variance mean
// sides with the less noisy one, and the path tracer's miss counts against it.
TEST(Auto, ThePathTracersMissCountsAgainstIt) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", -30, 10, 0.1, 6),
                                     syntheticPilot("progressivePhotonMap", 0, 3, 0.1, 7)};
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_EQ(choice.integrator, "progressivePhotonMap");
    const AutoPrediction& path = prediction(choice, "path");
    EXPECT_GT(path.bias, 500);
    // A consistent technique's bias falls with time as its noise does: b2 * min(1, K r) + noise(r),
    // r = 0.1 (a batch's 0.1 s per pixel against the render's 4 s for 4x the pixels).
    EXPECT_NEAR(path.predictedRmse * path.predictedRmse,
                path.bias * std::min(1.0, kAutoPilotBatches * 0.1) + predictedNoise(pilots[0], 0.1),
                1e-9 * path.bias);
}

// A light the path tracer finds once in a long while (a sun through glass) leaves its batches dark
// but for one, whose fireflies bring the pilot's mean up to the photon map's: the miss is judged on
// the typical batch (the median), so it still counts against the path tracer (judged on the mean,
// the photon map's difference from it would count as its blur, and the path tracer be chosen).
TEST(Auto, AMissIsSeenPastOneBrightBatch) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", -30, 10, 0.1, 6),
                                     syntheticPilot("progressivePhotonMap", 0, 3, 0.1, 7)};
    double pathSum = 0, progressiveSum = 0;
    for (const auto& batch : pilots[0].batches)
        for (float v : batch) pathSum += v;
    for (const auto& batch : pilots[1].batches)
        for (float v : batch) progressiveSum += v;
    // A firefly in one value of every 100 of one batch carries the difference of the means: the
    // means agree, and the pixels' codes clip, so the noise they show is far below their size.
    auto& batch = pilots[0].batches[3];
    const double lift = (progressiveSum - pathSum) / double((batch.size() + 99) / 100);
    for (size_t i = 0; i < batch.size(); i += 100) batch[i] += float(lift);
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_EQ(choice.integrator, "progressivePhotonMap");
    EXPECT_GT(prediction(choice, "path").predictedRmse, 3 * prediction(choice, "progressivePhotonMap").predictedRmse);
}

// The pilots' pixels: the render's own, in about kAutoPilotTiles tiles of kAutoPilotPixels in all,
// spread over the image and inside it; a render of at most twice that is its own pilot.
TEST(Auto, PilotsRenderTheRendersOwnPixelsInTiles) {
    for (auto [width, height] : {std::pair{160, 120}, std::pair{1024, 768}, std::pair{1920, 1080},
                                 std::pair{2000, 40}, std::pair{60, 60}}) {
        const PixelMosaic mosaic = pilotMosaic(width, height);
        ASSERT_GT(mosaic.tile, 0) << width << "x" << height;
        EXPECT_EQ(mosaic.tiles() % mosaic.across, 0);
        EXPECT_GE(mosaic.tiles(), kAutoPilotTiles - 2);
        EXPECT_LE(mosaic.tiles(), kAutoPilotTiles + 2);
        const double pixels = double(mosaic.width()) * mosaic.height();
        if (height > 100) {  // room for the tiles' full size
            EXPECT_GT(pixels, 0.75 * kAutoPilotPixels);
            EXPECT_LT(pixels, 1.3 * kAutoPilotPixels);
        }
        int left = width, right = 0;
        for (int t = 0; t < mosaic.tiles(); ++t) {
            EXPECT_GE(mosaic.x0[size_t(t)], 0);
            EXPECT_GE(mosaic.y0[size_t(t)], 0);
            EXPECT_LE(mosaic.x0[size_t(t)] + mosaic.tile, width);
            EXPECT_LE(mosaic.y0[size_t(t)] + mosaic.tile, height);
            left = std::min(left, mosaic.x0[size_t(t)]);
            right = std::max(right, mosaic.x0[size_t(t)] + mosaic.tile);
        }
        EXPECT_GT(right - left, width / 2);  // spread over the image, not bunched in one place
    }
    EXPECT_EQ(pilotMosaic(40, 30).tile, 0);
    EXPECT_EQ(pilotMosaic(64, 32).tile, 0);
}

// A cache's own noise (two caches of different seeds differ by it) is told from its fixed bias:
// cache noise 3 codes (9), bias 2 (4), batch noise 2. The two caches' mean difference, about
// 2 * 9 + 2 * 4 / 4 = 20, less the batches' noise, over 2: its standard error over n = 6144
// values is about 2 * 20 / sqrt(n) / 2 = 0.26, 4 sigma 1.0; the bias then carries R's noise (the
// path tracer's: 4 / 8) and half the cache noise's error: within 1.2. The prediction at the
// budget: the bias, plus the cache noise as the records gain paths (K / 2 r, r = 0.1, of it) or
// all of it (records not refined), or the photon map's share (its photons over the render's).
TEST(Auto, SeparatesACachesNoiseFromItsBias) {
    auto fixed = [](size_t) { return 2.0; };
    AutoPilot path = syntheticPilot("path", 0, 2, 0.1, 11);
    AutoPilot refined = twoCachePilot("irradianceCache", fixed, 2, 3, 0.1, 12);
    refined.records = refined.refinesRecords = true;
    AutoPilot fixedRecords = refined;
    fixedRecords.integrator = "adaptiveIrradianceCache";
    fixedRecords.refinesRecords = false;
    AutoPilot photons = twoCachePilot("photonMapFinalGather", fixed, 2, 3, 0.1, 13);
    photons.photonShare = 0.05;
    AutoChoice choice = predictFromPilots({path, refined, fixedRecords, photons}, kPilotPixels,
                                          4.0 * kPilotPixels, 4.0);
    for (const char* name : {"irradianceCache", "adaptiveIrradianceCache", "photonMapFinalGather"}) {
        const AutoPrediction& p = prediction(choice, name);
        EXPECT_NEAR(p.cacheNoise, 9, 1.0) << name;
        EXPECT_NEAR(p.bias, 4, 1.2) << name;
        EXPECT_NEAR(p.noise, 4, 0.2) << name;  // from each cache's own batches: no cache noise in it
    }
    auto mse = [&](const char* name) { return std::pow(prediction(choice, name).predictedRmse, 2); };
    const AutoPrediction& r = prediction(choice, "irradianceCache");
    EXPECT_NEAR(mse("irradianceCache"), r.bias + r.cacheNoise * 0.4 + predictedNoise(refined, 0.1), 1e-9);
    const AutoPrediction& f = prediction(choice, "adaptiveIrradianceCache");
    EXPECT_NEAR(mse("adaptiveIrradianceCache"), f.bias + f.cacheNoise + predictedNoise(fixedRecords, 0.1), 1e-9);
    const AutoPrediction& g = prediction(choice, "photonMapFinalGather");
    EXPECT_NEAR(mse("photonMapFinalGather"), g.bias + g.cacheNoise * 0.05 + predictedNoise(photons, 0.1), 1e-9);
    // The log's parts of each prediction are these terms, and they add up to it.
    EXPECT_NEAR(r.predictedBias, r.bias, 1e-9);
    EXPECT_NEAR(r.predictedCacheNoise, r.cacheNoise * 0.4, 1e-9);
    EXPECT_NEAR(r.predictedSampleNoise, predictedNoise(refined, 0.1), 1e-9);
    for (const AutoPrediction& p : choice.predictions)
        EXPECT_NEAR(p.predictedBias + p.predictedCacheNoise + p.predictedSampleNoise, mse(p.integrator.c_str()), 1e-9)
            << p.integrator;
    char part[128];
    std::snprintf(part, sizeof part, "irradianceCache %.2f (%.2f +- %.2f + %.2f + %.2f; %.0f spp)", r.predictedRmse,
                  r.predictedBias, r.biasError, r.predictedCacheNoise, r.predictedSampleNoise, r.predictedSamples);
    EXPECT_NE(choice.summary().find(part), std::string::npos) << choice.summary();
}

// Two caches of the same camera samples (auto_pilots.cpp: common random numbers): batch k of each
// has the same sample noise, sigma = 10 codes, and each cache its own offset of 2 codes (c2 = 4)
// beside a bias of 2 codes (4 codes squared). Unpaired, c2 would be the means' difference less
// both means' noise, 2 x 25 codes squared, each estimated to about 1%: within 1 either way. Paired,
// the difference has no sample noise, and c2 is within 4 sigma of its estimate (the difference's
// squared mean over n = 6144 values: 8 (1 +- 4 sqrt(2 / n))), 0.3. The mean's noise is then that
// of one cache's (the batches' noise is shared), 25 and not 12.5: the bias holds only 4 if that is
// counted, within 4 sigma of e (each value's (2 + d)^2 with d ~ N(0, 25 + 2): sqrt((4 * 4 * 27 + 2
// * 27^2) / n) = 0.54, 4 sigma 2.2) and of the noises.
TEST(Auto, PairsTheTwoCachesSamples) {
    std::mt19937 rng(41);
    std::normal_distribution<double> gauss(0.0, 1.0);
    constexpr double kSigma = 10, kCacheSigma = 2, kBias = 2;
    AutoPilot cache = syntheticPilot("irradianceCache", 0, 0, 0.1, 41);
    cache.firstCacheBatches = kAutoPilotBatches / 2;
    std::vector<double> first(kPilotPixels * 3), second(kPilotPixels * 3);
    for (size_t i = 0; i < first.size(); ++i) {
        first[i] = kBias + kCacheSigma * gauss(rng);
        second[i] = kBias + kCacheSigma * gauss(rng);
    }
    const size_t pairs = kAutoPilotBatches / 2;
    for (size_t k = 0; k < pairs; ++k)
        for (size_t i = 0; i < first.size(); ++i) {
            const double noise = kSigma * gauss(rng);
            const double a = kTruth + first[i], b = kTruth + second[i];
            cache.batches[k][i] = float(linearOf(a) + noise / slopeAt(a));
            cache.batches[k + pairs][i] = float(linearOf(b) + noise / slopeAt(b));
        }
    AutoChoice choice = predictFromPilots({syntheticPilot("path", 0, 2, 0.1, 42), cache}, kPilotPixels,
                                          4.0 * kPilotPixels, 4.0);
    const AutoPrediction& p = prediction(choice, "irradianceCache");
    EXPECT_NEAR(p.cacheNoise, kCacheSigma * kCacheSigma, 0.3);
    EXPECT_NEAR(p.bias, kBias * kBias, 2.5);
}

// Refined records' own noise falls as 1 / their paths, which grow more slowly than the samples
// where the render keeps making records (recordPathsShare). A pilot whose records have 100 paths,
// 0.5 per pixel after 4 samples per pixel, growing as samples^0.2, 5 rays a path, 2 rays a sample:
// at 1000 samples per pixel of 4 x its pixels the render's records are 0.5 x 8192 x 250^0.2 =
// 12,358 with 2 x 1000 x 8192 / 5 / 12,358 = 265 paths each, so its cache noise is 100 / 265 of the
// pilot's, where the samples' law said 4 batches x 0.001.
TEST(Auto, RefinedRecordsNoiseFallsWithTheirPaths) {
    auto fixed = [](size_t) { return 0.0; };
    AutoPilot cache = twoCachePilot("irradianceCache", fixed, 1, 3, 0.1, 43);
    cache.records = cache.refinesRecords = true;
    cache.recordPaths = 100;
    cache.recordsPerPixel = 0.5;
    cache.recordGrowth = 0.2;
    cache.recordRaysPerPath = 5;
    cache.passRaysPerSample = 2;
    cache.cacheSamples = 4;
    // 400 s: r = 0.1 s / (400 s / 4) = 0.001 of a batch's samples, 1000 samples per pixel.
    AutoChoice choice = predictFromPilots({syntheticPilot("path", 0, 1, 0.1, 44), cache}, kPilotPixels,
                                          4.0 * kPilotPixels, 400.0);
    const AutoPrediction& p = prediction(choice, "irradianceCache");
    const double records = 0.5 * 4 * kPilotPixels * std::pow(1000.0 / 4, 0.2);
    const double paths = 2 * 1000.0 * 4 * kPilotPixels / 5 / records;
    EXPECT_NEAR(paths, 265, 1);
    EXPECT_GT(p.cacheNoise, 8);
    EXPECT_NEAR(p.predictedCacheNoise, p.cacheNoise * 100 / paths, 1e-6 * p.cacheNoise);
}

// A photon technique whose second cache traced 4x the first's photons: shares 0.05 and 0.2 of the
// render's, so x = 20 and 5. Each batch's noise is a + b x codes squared (a = 1, b = 0.2: 5 and
// 2), each cache's own noise 0.2 x (4 and 1), its bias 2 codes. At the render (x = 1, r = 0.1)
// the samples' noise is (a + b) r = 0.12 (both caches' noise pooled said 0.35) and the cache's
// 0.2. Estimates: each cache's noise from 4 batches of n = 6144 values, 1% (a + b within 3%,
// second-order terms below 1%: 6%); the caches' difference 5, its standard error about
// 2 * 5 / sqrt(n) = 0.13, four-fifths of it the first cache's (4 sigma: 0.4); the bias then
// within 1.2, as for alike caches.
TEST(Auto, LearnsThePhotonMapsNoiseLaw) {
    constexpr double x1 = 20, x2 = 5, a = 1, b = 0.2, cacheNoise = 0.2, bias = 2;
    std::mt19937 rng(61);
    std::normal_distribution<double> gauss(0.0, 1.0);
    AutoPilot photons = syntheticPilot("photonMapFinalGather", 0, 0, 0.1, 61);
    std::vector<double> offset(kPilotPixels * 3);
    for (size_t k = 0; k < photons.batches.size(); ++k) {
        const double x = k < kAutoPilotBatches / 2 ? x1 : x2;
        if (k % (kAutoPilotBatches / 2) == 0)
            for (double& o : offset) o = bias + std::sqrt(cacheNoise * x) * gauss(rng);
        for (size_t i = 0; i < offset.size(); ++i) {
            const double code = kTruth + offset[i];
            photons.batches[k][i] = float(linearOf(code) + std::sqrt(a + b * x) / slopeAt(code) * gauss(rng));
        }
    }
    photons.firstCacheBatches = kAutoPilotBatches / 2;
    photons.photonShare = 1 / x1;
    photons.secondPhotonShare = 1 / x2;
    AutoChoice choice = predictFromPilots({syntheticPilot("path", 0, 2, 0.1, 62), photons}, kPilotPixels,
                                          4.0 * kPilotPixels, 4.0);
    const AutoPrediction& p = prediction(choice, "photonMapFinalGather");
    EXPECT_NEAR(p.predictedSampleNoise, (a + b) * 0.1, 0.06 * (a + b) * 0.1);
    EXPECT_NEAR(p.cacheNoise, cacheNoise * x1, 0.4);
    EXPECT_NEAR(p.predictedCacheNoise, cacheNoise, 0.4 / x1);
    EXPECT_NEAR(p.bias, bias * bias, 1.2);
    // Without the second cache's photon count, the old pooled estimate: about 0.35.
    photons.secondPhotonShare = 0;
    const AutoChoice pooled =
        predictFromPilots({syntheticPilot("path", 0, 2, 0.1, 62), photons}, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_GT(prediction(pooled, "photonMapFinalGather").predictedSampleNoise, 0.3);
}

// The progressive photon map's pilot blurs (+-6 codes on alternate values, the image's mean kept):
// where the path tracer misses nothing, R weighs it by its blur (36) with its noise, so it takes
// a quarter of R (the path tracer's mean has noise 100 / 8 = 12.5), and R's error, 1 / the
// weights' sum, is removed from the others' bias: a cache of bias 2 measures 4 codes squared,
// where R of noise weights alone measured the blur's 36 more. The photon map's own bias is its blur,
// scaled to the render's narrower radii in the world (its pixels a quarter of the pilot's: 9).
TEST(Auto, TheReferenceWeighsThePhotonMapsBlur) {
    auto blur = [](size_t i) { return i % 2 ? 6.0 : -6.0; };
    auto fixed = [](size_t) { return 2.0; };
    AutoPilot progressive = twoCachePilot("progressivePhotonMap", blur, 1, 0, 0.1, 21);
    progressive.firstCacheBatches = 0;  // one photon map per sample: no cache
    std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 10, 0.1, 22), progressive,
                                     twoCachePilot("irradianceCache", fixed, 2, 0.5, 0.1, 23)};
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    // Its estimate's standard error: about sqrt(2 * 9.3^2 + 4 * 4 * 9.3) / sqrt(n) = 0.2; 4 sigma
    // and the second-order terms of +-6 codes, 1.2.
    EXPECT_NEAR(prediction(choice, "irradianceCache").bias, 4, 1.2);
    EXPECT_NEAR(prediction(choice, "progressivePhotonMap").bias, 36.0 / 4, 2.5 / 4);
}

// The progressive photon map's samples: a camera part of sigma_c = 2 codes, which its radii do not
// touch, and a photons' part of sigma_p = 2 codes at the first radius, whose variance grows as
// 1 / s_i. Pilot batches of one sample (index 0), and its ray-traced part alone, darker (code 60)
// with the camera's noise as it is in the image (at code 100). The render of N = 10 samples (r =
// 0.1) has (sigma_c^2 + sigma_p^2 g) / 10 codes squared, g the mean of 1 / s_i over its samples;
// all of it grown (the radius law alone) is (sigma_c^2 + sigma_p^2) g / 10 (g = 1.57: 1.26 against
// 1.03), and with the part's noise taken at its own code 60, where f is steeper, 1.33. The estimates
// (n = 2048 * 3 values, 7 degrees of freedom each, 0.7% each) and their difference: 4 sigma, 5%.
TEST(Auto, OnlyThePhotonMapsPhotonNoiseGrowsAsItsRadiiShrink) {
    constexpr double sigmaCamera = 2, sigmaPhotons = 2, alpha = 2.0 / 3;
    std::mt19937 rng(71);
    std::normal_distribution<double> gauss(0.0, 1.0);
    AutoPilot progressive =
        syntheticPilot("progressivePhotonMap", 0, std::hypot(sigmaCamera, sigmaPhotons), 0.1, 71);
    progressive.radiusAlpha = alpha;
    for (int k = 0; k < kAutoPilotBatches; ++k) {
        std::vector<float> batch(kPilotPixels * 3);
        for (float& v : batch) v = float(linearOf(60) + sigmaCamera / slopeAt(kTruth) * gauss(rng));
        progressive.rayTracedBatches.push_back(std::move(batch));
    }
    progressive.rayTracedBatchSamples.assign(kAutoPilotBatches, 1.0);
    double g = 0;
    for (uint32_t i = 0; i < 10; ++i)
        g += std::pow(double(ProgressivePhotonMapIntegrator::radiusScale(i, float(alpha))), -2.0) / 10;
    const AutoPilot path = syntheticPilot("path", 0, 2, 0.1, 72);
    auto sampleNoise = [&](const AutoPilot& pilot) {
        return prediction(predictFromPilots({path, pilot}, kPilotPixels, 4.0 * kPilotPixels, 4.0),
                          "progressivePhotonMap")
            .predictedSampleNoise;
    };
    const double expected = (sigmaCamera * sigmaCamera + sigmaPhotons * sigmaPhotons * g) / 10;
    EXPECT_NEAR(sampleNoise(progressive), expected, 0.05 * expected);
    progressive.rayTracedBatches.clear();
    progressive.rayTracedBatchSamples.clear();
    const double grown = (sigmaCamera * sigmaCamera + sigmaPhotons * sigmaPhotons) * g / 10;
    EXPECT_NEAR(sampleNoise(progressive), grown, 0.05 * grown);
    EXPECT_GT(grown, 1.2 * expected);
}

// Beside a light the 3x3 window's mean clips at code 255, where f is flat: a centre taken there
// would hide the pixel's own noise. Every other column is a light (linear 100), the others code
// 100 with a noise of 10 codes a batch: noise(1) is half the values' 100, to the estimate's
// standard error (about sqrt(2 / (7 n / 2)) = 1%) and the second-order terms of 10 codes (up to
// 5%): within 8%. With the window's centre on every value it was 0.
TEST(Auto, SeesTheNoiseBesideALight) {
    AutoPilot path = syntheticPilot("path", 0, 10, 0.1, 51);
    for (auto& batch : path.batches)
        for (size_t i = 0; i < batch.size(); ++i)
            if (i / 3 % 2 == 0) batch[i] = 100.0f;
    EXPECT_NEAR(predictedNoise(path, 1.0), 50, 0.08 * 50);
}

// R is mixed in codes. Half the image is a light (linear 100, code 255); the progressive photon
// map's blur moves 50 of each of its values into a dark one (code 100 -> 255; the image's mean kept, so
// the path tracer misses nothing). Its blur, about 0.5 * 155^2 codes squared, gives it a weight of
// about 1 / 12,000 beside the path tracer's 1 / 6.25 (noise 10 codes on the dark values, over K = 8
// batches, on half the values): mixed as linear values, its 50 still moves R's dark values by
// several codes (each 0.01 linear there is 3.7 codes; the cache's bias estimate came out at 22.4);
// mixed in codes, by 0.1 code. The cache's bias, 2 codes on the dark values, is 2 codes squared; its
// estimate's standard error is about sqrt(0.5 * (2 * 12.6^2 + 4 * 4 * 12.6) / n) = 0.2: within 1.
TEST(Auto, TheReferenceIsMixedInCodes) {
    const double light = 100, spill = 50;
    // The right half.
    auto dark = [](size_t i) { return i / 3 % kPilotWidth >= kPilotWidth / 2; };
    AutoPilot path = syntheticPilot("path", 0, 0, 0.1, 41);
    AutoPilot progressive = syntheticPilot("progressivePhotonMap", 0, 0, 0.1, 42);
    AutoPilot cache = syntheticPilot("irradianceCache", 0, 0, 0.1, 43);
    std::mt19937 rng(44);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (size_t k = 0; k < path.batches.size(); ++k)
        for (size_t i = 0; i < path.batches[k].size(); ++i) {
            if (!dark(i)) {
                path.batches[k][i] = float(light);
                progressive.batches[k][i] = float(light - spill);
                cache.batches[k][i] = float(light);
                continue;
            }
            path.batches[k][i] = float(linearOf(kTruth) + 10 / slopeAt(kTruth) * gauss(rng));
            progressive.batches[k][i] = float(linearOf(kTruth) + spill + gauss(rng) / slopeAt(kTruth));
            cache.batches[k][i] = float(linearOf(kTruth + 2) + 2 / slopeAt(kTruth + 2) * gauss(rng));
        }
    AutoChoice choice = predictFromPilots({path, progressive, cache}, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_NEAR(prediction(choice, "irradianceCache").bias, 2, 1.0);
}

// A cache whose first samples cost more (records made where pixels first need them): its
// pilot's time slices hold 1, 2 and then 4 samples per pixel (mean 3.375), of noise 64 / s codes
// squared each, and its last batch ran at 0.01 s a sample (its first took far longer).
// The render (4x the pixels in 4 s, 1 s per pilot image's worth of pixels) takes 100 samples at
// that rate: noise 64 / 100 = 0.64, the ratio 3.375 / 100. The unequal batches' mean is weighted
// by their samples (variance 64 / 27), which noise(1 / K) of batches scaled to the mean's samples
// removes: its bias, 0, within 4 sigma of the estimate (sqrt(2 * 2.4^2 / n) = 0.04).
TEST(Auto, CountsSamplesAtTheRateOfThePilotsLastBatches) {
    const std::vector<double> samples = {1, 2, 4, 4, 4, 4, 4, 4};
    std::mt19937 rng(31);
    std::normal_distribution<double> gauss(0.0, 1.0);
    AutoPilot cache = syntheticPilot("irradianceCache", 0, 0, 0.5, 31);
    for (size_t k = 0; k < cache.batches.size(); ++k)
        for (float& v : cache.batches[k])
            v = float(linearOf(kTruth) + 8 / std::sqrt(samples[k]) / slopeAt(kTruth) * gauss(rng));
    cache.batchSamples = samples;
    cache.steadySecondsPerSample = 0.01 / kPilotPixels;
    AutoChoice choice = predictFromPilots({syntheticPilot("path", 0, 0.5, 0.1, 32), cache}, kPilotPixels,
                                          4.0 * kPilotPixels, 4.0);
    const AutoPrediction& p = prediction(choice, "irradianceCache");
    EXPECT_NEAR(p.noise, 64 / 3.375, 0.05 * 64 / 3.375);  // one batch of the mean's samples
    EXPECT_LT(p.bias, 0.16);
    EXPECT_NEAR(p.predictedRmse * p.predictedRmse, p.bias + predictedNoise(cache, 3.375 / 100), 1e-9);
    EXPECT_NEAR(predictedNoise(cache, 3.375 / 100), 0.64, 0.05);
}

// A refined cache's render pays for its records as it goes (AutoPilot's start-up and refinement
// rates): its start-up grows as the log of the samples, and past the fill's rays every ray of its
// passes, start-up records included, costs a record ray more. Synthetic rates: 1 us a pixel
// sample, 2 rays a sample besides the records, 0.5 us a record ray, a fill of 10^5 rays, a start-up
// of 0.05 s at 4 samples per pixel growing by 0.02 s per unit of ln(samples), all on the pilot's
// pixels; the render has 4 times them and 4 s. The samples it is predicted to take spend the 4 s.
TEST(Auto, ARefinedCachesSamplesPayForItsRecords) {
    AutoPilot cache = syntheticPilot("irradianceCache", 0, 1, 0.01, 47);
    cache.records = cache.refinesRecords = true;
    cache.steadySecondsPerSample = 1e-6;
    cache.steadyRaysPerSample = 2;
    cache.recordRaySeconds = 0.5e-6;
    cache.fillRays = 1e5;
    cache.startupSeconds = 0.05;
    cache.startupGrowthSeconds = 0.02;
    cache.startupSamples = 4;
    const double pixels = 4.0 * kPilotPixels, seconds = 4.0;
    AutoChoice choice = predictFromPilots({syntheticPilot("path", 0, 1, 0.1, 48), cache}, kPilotPixels, pixels, seconds);
    const double n = prediction(choice, "irradianceCache").predictedSamples;
    const double startup = 4 * (0.05 + 0.02 * std::log(n / 4));
    const double refinement = 0.5e-6 * (n * pixels * 2 + startup / 0.5e-6 - 4 * 1e5);
    EXPECT_GT(refinement, 0);
    EXPECT_NEAR(n * pixels * 1e-6 + startup + refinement, seconds, 1e-6);
    // Without refinement, at the steady rate and the start-up alone: more samples.
    cache.refinesRecords = false;
    cache.recordRaySeconds = 0;
    choice = predictFromPilots({syntheticPilot("path", 0, 1, 0.1, 48), cache}, kPilotPixels, pixels, seconds);
    const double plain = prediction(choice, "irradianceCache").predictedSamples;
    EXPECT_NEAR(plain * pixels * 1e-6 + 4 * (0.05 + 0.02 * std::log(plain / 4)), seconds, 1e-6);
    EXPECT_GT(plain, 1.5 * n);
}

// Two caches' batches of very unequal samples (time slices: a cache's first samples make its
// records), each value's noise sigma / sqrt(samples) codes: one batch of the mean samples has
// sigma^2 / mean. Deviations from the others' unweighted mean said 1.4 times that; 4 sigma of the
// estimate (n = 2048 * 3 values, 6 degrees of freedom each) is 3%.
TEST(Auto, WeighsBatchesByTheirSamples) {
    const std::vector<double> samples = {7, 29, 59, 75, 6, 26, 55, 77};
    constexpr double kSigma = 40;  // one sample's noise, in codes
    std::mt19937 rng(37);
    std::normal_distribution<double> gauss(0.0, 1.0);
    AutoPilot cache = syntheticPilot("irradianceCache", 0, 0, 0.5, 37);
    for (size_t k = 0; k < cache.batches.size(); ++k)
        for (float& v : cache.batches[k])
            v = float(linearOf(kTruth) + kSigma / std::sqrt(samples[k]) / slopeAt(kTruth) * gauss(rng));
    cache.batchSamples = samples;
    cache.firstCacheBatches = 4;
    double mean = 0;
    for (double n : samples) mean += n / double(samples.size());
    EXPECT_NEAR(predictedNoise(cache, 1.0), kSigma * kSigma / mean, 0.03 * kSigma * kSigma / mean);
}

// Pilot batches take their own seeds' samples from index 0 (auto_select.h), because batches of
// consecutive indices of one seed are stratified against each other: their mean is less noisy
// than their spread says, which hid biases under the noise subtracted. A floor under a rect light,
// one sample per batch, so each pixel's value is one light sample's estimate (pixels have their own
// scrambles, so 1024 of them are 1024 draws): the variance of the 8 batches' mean over the pixels
// against the mean of their spread / 8. Independent batches: 1 to within the estimates' error
// (about 5% each); consecutive ones: far below.
TEST(Auto, PilotBatchesAreIndependentSoTheirSpreadIsTheirMeansNoise) {
    Scene scene;
    buildFloorUnderRectLight(scene, 0.5f, 4.0f);
    scene.commit();
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.spp = 1 << 20;
    settings.integrator = "path";
    settings.seed = 3;
    Renderer renderer(scene, settings);
    ASSERT_TRUE(renderer.preprocess());
    constexpr int kBatches = 8, kPixels = 32 * 32;
    auto meanNoiseOverSpread = [&](bool independent) {
        std::vector<std::vector<float>> batches;
        for (int k = 0; k < kBatches; ++k) {
            if (independent) renderer.reset(0, 1000 + uint32_t(k));
            else renderer.reset(k);
            EXPECT_TRUE(renderer.renderPass(independent ? 0 : k, 1));
            batches.push_back(renderer.film().color());
        }
        double meanOfMeans = 0, spread = 0;
        std::vector<double> means(kPixels);
        for (int i = 0; i < kPixels; ++i) {
            double sum = 0, squares = 0;
            for (const auto& b : batches) {
                sum += b[size_t(i) * 3];
                squares += double(b[size_t(i) * 3]) * b[size_t(i) * 3];
            }
            means[size_t(i)] = sum / kBatches;
            meanOfMeans += means[size_t(i)] / kPixels;
            spread += (squares - sum * sum / kBatches) / (kBatches - 1) / kBatches / kPixels;
        }
        double variance = 0;
        for (double m : means) variance += (m - meanOfMeans) * (m - meanOfMeans) / (kPixels - 1);
        return variance / spread;
    };
    const double independent = meanNoiseOverSpread(true), consecutive = meanNoiseOverSpread(false);
    EXPECT_GT(independent, 0.8);
    EXPECT_LT(independent, 1.25);
    EXPECT_LT(consecutive, 0.5);
}

// The bias's standard error (the jackknife over the pilot's batches, or pairs of batches with two
// caches) against the spread of the bias estimate itself over 40 draws of the same pilots: a cache
// of bias 1 code (1 code squared) under noise of 6 codes a batch, one cache and two, beside a path
// tracer of the same noise. The draws' standard deviation is known to about 1 / sqrt(2 * 39) = 11%;
// the jackknife's mean over them must lie within a factor 1.5 of it either way.
TEST(Auto, TheBiasStandardErrorIsItsSpreadOverPilots) {
    auto fixed = [](size_t) { return 1.0; };
    constexpr int kDraws = 40;
    for (bool twoCaches : {false, true}) {
        double sum = 0, squares = 0, errors = 0;
        for (uint32_t draw = 0; draw < kDraws; ++draw) {
            AutoPilot path = syntheticPilot("path", 0, 6, 0.1, 1000 + 2 * draw);
            AutoPilot cache = twoCaches ? twoCachePilot("adaptiveIrradianceCache", fixed, 6, 0, 0.1, 1001 + 2 * draw)
                                        : syntheticPilot("adaptiveIrradianceCache", 1, 6, 0.1, 1001 + 2 * draw);
            AutoChoice choice = predictFromPilots({path, cache}, kPilotPixels, 4.0 * kPilotPixels, 4.0);
            const AutoPrediction& p = prediction(choice, "adaptiveIrradianceCache");
            EXPECT_GT(p.biasError, 0) << p.integrator;
            EXPECT_EQ(prediction(choice, "path").biasError, 0);  // consistent: not asked
            sum += p.bias;
            squares += p.bias * p.bias;
            errors += p.biasError / kDraws;
        }
        const double spread = std::sqrt((squares - sum * sum / kDraws) / (kDraws - 1));
        EXPECT_GT(errors, spread / 1.5) << "two caches: " << twoCaches;
        EXPECT_LT(errors, spread * 1.5) << "two caches: " << twoCaches;
    }
}

// noise(q) over blocks of values: each batch's deviations are averaged over a block before they
// are squared, so that noise apart from value to value falls in a block's mean as its values (a
// quarter in blocks of 2 x 2), and noise its values share (a record under them, moved between
// batches) does not fall at all.
TEST(Auto, BlocksCountTheNoiseTheirValuesShare) {
    AutoPilot apart = syntheticPilot("path", 0, 3, 0.1, 21);
    AutoPilot shared = apart;
    std::mt19937 rng(22);
    std::normal_distribution<double> gauss(0.0, 3 / slopeAt(kTruth));
    for (auto& batch : shared.batches)
        for (int y = 0; y < kPilotHeight; y += 2)
            for (int x = 0; x < kPilotWidth; x += 2)
                for (int c = 0; c < 3; ++c) {
                    const float value = float(linearOf(kTruth) + gauss(rng));
                    for (int v = y; v < y + 2; ++v)
                        for (int u = x; u < x + 2; ++u) batch[(size_t(v) * kPilotWidth + size_t(u)) * 3 + size_t(c)] = value;
                }
    const BiasBlocks quads = biasBlocks(apart, nullptr, 2), single = biasBlocks(apart, nullptr, 1);
    EXPECT_EQ(quads.count, kPilotPixels / 4 * 3);
    // One batch's noise is 9 codes squared per value, to 3% (EstimatesNoiseAndBiasOfSyntheticPilots).
    EXPECT_NEAR(predictedNoise(apart, single, 1), 9, 0.3);
    EXPECT_NEAR(predictedNoise(apart, single, 1), predictedNoise(apart, 1), 1e-12);
    EXPECT_NEAR(predictedNoise(apart, quads, 1), 9.0 / 4, 0.1);
    EXPECT_NEAR(predictedNoise(shared, quads, 1), 9, 0.5);  // a quarter of the values: 6% standard error
    EXPECT_NEAR(predictedNoise(shared, single, 1), 9, 0.5);
}

// A bias is measured on blocks' means because R's noise, apart from pixel to pixel, then falls by
// the block's values while a smooth bias stays. A cache 1 code off (b2 = 1) against a path tracer
// of 8 codes a batch (its mean's variance 8 per value): per value each term of b2's estimate has
// variance 2 * 8.5^2 + 4 * 8.5 = 178, over 6,144 values a standard error of 0.17; in blocks of 2 x 2
// (mean's variance 2.1) 2 * 2.1^2 + 4 * 2.1 = 17.5 over 1,536 blocks, 0.11. Over 24 draws both must be
// right on average (f's curvature moves R by 0.05 codes here), and the blocks' estimates spread less.
TEST(Auto, BiasInBlocksIsSteadierBehindANoisyReference) {
    constexpr int kDraws = 24;
    std::vector<double> sum(2, 0.0), squares(2, 0.0);
    for (uint32_t draw = 0; draw < kDraws; ++draw) {
        std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 8, 0.1, 2000 + 2 * draw),
                                         syntheticPilot("irradianceCache", 1, 2, 0.1, 2001 + 2 * draw)};
        for (int side : {1, 2}) {
            AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0, side);
            const double bias = prediction(choice, "irradianceCache").bias;
            sum[size_t(side - 1)] += bias;
            squares[size_t(side - 1)] += bias * bias;
        }
    }
    std::vector<double> spread(2);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(sum[i] / kDraws, 1.0, 0.3) << "side " << i + 1;
        spread[i] = std::sqrt((squares[i] - sum[i] * sum[i] / kDraws) / (kDraws - 1));
    }
    EXPECT_LT(spread[1], 0.8 * spread[0]) << spread[0] << " " << spread[1];
}

// A sphere that reflects and emits half (no other light), and a 32x24 render of it (the default camera).
void addGreySphere(Scene& scene) {
    addIcosphere(scene, 1.0f, 2, scene.addMaterial(lambert(Color(0.5f), Color(0.5f))));
    scene.commit();
}
RenderSettings smallRender() {
    RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    return settings;
}

TEST(Auto, TheRendererResolvesAutoAndKeepsTheTimeLimit) {
    Scene scene;
    addGreySphere(scene);
    RenderSettings settings = smallRender();
    settings.spp = 1 << 20;
    settings.integrator = "auto";
    settings.timeLimit = 1.0;
    Renderer renderer(scene, settings);
    renderer.render();
    const AutoChoice& choice = renderer.autoChoice();
    EXPECT_EQ(renderer.integratorName(), choice.integrator);
    EXPECT_EQ(choice.predictions.size(), autoCandidates().size());
    // Pilots keep their share (autoPilotShare, 0.1) to within one pilot pass; the render its limit.
    EXPECT_LT(choice.pilotSeconds, 0.1 + 0.2);
    EXPECT_LT(renderer.stats().seconds, 1.0 * 1.05 + 0.2);
    EXPECT_GT(renderer.samplesTaken(), 0);
}

// A kept choice (a sequence's later frames, a Hydra session's restarts) renders that technique
// without pilots, the image bit for bit the technique's own; a name auto does not choose, or a
// kept choice for another integrator, is refused.
TEST(Auto, AKeptChoiceRendersThatTechniqueWithoutPilots) {
    Scene scene;
    addGreySphere(scene);
    RenderSettings settings = smallRender();
    settings.spp = 2;
    settings.seed = 7;
    settings.integrator = "irradianceCache";
    Renderer direct(scene, settings);
    direct.render();
    settings.integrator = "auto";
    settings.keptAutoChoice = "irradianceCache";
    Renderer kept(scene, settings);
    kept.render();
    EXPECT_EQ(kept.integratorName(), "irradianceCache");
    EXPECT_TRUE(kept.autoChoice().kept);
    EXPECT_TRUE(kept.autoChoice().predictions.empty());
    EXPECT_EQ(kept.autoChoice().pilotSeconds, 0.0);
    EXPECT_EQ(kept.autoChoice().summary(), "auto: kept irradianceCache, chosen by an earlier render (no pilots)");
    EXPECT_EQ(kept.film().color(), direct.film().color());
    settings.keptAutoChoice = "direct";
    EXPECT_THROW(Renderer(scene, settings), std::invalid_argument);
    settings.integrator = "path";
    settings.keptAutoChoice = "irradianceCache";
    EXPECT_THROW(Renderer(scene, settings), std::invalid_argument);
}

}  // namespace
}  // namespace gi
