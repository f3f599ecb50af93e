// The UsdPreviewSurface BSDF at one shading point, in the local frame (normal = +z).
// Lobes: Lambertian diffuse, GGX specular (Schlick Fresnel from F0/F90), GGX clearcoat on
// top, and a dielectric (smooth or rough GGX) for opacity < 1 in "transparent" mode, whose
// transmission is tinted by the diffuse colour at every refraction event.
#pragma once
#include "math.h"
#include "microfacet.h"

namespace gi {

enum class TransportMode { Radiance, Importance };

struct BsdfSample {
    Vec3 wi;
    Color weight;   // f * |cos| / pdf
    float pdf = 0;  // solid-angle pdf; for delta lobes the discrete probability of the lobe
    bool delta = false;
    bool transmission = false;
    bool valid = false;
};

struct BsdfParams {
    Color diffuse{0.18f};
    Color specularF0{0.04f};
    float specularF90 = 1;
    float roughness = 0.5f;
    float clearcoat = 0;
    float clearcoatRoughness = 0.01f;
    float transmission = 0;  // 1 - opacity in transparent mode
    float ior = 1.5f;
    Color transmissionTint{1.0f};
};

class Bsdf {
public:
    Bsdf() = default;
    explicit Bsdf(const BsdfParams& p);

    // f(wo, wi) of the non-delta lobes, without the cosine.
    Color eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    BsdfSample sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode = TransportMode::Radiance) const;

    // Every delta lobe's direction and full weight (f*cos/pdf without lobe selection), for
    // ray tracers that recurse into all specular branches instead of picking one. Returns the count.
    int deltaBranches(const Vec3& wo, BsdfSample out[3], TransportMode mode = TransportMode::Radiance) const;

    bool hasNonDelta() const { return nonDeltaWeight_ > 0; }
    bool isPurelyDelta() const { return !hasNonDelta(); }
    bool transmits() const { return params_.transmission > 0; }
    // Approximate hemispherical reflectance, for the albedo AOV and photon survival.
    Color albedo() const;
    // Lambertian part only (its reflectance, before the Fresnel of the lobes above it).
    Color diffuseReflectance() const { return diffuse_; }
    // The Lambertian lobe's f towards wo, the same for every wi in wo's hemisphere (what eval
    // holds of it: less the Fresnel reflected by the specular and clearcoat lobes above it): what
    // an irradiance estimate is multiplied by.
    Color diffuseLobe(const Vec3& wo) const;
    // Whether any non-delta lobe other than the Lambertian one can reflect light (a rough
    // specular, clearcoat or dielectric lobe).
    bool hasGlossy() const { return glossy_; }
    const BsdfParams& params() const { return params_; }

private:
    struct LobeWeights {
        float diffuse, specular, clearcoat, dielectric;
    };
    LobeWeights lobeWeights(const Vec3& wo) const;
    Color evalOpaque(const Vec3& wo, const Vec3& wi) const;
    float pdfOpaqueLobes(const Vec3& wo, const Vec3& wi, const LobeWeights& w) const;
    Color evalRoughDielectric(const Vec3& wo, const Vec3& wi, TransportMode mode) const;
    float pdfRoughDielectric(const Vec3& wo, const Vec3& wi) const;
    float pdfWithWeights(const Vec3& wo, const Vec3& wi, const LobeWeights& w) const;
    BsdfSample sampleLambertian(const Vec3& wo, Vec2 u) const;
    BsdfSample sampleDielectric(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const;

    BsdfParams params_;
    Color diffuse_;  // diffuse reflectance after metallic and transmission
    GGX specular_{0.25f}, clearcoat_{0.01f}, dielectric_{0.01f};
    float nonDeltaWeight_ = 1;
    // Lobes that can contribute at all: lets a plain Lambertian surface skip the microfacet math.
    bool hasSpecular_ = true, hasClearcoat_ = true;
    // Only the Lambertian lobe (most of a typical scene): eval, pdf and sample skip lobe selection.
    bool lambertian_ = false;
    bool glossy_ = false;
};

}  // namespace gi
