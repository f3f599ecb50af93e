// UsdPreviewSurface as a material: constant inputs or textures, turned into a Bsdf per point.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "bsdf.h"
#include "texture.h"

namespace gi {

struct MaterialDesc {
    std::string name = "default";
    Color diffuseColor{0.18f};
    Color emissiveColor{0.0f};
    bool useSpecularWorkflow = false;
    Color specularColor{0.0f};
    float metallic = 0;
    float roughness = 0.5f;
    float clearcoat = 0;
    float clearcoatRoughness = 0.01f;
    float opacity = 1;
    std::string opacityMode = "transparent";
    float opacityThreshold = 0;
    float ior = 1.5f;
    TextureDesc diffuseColorTexture, emissiveColorTexture, specularColorTexture, metallicTexture,
        roughnessTexture, opacityTexture, normalTexture;
};

class Material {
public:
    Material() = default;
    // bindTexture turns a descriptor into a loaded texture (or an invalid one, after warning);
    // it is only called for inputs that name a file.
    using TextureBinder = std::function<Texture(const TextureDesc&, const std::string& input)>;
    Material(const MaterialDesc& desc, const TextureBinder& bindTexture);

    // `footprint`: the width its textures are read over, in uv units (Texture::evalColor).
    Bsdf bsdf(Vec2 uv, float footprint = 0) const;
    // Whether bsdf() reads textures (and so needs a footprint).
    bool texturedBsdf() const { return !constantBsdf_; }
    Color emission(Vec2 uv) const;
    bool isEmissive() const { return emissive_; }
    // UsdPreviewSurface's `normal` input: a tangent-space normal (+z = the surface normal; the
    // texture's scale and bias map its texels to [-1, 1], as USD authors them).
    bool hasNormalMap() const { return normalTex_.valid(); }
    // Read at the texture's finest level: a normal map's coarser levels flatten its bumps (they
    // brightened Sibenik's indirect light by 0.2%), which no cone should.
    Vec3 tangentNormal(Vec2 uv) const;
    // Stochastic presence (opacityMode "presence" or an opacity threshold): probability that a
    // ray stops here. 1 for solid surfaces.
    float presence(Vec2 uv) const;
    bool hasPresence() const { return hasPresence_; }
    // True when any lobe is a delta or glossy reflector/transmitter (caustic paths need these).
    bool isSpecular() const { return specular_; }
    bool transmits() const { return transparentMode_ && (desc_.opacity < 1 || opacity_.valid()); }
    const MaterialDesc& desc() const { return desc_; }
    // Inputs whose NaN, Inf or negative values were replaced by defaults.
    const std::vector<std::string>& repairedInputs() const { return repaired_; }

private:
    Bsdf evalBsdf(Vec2 uv, float footprint = 0) const;

    MaterialDesc desc_;
    Texture diffuseTex_, emissiveTex_, specularTex_, metallicTex_, roughnessTex_, opacity_, normalTex_;
    bool emissive_ = false;
    bool hasPresence_ = false;
    bool specular_ = false;
    bool transparentMode_ = true;
    // Untextured materials build their BSDF once, not at every shading point.
    bool constantBsdf_ = false;
    Bsdf bsdf_;
    std::vector<std::string> repaired_;
};

}  // namespace gi
