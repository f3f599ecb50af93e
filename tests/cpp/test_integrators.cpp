// Integrators against analytic answers: the white furnace, a diffuse plane under a distant
// light, and the irradiance of a rectangular light (Lambert's polygon formula).
#include <gtest/gtest.h>

#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

struct FurnaceCase {
    const char* integrator;
    float albedo;
    double paths = 0;  // when set, the integrator's "paths" (hemisphere paths of a cache record)
    std::vector<std::pair<const char*, double>> params = {};  // further parameters
};

class WhiteFurnace : public ::testing::TestWithParam<FurnaceCase> {};

// Inside a closed surface of uniform albedo a and emission Le, radiance is Le / (1 - a) everywhere.
TEST_P(WhiteFurnace, ReturnsLeOverOneMinusAlbedo) {
    const FurnaceCase& c = GetParam();
    Scene scene;
    const Color Le(0.5f);
    buildFurnace(scene, Color(c.albedo), Le);
    std::map<std::string, double> params = {{"pathDepth", 1000}, {"rayDepth", 1000}};
    if (c.paths > 0) params["paths"] = c.paths;
    for (const auto& [name, value] : c.params) params[name] = value;
    auto image = renderImage(scene, c.integrator, 16, 128, takenBy(c.integrator, params));
    double expected = Le.x / (1 - c.albedo);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(channelMean(image, ch), expected, 0.01 * expected) << "channel " << ch;
}

INSTANTIATE_TEST_SUITE_P(Path, WhiteFurnace, ::testing::Values(FurnaceCase{"path", 0.5f}, FurnaceCase{"path", 0.9f}),
                         [](const auto& info) { return std::string(info.param.integrator) + "_albedo" +
                                                       std::to_string(int(info.param.albedo * 10)); });
// Irradiance caches: constant indirect irradiance, so interpolation is exact and only the
// records' Monte Carlo noise remains; 1024 hemisphere paths keep it well under 1%.
INSTANTIATE_TEST_SUITE_P(IrradianceCache, WhiteFurnace,
                         ::testing::Values(FurnaceCase{"irradianceCache", 0.5f, 1024},
                                           FurnaceCase{"irradianceCache", 0.9f, 1024},
                                           FurnaceCase{"adaptiveIrradianceCache", 0.5f, 1024},
                                           FurnaceCase{"adaptiveIrradianceCache", 0.9f, 1024}),
                         [](const auto& info) { return std::string(info.param.integrator) + "_albedo" +
                                                       std::to_string(int(info.param.albedo * 10)); });
// Photon maps: the emissive triangles are two-sided lights, so half their photons leave the
// sphere through its outside and are lost (the light selection keeps them: its inside half
// lands where the camera looks); the rest bounce about 1 / (1 - a) times, so photonDepth must
// be far above that to leave no truncation bias (0.9^50 = 0.5%). The density estimates are
// unbiased on the icosphere's flat facets; where a disc spans two facets the flattened kernel
// loses a little (under 0.5% in all); the rest is Monte Carlo noise.
INSTANTIATE_TEST_SUITE_P(
    PhotonMap, WhiteFurnace,
    ::testing::Values(
        FurnaceCase{"photonMapFinalGather", 0.5f, 0, {{"photons", 200000}, {"photonDepth", 1000}}},
        FurnaceCase{"photonMapFinalGather", 0.9f, 0, {{"photons", 200000}, {"photonDepth", 1000}}},
        FurnaceCase{"photonMapIrradianceCache", 0.5f, 0, {{"photons", 200000}, {"photonDepth", 1000}, {"gatherPhotons", 200}}},
        FurnaceCase{"photonMapIrradianceCache", 0.9f, 0, {{"photons", 200000}, {"photonDepth", 1000}, {"gatherPhotons", 200}}}),
    [](const auto& info) { return std::string(info.param.integrator) + "_albedo" + std::to_string(int(info.param.albedo * 10)); });

// The same furnace at every technique's default parameters (issue 15: defaults converge). Only
// the albedo 0.9 case, where a depth-5 path keeps 1 - 0.9^5 = 41% of the light and any depth
// truncation shows at once; every depth defaults to the safety cap, Russian roulette ends paths.
// The bound, 1%: the noise measured over seeds 1-4 is under 0.3% for every technique as rendered
// here (the caches' average 0.25%, below), so it is 3.3-4 of their standard deviations. What it
// rules out: a path cut after d scattering vertices returns 1 - 0.9^(d+1) of Le/(1-a), so any
// cut shallower than about 40 vertices (0.9^44 = 0.97%) fails, the old depth-5 default (0.47 of
// it) by far; a Lambert BSDF scaled by 1 - e moves the answer by about 9e, so e >= 0.2% fails.
// (The path tracer against closed forms with error bars measured over seeds: test_unbiased.cpp.)
// The caches' error is the noise of their records' 108 paths: one 64x64 image (~70 records)
// has a standard deviation of 0.9% (measured over seeds 1-6: 0.994-1.015), so they average
// four seeds at 128x128 (~280 records each): 0.25%, a quarter of the bound. The progressive
// photon map's first radius is 4 pixel footprints: at 16x16 that disc spans several of the
// icosphere's facets and the normal guard dropped photons (-1.3% after 16 samples, with the
// 26-degree guard of then), at 64x64 not.
struct DefaultFurnaceCase {
    const char* integrator;
    int size, spp, seeds;
};
class DefaultFurnace : public ::testing::TestWithParam<DefaultFurnaceCase> {};

TEST_P(DefaultFurnace, ReturnsLeOverOneMinusAlbedo) {
    Scene scene;
    const Color Le(0.5f);
    const float albedo = 0.9f;
    buildFurnace(scene, Color(albedo), Le);
    const DefaultFurnaceCase& c = GetParam();
    double mean[3] = {0, 0, 0};
    for (int seed = 1; seed <= c.seeds; ++seed) {
        Rendered r = render(scene, c.integrator, c.size, c.spp, {}, uint32_t(seed));
        for (int ch = 0; ch < 3; ++ch) mean[ch] += channelMean(r.rgb, ch) / c.seeds;
        EXPECT_EQ(r.stats.depthCappedPaths, 0u);
        EXPECT_EQ(r.stats.nonFiniteSamples, 0u);
    }
    double expected = Le.x / (1 - albedo);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(mean[ch], expected, 0.01 * expected) << "channel " << ch;
}

INSTANTIATE_TEST_SUITE_P(AllTechniques, DefaultFurnace,
                         ::testing::Values(DefaultFurnaceCase{"path", 16, 64, 1},
                                           DefaultFurnaceCase{"irradianceCache", 128, 4, 4},
                                           DefaultFurnaceCase{"adaptiveIrradianceCache", 128, 4, 4},
                                           DefaultFurnaceCase{"photonMapFinalGather", 16, 64, 1},
                                           DefaultFurnaceCase{"photonMapIrradianceCache", 64, 16, 1},
                                           DefaultFurnaceCase{"progressivePhotonMap", 64, 4, 1}),
                         [](const auto& info) { return std::string(info.param.integrator); });

// A furnace whose wall has a glossy lobe above its Lambertian one (UsdPreviewSurface's
// default: specular workflow off, ior 1.5, here roughness 0.3): the caches interpolate the
// Lambertian lobe's indirect light (less the Fresnel the glossy lobe takes) and trace the glossy
// lobe's (DirectIntegrator::glossyIndirect); in a furnace the two must add up to the path
// tracer's mean, neither counted twice nor lost (the GGX lobe loses energy, so the value has no
// closed form). Measured 1.0014, 0.9963, 0.9925. A sunlit wall reflected at grazing angles, where
// leaving the glossy lobe out matters, is test_irradiance_cache.cpp's GlossyFloorAtGrazingAngles.
TEST(GlossyFurnace, CachesTraceTheGlossyLobesIndirectLight) {
    Scene scene;
    MaterialDesc wall = lambert(Color(0.9f), Color(0.5f));
    wall.useSpecularWorkflow = false;
    wall.roughness = 0.3f;
    addIcosphere(scene, 1.0f, 3, scene.addMaterial(wall));
    CameraDesc cam;
    cam.clipNear = 1e-3f;
    scene.setCamera(cam);
    auto mean = [&](const char* integrator, int size, int spp, int seeds) {
        double sum = 0;
        for (int seed = 1; seed <= seeds; ++seed) {
            Rendered r = render(scene, integrator, size, spp, {}, uint32_t(seed));
            EXPECT_EQ(r.stats.nonFiniteSamples, 0u) << integrator;
            sum += channelMean(r.rgb, 1) / seeds;
        }
        return sum;
    };
    double path = mean("path", 32, 256, 1);
    for (const char* cache : {"irradianceCache", "adaptiveIrradianceCache", "photonMapIrradianceCache"}) {
        double m = mean(cache, 64, 16, 2);
        std::printf("[ glossy   ] %s %.4f of the path tracer's %.4f\n", cache, m / path, path);
        EXPECT_NEAR(m / path, 1.0, 0.01) << cache;
    }
}

// The thesis preset keeps the thesis's depth 5: the furnace then returns the truncated sum
// Le (1 - a^6) / (1 - a) (the camera's first hit plus five scattering vertices), which shows
// that the preset reaches the integrator.
TEST(Presets, ThesisPresetTruncatesThePathTracerAtDepthFive) {
    Scene scene;
    const float albedo = 0.9f;
    buildFurnace(scene, Color(albedo), Color(0.5f));
    scene.commit();
    RenderSettings settings;
    settings.width = settings.height = 16;
    settings.spp = 64;
    settings.integrator = "path";
    settings.preset = "thesis";
    Renderer renderer(scene, settings);
    renderer.render();
    double expected = 0.5 * (1 - std::pow(albedo, 6)) / (1 - albedo);
    EXPECT_NEAR(channelMean(renderer.film().color(), 0), expected, 0.01 * expected);
    settings.preset = "no-such-preset";
    EXPECT_THROW(Renderer(scene, settings), std::invalid_argument);
}

// A parameter the integrator does not take (a typo, or one of another integrator's) is refused
// naming it, not rendered at its default; each integrator takes every name it declares.
TEST(Parameters, UnknownNameIsRefusedNamingIt) {
    Scene scene;
    buildFurnace(scene, Color(0.5f), Color(0.5f));
    scene.commit();
    RenderSettings settings;
    settings.width = settings.height = 4;
    settings.spp = 1;
    for (const IntegratorInfo& info : integratorRegistry()) {
        settings.integrator = info.name;
        settings.params = ParamSet();
        for (const ParamInfo& p : info.params) settings.params.set(p.name, p.defaultValue);
        EXPECT_NO_THROW(Renderer(scene, settings)) << info.name;
        settings.params.set("pathDepht", 3);
        try {
            Renderer renderer(scene, settings);
            ADD_FAILURE() << info.name << " accepted the unknown parameter pathDepht";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("pathDepht"), std::string::npos) << e.what();
        }
    }
}

// A delta distant light of irradiance E on a Lambertian plane: L = albedo * E / pi, exactly.
TEST(DirectLighting, PlaneUnderDistantLight) {
    for (const char* integrator : {"direct", "path"}) {
        Scene scene;
        int m = scene.addMaterial(lambert(Color(0.5f, 0.25f, 0.75f)));
        addQuad(scene, "/Plane", {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, m);
        LightDesc sun;
        sun.name = "/Sun";
        sun.kind = "distant";
        sun.angle = 0;
        sun.intensity = 3;
        sun.transform.m[1][1] = 0, sun.transform.m[1][2] = -1;  // rotate -90 about X: shines along -Y
        sun.transform.m[2][1] = 1, sun.transform.m[2][2] = 0;
        scene.addLight(sun);
        scene.setCamera(lookingDown({0, 5, 0}, true, 10));
        auto image = renderImage(scene, integrator, 8, 4, takenBy(integrator, {{"pathDepth", 1}}));
        EXPECT_NEAR(channelMean(image, 0), 0.5 * 3 / kPi, 1e-4) << integrator;
        EXPECT_NEAR(channelMean(image, 1), 0.25 * 3 / kPi, 1e-4) << integrator;
        EXPECT_NEAR(channelMean(image, 2), 0.75 * 3 / kPi, 1e-4) << integrator;
    }
}

TEST(DirectLighting, RectLightMatchesPolygonFormFactor) {
    Scene scene;
    double expected = buildFloorUnderRectLight(scene, 0.8f, 5);
    auto image = renderImage(scene, "direct", 4, 1024, {{"lightSamples", 16}});
    EXPECT_NEAR(channelMean(image, 1), expected, 0.005 * expected);
}

TEST(Integrators, RegistryReflectsParameters) {
    const IntegratorInfo* path = findIntegrator("path");
    ASSERT_NE(path, nullptr);
    std::vector<std::string> names;
    for (const ParamInfo& p : path->params) names.push_back(p.name);
    EXPECT_NE(std::find(names.begin(), names.end(), "pathDepth"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "rayDepth"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "paths"), names.end());
    ParamSet p;
    p.set("pathDepth", 1e9);  // out of range: clamped, not trusted
    EXPECT_EQ(paramValue(*path, p, "pathDepth"), 1024);
}

TEST(Renderer, DeterministicGivenSeed) {
    auto once = [](uint32_t seed) {
        Scene scene;
        int m = scene.addMaterial(lambert(Color(0.7f), Color(0.2f)));
        addIcosphere(scene, 1.0f, 2, m);
        return renderImage(scene, "path", 16, 8, {}, seed);
    };
    EXPECT_EQ(once(7), once(7));
    EXPECT_NE(once(7), once(8));
}

}  // namespace
