// resolvePreviewSurface (renderer/preview_surface.h): the UsdPreviewSurface network rules both USD
// hosts share, one test per rule, on networks written the way the hosts hand them over.
#include <gtest/gtest.h>

#include "renderer/preview_surface.h"

using namespace gi;

namespace {

struct Warnings {
    std::vector<std::pair<std::string, std::string>> said;
    ShadingWarning sink() {
        return [this](const std::string& path, const std::string& message) { said.emplace_back(path, message); };
    }
    // The one warning whose message contains every part, else a test failure.
    std::string one(std::initializer_list<std::string> parts) const {
        std::vector<std::string> found;
        for (const auto& [path, message] : said) {
            bool all = true;
            for (const std::string& part : parts) all = all && message.find(part) != std::string::npos;
            if (all) found.push_back(path + ": " + message);
        }
        EXPECT_EQ(found.size(), 1u) << text();
        return found.empty() ? "" : found[0];
    }
    std::string text() const {
        std::string all;
        for (const auto& [path, message] : said) all += path + ": " + message + "\n";
        return all;
    }
};

const std::string kMaterial = "/Looks/Brick";

// A UsdPreviewSurface at /Looks/Brick/Surface with a UsdUVTexture /Looks/Brick/Tex (file brick.png,
// found) driving `input` through `output`, and the texture's st read from primvar `varname`.
ShaderNetwork texturedNetwork(const std::string& input, const std::string& output, const std::string& varname = "st") {
    ShaderNetwork n;
    ShaderNode& surface = n.nodes["/Looks/Brick/Surface"];
    surface.id = "UsdPreviewSurface";
    surface.connections[input] = {"/Looks/Brick/Tex", output};
    ShaderNode& tex = n.nodes["/Looks/Brick/Tex"];
    tex.id = "UsdUVTexture";
    tex.parameters["file"] = ShaderAsset{"./brick.png", "/stage/brick.png"};
    tex.connections["st"] = {"/Looks/Brick/Reader", "result"};
    ShaderNode& reader = n.nodes["/Looks/Brick/Reader"];
    reader.id = "UsdPrimvarReader_float2";
    reader.parameters["varname"] = varname;
    return n;
}

PreviewSurface resolve(const ShaderNetwork& n, Warnings& w, const std::string& surface = "/Looks/Brick/Surface") {
    std::optional<PreviewSurface> s = resolvePreviewSurface(kMaterial, n, surface, w.sink());
    EXPECT_TRUE(s.has_value()) << w.text();
    return s ? *s : PreviewSurface();
}

void ExpectColor(Color actual, Color expected) {
    for (int i = 0; i < 3; ++i) EXPECT_EQ(actual[i], expected[i]) << "component " << i;
}

}  // namespace

TEST(PreviewSurface, UnauthoredInputsKeepTheSpecsDefaultsAndConstantsAreRead) {
    ShaderNetwork n;
    n.nodes["/S"].id = "UsdPreviewSurface";
    Warnings w;
    MaterialDesc spec, plain = resolve(n, w, "/S").material;
    ExpectColor(plain.diffuseColor, spec.diffuseColor);
    EXPECT_EQ(plain.roughness, spec.roughness);
    EXPECT_EQ(plain.ior, spec.ior);
    EXPECT_EQ(plain.name, kMaterial);
    auto& p = n.nodes["/S"].parameters;
    p["diffuseColor"] = std::array<float, 3>{0.1f, 0.2f, 0.3f};
    p["useSpecularWorkflow"] = 1.0f;
    p["roughness"] = 0.25f;
    p["opacityMode"] = std::string("presence");
    MaterialDesc authored = resolve(n, w, "/S").material;
    ExpectColor(authored.diffuseColor, Color(0.1f, 0.2f, 0.3f));
    EXPECT_TRUE(authored.useSpecularWorkflow);
    EXPECT_EQ(authored.roughness, 0.25f);
    EXPECT_EQ(authored.opacityMode, "presence");
    EXPECT_TRUE(w.said.empty()) << w.text();
}

TEST(PreviewSurface, AConstantOfTheWrongTypeWarnsAndKeepsTheDefault) {
    ShaderNetwork n;
    n.nodes["/S"].id = "UsdPreviewSurface";
    n.nodes["/S"].parameters["roughness"] = std::array<float, 3>{1, 1, 1};
    Warnings w;
    EXPECT_EQ(resolve(n, w, "/S").material.roughness, MaterialDesc().roughness);
    std::string warning = w.one({"inputs:roughness of /S", "type float3, not float;"});
    EXPECT_EQ(warning.rfind(kMaterial + ": ", 0), 0u) << warning;
}

TEST(PreviewSurface, TextureOutputsPickTheChannel) {
    for (const char* output : {"r", "g", "b", "a", "rgb", "result"}) {
        Warnings w;
        PreviewSurface s = resolve(texturedNetwork("roughness", output), w);
        std::string expected = std::string(output) == "result" ? "rgb" : output;
        EXPECT_EQ(s.material.roughnessTexture.channel, expected) << output;
        EXPECT_EQ(s.material.roughnessTexture.file, "/stage/brick.png");
        EXPECT_TRUE(w.said.empty()) << w.text();
    }
}

TEST(PreviewSurface, TextureParametersScaleBiasWrapAndColorSpaceAreRead) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    auto& p = n.nodes["/Looks/Brick/Tex"].parameters;
    p["scale"] = std::array<float, 4>{2, 2, 2, 1};
    p["bias"] = std::array<float, 4>{-1, -0.5f, 0, 0};
    p["wrapS"] = std::string("clamp");
    p["wrapT"] = std::string("mirror");
    p["sourceColorSpace"] = std::string("raw");
    Warnings w;
    const TextureDesc& t = resolve(n, w).material.diffuseColorTexture;
    EXPECT_EQ(t.scale[0], 2);
    EXPECT_EQ(t.scale[3], 1);
    EXPECT_EQ(t.bias[0], -1);
    EXPECT_EQ(t.bias[1], -0.5f);
    EXPECT_EQ(t.wrapS, "clamp");
    EXPECT_EQ(t.wrapT, "mirror");
    EXPECT_EQ(t.sourceColorSpace, "raw");
    EXPECT_TRUE(w.said.empty()) << w.text();
    // Unauthored: the spec's defaults (texture.h).
    Warnings quiet;
    const TextureDesc& d = resolve(texturedNetwork("diffuseColor", "rgb"), quiet).material.diffuseColorTexture;
    TextureDesc spec;
    EXPECT_EQ(d.wrapS, spec.wrapS);
    EXPECT_EQ(d.scale[0], spec.scale[0]);
    EXPECT_EQ(d.bias[0], spec.bias[0]);
}

TEST(PreviewSurface, AnUnknownWrapTokenWarnsNamingTheTexture) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    n.nodes["/Looks/Brick/Tex"].parameters["wrapT"] = std::string("tile");
    Warnings w;
    resolve(n, w);
    w.one({"wrapT 'tile'", "/Looks/Brick/Tex", "using repeat"});
    EXPECT_EQ(w.said.size(), 1u) << w.text();  // wrapS's default, useMetadata, is valid
}

TEST(PreviewSurface, Transform2dFeedsTheTexturesStAndTheReaderBehindIt) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb", "uvSet1");
    n.nodes["/Looks/Brick/Tex"].connections["st"] = {"/Looks/Brick/Transform", "result"};
    ShaderNode& transform = n.nodes["/Looks/Brick/Transform"];
    transform.id = "UsdTransform2d";
    transform.parameters["rotation"] = 30.0f;
    transform.parameters["scale"] = std::array<float, 2>{4, 2};
    transform.parameters["translation"] = std::array<float, 2>{0.5f, -1};
    transform.connections["in"] = {"/Looks/Brick/Reader", "result"};
    Warnings w;
    PreviewSurface s = resolve(n, w);
    const TextureDesc& t = s.material.diffuseColorTexture;
    EXPECT_EQ(t.stRotation, 30);
    EXPECT_EQ(t.stScale.x, 4);
    EXPECT_EQ(t.stScale.y, 2);
    EXPECT_EQ(t.stTranslation.x, 0.5f);
    EXPECT_EQ(t.stTranslation.y, -1);
    EXPECT_EQ(s.readerVarnames, std::vector<std::string>{"uvSet1"});
    EXPECT_TRUE(w.said.empty()) << w.text();
}

TEST(PreviewSurface, ReaderVarnamesAreListedOnceInInputOrder) {
    ShaderNetwork n = texturedNetwork("roughness", "r", "uvB");
    ShaderNode& surface = n.nodes["/Looks/Brick/Surface"];
    surface.connections["diffuseColor"] = {"/Looks/Brick/Tex2", "rgb"};
    surface.connections["opacity"] = {"/Looks/Brick/Tex", "a"};
    ShaderNode& tex2 = n.nodes["/Looks/Brick/Tex2"] = n.nodes["/Looks/Brick/Tex"];
    tex2.connections["st"] = {"/Looks/Brick/Reader2", "result"};
    n.nodes["/Looks/Brick/Reader2"] = {"UsdPrimvarReader_float2", {{"varname", std::string("uvA")}}, {}};
    Warnings w;
    PreviewSurface s = resolve(n, w);
    // diffuseColor (uvA) comes before roughness and opacity (both uvB).
    EXPECT_EQ(s.readerVarnames, (std::vector<std::string>{"uvA", "uvB"}));
    ASSERT_EQ(s.textureFiles.size(), 1u);  // one file, read by two textures
    EXPECT_EQ(s.textureFiles[0].authored, "./brick.png");
}

TEST(PreviewSurface, AStNotFromAPrimvarReaderWarnsAndNamesNoVarname) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    n.nodes["/Looks/Brick/Reader"].id = "UsdUVTexture";
    Warnings w;
    EXPECT_TRUE(resolve(n, w).readerVarnames.empty());
    w.one({"inputs:st of /Looks/Brick/Tex", "/Looks/Brick/Reader (UsdUVTexture)", "not supported"});
}

TEST(PreviewSurface, MissingTextureReadsItsAuthoredFallbackInTheChannel) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    n.nodes["/Looks/Brick/Surface"].connections["metallic"] = {"/Looks/Brick/Tex", "g"};
    n.nodes["/Looks/Brick/Surface"].parameters["diffuseColor"] = std::array<float, 3>{1, 1, 1};  // overridden
    auto& tex = n.nodes["/Looks/Brick/Tex"].parameters;
    tex["file"] = ShaderAsset{"./missing.png", ""};
    tex["fallback"] = std::array<float, 4>{0.2f, 0.5f, 0.8f, 1};
    Warnings w;
    PreviewSurface s = resolve(n, w);
    EXPECT_EQ(s.material.diffuseColorTexture.file, "");
    ExpectColor(s.material.diffuseColor, Color(0.2f, 0.5f, 0.8f));
    EXPECT_EQ(s.material.metallic, 0.5f);
    // Two inputs read the missing file: one warning, naming the material, the file and the texture.
    std::string warning = w.one({"'./missing.png'", "/Looks/Brick/Tex", "not found"});
    EXPECT_EQ(warning.rfind(kMaterial + ": ", 0), 0u) << warning;
    EXPECT_EQ(w.said.size(), 1u) << w.text();
    ASSERT_EQ(s.textureFiles.size(), 1u);
    EXPECT_EQ(s.textureFiles[0].resolved, "");
}

TEST(PreviewSurface, MissingTextureWithoutFallbackIsTheSpecsBlack) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    n.nodes["/Looks/Brick/Surface"].parameters["diffuseColor"] = std::array<float, 3>{1, 1, 1};
    n.nodes["/Looks/Brick/Tex"].parameters["file"] = ShaderAsset{"./missing.png", ""};
    Warnings w;
    ExpectColor(resolve(n, w).material.diffuseColor, Color(0.0f));
    w.one({"'./missing.png'", "not found"});
}

TEST(PreviewSurface, ATextureWithoutAFileWarns) {
    ShaderNetwork n = texturedNetwork("diffuseColor", "rgb");
    n.nodes["/Looks/Brick/Tex"].parameters.erase("file");
    Warnings w;
    EXPECT_EQ(resolve(n, w).material.diffuseColorTexture.file, "");
    w.one({"texture /Looks/Brick/Tex has no file"});
}

TEST(PreviewSurface, AnUnsupportedNodeOnAnInputWarnsNamingItAndKeepsTheDefault) {
    ShaderNetwork n = texturedNetwork("roughness", "r");
    n.nodes["/Looks/Brick/Tex"].id = "ND_noise2d_float";
    n.nodes["/Looks/Brick/Surface"].parameters["roughness"] = 0.9f;  // connected: not read
    Warnings w;
    EXPECT_EQ(resolve(n, w).material.roughness, MaterialDesc().roughness);
    w.one({"inputs:roughness", "/Looks/Brick/Tex (ND_noise2d_float)", "not supported"});
}

TEST(PreviewSurface, ATextureOnAnUntexturableInputWarnsAndDisplacementIsIgnored) {
    ShaderNetwork n = texturedNetwork("clearcoat", "r");
    n.nodes["/Looks/Brick/Surface"].connections["displacement"] = {"/Looks/Brick/Tex", "r"};
    n.nodes["/Looks/Brick/Surface"].connections["occlusion"] = {"/Looks/Brick/Tex", "r"};
    Warnings w;
    PreviewSurface s = resolve(n, w);
    EXPECT_EQ(s.material.clearcoat, MaterialDesc().clearcoat);
    w.one({"inputs:clearcoat", "/Looks/Brick/Tex (UsdUVTexture)", "not supported"});
    w.one({"displacement is not supported"});
    EXPECT_EQ(w.said.size(), 2u) << w.text();  // occlusion: silently left to the path tracer
}

TEST(PreviewSurface, ASurfaceThatIsNotAPreviewSurfaceWarnsAndResolvesToNothing) {
    ShaderNetwork n;
    n.nodes["/Looks/Brick/Std"].id = "ND_standard_surface_surfaceshader";
    Warnings w;
    EXPECT_FALSE(resolvePreviewSurface(kMaterial, n, "/Looks/Brick/Std", w.sink()).has_value());
    w.one({"/Looks/Brick/Std (ND_standard_surface_surfaceshader)", "not a UsdPreviewSurface", "displayColor"});
    EXPECT_FALSE(resolvePreviewSurface(kMaterial, n, "", w.sink()).has_value());
    w.one({"nothing drives its surface output"});
}
