#include "usd_shading.h"

#include <algorithm>

namespace gi {

namespace {

// The component of a 4-channel texture value that the connected output (r, g, b, a; rgb) delivers.
float channelOf(const TextureDesc& t) {
    int c = t.channel == "g" ? 1 : t.channel == "b" ? 2 : t.channel == "a" ? 3 : 0;
    return t.fallback[c];
}

Color colorOf(const TextureDesc& t) {
    return t.channel == "rgb" ? Color(t.fallback[0], t.fallback[1], t.fallback[2]) : Color(channelOf(t));
}

}  // namespace

bool connectTexture(MaterialDesc& m, const std::string& input, const TextureDesc& t) {
    struct ColorInput { const char* name; Color MaterialDesc::*constant; TextureDesc MaterialDesc::*texture; };
    struct FloatInput { const char* name; float MaterialDesc::*constant; TextureDesc MaterialDesc::*texture; };
    static const ColorInput colors[] = {{"diffuseColor", &MaterialDesc::diffuseColor, &MaterialDesc::diffuseColorTexture},
                                        {"emissiveColor", &MaterialDesc::emissiveColor, &MaterialDesc::emissiveColorTexture},
                                        {"specularColor", &MaterialDesc::specularColor, &MaterialDesc::specularColorTexture}};
    static const FloatInput floats[] = {{"metallic", &MaterialDesc::metallic, &MaterialDesc::metallicTexture},
                                        {"roughness", &MaterialDesc::roughness, &MaterialDesc::roughnessTexture},
                                        {"opacity", &MaterialDesc::opacity, &MaterialDesc::opacityTexture}};
    for (const ColorInput& c : colors)
        if (input == c.name) {
            m.*c.texture = t;
            m.*c.constant = colorOf(t);
            return true;
        }
    for (const FloatInput& f : floats)
        if (input == f.name) {
            m.*f.texture = t;
            m.*f.constant = channelOf(t);
            return true;
        }
    if (input != "normal") return false;
    m.normalTexture = t;  // no constant: the surface's own normal stands in
    return true;
}

MaterialDesc displayColorMaterial(const std::string& primPath, const Color* displayColor) {
    MaterialDesc d;  // UsdPreviewSurface's defaults
    d.name = primPath + ".primvars:displayColor";
    if (displayColor) d.diffuseColor = *displayColor;
    return d;
}

std::string uvPrimvarOf(const std::vector<std::string>& readerVarnames, const std::vector<std::string>& meshPrimvars) {
    for (const std::string& name : readerVarnames)
        if (!name.empty() && std::find(meshPrimvars.begin(), meshPrimvars.end(), name) != meshPrimvars.end()) return name;
    return "";
}

}  // namespace gi
