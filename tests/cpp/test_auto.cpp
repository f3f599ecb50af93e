// Integrator "auto": the prediction from pilot images (auto_select.h), on synthetic pilots whose
// noise and bias are known, and the renderer's resolution of "auto" into one technique.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "renderer/auto_select.h"
#include "renderer/render.h"
#include "scenes.h"

namespace gi {
namespace {

using test::addIcosphere;
using test::lambert;

constexpr int kPilotPixels = 2048;
constexpr double kTruth = 100;  // every pixel's true value, in sRGB codes

// Two images of kTruth + bias + N(0, sigma^2) per pixel, rendered in `seconds` each.
AutoPilot syntheticPilot(const std::string& integrator, double bias, double sigma, double seconds, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    AutoPilot pilot;
    pilot.integrator = integrator;
    for (auto& image : pilot.codes) {
        image.resize(kPilotPixels * 3);
        for (double& v : image) v = kTruth + bias + noise(rng);
    }
    pilot.renderSeconds = seconds;
    pilot.complete = true;
    return pilot;
}

const AutoPrediction& prediction(const AutoChoice& choice, const std::string& integrator) {
    for (const AutoPrediction& p : choice.predictions)
        if (p.integrator == integrator) return p;
    throw std::runtime_error("no prediction for " + integrator);
}

// Noise and bias estimates: a path tracer of sigma 2 per image and a cache of bias 5, sigma 2.
// n = 2048 * 3 values. The noise estimate mean((a - b)^2) / 2 has relative standard error
// sqrt(2 / n) = 1.8%: 4 sigma is 7%. The cache's bias estimate mean((m - R)^2) - Var(R) - v / 2
// with m - R = 5 + d, d ~ N(0, 2 + 2): each term's variance is 4 * 25 * 4 + 2 * 4^2 = 432, so the
// mean's standard error is sqrt(432 / n) = 0.27 codes^2: 4 sigma is 1.1.
TEST(Auto, EstimatesNoiseAndBiasOfSyntheticPilots) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 2, 0.1, 1),
                                     syntheticPilot("irradianceCache", 5, 2, 0.1, 2)};
    // The final render: 4x the pilot's pixels in 4 s, so 10x the pilot's 0.1 s per pixel (r = 0.1).
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    const AutoPrediction& path = prediction(choice, "path");
    const AutoPrediction& cache = prediction(choice, "irradianceCache");
    EXPECT_NEAR(path.noise, 4, 0.07 * 4);
    EXPECT_NEAR(cache.noise, 4, 0.07 * 4);
    EXPECT_NEAR(cache.bias, 25, 1.1);
    EXPECT_LT(path.bias, 1.1);  // it is the reference here: nothing but noise
    // Consistent: (bias + noise) * r; a cache: bias + noise * r.
    EXPECT_NEAR(path.predictedRmse * path.predictedRmse, (path.bias + path.noise) * 0.1, 1e-9);
    EXPECT_NEAR(cache.predictedRmse * cache.predictedRmse, cache.bias + cache.noise * 0.1, 1e-9);
    EXPECT_EQ(choice.integrator, "path");
}

// The choice as the budget grows: a path tracer of sigma 20 per image (its MSE 400 r) against a
// cache of bias b, sigma 2 (MSE b^2 + 4 r). The cache's bias estimate now has R's noise in it:
// m - R = b + d, d ~ N(0, 200 + 2), so its standard error is sqrt((4 b^2 202 + 2 202^2) / n),
// 3.8 for b = 3 and 4.1 for b = 5: the choices below hold within 4 sigma of it.
TEST(Auto, ChoosesTheCacheAtShortBudgetsAndThePathTracerAtLongOnes) {
    // 4 s, r = 0.1: the path tracer 40 (its margin: 32), the cache 9 + 0.4 (at most 24.6).
    std::vector<AutoPilot> shortRun = {syntheticPilot("path", 0, 20, 0.1, 3),
                                       syntheticPilot("irradianceCache", 3, 2, 0.1, 4)};
    EXPECT_EQ(predictFromPilots(shortRun, kPilotPixels, 4.0 * kPilotPixels, 4.0).integrator, "irradianceCache");
    // 40 s, r = 0.01: the path tracer 4 (margin 3.2), the cache 25 + 0.04 (at least 8.6).
    std::vector<AutoPilot> longRun = {syntheticPilot("path", 0, 20, 0.1, 5),
                                      syntheticPilot("irradianceCache", 5, 2, 0.1, 6)};
    AutoChoice choice = predictFromPilots(longRun, kPilotPixels, 4.0 * kPilotPixels, 40.0);
    EXPECT_EQ(choice.integrator, "path");
    EXPECT_NEAR(prediction(choice, "path").predictedRmse, 2.0, 0.2);  // sqrt(400 * 0.01), noise 7%
}

TEST(Auto, LeavesOutIncompletePilotsAndFallsBackOnThePathTracer) {
    std::vector<AutoPilot> pilots = {syntheticPilot("path", 0, 20, 0.1, 5), AutoPilot{"photonMapFinalGather"}};
    AutoChoice choice = predictFromPilots(pilots, kPilotPixels, 4.0 * kPilotPixels, 4.0);
    EXPECT_EQ(choice.integrator, "path");
    EXPECT_FALSE(prediction(choice, "photonMapFinalGather").complete);
    EXPECT_NE(choice.summary().find("photonMapFinalGather (no pilot in time)"), std::string::npos);
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
    EXPECT_GT(prediction(choice, "path").bias, 500);
}

TEST(Auto, TheRendererResolvesAutoAndKeepsTheTimeLimit) {
    Scene scene;
    int m = scene.addMaterial(lambert(Color(0.5f), Color(0.5f)));
    addIcosphere(scene, 1.0f, 2, m);
    scene.commit();
    RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
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

}  // namespace
}  // namespace gi
