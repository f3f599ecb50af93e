// The path tracer at its default parameters against closed-form answers (issue 19 item 3): a
// coloured furnace (Le / (1 - albedo): BSDF, Russian roulette, depth), a plane under a uniform
// sky (albedo x sky radiance: dome sampling, MIS with the BSDF) and a plane under a rect light
// (Lambert's polygon formula: area-light sampling, MIS when BSDF rays hit the light). Nothing
// here is compared with the path tracer itself, so a wrong BSDF, pdf or depth truncation shows.
//
// Tolerance: each estimate is the mean of kSeeds independent renders; its standard error SE is
// measured from their spread. For an unbiased renderer (mean - exact) / SE follows Student's t
// with kSeeds - 1 = 15 degrees of freedom, and P(|t| > 5) = 1.6e-4 per channel, so kSigma = 5
// leaves about one false failure in 700 runs of the whole file (9 channels) as the random
// sequences change. A floor of 1e-5 relative covers float rounding where the estimator has no
// variance. Each test also asserts that kSigma * SE is small enough to see a 2% error in the
// BSDF: under 0.5% of the exact value where the answer is linear in the albedo (the planes);
// under 2% in the furnace, where a BSDF scaled by 1 - e moves Le / (1 - a) by about
// e a / (1 - a): 0.9% for blue (a = 0.3), 4.6% for green, 38% for red.
#include <gtest/gtest.h>

#include <cmath>

#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

constexpr int kSeeds = 16;
constexpr double kSigma = 5, kRoundingFloor = 1e-5;

struct Estimate {
    double mean[3] = {0, 0, 0}, standardError[3] = {0, 0, 0};
};

// Per channel: the mean over seeds of the image's mean, and its standard error.
Estimate overSeeds(Scene& scene, const char* integrator, int size, int spp) {
    std::vector<double> means[3];
    for (int seed = 1; seed <= kSeeds; ++seed) {
        Rendered r = render(scene, integrator, size, spp, {}, uint32_t(seed));
        EXPECT_EQ(r.stats.nonFiniteSamples, 0u);
        EXPECT_EQ(r.stats.depthCappedPaths, 0u);
        for (int c = 0; c < 3; ++c) means[c].push_back(channelMean(r.rgb, c));
    }
    Estimate e;
    for (int c = 0; c < 3; ++c) {
        for (double m : means[c]) e.mean[c] += m / kSeeds;
        double squares = 0;
        for (double m : means[c]) squares += (m - e.mean[c]) * (m - e.mean[c]);
        e.standardError[c] = std::sqrt(squares / (kSeeds - 1) / kSeeds);
    }
    return e;
}

// `resolvable`: the relative error the test must be able to see (kSigma * SE below it).
void expectMatches(const Estimate& e, const double exact[3], const char* what, double resolvable) {
    for (int c = 0; c < 3; ++c) {
        double bound = std::max(kSigma * e.standardError[c], kRoundingFloor * exact[c]);
        std::printf("[ unbiased ] %s channel %d: %.6f, exact %.6f, SE %.2e (%.3f%%), %+.2f SE\n", what, c, e.mean[c],
                    exact[c], e.standardError[c], 100 * e.standardError[c] / exact[c],
                    e.standardError[c] > 0 ? (e.mean[c] - exact[c]) / e.standardError[c] : 0.0);
        EXPECT_NEAR(e.mean[c], exact[c], bound) << what << " channel " << c;
        EXPECT_LT(bound, resolvable * exact[c]) << what << " channel " << c << ": too noisy to resolve a "
                                                << 100 * resolvable << "% error";
    }
}

TEST(UnbiasedAtDefaults, ColouredFurnace) {
    // Red's albedo 0.95 needs about 20 bounces on average: a path cut at depth 5 keeps
    // 1 - 0.95^6 = 26% of it; blue (0.3) tests that channels do not mix. Measured SE over the
    // 16 seeds (16x16, 16 spp): red 0.24%, green 0.02%, blue 0.003%.
    Scene scene;
    const Color albedo(0.95f, 0.7f, 0.3f), Le(0.5f);
    buildFurnace(scene, albedo, Le);
    double exact[3];
    for (int c = 0; c < 3; ++c) exact[c] = Le[c] / (1 - albedo[c]);
    expectMatches(overSeeds(scene, "path", 16, 16), exact, "furnace", 0.02);
}

TEST(UnbiasedAtDefaults, PlaneUnderUniformSky) {
    // A plane sees the whole upper hemisphere of a uniform sky of radiance Ls and nothing else
    // (it does not see itself): E = pi Ls and L = albedo Ls.
    Scene scene;
    const Color albedo(0.8f, 0.5f, 0.3f), sky(0.2f, 0.5f, 1.0f);
    const float intensity = 2;
    int m = scene.addMaterial(lambert(albedo));
    addQuad(scene, "/Plane", {-1000, 0, -1000}, {-1000, 0, 1000}, {1000, 0, 1000}, {1000, 0, -1000}, m);
    LightDesc dome;
    dome.name = "/Sky";
    dome.kind = "dome";
    dome.color = sky;
    dome.intensity = intensity;
    scene.addLight(dome);
    scene.setCamera(lookingDown({0, 1, 0}, true, 10));
    double exact[3];
    for (int c = 0; c < 3; ++c) exact[c] = double(albedo[c]) * sky[c] * intensity;
    expectMatches(overSeeds(scene, "path", 16, 16), exact, "sky", 0.005);
}

TEST(UnbiasedAtDefaults, PlaneUnderRectLight) {
    // The rect light of test_integrators' DirectLighting test, now through the path tracer: its
    // BSDF rays hit the light too (MIS), and light reflected up meets only the light's back.
    Scene scene;
    double radiance = buildFloorUnderRectLight(scene, 0.8f, 5);
    double exact[3] = {radiance, radiance, radiance};
    expectMatches(overSeeds(scene, "path", 8, 64), exact, "rect light", 0.005);
}

}  // namespace
