// The shading rules both USD hosts share (renderer/usd_shading.h): what a textured input reads when
// its file is missing, the material of an unbound gprim, and which primvar holds the uvs.
#include <gtest/gtest.h>

#include "renderer/usd_shading.h"

using namespace gi;

namespace {
void ExpectColor(Color actual, Color expected) {
    for (int i = 0; i < 3; ++i) EXPECT_EQ(actual[i], expected[i]) << "component " << i;
}
}  // namespace

TEST(UsdShading, TexturedInputReadsTheTexturesFallbackInItsChannel) {
    MaterialDesc m;
    m.diffuseColor = Color(1.0f);  // authored on the input: the connection overrides it
    m.roughness = 0.9f;
    TextureDesc t;
    t.file = "missing.png";
    float fallback[4] = {0.2f, 0.5f, 0.8f, 0.4f};
    std::copy(fallback, fallback + 4, t.fallback);
    ASSERT_TRUE(connectTexture(m, "diffuseColor", t));
    EXPECT_EQ(m.diffuseColorTexture.file, "missing.png");
    ExpectColor(m.diffuseColor, Color(0.2f, 0.5f, 0.8f));
    t.channel = "g";  // a single channel read as a colour is grey
    ASSERT_TRUE(connectTexture(m, "emissiveColor", t));
    ExpectColor(m.emissiveColor, Color(0.5f));
    t.channel = "a";
    ASSERT_TRUE(connectTexture(m, "roughness", t));
    EXPECT_EQ(m.roughness, 0.4f);
    t.channel = "rgb";  // a float input reads the first channel of rgb
    ASSERT_TRUE(connectTexture(m, "opacity", t));
    EXPECT_EQ(m.opacity, 0.2f);
    EXPECT_FALSE(connectTexture(m, "displacement", t));
}

TEST(UsdShading, UnauthoredFallbackIsTheSpecsBlackOpaque) {
    MaterialDesc m;
    m.metallic = 1;
    TextureDesc t;  // no fallback authored: (0, 0, 0, 1)
    t.channel = "r";
    ASSERT_TRUE(connectTexture(m, "metallic", t));
    EXPECT_EQ(m.metallic, 0.0f);
    t.channel = "rgb";
    ASSERT_TRUE(connectTexture(m, "specularColor", t));
    ExpectColor(m.specularColor, Color(0.0f));
}

TEST(UsdShading, DisplayColorMaterialIsAPreviewSurfaceWithThatDiffuse) {
    Color c(0.25f, 0.5f, 0.75f);
    MaterialDesc painted = displayColorMaterial("/World/Quad", &c), plain = displayColorMaterial("/World/Quad", nullptr);
    MaterialDesc spec;  // UsdPreviewSurface's defaults
    ExpectColor(painted.diffuseColor, c);
    ExpectColor(plain.diffuseColor, spec.diffuseColor);
    for (const MaterialDesc* m : {&painted, &plain}) {
        EXPECT_EQ(m->name, "/World/Quad.primvars:displayColor");
        // The specular lobe of the spec's defaults (metallic workflow, ior 1.5), not a plain Lambert.
        EXPECT_FALSE(m->useSpecularWorkflow);
        EXPECT_EQ(m->ior, 1.5f);
        EXPECT_EQ(m->roughness, 0.5f);
        EXPECT_EQ(m->metallic, 0.0f);
    }
}

TEST(UsdShading, UvPrimvarIsTheFirstNamedByAReaderThatTheMeshHas) {
    std::vector<std::string> mesh{"st", "uvSet1", "displayColor"};
    EXPECT_EQ(uvPrimvarOf({"uvSet1"}, mesh), "uvSet1");                // a decoy st is not read
    EXPECT_EQ(uvPrimvarOf({"st0", "st"}, mesh), "st");                 // a subset's reader, when the first is absent
    EXPECT_EQ(uvPrimvarOf({"st0"}, mesh), "");                         // no guess: the reader's (0, 0)
    EXPECT_EQ(uvPrimvarOf({}, mesh), "");                              // no reader, no uvs
    EXPECT_EQ(uvPrimvarOf({"", "uvSet1"}, mesh), "uvSet1");
}
