// Stiff cases at the edges of the numbers (issue 8): BSDFs at exactly grazing, denormal and
// back-facing angles with extreme roughness and IOR, light sampling from points on or inside a
// light (pdf ~ 0 or ~ infinite), and every estimate finite and non-negative.
#include <gtest/gtest.h>

#include <cfloat>
#include <string>
#include <vector>

#include "renderer/bsdf.h"
#include "renderer/light.h"
#include "renderer/sampler.h"

using namespace gi;

namespace {

struct Case {
    std::string name;
    BsdfParams p;
};

std::vector<Case> extremeMaterials() {
    std::vector<Case> cases;
    for (float roughness : {0.0f, 1e-4f, 0.0316f, 0.5f, 1.0f}) {
        BsdfParams dielectricCoat;
        dielectricCoat.roughness = roughness;
        dielectricCoat.diffuse = Color(0.8f);
        dielectricCoat.clearcoat = 1;
        dielectricCoat.clearcoatRoughness = roughness;
        cases.push_back({"plastic r=" + std::to_string(roughness), dielectricCoat});
        BsdfParams metal;
        metal.roughness = roughness;
        metal.diffuse = Color(0);
        metal.specularF0 = Color(1.0f, 0.8f, 0.3f);
        cases.push_back({"metal r=" + std::to_string(roughness), metal});
        for (float ior : {1.0001f, 1.0f, 4.0f, 0.5f}) {
            BsdfParams glass;
            glass.roughness = roughness;
            glass.diffuse = Color(0);
            glass.transmission = 1;
            glass.ior = ior;
            glass.transmissionTint = Color(1.0f);
            cases.push_back({"glass r=" + std::to_string(roughness) + " ior=" + std::to_string(ior), glass});
        }
    }
    return cases;
}

// Directions with cos(theta) exactly 0, denormal, tiny, ordinary, and below the surface.
std::vector<Vec3> stiffDirections() {
    std::vector<Vec3> out;
    for (float c : {1.0f, 0.5f, 1e-3f, 1e-7f, 1e-20f, FLT_MIN, 1e-44f, 0.0f, -1e-20f, -0.5f, -1.0f}) {
        float s = std::sqrt(std::max(0.0f, 1 - c * c));
        out.push_back(Vec3(s, 0, c));
        out.push_back(Vec3(-s * 0.6f, s * 0.8f, c));
    }
    return out;
}

bool finiteNonNegative(const Color& c) { return isFinite(c) && c.x >= 0 && c.y >= 0 && c.z >= 0; }

}  // namespace

TEST(Stiff, BsdfAtGrazingDenormalAndBackFacingAnglesStaysFiniteAndBounded) {
    Sampler sampler(5);
    for (const Case& m : extremeMaterials()) {
        Bsdf bsdf(m.p);
        for (const Vec3& wo : stiffDirections())
            for (const Vec3& wi : stiffDirections()) {
                Color f = bsdf.eval(wo, wi);
                float pdf = bsdf.pdf(wo, wi);
                ASSERT_TRUE(finiteNonNegative(f)) << m.name << " wo.z=" << wo.z << " wi.z=" << wi.z;
                ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0) << m.name << " wo.z=" << wo.z << " wi.z=" << wi.z;
            }
        for (const Vec3& wo : stiffDirections())
            for (int i = 0; i < 64; ++i) {
                sampler.start(i, 0, 0);
                float uc = sampler.get1D();
                BsdfSample s = bsdf.sample(wo, uc, sampler.get2D());
                if (!s.valid) continue;
                ASSERT_TRUE(finiteNonNegative(s.weight)) << m.name << " wo.z=" << wo.z;
                ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > 0) << m.name << " wo.z=" << wo.z << " pdf " << s.pdf;
                ASSERT_TRUE(isFinite(s.wi) && std::fabs(length(s.wi) - 1) < 1e-3f) << m.name;
                // Importance sampling keeps f cos / pdf near the albedo: never a division by a pdf ~ 0.
                // Radiance entering a denser medium is compressed by ior^2 (and spread out leaving it).
                float compression = m.p.transmission > 0 ? std::max(m.p.ior * m.p.ior, 1 / (m.p.ior * m.p.ior)) : 1.0f;
                EXPECT_LE(maxComponent(s.weight), 4.0f * compression) << m.name << " wo.z=" << wo.z << " wi.z=" << s.wi.z;
            }
    }
}

TEST(Stiff, LightSamplesFromOnOrInsideTheLightAreFinite) {
    std::vector<LightDesc> lights;
    for (const char* kind : {"rect", "disk", "sphere", "cylinder", "distant", "dome"}) {
        LightDesc d;
        d.name = kind;
        d.kind = kind;
        d.intensity = 1e6f;
        d.radius = 1e-4f;
        d.width = d.height = 1e-4f;
        d.length = 1e-4f;
        lights.push_back(d);
    }
    std::vector<Vec3> points = {Vec3(0.0f), Vec3(0, 0, 1e-30f), Vec3(0, 0, -1e-30f), Vec3(5e-5f, 0, 0),
                                Vec3(1e-4f, 0, 0), Vec3(0, 1e-4f, 0), Vec3(1e5f, 0, 0), Vec3(0, 0, -1)};
    SceneBounds bounds;
    bounds.center = Vec3(0.0f);
    bounds.radius = 1;
    for (const LightDesc& d : lights) {
        std::string warning;
        auto light = createLight(d, warning);
        ASSERT_TRUE(light) << d.kind << ": " << warning;
        light->preprocess(bounds);
        Sampler sampler(3);
        for (const Vec3& p : points)
            for (int i = 0; i < 32; ++i) {
                sampler.start(i, 1, 0);
                LightSample ls = light->sample(p, sampler.get2D(), 0);
                ASSERT_TRUE(std::isfinite(ls.pdf) && ls.pdf >= 0) << d.kind << " pdf " << ls.pdf;
                ASSERT_TRUE(finiteNonNegative(ls.Li)) << d.kind;
                if (ls.pdf > 0 && !ls.delta) {
                    ASSERT_TRUE(isFinite(ls.wi)) << d.kind;
                    EXPECT_TRUE(std::isfinite(maxComponent(ls.Li) / ls.pdf)) << d.kind << " Li/pdf overflows";
                }
                float pdf = light->pdf(p, ls.wi, ls.distance, 0);
                ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0) << d.kind;
            }
        auto emission = light->emit(Vec2(0.3f, 0.7f), Vec2(0.5f, 0.5f), bounds, 0.5f);
        EXPECT_TRUE(finiteNonNegative(emission.power) && isFinite(emission.ray.o) && isFinite(emission.ray.d)) << d.kind;
    }
}
