#include "material.h"

namespace gi {

namespace {
Color sanitize(Color c) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(c[i]) || c[i] < 0) c[i] = 0;
    return c;
}
float sanitize01(float v, float fallback) { return std::isfinite(v) ? clamp01(v) : fallback; }
}  // namespace

Material::Material(const MaterialDesc& desc, const TextureBinder& bindTexture) : desc_(desc) {
    auto bind = [&](Texture& slot, const TextureDesc& t, const char* input) {
        if (!t.file.empty()) slot = bindTexture(t, input);
    };
    bind(diffuseTex_, desc.diffuseColorTexture, "diffuseColor");
    bind(emissiveTex_, desc.emissiveColorTexture, "emissiveColor");
    bind(specularTex_, desc.specularColorTexture, "specularColor");
    bind(metallicTex_, desc.metallicTexture, "metallic");
    bind(roughnessTex_, desc.roughnessTexture, "roughness");
    bind(opacity_, desc.opacityTexture, "opacity");
    bind(normalTex_, desc.normalTexture, "normal");
    // NaN, Inf and negative inputs are replaced (and named in repairedInputs(), so the scene can
    // warn); values merely outside [0, 1] are clamped silently, as UsdPreviewSurface says.
    auto color = [&](Color c, const char* input) {
        if (!isFinite(c) || c.x < 0 || c.y < 0 || c.z < 0) repaired_.push_back(input);
        return sanitize(c);
    };
    auto unit = [&](float v, float fallback, const char* input) {
        if (!std::isfinite(v)) repaired_.push_back(input);
        return sanitize01(v, fallback);
    };
    desc_.diffuseColor = color(desc.diffuseColor, "diffuseColor");
    desc_.emissiveColor = color(desc.emissiveColor, "emissiveColor");
    desc_.specularColor = color(desc.specularColor, "specularColor");
    desc_.metallic = unit(desc.metallic, 0, "metallic");
    desc_.roughness = unit(desc.roughness, 0.5f, "roughness");
    desc_.clearcoat = unit(desc.clearcoat, 0, "clearcoat");
    desc_.clearcoatRoughness = unit(desc.clearcoatRoughness, 0.01f, "clearcoatRoughness");
    desc_.opacity = unit(desc.opacity, 1, "opacity");
    desc_.opacityThreshold = unit(desc.opacityThreshold, 0, "opacityThreshold");
    // An index of refraction must be a positive finite number; 1e-3..1e3 keeps Fresnel and
    // refraction in float range.
    if (!(desc.ior >= 1e-3f && desc.ior <= 1e3f)) {
        repaired_.push_back("ior");
        desc_.ior = 1.5f;
    }
    emissive_ = maxComponent(desc_.emissiveColor) > 0 || emissiveTex_.valid();
    hasPresence_ = desc_.opacityMode == "presence" || desc_.opacityThreshold > 0;
    transparentMode_ = desc_.opacityMode == "transparent";
    // Caustic paths need a smooth reflector or a transmitter somewhere; rough lobes blur them
    // into ordinary indirect light that the global photon map already carries.
    constexpr float kCausticRoughness = 0.2f;
    bool reflectsSpecularly = desc_.useSpecularWorkflow ? maxComponent(desc_.specularColor) > 0 || specularTex_.valid()
                                                        : true;  // metallic workflow always has a Fresnel lobe
    specular_ = transmits() || (desc_.roughness < kCausticRoughness && reflectsSpecularly) ||
                (desc_.clearcoat > 0 && desc_.clearcoatRoughness < kCausticRoughness);
    constantBsdf_ = !diffuseTex_.valid() && !specularTex_.valid() && !metallicTex_.valid() && !roughnessTex_.valid() &&
                    !(transparentMode_ && opacity_.valid());
    if (constantBsdf_) bsdf_ = evalBsdf(Vec2(0.0f, 0.0f));
}

Vec3 Material::tangentNormal(Vec2 uv) const {
    Vec3 n = normalTex_.evalColor(uv);
    // A texel that is not a usable direction (NaN, zero, or pointing into the surface) leaves
    // the surface normal as it is.
    if (!isFinite(n) || !(n.z > 1e-3f)) return Vec3(0, 0, 1);
    return normalize(n);
}

Color Material::emission(Vec2 uv) const {
    if (emissiveTex_.valid()) return sanitize(emissiveTex_.evalColor(uv));
    return desc_.emissiveColor;
}

float Material::presence(Vec2 uv) const {
    if (!hasPresence_) return 1;
    float a = opacity_.valid() ? opacity_.evalFloat(uv) : desc_.opacity;
    a = sanitize01(a, 1);
    if (desc_.opacityThreshold > 0) return a >= desc_.opacityThreshold ? 1.0f : 0.0f;
    return a;
}

Bsdf Material::bsdf(Vec2 uv, float footprint) const { return constantBsdf_ ? bsdf_ : evalBsdf(uv, footprint); }

Bsdf Material::evalBsdf(Vec2 uv, float footprint) const {
    BsdfParams p;
    Color base = diffuseTex_.valid() ? sanitize(diffuseTex_.evalColor(uv, footprint)) : desc_.diffuseColor;
    base = vmin(base, Color(1.0f));
    float roughness =
        roughnessTex_.valid() ? sanitize01(roughnessTex_.evalFloat(uv, footprint), 0.5f) : desc_.roughness;
    float opacity = 1;
    if (transparentMode_)
        opacity = opacity_.valid() ? sanitize01(opacity_.evalFloat(uv, footprint), 1) : desc_.opacity;
    p.roughness = roughness;
    p.clearcoat = desc_.clearcoat;
    p.clearcoatRoughness = desc_.clearcoatRoughness;
    p.ior = desc_.ior;
    p.transmission = 1 - opacity;
    p.transmissionTint = base;
    if (desc_.useSpecularWorkflow) {
        Color spec = specularTex_.valid() ? sanitize(specularTex_.evalColor(uv, footprint)) : desc_.specularColor;
        p.specularF0 = vmin(spec, Color(1.0f));
        // Filament's trick: a black specular colour means no specular at grazing angles either.
        p.specularF90 = clamp01(50.0f * maxComponent(p.specularF0));
        p.diffuse = base;
    } else {
        float metallic =
            metallicTex_.valid() ? sanitize01(metallicTex_.evalFloat(uv, footprint), 0) : desc_.metallic;
        float r = (1 - p.ior) / (1 + p.ior);
        p.specularF0 = lerp(Color(r * r), base, metallic);
        p.specularF90 = 1;
        p.diffuse = base * (1 - metallic);
    }
    return Bsdf(p);
}

}  // namespace gi
