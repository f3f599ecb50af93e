#include "bsdf.h"

#include "sampling.h"

namespace gi {

namespace {
constexpr float kClearcoatF0 = 0.04f;  // polyurethane, ior 1.5

float lobeAlpha(float roughness) { return roughness * roughness; }
}  // namespace

Bsdf::Bsdf(const BsdfParams& p)
    : params_(p),
      specular_(lobeAlpha(p.roughness)),
      clearcoat_(lobeAlpha(p.clearcoatRoughness)),
      dielectric_(lobeAlpha(p.roughness)) {
    params_.transmission = clamp01(p.transmission);
    params_.clearcoat = clamp01(p.clearcoat);
    params_.ior = std::isfinite(p.ior) && p.ior > 1e-3f ? p.ior : 1.5f;
    diffuse_ = p.diffuse * (1 - params_.transmission);
    bool opaqueNonDelta = (1 - params_.transmission) > 0 &&
                          (maxComponent(diffuse_) > 0 || !specular_.smooth() ||
                           (params_.clearcoat > 0 && !clearcoat_.smooth()));
    bool dielectricNonDelta = params_.transmission > 0 && !dielectric_.smooth();
    hasSpecular_ = maxComponent(params_.specularF0) > 0 || params_.specularF90 > 0;
    hasClearcoat_ = params_.clearcoat > 0;
    nonDeltaWeight_ = (opaqueNonDelta || dielectricNonDelta) ? 1.0f : 0.0f;
    lambertian_ = params_.transmission == 0 && !hasSpecular_ && !hasClearcoat_;
    glossy_ = ((1 - params_.transmission) > 0 && ((hasSpecular_ && !specular_.smooth()) ||
                                                   (hasClearcoat_ && !clearcoat_.smooth()))) ||
              dielectricNonDelta;
}

Color Bsdf::diffuseLobe(const Vec3& wo) const {
    if (wo.z <= 0) return Color(0.0f);
    Color base = diffuse_ * kInvPi;
    if (lambertian_) return base;
    if (hasSpecular_) base = base * (1 - maxComponent(fresnelSchlick(params_.specularF0, params_.specularF90, wo.z)));
    return base * (1 - params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, wo.z).x);
}

Bsdf::LobeWeights Bsdf::lobeWeights(const Vec3& wo) const {
    float c = absCosTheta(wo);
    float opaque = 1 - params_.transmission;
    float cc = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, c).x;
    Color fs = fresnelSchlick(params_.specularF0, params_.specularF90, c);
    LobeWeights w;
    w.clearcoat = opaque * cc;
    w.specular = opaque * (1 - cc) * luminance(fs);
    w.diffuse = opaque * (1 - cc) * luminance(diffuse_ / std::max(1e-6f, opaque)) * (1 - maxComponent(fs));
    w.dielectric = params_.transmission;
    float sum = w.clearcoat + w.specular + w.diffuse + w.dielectric;
    if (!(sum > 0)) return {1, 0, 0, 0};
    return {w.diffuse / sum, w.specular / sum, w.clearcoat / sum, w.dielectric / sum};
}

Color Bsdf::albedo() const {
    Color fs = fresnelSchlick(params_.specularF0, params_.specularF90, 1);
    return diffuse_ + fs * (1 - params_.transmission) + params_.transmissionTint * params_.transmission;
}

// Opaque layers: clearcoat over (GGX specular + (1 - F) * Lambert), all scaled by the opaque
// fraction (diffuse_ already carries it).
Color Bsdf::evalOpaque(const Vec3& wo, const Vec3& wi) const {
    if (wo.z <= 0 || wi.z <= 0) return Color(0);
    float opaque = 1 - params_.transmission;
    Vec3 wm = normalize(wo + wi);
    float ccF = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, dot(wo, wm)).x;
    float ccView = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, wo.z).x;
    Color f(0);
    if (hasClearcoat_ && !clearcoat_.smooth())
        f += Color(opaque * clearcoat_.D(wm) * clearcoat_.GOverCosines(wo, wi) * ccF / 4);
    Color base = diffuse_ * kInvPi;
    if (hasSpecular_) {
        Color fs = fresnelSchlick(params_.specularF0, params_.specularF90, dot(wo, wm));
        if (!specular_.smooth()) base += fs * (opaque * specular_.D(wm) * specular_.GOverCosines(wo, wi) / 4);
        Color fView = fresnelSchlick(params_.specularF0, params_.specularF90, wo.z);
        base += diffuse_ * (-kInvPi * maxComponent(fView));
    }
    return f + base * (1 - ccView);
}

float Bsdf::pdfOpaqueLobes(const Vec3& wo, const Vec3& wi, const LobeWeights& w) const {
    if (wo.z <= 0 || wi.z <= 0) return 0;
    float pdf = w.diffuse * cosineHemispherePdf(wi.z);
    if (w.specular <= 0 && w.clearcoat <= 0) return pdf;
    Vec3 wm = normalize(wo + wi);
    float jacobian = 1 / (4 * absDot(wo, wm));
    if (w.specular > 0 && !specular_.smooth()) pdf += w.specular * specular_.pdf(wo, wm) * jacobian;
    if (w.clearcoat > 0 && !clearcoat_.smooth()) pdf += w.clearcoat * clearcoat_.pdf(wo, wm) * jacobian;
    return pdf;
}

Color Bsdf::evalRoughDielectric(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (dielectric_.smooth() || params_.transmission <= 0) return Color(0);
    float cosO = wo.z, cosI = wi.z;
    if (cosO == 0 || cosI == 0) return Color(0);
    bool reflection = cosO * cosI > 0;
    float etap = reflection ? 1 : (cosO > 0 ? params_.ior : 1 / params_.ior);
    Vec3 wm = wi * etap + wo;
    if (lengthSquared(wm) == 0) return Color(0);
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    if (dot(wm, wi) * cosI < 0 || dot(wm, wo) * cosO < 0) return Color(0);  // back-facing microfacet
    float F = fresnelDielectric(dot(wo, wm), params_.ior);
    float D = dielectric_.D(wm), GoC = dielectric_.GOverCosines(wo, wi);  // G / |cosI cosO|
    if (reflection) return Color(params_.transmission * D * GoC * F / 4);
    float denom = dot(wi, wm) + dot(wo, wm) / etap;
    denom = denom * denom;
    if (!(denom > 0)) return Color(0);
    float ft = D * (1 - F) * GoC * std::fabs(dot(wi, wm) * dot(wo, wm) / denom);
    if (mode == TransportMode::Radiance) ft /= etap * etap;
    return params_.transmissionTint * (params_.transmission * ft);
}

float Bsdf::pdfRoughDielectric(const Vec3& wo, const Vec3& wi) const {
    if (dielectric_.smooth() || params_.transmission <= 0) return 0;
    float cosO = wo.z, cosI = wi.z;
    if (cosO == 0 || cosI == 0) return 0;
    bool reflection = cosO * cosI > 0;
    float etap = reflection ? 1 : (cosO > 0 ? params_.ior : 1 / params_.ior);
    Vec3 wm = wi * etap + wo;
    if (lengthSquared(wm) == 0) return 0;
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    if (dot(wm, wi) * cosI < 0 || dot(wm, wo) * cosO < 0) return 0;
    float R = fresnelDielectric(dot(wo, wm), params_.ior), T = 1 - R;
    if (reflection) return dielectric_.pdf(wo, wm) / (4 * absDot(wo, wm)) * R;
    float denom = dot(wi, wm) + dot(wo, wm) / etap;
    return dielectric_.pdf(wo, wm) * absDot(wi, wm) / (denom * denom) * T;
}

Color Bsdf::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (lambertian_) return wo.z > 0 && wi.z > 0 ? diffuse_ * kInvPi : Color(0.0f);
    Color f = evalOpaque(wo, wi);
    if (params_.transmission > 0) f += evalRoughDielectric(wo, wi, mode);
    return f;
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    if (lambertian_) return wo.z > 0 ? cosineHemispherePdf(wi.z) : 0.0f;
    return pdfWithWeights(wo, wi, lobeWeights(wo));
}

float Bsdf::pdfWithWeights(const Vec3& wo, const Vec3& wi, const LobeWeights& w) const {
    float p = pdfOpaqueLobes(wo, wi, w);
    if (w.dielectric > 0) p += w.dielectric * pdfRoughDielectric(wo, wi);
    return p;
}

BsdfSample Bsdf::sampleDielectric(const Vec3& wo, float uc, Vec2 u, TransportMode mode) const {
    BsdfSample s;
    float eta = params_.ior;
    if (dielectric_.smooth()) {
        float R = fresnelDielectric(wo.z, eta), T = 1 - R;
        s.delta = true;
        s.valid = true;
        if (uc < R) {
            s.wi = Vec3(-wo.x, -wo.y, wo.z);
            s.pdf = R;
            s.weight = Color(1.0f);  // f*cos/pdf = R / R
            return s;
        }
        float etap;
        Vec3 wi;
        if (!refract(wo, Vec3(0, 0, 1), eta, &etap, &wi)) return BsdfSample();
        s.wi = wi;
        s.pdf = T;
        s.transmission = true;
        float scale = mode == TransportMode::Radiance ? 1 / (etap * etap) : 1.0f;
        s.weight = params_.transmissionTint * scale;
        return s;
    }
    Vec3 wm = dielectric_.sampleVisibleNormal(wo, u);
    float R = fresnelDielectric(dot(wo, wm), eta), T = 1 - R;
    Vec3 wi;
    if (uc < R / (R + T)) {
        wi = reflect(wo, wm);
        if (!sameHemisphere(wo, wi)) return BsdfSample();
    } else {
        float etap;
        if (!refract(wo, wm, eta, &etap, &wi) || sameHemisphere(wo, wi) || wi.z == 0) return BsdfSample();
        s.transmission = true;
    }
    s.wi = wi;
    s.valid = true;
    return s;  // weight and pdf are filled by the caller from eval/pdf (one-sample MIS over lobes)
}

BsdfSample Bsdf::sampleLambertian(const Vec3& wo, Vec2 u) const {
    BsdfSample s;
    if (wo.z <= 0 || isBlack(diffuse_)) return s;
    s.wi = sampleCosineHemisphere(u);
    s.pdf = cosineHemispherePdf(s.wi.z);
    if (!(s.pdf > 0)) return BsdfSample();
    s.weight = diffuse_;  // (albedo / pi) * cos / (cos / pi)
    s.valid = true;
    return s;
}

BsdfSample Bsdf::sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const {
    if (wo.z == 0) return BsdfSample();
    if (lambertian_) return sampleLambertian(wo, u);
    LobeWeights w = lobeWeights(wo);
    BsdfSample s;
    float uc = uLobe;
    if (uc < w.dielectric) {
        s = sampleDielectric(wo, uc / w.dielectric, u, mode);
        if (!s.valid) return s;
        if (s.delta) {
            s.pdf *= w.dielectric;
            s.weight = s.weight * (1 / w.dielectric) * params_.transmission;
            return s;
        }
    } else {
        if (wo.z <= 0) return BsdfSample();  // opaque lobes are reflective only
        uc -= w.dielectric;
        if (uc < w.diffuse) {
            s.wi = sampleCosineHemisphere(u);
        } else if (uc < w.diffuse + w.specular) {
            if (specular_.smooth()) {
                s.wi = Vec3(-wo.x, -wo.y, wo.z);
                s.delta = true;
                s.pdf = w.specular;
                float ccView = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, wo.z).x;
                s.weight = fresnelSchlick(params_.specularF0, params_.specularF90, wo.z) * ((1 - ccView) / w.specular);
                s.valid = true;
                return s;
            }
            s.wi = reflect(wo, specular_.sampleVisibleNormal(wo, u));
        } else {
            if (clearcoat_.smooth()) {
                s.wi = Vec3(-wo.x, -wo.y, wo.z);
                s.delta = true;
                s.pdf = w.clearcoat;
                float F = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, wo.z).x;
                s.weight = Color(F / w.clearcoat);
                s.valid = true;
                return s;
            }
            s.wi = reflect(wo, clearcoat_.sampleVisibleNormal(wo, u));
        }
        if (s.wi.z <= 0) return BsdfSample();
        s.valid = true;
    }
    s.pdf = pdfWithWeights(wo, s.wi, w);
    Color f = eval(wo, s.wi, mode);
    if (!(s.pdf > 0) || isBlack(f)) return BsdfSample();
    s.weight = f * (absCosTheta(s.wi) / s.pdf);
    return s;
}

int Bsdf::deltaBranches(const Vec3& wo, BsdfSample out[3], TransportMode mode) const {
    int n = 0;
    auto add = [&](const Vec3& wi, Color weight, bool transmission) {
        if (isBlack(weight)) return;
        BsdfSample& s = out[n++];
        s.wi = wi;
        s.weight = weight;
        s.pdf = 1;
        s.delta = true;
        s.transmission = transmission;
        s.valid = true;
    };
    Vec3 mirror(-wo.x, -wo.y, wo.z);
    if (params_.transmission > 0 && dielectric_.smooth()) {
        float F = fresnelDielectric(wo.z, params_.ior);
        add(mirror, Color(params_.transmission * F), false);
        float etap;
        Vec3 wt;
        if (F < 1 && refract(wo, Vec3(0, 0, 1), params_.ior, &etap, &wt)) {
            float scale = mode == TransportMode::Radiance ? 1 / (etap * etap) : 1.0f;
            add(wt, params_.transmissionTint * (params_.transmission * (1 - F) * scale), true);
        }
    }
    float opaque = 1 - params_.transmission;
    if (opaque > 0 && wo.z > 0) {
        float ccView = params_.clearcoat * fresnelSchlick(Color(kClearcoatF0), 1, wo.z).x;
        if (specular_.smooth())
            add(mirror, fresnelSchlick(params_.specularF0, params_.specularF90, wo.z) * (opaque * (1 - ccView)), false);
        if (clearcoat_.smooth() && params_.clearcoat > 0) add(mirror, Color(opaque * ccView), false);
    }
    return n;
}

}  // namespace gi
