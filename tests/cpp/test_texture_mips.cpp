// Textures' MIP levels and the ray cones that choose them (ray_cone.h): each level keeps the
// image's mean in linear values, a footprint reads the level it spans a texel or two of, camera
// rays and a path's rays carry the cones the header describes, and light bounced off a texture
// finer than any cone keeps its mean.
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "renderer/camera.h"
#include "renderer/integrators/lighting.h"
#include "renderer/ray_cone.h"
#include "renderer/texture.h"
#include "scenes.h"

using namespace gi;

namespace {

// A w x h checker of single texels, 8-bit black and white (sRGB-decoded to 0 and 1).
std::shared_ptr<Image> checker(int w, int h) {
    std::vector<uint8_t> rgba(size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint8_t v = (x + y) % 2 ? 255 : 0;
            uint8_t* t = &rgba[(size_t(y) * w + x) * 4];
            t[0] = t[1] = t[2] = v;
            t[3] = 255;
        }
    return Image::fromBytes(w, h, std::move(rgba), true);
}

// The same as an 8-bit RGB PNG of n x n texels, per process (ctest runs tests side by side).
std::string writeChecker(const std::string& name, int n) {
    const std::string path = (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + "_" + name)).string();
    std::vector<uint8_t> rgb(size_t(n) * n * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = ((i / 3) % n + (i / 3) / n) % 2 ? 255 : 0;
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(n, n, 3, OIIO::TypeDesc::UINT8)));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
    out->close();
    return path;
}

double levelMean(const Image& image, int level, int channel) {
    int w = std::max(1, image.width() >> level), h = std::max(1, image.height() >> level);
    double sum = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float t[4];
            image.texel(level, x, y, t);
            sum += t[channel];
        }
    return sum / (double(w) * h);
}

}  // namespace

TEST(TextureMips, EveryLevelKeepsTheImagesLinearMean) {
    // 8-bit sRGB: averaging codes instead of linear values would darken each level.
    std::vector<uint8_t> rgba(64 * 32 * 4);
    uint32_t state = 12345;
    for (uint8_t& b : rgba) b = uint8_t((state = state * 1664525u + 1013904223u) >> 24);
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 255;  // opaque: colour weighs evenly
    auto bytes = Image::fromBytes(64, 32, rgba, true);
    ASSERT_EQ(bytes->levels(), 7);  // 64x32, 32x16, ..., 2x1, 1x1
    std::vector<float> pixels(64 * 32 * 4);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(rgba[i]) / 255 * 3;  // floats stay linear
    auto floats = Image::fromPixels(64, 32, pixels);
    for (int c = 0; c < 3; ++c) {
        const double byteMean = levelMean(*bytes, 0, c), floatMean = levelMean(*floats, 0, c);
        for (int level = 1; level < bytes->levels(); ++level) {
            EXPECT_NEAR(levelMean(*bytes, level, c), byteMean, 2e-5) << "level " << level;
            EXPECT_NEAR(levelMean(*floats, level, c), floatMean, 1e-5 * floatMean) << "level " << level;
        }
    }
    // Levels past the first are kept in 16 bits: 2/3 of an 8-bit image's bytes at most.
    EXPECT_EQ(bytes->memoryBytes(), 64u * 32 * 4 + (32u * 16 + 16 * 8 + 8 * 4 + 4 * 2 + 2 * 1 + 1 * 1) * 4 * 2);
}

TEST(TextureMips, AFootprintReadsTheLevelItSpansATexelOrTwoOf) {
    auto image = checker(64, 64);
    float t[4];
    const float u = 10.5f / 64, v = 1 - 20.5f / 64;  // texel (10, 20): black
    image->lookup(u, v, kWrapRepeat, kWrapRepeat, t);
    EXPECT_FLOAT_EQ(t[0], 0.0f);
    image->lookup(u, v, kWrapRepeat, kWrapRepeat, t, 1.5f / 64);  // under two texels: still the image
    EXPECT_FLOAT_EQ(t[0], 0.0f);
    for (float texels : {2.0f, 5.0f, 64.0f, 1e6f}) {  // a coarser level: every texel is the checker's mean
        image->lookup(u, v, kWrapRepeat, kWrapRepeat, t, texels / 64);
        EXPECT_NEAR(t[0], 0.5f, 1e-4f) << texels << " texels";
        EXPECT_FLOAT_EQ(t[3], 1.0f);
    }
}

TEST(TextureMips, ColourWeighsByAlpha) {
    // Opaque red beside a transparent black texel: the level above is red, half covered.
    auto image = Image::fromBytes(2, 1, {255, 0, 0, 255, 0, 0, 0, 0}, false);
    float t[4];
    image->texel(1, 0, 0, t);
    EXPECT_NEAR(t[0], 1.0f, 1e-4f);
    EXPECT_NEAR(t[1], 0.0f, 1e-4f);
    EXPECT_NEAR(t[3], 0.5f, 1e-4f);
}

TEST(RayCones, CameraRaysCarryAnEighthOfTheirPixel) {
    CameraDesc desc = test::lookingDown({0, 1, 0}, false, 2.0f);  // aperture over focal length: 2
    desc.focalLength = 1.0f;                                      // 2 units wide at unit distance
    Camera camera(desc, 100, 100);
    Ray centre = camera.generateRay(50, 50, Vec2(0.5f, 0.5f));
    EXPECT_NEAR(centre.coneSpread, kConeSpreadScale * 2.0f / 100, 1e-6f);  // a pixel is 0.02 rad
    EXPECT_EQ(centre.coneWidth, 0.0f);
    Camera ortho(test::lookingDown({0, 1, 0}, true, 20.0f), 100, 100);  // 2 units wide
    Ray parallel = ortho.generateRay(50, 50, Vec2(0.5f, 0.5f));
    EXPECT_EQ(parallel.coneSpread, 0.0f);
    EXPECT_NEAR(parallel.coneWidth, kConeSpreadScale * 2.0f / 100, 1e-6f);
}

TEST(RayCones, AHitsFootprintIsTheConesWidthInUvUnits) {
    Scene scene;
    MaterialDesc textured = test::lambert(Color(0.5f));
    textured.diffuseColorTexture.file = writeChecker("gi_footprint_checker.png", 4);
    int m = scene.addMaterial(textured);
    // 4 x 2 units of floor under uvs (0..1, 0..1): 1/4 of u and 1/2 of v per unit.
    scene.addMesh("/Floor", {{-2, 0, 1}, {2, 0, 1}, {2, 0, -1}, {-2, 0, -1}}, {0, 1, 2, 0, 2, 3}, {},
                  {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, m, nullptr, true, -1);
    scene.commit();
    Ray ray;
    ray.o = Vec3(0.3f, 2, 0.1f);
    ray.d = Vec3(0, -1, 0);
    ray.coneWidth = 0.01f;
    ray.coneSpread = 0.05f;
    RayStats stats;
    Intersection hit = scene.intersect(ray, stats);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    EXPECT_NEAR(hit.si.coneWidth, 0.01f + 0.05f * 2, 1e-5f);
    EXPECT_EQ(hit.si.coneSpread, 0.05f);
    EXPECT_NEAR(hit.si.uvFootprint, 0.11f * std::sqrt(1.0f / 8), 1e-5f);  // uv area 1 over 8 square units
    ray.coneWidth = ray.coneSpread = 0;  // no cone: the finest level
    EXPECT_EQ(scene.intersect(ray, stats).si.uvFootprint, 0.0f);
}

TEST(RayCones, ADeltaBounceKeepsTheSpreadAndADiffuseOneWidensIt) {
    BsdfSample mirror;
    mirror.delta = true;
    mirror.pdf = 1;
    EXPECT_EQ(continuedConeSpread(0.003f, mirror), 0.003f);
    BsdfSample diffuse;
    diffuse.pdf = 1 / kPi;  // straight up from a Lambertian surface
    EXPECT_NEAR(continuedConeSpread(0.003f, diffuse), kConeSpreadScale * 2, 1e-3f);  // a 12-bit estimate
    diffuse.pdf = 0;  // no wider than a radian
    EXPECT_EQ(continuedConeSpread(0.003f, diffuse), 1.0f);
    diffuse.pdf = std::nanf("");
    EXPECT_EQ(continuedConeSpread(0.003f, diffuse), 1.0f);
}

namespace {

// The underside of a small white patch 1 unit above a sunlit floor, seen from below: lit only by
// the floor's light. The floor is a checker of single black and white texels (8-bit sRGB),
// 1,024 texels a unit, or, without `textured`, uniform at their mean, 0.5.
// Returns the green channel's mean and its pixels' relative spread.
std::pair<double, double> patchLitByTheFloor(bool textured, uint32_t seed) {
    Scene scene;
    MaterialDesc floor = test::lambert(Color(0.5f));
    if (textured) {
        floor.diffuseColorTexture.file = writeChecker("gi_floor_checker.png", 1024);
        floor.diffuseColorTexture.wrapS = floor.diffuseColorTexture.wrapT = "repeat";
    }
    int floorMaterial = scene.addMaterial(floor);
    scene.addMesh("/Floor", {{-6, 0, 6}, {6, 0, 6}, {6, 0, -6}, {-6, 0, -6}}, {0, 1, 2, 0, 2, 3}, {},
                  {{0, 0}, {12, 0}, {12, 12}, {0, 12}}, floorMaterial, nullptr, true, -1);
    test::addQuad(scene, "/Patch", {-0.1f, 1, -0.1f}, {0.1f, 1, -0.1f}, {0.1f, 1, 0.1f}, {-0.1f, 1, 0.1f},
                  scene.addMaterial(test::lambert(Color(0.8f))));
    LightDesc sun;
    sun.name = "/Sun";
    sun.kind = "distant";
    sun.angle = 0;
    sun.transform.m[1][1] = 0, sun.transform.m[1][2] = -1;  // shines down -y
    sun.transform.m[2][1] = 1, sun.transform.m[2][2] = 0;
    scene.addLight(sun);
    CameraDesc up = test::lookingDown({0, 0.5f, 0}, true, 0.5f);
    up.transform.m[1][2] = 1, up.transform.m[2][1] = -1;  // looks up +y
    scene.setCamera(up);
    const std::vector<float> rgb = test::renderImage(scene, "path", 4, 4096, {}, seed);
    const double mean = test::channelMean(rgb, 1);
    double squares = 0;
    for (size_t i = 1; i < rgb.size(); i += 3) squares += (rgb[i] - mean) * (rgb[i] - mean);
    return {mean, std::sqrt(squares / double(rgb.size() / 3)) / mean};
}

}  // namespace

TEST(RayCones, LightOffATextureFinerThanItsConesKeepsItsMean) {
    const auto [uniform, uniformSpread] = patchLitByTheFloor(false, 1);
    const auto [textured, texturedSpread] = patchLitByTheFloor(true, 2);
    ASSERT_GT(uniform, 0.01);
    EXPECT_NEAR(textured / uniform, 1.0, 0.02) << "uniform " << uniform << ", checker " << textured;
    // The floor reads as its mean: read at its finest level, its texels, 0 or 1, spread the
    // pixels by 0.48% (measured); with the cones 0.12%, uniform 0.09%.
    EXPECT_LT(texturedSpread, 2 * uniformSpread + 0.001) << "uniform " << uniformSpread;
}

// Texel coordinates outside the image wrap as UsdUVTexture's modes say, far on either side: a row
// of four texels 0..3 read at texel centres from -9 to 12 repeats as 0 1 2 3 and mirrors as
// 0 1 2 3 3 2 1 0.
TEST(TextureWrap, RepeatAndMirrorFarOnEitherSide) {
    const int width = 4;
    std::vector<float> pixels;
    for (int i = 0; i < width; ++i) pixels.insert(pixels.end(), {float(i), 0, 0, 1});
    auto image = Image::fromPixels(width, 1, pixels);
    for (int texel = -9; texel <= 12; ++texel) {
        const float u = (texel + 0.5f) / width;
        float repeat[4], mirror[4];
        image->lookup(u, 0.5f, kWrapRepeat, kWrapRepeat, repeat);
        image->lookup(u, 0.5f, kWrapMirror, kWrapMirror, mirror);
        const int r = ((texel % width) + width) % width, m = ((texel % 8) + 8) % 8;
        EXPECT_FLOAT_EQ(repeat[0], float(r)) << "texel " << texel;
        EXPECT_FLOAT_EQ(mirror[0], float(m < width ? m : 7 - m)) << "texel " << texel;
    }
}
