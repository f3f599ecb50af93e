// Texture decoding: 8-bit images are kept as bytes and decoded through a table, float images as
// floats; both must give UsdUVTexture's values (sRGB decode for 8-bit 'auto', linear for float).
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <map>

#include "renderer/texture.h"
#include "scenes.h"

using namespace gi;

namespace {

float srgbDecode(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

template <typename T>
std::string writeImage(const std::string& name, int channels, const std::vector<T>& pixels, OIIO::TypeDesc type) {
    // Per process: ctest runs tests side by side, and two that wrote one file raced.
    std::string path = (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + "_" + name)).string();
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(int(pixels.size() / channels), 1, channels, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // store colour as given, as a painted PNG has it
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(type, pixels.data()));
    out->close();
    return path;
}

// The texel centre of column x in a w x 1 image.
void lookupTexel(const Image& image, int x, float out[4]) {
    image.lookup((x + 0.5f) / image.width(), 0.5f, kWrapClamp, kWrapClamp, out);
}

}  // namespace

TEST(Texture, EightBitRgbDecodesThroughSrgbOrRaw) {
    std::vector<uint8_t> bytes = {0, 128, 255, 10, 200, 37};
    std::string path = writeImage("gi_texture_rgb8.png", 3, bytes, OIIO::TypeDesc::UINT8);
    for (const char* space : {"auto", "sRGB", "raw"}) {
        std::string error;
        auto image = Image::load(path, space, error);
        ASSERT_TRUE(image) << error;
        EXPECT_EQ(image->memoryBytes(), 2u * 4u + 4u * 2u);  // bytes, not floats (its 1 x 1 level in 16 bits)
        bool srgb = std::string(space) != "raw";
        for (int x = 0; x < 2; ++x) {
            float t[4];
            lookupTexel(*image, x, t);
            for (int c = 0; c < 3; ++c) {
                float v = bytes[x * 3 + c] / 255.0f;
                EXPECT_NEAR(t[c], srgb ? srgbDecode(v) : v, 1e-6f) << space << " texel " << x << " channel " << c;
            }
            EXPECT_FLOAT_EQ(t[3], 1.0f);
        }
    }
}

TEST(Texture, EightBitGreyAlphaWidensAndKeepsAlphaLinear) {
    std::vector<uint8_t> bytes = {128, 64, 255, 0};
    std::string path = writeImage("gi_texture_ga8.png", 2, bytes, OIIO::TypeDesc::UINT8);
    std::string error;
    auto image = Image::load(path, "auto", error);
    ASSERT_TRUE(image) << error;
    float t[4];
    lookupTexel(*image, 0, t);
    EXPECT_NEAR(t[0], srgbDecode(128 / 255.0f), 1e-6f);
    EXPECT_EQ(t[0], t[1]);
    EXPECT_EQ(t[0], t[2]);
    EXPECT_NEAR(t[3], 64 / 255.0f, 1e-6f);
    lookupTexel(*image, 1, t);
    EXPECT_NEAR(t[0], 1.0f, 1e-6f);
    EXPECT_NEAR(t[3], 0.0f, 1e-6f);
}

TEST(Texture, FloatImagesStayLinearAndBilinearBlends) {
    std::vector<float> pixels = {0.25f, 2.0f, 0.5f, 1, 0.75f, 0.0f, 0.5f, 1};
    std::string path = writeImage("gi_texture_rgba32.exr", 4, pixels, OIIO::TypeDesc::FLOAT);
    std::string error;
    auto image = Image::load(path, "auto", error);
    ASSERT_TRUE(image) << error;
    EXPECT_EQ(image->memoryBytes(), (2u + 1u) * 4u * sizeof(float));  // and its 1 x 1 level
    float t[4];
    lookupTexel(*image, 0, t);
    EXPECT_FLOAT_EQ(t[1], 2.0f);  // not decoded, not clamped
    image->lookup(0.5f, 0.5f, kWrapClamp, kWrapClamp, t);  // half-way between the two texels
    EXPECT_FLOAT_EQ(t[0], 0.5f);
    EXPECT_FLOAT_EQ(t[1], 1.0f);
}

namespace {

// A floor at y = 0 whose u runs along +x and v along -z, under a delta distant light whose
// direction towards the light is +y tilted by `lightTilt` radians towards `lightAxis` (x or -z);
// with a constant tangent-space normal map `mapNormal` (none if zero). Returns the floor's value.
double normalMappedFloor(Vec3 mapNormal, float lightTilt, Vec3 lightAxis) {
    Scene scene;
    MaterialDesc m = test::lambert(Color(0.5f));
    if (lengthSquared(mapNormal) > 0) {
        std::vector<float> texel = {mapNormal.x, mapNormal.y, mapNormal.z, 1, mapNormal.x, mapNormal.y, mapNormal.z, 1};
        m.normalTexture.file = writeImage("gi_normal_map.exr", 4, texel, OIIO::TypeDesc::FLOAT);
        m.normalTexture.sourceColorSpace = "raw";
    }
    int material = scene.addMaterial(m);
    scene.addMesh("/Floor", {{-5, 0, 5}, {5, 0, 5}, {5, 0, -5}, {-5, 0, -5}}, {0, 1, 2, 0, 2, 3}, {},
                  {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, material, nullptr, true, -1);
    LightDesc light;
    light.name = "/Sun";
    light.kind = "distant";
    light.angle = 0;
    // Rows: where local x, y, z go; the light shines along local -z, so local z = towards it.
    Vec3 toLight = Vec3(0, 1, 0) * std::cos(lightTilt) + lightAxis * std::sin(lightTilt);
    Vec3 helper = std::fabs(toLight.z) < 0.9f ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
    Vec3 x = normalize(cross(helper, toLight));
    Vec3 y = cross(toLight, x);
    for (int c = 0; c < 3; ++c) {
        light.transform.m[0][c] = x[c];
        light.transform.m[1][c] = y[c];
        light.transform.m[2][c] = toLight[c];
    }
    scene.addLight(light);
    scene.setCamera(test::lookingDown({0, 0.05f, 0}, true, 0.01f));
    return test::channelMean(test::renderImage(scene, "direct", 4, 4), 1);
}

}  // namespace

// UsdPreviewSurface's normal input: a tangent-space map tilts the shading normal along the
// surface's own u (tangent) and v (bitangent) directions.
TEST(NormalMap, TiltsTheShadingNormalAlongUAndV) {
    const float tilt = 30 * kPi / 180;
    const Vec3 alongX(1, 0, 0), alongMinusZ(0, 0, -1);
    double flat = normalMappedFloor(Vec3(0.0f), 0, alongX);
    ASSERT_GT(flat, 0);
    // An untilted map changes nothing.
    EXPECT_NEAR(normalMappedFloor(Vec3(0, 0, 1), 0, alongX) / flat, 1.0, 1e-4);
    Vec3 towardsU(std::sin(tilt), 0, std::cos(tilt)), towardsV(0, std::sin(tilt), std::cos(tilt));
    // Light from straight above: cos 30 whichever way the normal leans.
    EXPECT_NEAR(normalMappedFloor(towardsU, 0, alongX) / flat, std::cos(tilt), 1e-3);
    // Leaning towards +u (= +x) faces a light tilted towards +x (cos 0), and turns 60 degrees
    // from one tilted towards -x.
    EXPECT_NEAR(normalMappedFloor(towardsU, tilt, alongX) / flat, 1.0, 1e-3);
    EXPECT_NEAR(normalMappedFloor(towardsU, -tilt, alongX) / flat, std::cos(2 * tilt), 1e-3);
    // Leaning towards +v (= -z) likewise.
    EXPECT_NEAR(normalMappedFloor(towardsV, tilt, alongMinusZ) / flat, 1.0, 1e-3);
    EXPECT_NEAR(normalMappedFloor(towardsV, -tilt, alongMinusZ) / flat, std::cos(2 * tilt), 1e-3);
}

// Texels that are no direction (zero, NaN, into the surface) leave the normal alone.
TEST(NormalMap, UnusableTexelsKeepTheSurfaceNormal) {
    double flat = normalMappedFloor(Vec3(0.0f), 0, Vec3(1, 0, 0));
    EXPECT_NEAR(normalMappedFloor(Vec3(0.5f, 0, -1), 0, Vec3(1, 0, 0)) / flat, 1.0, 1e-4);
    EXPECT_NEAR(normalMappedFloor(Vec3(std::nanf(""), 0, 1), 0, Vec3(1, 0, 0)) / flat, 1.0, 1e-4);
}

namespace {

// A scene with one textured quad whose texture is `file`, committed.
std::unique_ptr<Scene> texturedScene(const std::string& file, std::shared_ptr<ImageCache> images) {
    auto scene = std::make_unique<Scene>();
    if (images) scene->shareImages(images);
    MaterialDesc m = test::lambert(Color(0.5f));
    m.diffuseColorTexture.file = file;
    int material = scene->addMaterial(m);
    test::addQuad(*scene, "/Quad", {0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}, material);
    scene->commit();
    return scene;
}

}  // namespace

// Scenes rebuilt one after another (a Hydra session on every edit) share the images they hold:
// a file is read again only when it changed on disk or no scene holds it any more.
TEST(ImageCache, RebuiltScenesReadATextureOnceWhileItIsUnchanged) {
    std::string file = writeImage("gi_shared_texture.png", 3, std::vector<uint8_t>{10, 20, 30}, OIIO::TypeDesc::UINT8);
    auto images = std::make_shared<ImageCache>();
    auto first = texturedScene(file, images);
    EXPECT_EQ(first->stats().textures, 1u);
    EXPECT_EQ(first->stats().texturesRead, 1u);
    auto second = texturedScene(file, images);  // the first still lives, as during a rebuild
    EXPECT_EQ(second->stats().textures, 1u);
    EXPECT_EQ(second->stats().texturesRead, 0u);
    // Without a shared cache every scene reads its own.
    EXPECT_EQ(texturedScene(file, nullptr)->stats().texturesRead, 1u);
    // A file rewritten on disk is read again.
    std::filesystem::last_write_time(file, std::filesystem::last_write_time(file) + std::chrono::seconds(5));
    auto third = texturedScene(file, images);
    EXPECT_EQ(third->stats().texturesRead, 1u);
    // Once no scene holds it, the cache lets it go (no growth over a long session).
    first.reset();
    second.reset();
    third.reset();
    EXPECT_EQ(texturedScene(file, images)->stats().texturesRead, 1u);
    // A missing file is a warning, and is looked for again next time.
    std::string missing = (std::filesystem::temp_directory_path() / "gi_not_there.png").string();
    std::filesystem::remove(missing);
    auto without = texturedScene(missing, images);
    EXPECT_EQ(without->stats().textures, 0u);
    ASSERT_FALSE(without->warnings().empty());
    EXPECT_NE(without->warnings().front().find("gi_not_there.png"), std::string::npos);
    std::filesystem::copy_file(file, missing);
    EXPECT_EQ(texturedScene(missing, images)->stats().texturesRead, 1u);
    std::filesystem::remove(missing);
}

// A UDIM texture (file.<UDIM>.exr): tile 1001 + u + 10 v covers st [u, u + 1) x [v, v + 1), each
// tile read clamped at its own edges; where no tile is, the texture reads its fallback.
TEST(Texture, UdimTilesCoverTheirSquaresOfSt) {
    const std::string stem = std::to_string(getpid()) + "_gi_udim";
    const auto dir = std::filesystem::temp_directory_path();
    std::map<int, Color> tiles = {{1001, Color(1, 0, 0)}, {1002, Color(0, 1, 0)}, {1011, Color(0, 0, 1)}};
    for (const auto& [tile, colour] : tiles) {
        // Two texels across: the tile's right edge must not bleed into its neighbour's left one.
        std::vector<float> texels = {colour.x, colour.y, colour.z, 1, colour.x, colour.y, colour.z, 1};
        std::string written = writeImage("gi_udim." + std::to_string(tile) + ".exr", 4, texels, OIIO::TypeDesc::FLOAT);
        std::filesystem::rename(written, dir / (stem + "." + std::to_string(tile) + ".exr"));
    }
    std::string pattern = (dir / (stem + ".<UDIM>.exr")).string();
    EXPECT_TRUE(isUdimPath(pattern));
    EXPECT_EQ(udimTilePath(pattern, 1002), (dir / (stem + ".1002.exr")).string());

    Scene scene;
    MaterialDesc m = test::lambert(Color(0.5f));
    m.emissiveColorTexture.file = pattern;
    for (int c = 0; c < 4; ++c) m.emissiveColorTexture.fallback[c] = 0.25f;
    int material = scene.addMaterial(m);
    test::addQuad(scene, "/Quad", {0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}, material);
    scene.commit();
    EXPECT_EQ(scene.stats().textures, 3u);
    const Material& mat = scene.material(material);
    auto expect = [&](float u, float v, Color want) {
        Color got = mat.emission(Vec2(u, v));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-6f) << "st (" << u << ", " << v << ") channel " << c;
    };
    expect(0.5f, 0.5f, Color(1, 0, 0));
    expect(0.99f, 0.5f, Color(1, 0, 0));  // clamped at the tile's edge, not wrapped into 1002
    expect(1.5f, 0.5f, Color(0, 1, 0));
    expect(0.5f, 1.5f, Color(0, 0, 1));
    expect(1.5f, 1.5f, Color(0.25f));   // tile 1012: none
    expect(-0.5f, 0.5f, Color(0.25f));  // left of every tile
    expect(10.5f, 0.5f, Color(0.25f));  // an eleventh column is no tile

    // A pattern with no tile at all is a warning naming it, and the constant value.
    Scene missing;
    MaterialDesc none = test::lambert(Color(0.5f));
    none.diffuseColorTexture.file = (dir / (stem + "_none.<UDIM>.exr")).string();
    missing.addMaterial(none);
    test::addQuad(missing, "/Quad", {0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}, 0);
    missing.commit();
    bool warned = false;
    for (const std::string& w : missing.warnings())
        warned = warned || (w.find("_none.<UDIM>.exr") != std::string::npos && w.find("no UDIM tile") != std::string::npos);
    EXPECT_TRUE(warned);
    for (const auto& [tile, colour] : tiles) std::filesystem::remove(dir / (stem + "." + std::to_string(tile) + ".exr"));
}
