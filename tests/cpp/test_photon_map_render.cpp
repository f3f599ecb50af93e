// Photon mapping's integrators (thesis 3.3.4, 3.3.5) on scenes with a known answer: a thin
// wall whose dark side must stay dark, lights that reach nothing, an absurd photon count,
// caustics and glossy lobes through glass against the path tracer, convergence on a glass
// Cornell box, determinism across thread counts, the registry's parameters and the progressive
// radius schedule. (The white furnace is in test_integrators.cpp; the kd-tree and the density
// estimate in test_photon_map.cpp.)
#include <gtest/gtest.h>

#include <cstdio>

#include "renderer/integrators/photon_final_gather.h"
#include "renderer/integrators/photon_map.h"
#include "renderer/integrators/progressive_photon_map.h"
#include "indirect_error.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

// ---------------------------------------------------------------------------------------
// Rendering

// A rect light of the given size at `center`, emitting along `direction`.
LightDesc rectLight(const char* name, Vec3 center, Vec3 direction, float size, float intensity) {
    LightDesc light;
    light.name = name;
    light.kind = "rect";
    light.width = light.height = size;
    light.intensity = intensity;
    Vec3 up = std::fabs(normalize(direction).y) > 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    light.transform = lookAlong(center, direction, up);  // a rect light emits along its -Z
    return light;
}

using Render = Rendered;  // scenes.h

// Finite, non-negative pixels and no sample replaced: the renderer zeroes NaN/Inf/negative
// samples before the film sees them, so the pixels alone cannot show that none occurred.
bool allFinite(const Render& r) {
    return r.stats.nonFiniteSamples == 0 &&
           std::all_of(r.rgb.begin(), r.rgb.end(), [](float v) { return std::isfinite(v) && v >= 0; });
}

bool warned(const Render& r, const std::string& text) {
    return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

const char* const kPhotonIntegrators[] = {"photonMapFinalGather", "photonMapIrradianceCache"};

// Two rooms side by side, open towards the camera, parted by a wall 1 mm thick (x = 0); a
// light under the left room's ceiling. Each room has its own floor, ceiling and back wall,
// level with the other room's: photons on the left lie 1 mm from the right room's wall and
// floor. No light reaches the right room (what leaves the left one through the open front
// never comes back), so every pixel that sees into it must be black.
void buildThinWallScene(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.8f)));
    const float t = 0.0005f;
    for (float side : {-1.0f, 1.0f}) {
        float inner = side * t, outer = side;
        auto quad = [&](const char* name, Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
            std::string full = std::string(side < 0 ? "/Left" : "/Right") + name;
            addQuad(scene, full.c_str(), a, b, c, d, white);
        };
        quad("/Floor", {inner, 0, -1}, {inner, 0, 1}, {outer, 0, 1}, {outer, 0, -1});
        quad("/Ceiling", {inner, 1, -1}, {outer, 1, -1}, {outer, 1, 1}, {inner, 1, 1});
        quad("/Back", {inner, 0, -1}, {outer, 0, -1}, {outer, 1, -1}, {inner, 1, -1});
        quad("/Side", {outer, 0, -1}, {outer, 0, 1}, {outer, 1, 1}, {outer, 1, -1});
        quad("/Partition", {inner, 0, -1}, {inner, 1, -1}, {inner, 1, 1}, {inner, 0, 1});
    }
    addQuad(scene, "/PartitionEdge", {-t, 0, 1}, {t, 0, 1}, {t, 1, 1}, {-t, 1, 1}, white);
    scene.addLight(rectLight("/Light", Vec3(-0.5f, 0.99f, -0.2f), Vec3(0, -1, 0), 0.3f, 20));
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 28;
    camera.transform = lookAlong(Vec3(0, 0.5f, 4), Vec3(0, 0, -1));
    scene.setCamera(camera);
}

// Pixels whose whole footprint sees one room: 1 = the lit (left) one, -1 = the dark one, 0 = other.
std::vector<int> classifyThinWallPixels(const Scene& scene, int size) {
    Camera camera(scene.cameraDesc(), size, size);
    auto side = [&](float x, float y) {
        RayStats stats;
        Intersection hit = scene.intersect(camera.generateRay(x, y, Vec2(0.5f, 0.5f)), stats, true);
        if (hit.kind != Intersection::Kind::Surface || hit.si.p.z > 0.999f) return 0;
        return hit.si.p.x < -0.001f ? 1 : (hit.si.p.x > 0.001f ? -1 : 0);
    };
    std::vector<int> classes(size * size);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            int c = side(x + 0.02f, y + 0.02f);
            for (Vec2 corner : {Vec2(0.98f, 0.02f), Vec2(0.02f, 0.98f), Vec2(0.98f, 0.98f), Vec2(0.5f, 0.5f)})
                if (side(x + corner.x, y + corner.y) != c) c = 0;
            classes[y * size + x] = c;
        }
    return classes;
}

// Thin strips (0.03 wide, a tenth of the photon disc on a full surface) hang 0.5 above a floor
// lit by a sun, facing it: their undersides get only the floor's light. Seen from below (the
// strips alone, against the black sky), photonMapIrradianceCache must read them as the path
// tracer does: a photon record there would divide the photons of a strip by a disc mostly off
// it and read dark, so the records are path-traced (PhotonEstimate::coverage).
void buildStripsOverAFloor(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.8f)));
    addQuad(scene, "/Floor", {-1.5f, 0, -1.5f}, {-1.5f, 0, 1.5f}, {1.5f, 0, 1.5f}, {1.5f, 0, -1.5f}, white);
    for (int i = 0; i < 4; ++i) {
        float x = -0.45f + 0.3f * float(i), w = 0.015f;
        std::string name = "/Strip" + std::to_string(i);
        addQuad(scene, name.c_str(), {x - w, 0.5f, -1}, {x + w, 0.5f, -1}, {x + w, 0.5f, 1}, {x - w, 0.5f, 1}, white);
    }
    LightDesc sun;
    sun.name = "/Sun";
    sun.kind = "distant";
    sun.angle = 0;
    sun.intensity = 3;
    sun.transform = lookAlong(Vec3(0.0f), Vec3(0.3f, -1, 0.2f), Vec3(1, 0, 0));
    scene.addLight(sun);
    CameraDesc camera = lookingDown({0, 0.25f, 0}, true, 12);
    camera.transform.m[1][2] = 1, camera.transform.m[2][1] = -1;  // looking up instead
    scene.setCamera(camera);
}

// The strips scene's green mean, path-traced at 256 spp: the photon techniques' reference.
double stripsPathTracedMean() {
    Scene reference;
    buildStripsOverAFloor(reference);
    return channelMean(renderImage(reference, "path", 64, 256, {}, 9), 1);
}

TEST(PhotonMapRender, PhotonRecordsStayOffThinStrips) {
    // Over seeds 1-8 the ratio to a 256-spp path-traced image measured 1.0023 (sd 0.0069):
    // |bias| + 4 sd = 3%. Photon records on the strips (no coverage rule) read 0.71-0.73.
    double expected = stripsPathTracedMean();
    ASSERT_GT(expected, 0);
    Scene scene;
    buildStripsOverAFloor(scene);
    Render r = render(scene, "photonMapIrradianceCache", 64, 4, {{"photons", 2e6}}, 1);
    EXPECT_GT(r.stats.integrator.at("globalMapPhotons"), 10000);  // photons do reach the strips
    EXPECT_NEAR(channelMean(r.rgb, 1) / expected, 1, 0.03);
}

TEST(PhotonMapRender, ProgressiveWideDiscsReadThinStripsRight) {
    // The strips of the test above read by a progressive photon map with few photons a pass: its
    // first discs (4 pixels, 0.04 in radius) are wider than a strip, and hold too few of its
    // photons to tell their coverage, so the strips read dark by the share of the disc they leave
    // empty unless the disc's surface is measured (disc_area.h). Over seeds 1-8 the ratio to the
    // path tracer measured 1.019 (sd 0.0075); without the measure, 0.40.
    double expected = stripsPathTracedMean();
    ASSERT_GT(expected, 0);
    Scene scene;
    buildStripsOverAFloor(scene);
    Render r = render(scene, "progressivePhotonMap", 64, 64, {{"photonsPerPass", 20000}, {"initialRadius", 4}}, 1);
    EXPECT_NEAR(channelMean(r.rgb, 1) / expected, 1, 0.05);
}

TEST(PhotonMapRender, ThinWallKeepsTheDarkSideDark) {
    const int size = 32;
    for (const char* integrator : kPhotonIntegrators) {
        Scene scene;
        buildThinWallScene(scene);
        Render r = render(scene, integrator, size, 8, {{"photons", 100000}});
        ASSERT_TRUE(allFinite(r)) << integrator;
        std::vector<int> classes = classifyThinWallPixels(scene, size);
        double lit = 0, dark = 0;
        int litPixels = 0, darkPixels = 0;
        for (int i = 0; i < size * size; ++i) {
            double y = luminance(Color(r.rgb[3 * i], r.rgb[3 * i + 1], r.rgb[3 * i + 2]));
            if (classes[i] == 1) lit += y, ++litPixels;
            if (classes[i] == -1) dark += y, ++darkPixels;
        }
        ASSERT_GT(litPixels, 100);
        ASSERT_GT(darkPixels, 100);
        EXPECT_EQ(r.stats.integrator.at("photonLightsSkipped"), 0) << integrator;
        EXPECT_GT(r.stats.integrator.at("globalMapPhotons"), 10000) << integrator;
        EXPECT_GT(lit / litPixels, 0.1) << integrator;
        EXPECT_EQ(dark, 0.0) << integrator << ": light leaked into the dark room, mean " << dark / darkPixels;
    }
}

// A rect light over a floor, facing up (and hidden from the camera): no photon lands anywhere.
TEST(PhotonMapRender, LightFacingAwayStoresNoPhotons) {
    for (const char* integrator : kPhotonIntegrators) {
        Scene scene;
        int white = scene.addMaterial(lambert(Color(0.8f)));
        addQuad(scene, "/Floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, white);
        LightDesc light = rectLight("/Light", Vec3(0, 1, 0), Vec3(0, 1, 0), 0.5f, 10);
        light.visibleToCamera = false;
        scene.addLight(light);
        scene.setCamera(lookingDown({0, 3, 0}, true, 30));
        Render r = render(scene, integrator, 8, 4, {{"photons", 20000}});
        EXPECT_TRUE(allFinite(r)) << integrator;
        EXPECT_EQ(channelMean(r.rgb, 1), 0.0) << integrator;
        EXPECT_EQ(r.stats.integrator.at("photonLightsSkipped"), 1) << integrator;
        EXPECT_EQ(r.stats.integrator.at("globalMapPhotons"), 0) << integrator;
        EXPECT_TRUE(warned(r, "none of")) << integrator;
        EXPECT_TRUE(warned(r, "no light reaches")) << integrator;
    }
}

// A sphere light sealed in a closed box on a floor lit by a big rect light: the box's light is
// left out of the photon maps (the inside of the box lies a centimetre above the floor the
// camera sees, but behind the box's walls), the other light's photons are all there, and the
// image matches the same scene without the box's light (which cannot reach the image).
void buildSealedBox(Scene& scene, bool withBoxLight) {
    int white = scene.addMaterial(lambert(Color(0.7f)));
    addQuad(scene, "/Floor", {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, white);
    const Vec3 lo(-0.5f, 0.01f, -0.5f), hi(0.5f, 1, 0.5f);
    addQuad(scene, "/Box/Bottom", {lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}, white);
    addQuad(scene, "/Box/Top", {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}, white);
    addQuad(scene, "/Box/Front", {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}, white);
    addQuad(scene, "/Box/Back", {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, lo.y, lo.z}, white);
    addQuad(scene, "/Box/Left", {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z}, white);
    addQuad(scene, "/Box/Right", {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z}, white);
    if (withBoxLight) {
        scene.addLight(sphereLight("/Box/Bulb", {0, 0.5f, 0}, 0.1f, 50));
    }
    scene.addLight(rectLight("/Sky", Vec3(1, 4, 1), Vec3(-0.2f, -1, -0.2f), 2, 3));
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 20;
    camera.transform = lookAlong(Vec3(2.5f, 2.5f, 3.5f), Vec3(-2.5f, -2.2f, -3.5f));
    scene.setCamera(camera);
}

TEST(PhotonMapRender, LightSealedInABoxEmitsNoPhotons) {
    for (const char* integrator : kPhotonIntegrators) {
        Scene sealed, open;
        buildSealedBox(sealed, true);
        buildSealedBox(open, false);
        std::map<std::string, double> params = {{"photons", 50000}, {"lightSamples", 4}};
        Render withBulb = render(sealed, integrator, 24, 16, params);
        Render without = render(open, integrator, 24, 16, params);
        ASSERT_TRUE(allFinite(withBulb)) << integrator;
        EXPECT_EQ(withBulb.stats.integrator.at("photonLightsSkipped"), 1) << integrator;
        EXPECT_TRUE(warned(withBulb, "/Box/Bulb")) << integrator;
        // The skipped light takes no share of the photons: the maps hold as many photons, up to
        // the pilot's own noise (the sky's pilot photons, fewer beside the bulb, shape its
        // emission guide): a Poisson count of n photons varies by sqrt(n), 4 sigma allowed.
        double stored = without.stats.integrator.at("globalMapPhotons");
        EXPECT_NEAR(withBulb.stats.integrator.at("globalMapPhotons"), stored, 4 * std::sqrt(stored)) << integrator;
        // Light sampling still picks the bulb (and finds it occluded): noise, not bias. Near the box
        // the light BVH (light_sampler.h) weighs the bulb by its importance there, so half or more
        // of those samples go to it and the sky gets fewer. The ratio of the two images' means over
        // seeds 1-8: 1.0050 sd 0.46% (final gathering), 1.0041 sd 0.35% (photon cache); 4 sd of
        // the larger is 1.8%. (With light picked by power alone it was sd 0.13% and 0.19%.)
        double a = channelMean(withBulb.rgb, 1), b = channelMean(without.rgb, 1);
        EXPECT_NEAR(a, b, 0.018 * b) << integrator;
    }
}

TEST(PhotonMapRender, AbsurdPhotonCountIsClampedWithAWarning) {
    // The light is far above a small floor, so nearly all of the 2^24 photons miss it: the
    // clamp is exercised in full at the cost of some 17 million cheap rays.
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.5f)));
    addQuad(scene, "/Floor", {-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}, white);
    scene.addLight(rectLight("/Light", Vec3(0, 30, 0), Vec3(0, -1, 0), 0.5f, 20000));
    scene.setCamera(lookingDown({0, 2, 0}, true, 10));
    Render r = render(scene, "photonMapFinalGather", 8, 2, {{"photons", 1e12}, {"photonDepth", 0}, {"finalGatherSamples", 1}});
    EXPECT_TRUE(allFinite(r));
    EXPECT_TRUE(warned(r, "clamped to 16777216"));
    EXPECT_EQ(r.stats.integrator.at("photonsEmitted"), kMaxPhotonsPerMap);
    EXPECT_GT(channelMean(r.rgb, 0), 0);
}

// A coloured glass sphere over a white floor under a big light: the floor under the sphere
// carries the caustic, an image of the light. Both integrators must put the path tracer's
// energy there (which it finds by BSDF sampling through the glass). The floor gets almost no
// indirect photons in this open scene, so the irradiance cache's records are path traced
// here: they must leave the caustic to the caustic map, not count it a second time.
TEST(PhotonMapRender, ColouredCausticMatchesThePathTracer) {
    auto build = [](Scene& scene) {
        int white = scene.addMaterial(lambert(Color(0.8f)));
        int g = scene.addMaterial(smoothGlass(Color(1.0f, 0.6f, 0.3f)));
        addQuad(scene, "/Floor", {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, white);
        scene.addSphere("/Ball", Vec3(0, 0.5f, 0), 0.3f, g, nullptr, -1);
        scene.addLight(rectLight("/Light", Vec3(0, 3, 0), Vec3(0, -1, 0), 0.6f, 60));
        // Looking at the floor under the ball past its side: a 0.5 x 0.5 orthographic window.
        CameraDesc camera;
        camera.name = "/Camera";
        camera.projection = "orthographic";
        camera.horizontalAperture = camera.verticalAperture = 5;  // tenths of a unit
        camera.transform = lookAlong(Vec3(0, 2, 2), Vec3(0, -1, -1));
        scene.setCamera(camera);
    };
    Scene reference;
    build(reference);
    Render path = render(reference, "path", 16, 1024, {{"pathDepth", 5}});
    // Each channel's mean over the path tracer's, over seeds 1-6 (photons seed s, path tracer s + 100):
    // final gathering 0.98-1.02, sd 1.1%, the reference's noise (0.5%) included: 4 sd is 4.5%. The
    // photon cache 0.99-1.02 on five seeds, but seed 3 reads 1.11 in red (its path-traced records
    // now and then catch a caustic path the caustic map also holds): sd 4.3%, 4 sd 17%.
    const std::map<std::string, double> bound = {{"photonMapFinalGather", 0.045}, {"photonMapIrradianceCache", 0.17}};
    for (const char* integrator : kPhotonIntegrators) {
        Scene scene;
        build(scene);
        Render photons = render(scene, integrator, 16, 16, {{"causticPhotons", 1000000}, {"photons", 100000}});
        ASSERT_TRUE(allFinite(photons)) << integrator;
        EXPECT_GT(photons.stats.integrator.at("causticMapPhotons"), 10000) << integrator;
        for (int c = 0; c < 3; ++c) {
            double p = channelMean(photons.rgb, c), expected = channelMean(path.rgb, c);
            EXPECT_NEAR(p, expected, bound.at(integrator) * expected) << integrator << " channel " << c;
        }
        // The caustic is coloured by the glass: less blue than red.
        EXPECT_LT(channelMean(photons.rgb, 2), 0.8 * channelMean(photons.rgb, 0)) << integrator;
    }
    // The plain and adaptive irradiance caches read a caustic map of their own at their pixels, and
    // their records' paths leave the caustic to it (irradiance_cache_integrator.h). Over seeds 1-4
    // each channel's mean read 0.987-1.042 of the path tracer's (plain) and 0.983-1.016 (adaptive),
    // green within 1.3% on every seed; the four seeds' mean within 0.5%, 4% is 4 sd. Without the map
    // (causticPhotons 0) the records' paths find the caustic by chance and clamp it as an outlier:
    // green 0.906-1.129 (plain), 0.860-0.904 (adaptive).
    for (const char* integrator : {"irradianceCache", "adaptiveIrradianceCache"}) {
        double sum[3] = {0, 0, 0};
        for (uint32_t seed = 1; seed <= 4; ++seed) {
            Scene scene;
            build(scene);
            Render cache = render(scene, integrator, 16, 16, {{"causticPhotons", 1000000}}, seed);
            ASSERT_TRUE(allFinite(cache)) << integrator;
            EXPECT_GT(cache.stats.integrator.at("causticMapPhotons"), 10000) << integrator;
            for (int c = 0; c < 3; ++c) sum[c] += channelMean(cache.rgb, c) / 4;
            EXPECT_NEAR(channelMean(cache.rgb, 1) / channelMean(path.rgb, 1), 1.0, 0.05) << integrator << " seed " << seed;
        }
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sum[c] / channelMean(path.rgb, c), 1.0, 0.04) << integrator << " channel " << c;
    }
}

// Light focused through a glass ball onto a floor (the ball sits in the only opening of a black
// shade), seen only after a bounce: the camera looks at a wall beside it that no light reaches
// directly. Final gathering's gather ray from the wall path-traces one vertex on the floor
// (gatherBounces = 1), so the caustic there must come from the caustic map at that vertex: without
// it the wall loses most of its light. So must the photon cache's path-traced records (here every
// record is one: no global map). The path tracer (its BSDF-sampled rays from the floor through the
// ball find the light) is the reference.
TEST(PhotonMapRender, CausticSeenAfterABounceMatchesThePathTracer) {
    auto build = [](Scene& scene) {
        int white = scene.addMaterial(lambert(Color(0.8f)));
        int black = scene.addMaterial(lambert(Color(0.0f)));
        int g = scene.addMaterial(smoothGlass(Color(0.18f)));
        addQuad(scene, "/Floor", {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, white);
        addQuad(scene, "/Wall", {1, 0, -1}, {1, 0, 1}, {1, 1, 1}, {1, 1, -1}, white);
        // The shade at y = 1, open over the ball only (a 0.6 x 0.6 hole: three quarters of its
        // light passes the glass).
        addQuad(scene, "/ShadeA", {-3, 1, -3}, {-0.3f, 1, -3}, {-0.3f, 1, 3}, {-3, 1, 3}, black);
        addQuad(scene, "/ShadeB", {0.3f, 1, -3}, {3, 1, -3}, {3, 1, 3}, {0.3f, 1, 3}, black);
        addQuad(scene, "/ShadeC", {-0.3f, 1, -3}, {0.3f, 1, -3}, {0.3f, 1, -0.3f}, {-0.3f, 1, -0.3f}, black);
        addQuad(scene, "/ShadeD", {-0.3f, 1, 0.3f}, {0.3f, 1, 0.3f}, {0.3f, 1, 3}, {-0.3f, 1, 3}, black);
        scene.addSphere("/Ball", Vec3(0, 0.6f, 0), 0.3f, g, nullptr, -1);
        scene.addLight(rectLight("/Light", Vec3(0, 3, 0), Vec3(0, -1, 0), 0.6f, 60));
        CameraDesc camera;  // orthographic, 0.6 x 0.6, onto the wall from in front of it
        camera.name = "/Camera";
        camera.projection = "orthographic";
        camera.horizontalAperture = camera.verticalAperture = 6;  // tenths of a unit
        camera.transform = lookAlong(Vec3(0.7f, 0.5f, 0), Vec3(1, 0, 0));
        scene.setCamera(camera);
    };
    // Both are noisy (a caustic): over five seeds each, per seed the path tracer's wall varies by
    // 1.4% (8192 spp) and final gathering's by 1.7% (16 spp), so the ratio of the five-seed means
    // by about 1%: 4% is 4 sigma. Measured: 0.98; without the caustic map at the bounce, 0.91.
    // The photon cache (4096 paths a record: its few records carry the caustic's noise) varies by
    // 2.1% a seed, 1% over five; its outlier clamp keeps about 2% of the caustic out (1.7%
    // measured with it off), so 5% is 3 sigma. Measured: 0.979; without the caustic map along
    // its records' paths, 0.913. The plain irradiance cache (its own caustic map, 4096 paths a
    // record) likewise: 1.002 measured, 1.097 without the map (its records count the caustic's
    // paths, clamped or not by chance).
    double pathSum = 0, gatherSum = 0, cacheSum = 0, icSum = 0;
    for (uint32_t seed = 1; seed <= 5; ++seed) {
        Scene reference, scene;
        build(reference);
        build(scene);
        Render path = render(reference, "path", 8, 8192, {}, seed);
        Render fg = render(scene, "photonMapFinalGather", 8, 16, {{"causticPhotons", 1000000}, {"photons", 200000}}, seed);
        Render cache = render(scene, "photonMapIrradianceCache", 8, 16,
                              {{"causticPhotons", 1000000}, {"photons", 0}, {"paths", 4096}}, seed);
        Scene icScene;
        build(icScene);
        Render ic = render(icScene, "irradianceCache", 8, 16, {{"causticPhotons", 1000000}, {"paths", 4096}}, seed);
        ASSERT_TRUE(allFinite(fg));
        ASSERT_TRUE(allFinite(ic));
        ASSERT_TRUE(allFinite(cache));
        pathSum += channelMean(path.rgb, 1);
        gatherSum += channelMean(fg.rgb, 1);
        cacheSum += channelMean(cache.rgb, 1);
        icSum += channelMean(ic.rgb, 1);
    }
    std::printf("[ caustic ] wall: final gathering %.5f, photon cache %.5f, path %.5f (ratios %.4f, %.4f)\n",
                gatherSum / 5, cacheSum / 5, pathSum / 5, gatherSum / pathSum, cacheSum / pathSum);
    EXPECT_NEAR(gatherSum / pathSum, 1.0, 0.04);
    EXPECT_NEAR(cacheSum / pathSum, 1.0, 0.05);
    std::printf("[ caustic ] wall: irradiance cache %.5f (ratio %.4f)\n", icSum / 5, icSum / pathSum);
    EXPECT_NEAR(icSum / pathSum, 1.0, 0.05);
}

// A closed room lit only through a glass pane in its ceiling (all its light a caustic, L S D, as
// in a church), by a sky and by a rect light above the pane. Final gathering and the photon cache
// leave the dome's photons out of their caustic maps and count the sky through the glass with
// their gather rays and record paths, while the rect light's caustic stays in the map: each light
// path exactly once. The path tracer (its BSDF-sampled rays find both through the pane) is the
// reference; the camera looks down at the floor under the window.
TEST(PhotonMapRender, SkyThroughGlassIsGatheredOnce) {
    auto build = [](Scene& scene) {
        int white = scene.addMaterial(lambert(Color(0.6f)));
        int g = scene.addMaterial(smoothGlass(Color(1.0f)));
        // A 2 x 2 x 2 room; the ceiling (y = 2) open over |x|, |z| < 0.5, where the pane is.
        addRoomWalls(scene, 2, white, white);
        addQuad(scene, "/CeilingA", {-1, 2, -1}, {-0.5f, 2, -1}, {-0.5f, 2, 1}, {-1, 2, 1}, white);
        addQuad(scene, "/CeilingB", {0.5f, 2, -1}, {1, 2, -1}, {1, 2, 1}, {0.5f, 2, 1}, white);
        addQuad(scene, "/CeilingC", {-0.5f, 2, -1}, {0.5f, 2, -1}, {0.5f, 2, -0.5f}, {-0.5f, 2, -0.5f}, white);
        addQuad(scene, "/CeilingD", {-0.5f, 2, 0.5f}, {0.5f, 2, 0.5f}, {0.5f, 2, 1}, {-0.5f, 2, 1}, white);
        addQuad(scene, "/Pane", {-0.5f, 2, -0.5f}, {-0.5f, 2, 0.5f}, {0.5f, 2, 0.5f}, {0.5f, 2, -0.5f}, g);
        LightDesc sky;
        sky.name = "/Sky";
        sky.kind = "dome";
        sky.intensity = 1;
        scene.addLight(sky);
        LightDesc lamp;  // 2 x 2, 2 m above the pane, facing down
        lamp.name = "/Lamp";
        lamp.kind = "rect";
        lamp.width = lamp.height = 2;
        lamp.intensity = 1;
        lamp.transform.m[1][1] = 0, lamp.transform.m[1][2] = -1;
        lamp.transform.m[2][1] = 1, lamp.transform.m[2][2] = 0;
        lamp.transform.m[3][1] = 4;
        scene.addLight(lamp);
        // The lamp lies outside the room's bounds and must shade the sky's photons as it shades
        // the sky from camera paths (Scene::photonBounds): photons starting on the room's bounds
        // passed it, and (darker pane) the photon cache read 1.42 of the path tracer, final
        // gathering 1.03.
        scene.setCamera(lookingDown({0, 1, 0}, true, 10));  // the floor's middle square metre
    };
    // Eight seeds. Per seed the path tracer (2048 spp) varies by 0.7%, final gathering (64 spp)
    // by 2.5%, the photon cache by 4-5%: the eight-seed ratios by about 1% and 1.7%. Measured:
    // final gathering 0.990, the photon cache 0.992, with path-traced records only 1.009. With a
    // darker pane (tint 0.18) and the sky alone, keeping the dome's photons in the caustic maps as
    // well read 1.82 (final gathering) and 1.94 (photon cache); final gathering without its gather
    // rays' sky, 0.16.
    double pathSum = 0, gatherSum = 0, cacheSum = 0, tracedSum = 0;
    for (uint32_t seed = 1; seed <= 8; ++seed) {
        Scene reference, scene;
        build(reference);
        build(scene);
        Render path = render(reference, "path", 8, 2048, {}, seed);
        Render fg = render(scene, "photonMapFinalGather", 8, 64, {}, seed);
        Scene cached;
        build(cached);
        Render cache = render(cached, "photonMapIrradianceCache", 8, 16, {}, seed);
        Scene traced;  // every record path-traced (no global map)
        build(traced);
        Render tracedOnly = render(traced, "photonMapIrradianceCache", 8, 16, {{"photons", 0}, {"paths", 1024}}, seed);
        ASSERT_TRUE(allFinite(fg));
        ASSERT_TRUE(allFinite(cache));
        EXPECT_GT(fg.stats.integrator.at("causticMapPhotons"), 0);  // the lamp's
        EXPECT_GT(cache.stats.integrator.at("causticMapPhotons"), 0);
        pathSum += channelMean(path.rgb, 1);
        gatherSum += channelMean(fg.rgb, 1);
        cacheSum += channelMean(cache.rgb, 1);
        tracedSum += channelMean(tracedOnly.rgb, 1);
    }
    std::printf("[ sky through glass ] floor: final gathering %.5f, path %.5f (ratio %.4f)\n", gatherSum / 8,
                pathSum / 8, gatherSum / pathSum);
    EXPECT_NEAR(gatherSum / pathSum, 1.0, 0.04);
    std::printf("[ sky through glass ] photon cache %.5f (ratio %.4f), path-traced records only %.5f (ratio %.4f)\n",
                cacheSum / 8, cacheSum / pathSum, tracedSum / 8, tracedSum / pathSum);
    EXPECT_NEAR(cacheSum / pathSum, 1.0, 0.05);
    EXPECT_NEAR(tracedSum / pathSum, 1.0, 0.05);
}

// A near-mirror: UsdPreviewSurface's specular workflow, specular 0.9, roughness 0.2, dark diffuse.
MaterialDesc nearMirror() {
    MaterialDesc mirror = lambert(Color(0.05f));
    mirror.specularColor = Color(0.9f);
    mirror.roughness = 0.2f;
    return mirror;
}

// A camera at `eye` looking along `forward`.
CameraDesc cameraAlong(Vec3 eye, Vec3 forward, float focalLength) {
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = focalLength;
    camera.transform = lookAlong(eye, forward);
    return camera;
}

// A glossy floor (specular 0.5, roughness 0.25) reflecting a lamp through a glass pane: light on
// the path lamp, pane, floor, eye (L S G E) is 99% of the image. The progressive photon map traces
// glossy lobes as the caches do and reads the photons that came through the pane alone through the
// whole BSDF (PhotonMap::radianceBesideGlossyRays); the caches read their caustic maps through the
// whole BSDF, so their glossy rays leave the lamp behind the pane to the maps
// (DirectIntegrator::glossyBranchEmitters_). Over four seeds against the path tracer (2048 spp):
// the progressive photon map 1.003 (1.002 reading every photon through the whole BSDF, before it
// traced glossy lobes); the plain, adaptive and photon caches 1.026, 2.015 when their glossy rays
// counted the lamp behind the pane as well, 0.999 without a caustic map. What remains of their
// 2.6% is the caustic map's: it reads as much too bright with a Lambertian floor (1.026 of the path
// tracer there, the progressive photon map 0.997), 1.027 and 1.025 with 4 million caustic photons
// at k = 8 and 200, 1.05 with 100,000 (not yet explained).
TEST(PhotonMapRender, GlossyReflectionThroughGlassCountedOnce) {
    auto build = [](Scene& scene) {
        MaterialDesc floorDesc = lambert(Color(0.2f));
        floorDesc.specularColor = Color(0.5f);
        floorDesc.roughness = 0.25f;
        int floor = scene.addMaterial(floorDesc), white = scene.addMaterial(lambert(Color(0.7f)));
        int glass = scene.addMaterial(smoothGlass(Color(1.0f)));
        addQuad(scene, "/Floor", {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, floor);
        addQuad(scene, "/Back", {-4, 0, -4}, {4, 0, -4}, {4, 3, -4}, {-4, 3, -4}, white);
        addQuad(scene, "/Pane", {-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}, glass);
        scene.addLight(rectLight("/Lamp", Vec3(0, 1, -3), Vec3(0, 0, 1), 1.5f, 10));
        scene.setCamera(cameraAlong(Vec3(0, 0.3f, 3), Vec3(0, -0.35f, -1), 50));  // the lamp itself above the frame, its reflection in it
    };
    const int seeds = 4;
    std::map<std::string, double> sums;
    for (uint32_t seed = 1; seed <= seeds; ++seed)
        for (const char* integrator : {"path", "progressivePhotonMap", "irradianceCache", "adaptiveIrradianceCache",
                                       "photonMapIrradianceCache"}) {
            Scene scene;
            build(scene);
            bool path = std::string(integrator) == "path";
            Render r = render(scene, integrator, 32, path ? 2048 : 64, {}, seed);
            ASSERT_TRUE(allFinite(r)) << integrator;
            sums[integrator] += channelMean(r.rgb, 1) / seeds;
        }
    for (const auto& [integrator, mean] : sums) {
        if (integrator == "path") continue;
        std::printf("[ glossy through glass ] %s %.4f of the path tracer (%.5f)\n", integrator.c_str(),
                    mean / sums["path"], sums["path"]);
        EXPECT_NEAR(mean / sums["path"], 1.0, integrator == "progressivePhotonMap" ? 0.02 : 0.05) << integrator;
    }
}

// A near-mirror floor (specular 0.9, roughness 0.2) reflecting a lamp-lit wall. The progressive
// photon map read the wall's reflection from the photons on the floor, through a lobe a few degrees
// wide that few of them fall in: blotches however many photons a pass has. It now traces the glossy
// lobe to the wall (DirectIntegrator::glossyIndirect). Squared error of 4 x 4 blocks' luminance
// against the path tracer (4096 spp), over its mean squared, at 16 samples per pixel, mean over
// four seeds: 0.41 before, 0.0006 now (the path tracer at 16 spp: 0.038).
TEST(PhotonMapRender, ProgressivePhotonMapTracesSharpGlossyLobes) {
    auto build = [](Scene& scene) {
        int floor = scene.addMaterial(nearMirror()), white = scene.addMaterial(lambert(Color(0.7f)));
        addQuad(scene, "/Floor", {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, floor);
        addQuad(scene, "/Back", {-4, 0, -4}, {4, 0, -4}, {4, 3, -4}, {-4, 3, -4}, white);
        scene.addLight(rectLight("/Lamp", Vec3(0, 2.5f, 0), Vec3(0, -0.3f, -1), 1.0f, 20));
        scene.setCamera(cameraAlong(Vec3(0, 0.4f, 3), Vec3(0, -0.3f, -1), 50));
    };
    const int size = 32;
    Scene reference;
    build(reference);
    std::vector<double> ref = blockLuminance(render(reference, "path", size, 4096, {}, 100).rgb, size);
    double refMean = 0;
    for (double v : ref) refMean += v / double(ref.size());
    auto e2 = [&](const char* integrator, uint32_t seed) {
        Scene scene;
        build(scene);
        Render r = render(scene, integrator, size, 16, {}, seed);
        EXPECT_TRUE(allFinite(r)) << integrator;
        std::vector<double> blocks = blockLuminance(r.rgb, size);
        double sum = 0;
        for (size_t i = 0; i < blocks.size(); ++i) sum += (blocks[i] - ref[i]) * (blocks[i] - ref[i]);
        return sum / double(blocks.size()) / (refMean * refMean);
    };
    double ppm = 0, path = 0;
    for (uint32_t seed = 1; seed <= 4; ++seed) {
        ppm += e2("progressivePhotonMap", seed) / 4;
        path += e2("path", seed) / 4;
    }
    std::printf("[ sharp glossy ] relative block e^2 at 16 spp: progressive photon map %.5f, path tracer %.5f\n", ppm, path);
    EXPECT_LT(ppm, 0.25 * path);
}

// A white floor lit through a near-mirror wall (specular 0.9, roughness 0.2) that reflects a
// lamp-lit white wall. Final gathering read the photon map at its gather hits through the
// Lambertian reflectance alone, and on the mirror that is nothing: the mirror's reflection of the
// lit wall was lost to the floor. It now traces the glossy lobes on from there (the map read at
// the next hit). Over two seeds against the path tracer (1024 spp), with the map read at the
// gather hit (gatherBounces 0) and one path-traced vertex before it (the default): 0.947 and 0.992
// before, 0.998 and 0.995 now. McGuire's Cornell boxes (a near-mirror ball or box) read 0.970-0.980
// of the path tracer away from their light before, 1.000 now.
TEST(PhotonMapRender, FinalGatherTracesGlossyLobesPastItsGatherHit) {
    auto build = [](Scene& scene) {
        int glossy = scene.addMaterial(nearMirror()), white = scene.addMaterial(lambert(Color(0.7f)));
        addQuad(scene, "/Floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, white);
        addQuad(scene, "/Mirror", {-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}, glossy);
        addQuad(scene, "/Left", {-2, 0, -2}, {-2, 2, -2}, {-2, 2, 2}, {-2, 0, 2}, white);
        scene.addLight(rectLight("/Lamp", Vec3(-1.6f, 1.2f, 0.5f), Vec3(-1, 0, 0), 0.5f, 40));  // lights the wall
        scene.setCamera(cameraAlong(Vec3(0.5f, 1.5f, 3), Vec3(-0.2f, -0.6f, -1), 35));
    };
    for (double bounces : {0.0, 1.0}) {
        double path = 0, gather = 0;
        for (uint32_t seed = 1; seed <= 2; ++seed) {
            Scene reference, scene;
            build(reference);
            build(scene);
            path += channelMean(render(reference, "path", 32, 1024, {}, seed).rgb, 1);
            Render fg = render(scene, "photonMapFinalGather", 32, 16, {{"gatherBounces", bounces}}, seed);
            ASSERT_TRUE(allFinite(fg));
            gather += channelMean(fg.rgb, 1);
        }
        std::printf("[ glossy gather ] gatherBounces %.0f: final gathering %.4f of the path tracer\n", bounces, gather / path);
        EXPECT_NEAR(gather / path, 1.0, 0.02) << "gatherBounces " << bounces;
    }
}

// The thesis's box ("Caixa"): a Cornell box with red and blue walls, a ceiling light and a
// tinted glass sphere, after scenes/cornell/cornell.usda.
void buildGlassCornellBox(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.73f)));
    int red = scene.addMaterial(lambert(Color(0.65f, 0.05f, 0.05f)));
    int blue = scene.addMaterial(lambert(Color(0.05f, 0.05f, 0.65f)));
    int g = scene.addMaterial(smoothGlass(Color(0.6f, 0.9f, 0.6f)));
    addQuad(scene, "/Floor", {-1, -1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}, white);
    addQuad(scene, "/Ceiling", {-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}, white);
    addQuad(scene, "/Back", {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, white);
    addQuad(scene, "/Left", {-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, -1, 1}, red);
    addQuad(scene, "/Right", {1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}, blue);
    scene.addSphere("/Glass", Vec3(0, -0.6f, 0), 0.4f, g, nullptr, -1);
    LightDesc light = rectLight("/Light", Vec3(0, 0.99f, 0), Vec3(0, -1, 0), 0.46f, 15);
    light.height = 0.38f;
    scene.addLight(light);
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 50;
    camera.horizontalAperture = camera.verticalAperture = 35.71429f;
    camera.transform.m[3][2] = 3.9f;
    scene.setCamera(camera);
}

// Both integrators approach the path tracer (all paths to depth 30 on each side) at the rate their
// estimators give as photons, gather photons and gather rays grow, and carry its energy.
//
// The error measured is that of the indirect light: an integrator's image minus the `direct`
// image of the same seed and light samples (the ray tracer's part draws the same random numbers
// in both), so the direct light's and the glass's noise, common to every integrator, cancel. The
// reference's indirect light is the path tracer's (two independent 1024-spp halves) minus a
// `direct` image (two 512-spp halves). e^2 is the mean squared error of the 4 x 4 blocks'
// luminance (block means: a pixel's noise is heavy-tailed), less the reference's own block
// variance (from its halves), over the square of the reference indirect's mean: what remains
// estimates the integrator's bias^2 + variance, averaged over three seeds.
//
// The rate: from the small budget to the large one the final gather's rays grow 16x (1 -> 16 per
// sample) and the density estimates' bias, proportional to the gather disc's area k/N, shrinks
// 9.6x (8 of 5000 photons -> 50 of 300000), so final gathering's e^2 must fall 16x; the photon
// cache's records (their hemisphere paths are most of its noise) grow 7.5x (16 -> 120 paths): 7.5x.
// So e^2(large) - e^2(small) / rate is 0 up to noise. Its noise, measured over ten independent runs
// of the whole test (references included, seeds 1000 k + ...): final gathering mean 0.00045, sd
// 0.0018 (e^2 0.0187 -> 0.00162, 11.6x), the photon cache 0.00022, sd 0.0027 (0.0461 -> 0.00637,
// 7.2x); the bounds are 4 sd. Error that falls at half the rate, or not at all (a density estimate
// whose radius does not shrink with the photons, gather rays that do not count) fails, as does a
// constant bias in the indirect light beyond ~8% (its square adds to e^2(large)); the mean catches
// smaller ones.
//
// The energy: the large budget's indirect mean over three seeds against the reference's, over the
// same ten runs: final gathering 0.997 (sd 0.0085), the photon cache 0.996 (sd 0.0099), most of it
// the reference's noise (its path tracer's direct light, which the subtracted `direct` image does
// not share); the bounds are 4 sd, 3.4% and 4.0%.
struct ConvergenceFigures {
    double e2Small, e2Large, indirectMean;  // e^2 at each budget (over seeds), indirect mean / reference's
};

// The figures of one run of the test below, its seeds offset by `seedBase` (the bounds were measured
// over cornellConvergence(1000 k, 3), k = 1..10).
std::map<std::string, ConvergenceFigures> cornellConvergence(uint32_t seedBase, int seeds) {
    const int size = 32;
    const std::map<std::string, double> deep = {{"photonDepth", 30}, {"rayDepth", 30}, {"pathDepth", 30}, {"lightSamples", 4}};
    auto blocksOf = [&](const char* integrator, int spp, const std::map<std::string, double>& params, uint32_t seed) {
        Scene scene;
        buildGlassCornellBox(scene);
        Render r = render(scene, integrator, size, spp, takenBy(integrator, params), seedBase + seed);
        EXPECT_TRUE(allFinite(r)) << integrator;
        return blockLuminance(r.rgb, size);
    };
    std::vector<double> path[2] = {blocksOf("path", 1024, deep, 101), blocksOf("path", 1024, deep, 102)};
    std::vector<double> direct[2] = {blocksOf("direct", 512, deep, 103), blocksOf("direct", 512, deep, 104)};
    const IndirectReference reference = indirectReference(path, direct);
    std::vector<std::vector<double>> directBySeed;
    for (int seed = 1; seed <= seeds; ++seed) directBySeed.push_back(blocksOf("direct", 16, deep, seed));

    struct Budget {
        double photons, gatherPhotons, finalGatherSamples, paths;
    };
    const Budget budgets[2] = {{5000, 8, 1, 16}, {300000, 50, 16, 120}};
    std::map<std::string, ConvergenceFigures> figures;
    for (const char* integrator : kPhotonIntegrators) {
        double e2[2] = {0, 0}, indirectMean = 0;
        for (int level = 0; level < 2; ++level) {
            const Budget& b = budgets[level];
            std::map<std::string, double> params = deep;
            params.insert({{"photons", b.photons}, {"causticPhotons", b.photons}, {"gatherPhotons", b.gatherPhotons},
                           {"finalGatherSamples", b.finalGatherSamples}, {"paths", b.paths}});
            for (int seed = 1; seed <= seeds; ++seed) {
                IndirectError e = indirectError(blocksOf(integrator, 16, params, seed), directBySeed[seed - 1], reference);
                e2[level] += e.e2 / seeds;
                if (level) indirectMean += e.mean / seeds;
            }
        }
        std::printf("[ cornell  ] %s: indirect e^2 %.5f -> %.5f (ratio %.1f), indirect mean %.4f of the reference's"
                    " (reference noise %.5f)\n",
                    integrator, e2[0], e2[1], e2[0] / e2[1], indirectMean, reference.variance / (reference.mean * reference.mean));
        figures[integrator] = {e2[0], e2[1], indirectMean};
    }
    return figures;
}

TEST(PhotonMapRender, CornellBoxConvergesToThePathTracer) {
    struct Expected {
        const char* integrator;
        double rate, fourSigmaOfDifference, fourSigmaOfMean;  // derived above
    };
    std::map<std::string, ConvergenceFigures> figures = cornellConvergence(0, 3);
    for (Expected expected : {Expected{"photonMapFinalGather", 16, 0.0072, 0.034}, Expected{"photonMapIrradianceCache", 7.5, 0.0108, 0.040}}) {
        const ConvergenceFigures& f = figures.at(expected.integrator);
        EXPECT_LT(f.e2Large - f.e2Small / expected.rate, expected.fourSigmaOfDifference) << expected.integrator;
        EXPECT_NEAR(f.indirectMean, 1.0, expected.fourSigmaOfMean) << expected.integrator;
    }
}

TEST(PhotonMapRender, SameImageWhateverTheThreadCount) {
    for (const char* integrator : kPhotonIntegrators) {
        auto once = [&](int threads) {
            Scene scene;
            buildThinWallScene(scene);
            return render(scene, integrator, 16, 2, takenBy(integrator, {{"photons", 20000}, {"finalGatherSamples", 4}, {"paths", 16}}), 1,
                          threads).rgb;
        };
        std::vector<float> first = once(0);
        EXPECT_EQ(first, once(0)) << integrator;
        EXPECT_EQ(first, once(1)) << integrator;
    }
}

TEST(PhotonMapRegistry, BothIntegratorsReflectTheirParameters) {
    for (const char* integrator : kPhotonIntegrators) {
        const IntegratorInfo* info = findIntegrator(integrator);
        ASSERT_NE(info, nullptr) << integrator;
        std::vector<std::string> names = paramNames(integrator);
        for (const char* name : {"photons", "causticPhotons", "photonDepth", "gatherPhotons", "maxGatherRadius", "rayDepth"})
            EXPECT_TRUE(hasParam(names, name)) << integrator << " " << name;
        ParamSet p;
        p.set("photons", 1e12);  // passed through: the integrator clamps it and says so
        EXPECT_EQ(paramValue(*info, p, "photons"), 1e12);
    }
    const IntegratorInfo* fg = findIntegrator("photonMapFinalGather");
    for (const char* name : {"finalGatherSamples", "finalGatherDepth"}) {
        bool found = false;
        for (const ParamInfo& p : fg->params) found = found || p.name == name;
        EXPECT_TRUE(found) << name;
    }
    const IntegratorInfo* ic = findIntegrator("photonMapIrradianceCache");
    ParamSet none;
    EXPECT_EQ(paramValue(*ic, none, "paths"), 120);  // thesis table 4.3
    EXPECT_EQ(paramValue(*ic, none, "photons"), 500000);
}

}  // namespace


TEST(ProgressivePhotonMap, RadiusShrinksAsHachisukaAndJensen) {
    // Iteration i reads its map with r_i^2 = r_1^2 prod_{k=1}^{i-1} (k + alpha) / (k + 1): the
    // closed form against the product, and a render's last radius against it. The convergence
    // tests cannot resolve a radius that never shrinks at their sample counts (the bias it leaves
    // is below their noise), so the schedule is checked here directly.
    for (float alpha : {0.5f, 2.0f / 3, 0.9f}) {
        double product = 1;
        for (uint32_t i = 1; i <= 1000; ++i) {
            if (i > 1) product *= (double(i - 1) + alpha) / double(i);
            EXPECT_NEAR(ProgressivePhotonMapIntegrator::radiusScale(i - 1, alpha), std::sqrt(product),
                        1e-5 * std::sqrt(product)) << "alpha " << alpha << " iteration " << i;
        }
    }
    Scene scene;
    buildSealedBox(scene, false);
    Render r = render(scene, "progressivePhotonMap", 8, 16, {{"photonsPerPass", 2000}});
    double product = 1;
    for (int k = 1; k < 16; ++k) product *= (k + 2.0 / 3) / (k + 1);
    EXPECT_NEAR(r.stats.integrator.at("lastRadiusScale"), std::sqrt(product), 1e-5);  // 16th iteration, alpha 2/3
}

TEST(ProgressivePhotonMap, WithoutPhotonsItIsTheRayTracer) {
    // photonsPerPass 0 (what auto's pilot measures the camera's own noise with): no photon is
    // traced and the image is the ray tracer's, bit for bit (the rooms' Lambertian walls have no
    // glossy lobe for it to trace); with photons, the indirect light adds to it.
    Scene scene;
    buildThinWallScene(scene);
    const Render none = render(scene, "progressivePhotonMap", 32, 4, {{"photonsPerPass", 0}});
    const Render direct = render(scene, "direct", 32, 4);
    const Render photons = render(scene, "progressivePhotonMap", 32, 4, {{"photonsPerPass", 20000}});
    EXPECT_EQ(none.stats.integrator.at("photonsTraced"), 0);
    EXPECT_TRUE(allFinite(none));
    EXPECT_EQ(none.rgb, direct.rgb);
    double sumNone = 0, sumPhotons = 0;
    for (size_t i = 0; i < none.rgb.size(); ++i) sumNone += none.rgb[i], sumPhotons += photons.rgb[i];
    EXPECT_GT(sumPhotons, 1.05 * sumNone);
}
