// Photon power from infinite lights (issue 15): distant and dome lights emit photons from a
// disc covering the scene's bounds. The global map's irradiance, read where the photons land,
// must match what the lights deliver: E cos(theta) from the sun and pi L times the visible
// share of the sky (a cosine-weighted shadow-ray estimate, independent of the photon code).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "renderer/integrators/photon_maps.h"
#include "renderer/sampling.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

const Vec3 kToSun = normalize(Vec3(0.3f, 0.8f, 0.45f));
constexpr float kSunIrradiance = 3, kSkyRadiance = 0.5f;

Mat4 alongMinusZ(Vec3 forward) {  // a transform whose -Z is `forward`
    Vec3 f = normalize(forward), up = std::fabs(f.y) > 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    Vec3 r = normalize(cross(f, up)), u = cross(r, f);
    Mat4 m;
    Vec3 rows[3] = {r, u, -f};
    for (int i = 0; i < 3; ++i) m.m[i][0] = rows[i].x, m.m[i][1] = rows[i].y, m.m[i][2] = rows[i].z;
    return m;
}

void addSun(Scene& scene) {
    LightDesc sun;
    sun.name = "/Sun";
    sun.kind = "distant";
    sun.intensity = kSunIrradiance;
    sun.angle = 0.53f;
    sun.normalize = true;  // intensity = irradiance at normal incidence (UsdLux)
    sun.transform = alongMinusZ(-kToSun);
    scene.addLight(sun);
}

void addSunAndSky(Scene& scene) {
    addSun(scene);
    LightDesc sky;
    sky.name = "/Sky";
    sky.kind = "dome";
    sky.intensity = kSkyRadiance;
    scene.addLight(sky);
}

CameraDesc lookingDownFrom(float height) {
    CameraDesc c = lookingDown(Vec3(0, height, 0), false, 36);
    c.focalLength = 20;
    return c;
}

PhotonMaps tracePhotons(Scene& scene, double photons, bool guide = true) {
    scene.commit();
    Camera camera(scene.cameraDesc(), 32, 32);
    PreprocessContext context{scene, camera, 32, 32, 7, nullptr};
    PhotonMapSettings settings;
    settings.photons = photons;
    settings.causticPhotons = 0;
    settings.globalKeepsDirectAndCaustic = true;
    settings.guideEmission = guide;
    PhotonMaps maps;
    buildPhotonMaps(context, settings, maps);
    return maps;
}

// Irradiance at p on an upward surface by shadow rays: the sun (a delta direction, unoccluded
// or not) and the sky's visible, cosine-weighted share.
double expectedIrradiance(const Scene& scene, Vec3 p, int skyRays, bool sky = true) {
    RayStats stats;
    Vec3 o = p + Vec3(0, 1e-4f, 0);
    double E = scene.occluded(o, kToSun, kInf, stats) ? 0 : kSunIrradiance * kToSun.y;
    Frame frame(Vec3(0, 1, 0));
    int visible = 0;
    for (int i = 0; i < skyRays; ++i) {
        Vec2 u((i + 0.5f) / skyRays, std::fmod(i * 0.618034f, 1.0f));
        Vec3 d = frame.toWorld(sampleCosineHemisphere(u));
        visible += !scene.occluded(o, d, kInf, stats);
    }
    return E + (sky ? kPi * kSkyRadiance * double(visible) / skyRays : 0.0);
}

// A grid of 11 x 11 floor points within `half` of the centre.
std::vector<Vec3> floorGrid(float half) {
    std::vector<Vec3> points;
    for (float x = -half; x <= half + 1e-4f; x += half / 5)
        for (float z = -half; z <= half + 1e-4f; z += half / 5) points.emplace_back(x, 0, z);
    return points;
}

// Mean photon and shadow-ray irradiance over floorGrid(half).
std::pair<double, double> compare(const Scene& scene, const PhotonMaps& maps, float half, int k, bool sky = true) {
    double photon = 0, expected = 0;
    int n = 0;
    for (Vec3 p : floorGrid(half)) {
        photon += maps.global.irradiance({p, Vec3(0, 1, 0)}, k, 10).value.x;
        expected += expectedIrradiance(scene, p, sky ? 4096 : 0, sky);
        ++n;
    }
    std::printf("[ irradiance ] photon map %.4f, shadow rays %.4f (ratio %.4f)\n", photon / n, expected / n, photon / expected);
    return {photon / n, expected / n};
}

}  // namespace

// An open plane: nothing shades it, E = E_sun cos(theta) + pi L_sky.
TEST(PhotonEmission, SunAndSkyOnAnOpenPlane) {
    Scene scene;
    int grey = scene.addMaterial(lambert(Color(0.5f)));
    addQuad(scene, "/Ground", {-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, grey);
    addSunAndSky(scene);
    scene.setCamera(lookingDownFrom(6));
    PhotonMaps maps = tracePhotons(scene, 1e6);
    auto [photon, expected] = compare(scene, maps, 2.0f, 400);
    EXPECT_NEAR(expected, kSunIrradiance * kToSun.y + kPi * kSkyRadiance, 0.002 * expected);
    // 121 estimates of k = 400 photons: under 0.5% noise (1/sqrt(400 * 121)); 2% is the bound.
    EXPECT_NEAR(photon, expected, 0.02 * expected);
}

// The box's open top, 1 cm above it; light passes downwards (its -Z), or, `upsideDown`, upwards.
LightDesc portalOverTheBox(bool upsideDown = false) {
    LightDesc portal;
    portal.name = "/Portal";
    portal.kind = "portal";
    portal.width = portal.height = 2;
    // Local Z onto world +Y, local Y onto -Z (rows: the x, y, z axes, then the translation).
    float s = upsideDown ? -1.0f : 1.0f;
    portal.transform.m[1][1] = 0, portal.transform.m[1][2] = -s;
    portal.transform.m[2][1] = s, portal.transform.m[2][2] = 0;
    portal.transform.m[3][1] = 1.01f;
    return portal;
}

// A half-open box (floor and four black walls, no roof): the walls shade part of the sky and,
// on one side, the sun; black walls store no photons and reflect nothing, so the floor's
// irradiance is the lights' alone.
void buildHalfOpenBox(Scene& scene, bool sky = true) {
    int grey = scene.addMaterial(lambert(Color(0.5f)));
    int black = scene.addMaterial(lambert(Color(0.0f)));
    addRoomWalls(scene, 1, grey, black);
    if (sky)
        addSunAndSky(scene);
    else
        addSun(scene);
}

void halfOpenBoxUnderSunAndSky(bool portal) {
    Scene scene;
    buildHalfOpenBox(scene);
    if (portal) scene.addLight(portalOverTheBox());
    scene.setCamera(lookingDownFrom(3));
    PhotonMaps maps = tracePhotons(scene, portal ? 2e5 : 2e6);
    EXPECT_EQ(scene.stats().portals, portal ? 1u : 0u);
    // Points at least 0.4 from the walls, beyond the estimates' disc radius (~0.1 here).
    auto [photon, expected] = compare(scene, maps, 0.6f, 200);
    double open = kSunIrradiance * kToSun.y + kPi * kSkyRadiance;
    EXPECT_LT(expected, 0.9 * open);  // the walls do shade the floor
    EXPECT_NEAR(photon, expected, 0.02 * expected);
}

TEST(PhotonEmission, SunAndSkyInAHalfOpenBox) { halfOpenBoxUnderSunAndSky(false); }

// The same box with a portal over its opening: every photon starts on the portal (a tenth of the
// photons give the same density on the floor), and the irradiance is the same.
TEST(PhotonEmission, SunAndSkyThroughAPortal) { halfOpenBoxUnderSunAndSky(true); }

// The portal's photons start inside the scene, so what shades the opening from outside must shade
// them: a black awning 1 above the portal keeps the sun off most of the floor and part of the sky.
// Measured 0.989 of the shadow rays' irradiance; 1.84 when photons ignored it (before the photon
// tracer tested their way back to the sky). 1e6 photons: the awning's shadow edge crosses the
// floor, and with 2e5 the estimates' wider discs blur it to 0.95 (the same without the portal).
TEST(PhotonEmission, PortalPhotonsAreShadedOutsideThePortal) {
    Scene scene;
    buildHalfOpenBox(scene);
    int black = scene.addMaterial(lambert(Color(0.0f)));
    addQuad(scene, "/Awning", {-3, 2, 0.9f}, {-3, 2, 3}, {3, 2, 3}, {3, 2, 0.9f}, black);
    scene.addLight(portalOverTheBox());
    scene.setCamera(lookingDownFrom(3));
    PhotonMaps maps = tracePhotons(scene, 1e6);
    EXPECT_EQ(scene.stats().portals, 1u);
    auto [photon, expected] = compare(scene, maps, 0.6f, 200);
    Scene open;
    buildHalfOpenBox(open);
    open.commit();
    double unshaded = 0;
    for (Vec3 p : floorGrid(0.6f)) unshaded += expectedIrradiance(open, p, 4096) / 121;
    EXPECT_LT(expected, 0.8 * unshaded);  // the awning does shade the floor
    EXPECT_NEAR(photon, expected, 0.02 * expected);
}

// Light reflected into the opening off the outside: a white wall behind the half-open box, lit by
// the sun. Photons from the lights' discs reach the floor off it as well as straight through the
// opening; portal photons that carried nothing where their way back hits the wall read 0.88 of the
// open scene's photon irradiance. The dome's portal photons now carry what the wall sends through
// the portal (a path traced from it for a quarter of them, weighted by 4; portal.h): 1.0015
// measured. 121 estimates of k = 200 photons, the two maps' noise about 1% each; 3%.
TEST(PhotonEmission, PortalsKeepLightReflectedInFromOutside) {
    auto floorIrradiance = [](bool portal) {
        Scene scene;
        buildHalfOpenBox(scene);
        int white = scene.addMaterial(lambert(Color(0.9f)));
        addQuad(scene, "/Reflector", {-3, 0, -1.3f}, {3, 0, -1.3f}, {3, 5, -1.3f}, {-3, 5, -1.3f}, white);
        if (portal) scene.addLight(portalOverTheBox());
        scene.setCamera(lookingDownFrom(3));
        PhotonMaps maps = tracePhotons(scene, portal ? 1e6 : 2e6);
        EXPECT_EQ(scene.stats().portals, portal ? 1u : 0u);
        double E = 0;
        for (Vec3 p : floorGrid(0.6f)) E += maps.global.irradiance({p, Vec3(0, 1, 0)}, 200, 10).value.x / 121;
        return E;
    };
    const double open = floorIrradiance(false), throughPortal = floorIrradiance(true);
    std::printf("[ irradiance ] open %.4f, through the portal %.4f (ratio %.4f)\n", open, throughPortal,
                throughPortal / open);
    EXPECT_NEAR(throughPortal, open, 0.03 * open);
}

// The box under the sun, beside a far, black wall that makes the scene's bounds 20 times wider: a
// uniform disc sends about 1 photon in 700 onto the floor. The emission guide, learnt from the
// pilot, starts the photons where they reach the floor (measured: 170 times as many stored), and
// the irradiance stays what the sun delivers (photons from a cell drawn with density p carry 1/p
// of the power): over seeds 1-7 the ratio was 0.979-1.005, mean 0.991, sd 0.009; the 2%.
// (The sky is not guided: its disc turns with each photon's direction, Light::emitsFromFixedPositions.)
TEST(PhotonEmission, GuideStartsPhotonsWhereTheyReachTheRender) {
    auto build = [](Scene& scene) {
        buildHalfOpenBox(scene, false);
        int black = scene.addMaterial(lambert(Color(0.0f)));
        addQuad(scene, "/FarWall", {40, 0, -1}, {40, 0, 1}, {40, 1, 1}, {40, 1, -1}, black);
        scene.setCamera(lookingDownFrom(3));
    };
    Scene uniformScene, guidedScene;
    build(uniformScene);
    build(guidedScene);
    PhotonMaps uniform = tracePhotons(uniformScene, 4e5, false), guided = tracePhotons(guidedScene, 4e5, true);
    EXPECT_EQ(guided.statistics.at("photonLightsGuided"), 1);  // the sun; the sky has no fixed disc
    std::printf("[ guide ] floor photons: uniform %zu, guided %zu\n", uniform.global.size(), guided.global.size());
    EXPECT_GT(guided.global.size(), 10 * uniform.global.size());
    auto [photon, expected] = compare(guidedScene, guided, 0.6f, 200, false);
    EXPECT_NEAR(photon, expected, 0.02 * expected);
}

// A portal walled in on both sides: below it a closed room with a small hole in its floor, right
// under the portal, that 2-3 of the 32 probe rays leave by; above it a closed box. The probe
// cannot tell its sides apart, so the portal as authored is kept (it was left out as facing the
// wrong way on one such ray: Sibenik's Portal_19).
TEST(PhotonEmission, APortalWalledInOnBothSidesIsKeptAsAuthored) {
    Scene scene;
    int grey = scene.addMaterial(lambert(Color(0.5f)));
    const float h = 0.25f, top = 1.01f;  // the hole's half-width; the portal's height
    addQuad(scene, "/FloorA", {-1, 0, -1}, {-1, 0, 1}, {-h, 0, 1}, {-h, 0, -1}, grey);
    addQuad(scene, "/FloorB", {h, 0, -1}, {h, 0, 1}, {1, 0, 1}, {1, 0, -1}, grey);
    addQuad(scene, "/FloorC", {-h, 0, -1}, {-h, 0, -h}, {h, 0, -h}, {h, 0, -1}, grey);
    addQuad(scene, "/FloorD", {-h, 0, h}, {-h, 0, 1}, {h, 0, 1}, {h, 0, h}, grey);
    for (float y0 : {0.0f, top}) {
        float y1 = y0 == 0 ? top : 2.0f;
        addQuad(scene, "/WallA", {-1, y0, -1}, {1, y0, -1}, {1, y1, -1}, {-1, y1, -1}, grey);
        addQuad(scene, "/WallB", {-1, y0, 1}, {1, y0, 1}, {1, y1, 1}, {-1, y1, 1}, grey);
        addQuad(scene, "/WallC", {-1, y0, -1}, {-1, y0, 1}, {-1, y1, 1}, {-1, y1, -1}, grey);
        addQuad(scene, "/WallD", {1, y0, -1}, {1, y0, 1}, {1, y1, 1}, {1, y1, -1}, grey);
    }
    addQuad(scene, "/Lid", {-1, 2, -1}, {-1, 2, 1}, {1, 2, 1}, {1, 2, -1}, grey);
    addSunAndSky(scene);
    scene.addLight(portalOverTheBox());
    scene.commit();
    EXPECT_EQ(scene.stats().portals, 1u);
    for (const std::string& w : scene.warnings()) EXPECT_EQ(w.find("wrong way"), std::string::npos) << w;
}

// Bad portals warn, naming the prim, and are left out (the scene renders as without them).
TEST(PhotonEmission, BadPortalsWarnAndAreIgnored) {
    auto build = [](LightDesc portal, bool dome) {
        Scene scene;
        int grey = scene.addMaterial(lambert(Color(0.5f)));
        addQuad(scene, "/Floor", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, grey);
        addQuad(scene, "/WallA", {-1, 0, -1}, {1, 0, -1}, {1, 1, -1}, {-1, 1, -1}, grey);
        if (dome) addSunAndSky(scene);
        scene.addLight(portal);
        scene.commit();
        return std::make_pair(scene.stats().portals, scene.warnings());
    };
    auto warnedAbout = [](const std::vector<std::string>& warnings, const std::string& text) {
        return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) {
            return w.find("/Portal") != std::string::npos && w.find(text) != std::string::npos;
        });
    };
    auto [good, goodWarnings] = build(portalOverTheBox(), true);
    EXPECT_EQ(good, 1u);
    auto [wrongWay, wrongWayWarnings] = build(portalOverTheBox(true), true);
    EXPECT_EQ(wrongWay, 0u);
    EXPECT_TRUE(warnedAbout(wrongWayWarnings, "faces the wrong way"));
    LightDesc flat = portalOverTheBox();
    flat.width = 0;
    auto [zero, zeroWarnings] = build(flat, true);
    EXPECT_EQ(zero, 0u);
    EXPECT_TRUE(warnedAbout(zeroWarnings, "zero size"));
    auto [noDome, noDomeWarnings] = build(portalOverTheBox(), false);
    EXPECT_EQ(noDome, 0u);
    EXPECT_TRUE(warnedAbout(noDomeWarnings, "no dome light"));
}
