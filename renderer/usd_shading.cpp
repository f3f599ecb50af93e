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
    if (input == "diffuseColor") {
        m.diffuseColorTexture = t;
        m.diffuseColor = colorOf(t);
    } else if (input == "emissiveColor") {
        m.emissiveColorTexture = t;
        m.emissiveColor = colorOf(t);
    } else if (input == "specularColor") {
        m.specularColorTexture = t;
        m.specularColor = colorOf(t);
    } else if (input == "metallic") {
        m.metallicTexture = t;
        m.metallic = channelOf(t);
    } else if (input == "roughness") {
        m.roughnessTexture = t;
        m.roughness = channelOf(t);
    } else if (input == "opacity") {
        m.opacityTexture = t;
        m.opacity = channelOf(t);
    } else if (input == "normal") {
        m.normalTexture = t;  // no constant: the surface's own normal stands in
    } else {
        return false;
    }
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
