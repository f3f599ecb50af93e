// BSDF sanity: energy conservation (the hemispherical integral of f*cos stays <= 1), the
// sampling weights agree with eval/pdf, and reciprocity of the reflective lobes.
#include <gtest/gtest.h>

#include "renderer/bsdf.h"
#include "renderer/sampler.h"
#include "renderer/sampling.h"

using namespace gi;

namespace {

BsdfParams opaque(Color diffuse, float roughness, Color f0, float f90) {
    BsdfParams p;
    p.diffuse = diffuse;
    p.roughness = roughness;
    p.specularF0 = f0;
    p.specularF90 = f90;
    return p;
}

// Estimates the directional albedo (integral of f*cos over all wi) by importance sampling.
Color albedoBySampling(const Bsdf& bsdf, Vec3 wo, int n) {
    Sampler s(11);
    Color sum(0.0f);
    for (int i = 0; i < n; ++i) {
        s.start(1, 2, uint32_t(i));
        float uc = s.get1D();
        BsdfSample bs = bsdf.sample(wo, uc, s.get2D());
        if (bs.valid) sum += bs.weight;
    }
    return sum / float(n);
}

// The same integral by uniform sphere sampling of eval (independent of the sampling code).
Color albedoByEval(const Bsdf& bsdf, Vec3 wo, int n) {
    Sampler s(13);
    Color sum(0.0f);
    for (int i = 0; i < n; ++i) {
        s.start(3, 4, uint32_t(i));
        Vec3 wi = sampleUniformSphere(s.get2D());
        sum += bsdf.eval(wo, wi) * (absCosTheta(wi) / uniformSpherePdf());
    }
    return sum / float(n);
}

}  // namespace

TEST(Bsdf, LambertianAlbedoEqualsDiffuseColor) {
    Bsdf b(opaque(Color(0.6f, 0.3f, 0.1f), 1, Color(0.0f), 0));
    Color a = albedoBySampling(b, normalize(Vec3(0.3f, 0.1f, 0.9f)), 4096);
    EXPECT_NEAR(a.x, 0.6f, 1e-3f);
    EXPECT_NEAR(a.y, 0.3f, 1e-3f);
}

TEST(Bsdf, EnergyConservedForEveryRoughnessAndAngle) {
    for (float roughness : {0.05f, 0.3f, 0.7f, 1.0f})
        for (float cosTheta : {1.0f, 0.5f, 0.1f, 0.01f}) {
            Vec3 wo(safeSqrt(1 - cosTheta * cosTheta), 0, cosTheta);
            Bsdf b(opaque(Color(1.0f), roughness, Color(0.04f), 1));
            Color a = albedoBySampling(b, wo, 2048);
            EXPECT_LE(maxComponent(a), 1.02f) << "roughness " << roughness << " cos " << cosTheta;
            EXPECT_TRUE(isFinite(a));
        }
}

TEST(Bsdf, SamplingAgreesWithEvalAndPdf) {
    for (float roughness : {0.2f, 0.5f, 0.9f}) {
        Bsdf b(opaque(Color(0.5f), roughness, Color(0.3f), 1));
        Vec3 wo = normalize(Vec3(0.4f, -0.2f, 0.8f));
        Color sampled = albedoBySampling(b, wo, 1 << 15);
        Color evaluated = albedoByEval(b, wo, 1 << 17);
        EXPECT_NEAR(sampled.x, evaluated.x, 0.02f) << "roughness " << roughness;
    }
}

TEST(Bsdf, ReflectionIsReciprocal) {
    Bsdf b(opaque(Color(0.0f), 0.4f, Color(0.5f), 1));
    Vec3 a = normalize(Vec3(0.2f, 0.3f, 0.9f)), c = normalize(Vec3(-0.5f, 0.1f, 0.6f));
    EXPECT_NEAR(b.eval(a, c).x, b.eval(c, a).x, 1e-5f);
}

TEST(Bsdf, SmoothDielectricConservesEnergyAndTints) {
    BsdfParams p;
    p.transmission = 1;
    p.roughness = 0;
    p.ior = 1.5f;
    p.transmissionTint = Color(0.6f, 0.9f, 0.6f);
    Bsdf b(p);
    EXPECT_FALSE(b.hasNonDelta());
    Vec3 wo(0, 0, 1);
    BsdfSample branches[3];
    int n = b.deltaBranches(wo, branches, TransportMode::Importance);
    ASSERT_EQ(n, 2);
    float F = fresnelDielectric(1, 1.5f);
    EXPECT_NEAR(F, 0.04f, 1e-4f);
    EXPECT_NEAR(branches[0].weight.x, F, 1e-5f);
    EXPECT_NEAR(branches[1].weight.y, 0.9f * (1 - F), 1e-5f);
    // Total internal reflection from inside beyond the critical angle.
    Vec3 inside(0.9f, 0, -safeSqrt(1 - 0.81f));
    n = b.deltaBranches(inside, branches);
    ASSERT_EQ(n, 1);
    EXPECT_NEAR(branches[0].weight.x, 1.0f, 1e-5f);
}

TEST(Bsdf, RoughDielectricConservesEnergy) {
    BsdfParams p;
    p.transmission = 1;
    p.roughness = 0.4f;
    p.ior = 1.5f;
    Bsdf b(p);
    for (float c : {0.9f, 0.4f, -0.7f}) {
        Vec3 wo(safeSqrt(1 - c * c), 0, c);
        Color a = albedoBySampling(b, wo, 1 << 14);
        // Radiance mode scales transmission by 1/eta^2 going in; importance mode conserves flux.
        Color flux(0.0f);
        Sampler s(3);
        for (int i = 0; i < (1 << 14); ++i) {
            s.start(0, 0, uint32_t(i));
            float uc = s.get1D();
            BsdfSample bs = b.sample(wo, uc, s.get2D(), TransportMode::Importance);
            if (bs.valid) flux += bs.weight;
        }
        flux = flux / float(1 << 14);
        EXPECT_LE(flux.x, 1.02f) << "cos " << c;
        EXPECT_GE(flux.x, 0.85f) << "cos " << c;  // a smooth-ish dielectric loses little
        EXPECT_TRUE(isFinite(a));
    }
}

TEST(Bsdf, GrazingAnglesStayFinite) {
    Bsdf b(opaque(Color(0.5f), 0.3f, Color(0.04f), 1));
    Vec3 grazing(1, 0, 0);
    EXPECT_TRUE(isFinite(b.eval(grazing, Vec3(0, 0, 1))));
    EXPECT_TRUE(std::isfinite(b.pdf(grazing, Vec3(0, 0, 1))));
    BsdfSample s = b.sample(grazing, 0.5f, Vec2(0.3f, 0.7f));
    EXPECT_FALSE(s.valid);
}
