// Texture decoding: 8-bit images are kept as bytes and decoded through a table, float images as
// floats; both must give UsdUVTexture's values (sRGB decode for 8-bit 'auto', linear for float).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "renderer/texture.h"

using namespace gi;

namespace {

float srgbDecode(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

template <typename T>
std::string writeImage(const std::string& name, int channels, const std::vector<T>& pixels, OIIO::TypeDesc type) {
    std::string path = (std::filesystem::temp_directory_path() / name).string();
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
        EXPECT_EQ(image->memoryBytes(), 2u * 4u);  // bytes, not floats
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
    EXPECT_EQ(image->memoryBytes(), 2u * 4u * sizeof(float));
    float t[4];
    lookupTexel(*image, 0, t);
    EXPECT_FLOAT_EQ(t[1], 2.0f);  // not decoded, not clamped
    image->lookup(0.5f, 0.5f, kWrapClamp, kWrapClamp, t);  // half-way between the two texels
    EXPECT_FLOAT_EQ(t[0], 0.5f);
    EXPECT_FLOAT_EQ(t[1], 1.0f);
}
