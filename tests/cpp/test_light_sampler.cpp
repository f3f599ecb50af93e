// Light selection at a shading point (renderer/light_sampler.h): each light is picked with the
// probability pmf() reports, no light that reaches a point is ever left out, and direct light from
// many lights matches Lambert's formula through both light sampling and MIS.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "renderer/light.h"
#include "renderer/light_sampler.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

// A one-sided w x h rect light centred at c, emitting towards n (its local -Z), edges along u.
LightDesc rectFacing(const std::string& name, Vec3 c, Vec3 n, float w, float h, float intensity) {
    n = normalize(n);
    Vec3 u = normalize(std::fabs(n.y) < 0.9f ? cross(Vec3(0, 1, 0), n) : cross(Vec3(1, 0, 0), n));
    Vec3 v = cross(n, u);
    LightDesc l;
    l.name = name;
    l.kind = "rect";
    l.width = w;
    l.height = h;
    l.intensity = intensity;
    Vec3 rows[4] = {u, v, -n, c};
    for (int r = 0; r < 4; ++r) l.transform.m[r][0] = rows[r].x, l.transform.m[r][1] = rows[r].y, l.transform.m[r][2] = rows[r].z;
    return l;
}

struct Lights {
    std::vector<std::unique_ptr<Light>> owned;
    std::vector<const Light*> lights;
    std::vector<float> power;
    void add(const LightDesc& d) {
        std::string warning;
        owned.push_back(createLight(d, warning));
        ASSERT_TRUE(owned.back()) << warning;
        SceneBounds bounds{Vec3(0.0f), 10};
        owned.back()->preprocess(bounds);
        lights.push_back(owned.back().get());
        power.push_back(luminance(owned.back()->power(bounds)));
    }
};

Vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    return normalize(Vec3(g(rng), g(rng), g(rng)));
}

// Thirty rect lights of random place, size, direction and power, a sphere and a disk light, a sun
// and a sky.
Lights manyLights() {
    Lights set;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-4, 4), size(0.1f, 1.5f), power(1, 50);
    for (int i = 0; i < 30; ++i)
        set.add(rectFacing("/Rect" + std::to_string(i), Vec3(pos(rng), pos(rng), pos(rng)), randomUnit(rng), size(rng),
                           size(rng), power(rng)));
    set.add(sphereLight("/Bulb", Vec3(1, 2, -1), 0.2f, 30));
    LightDesc disk;
    disk.name = "/Disk";
    disk.kind = "disk";
    disk.radius = 0.4f;
    disk.intensity = 8;
    set.add(disk);
    LightDesc sun;
    sun.name = "/Sun";
    sun.kind = "distant";
    sun.intensity = 3;
    set.add(sun);
    LightDesc sky;
    sky.name = "/Sky";
    sky.kind = "dome";
    set.add(sky);
    return set;
}

}  // namespace

TEST(LightSampler, PicksEachLightWithThePmfItReports) {
    Lights set = manyLights();
    LightSampler sampler(set.lights, set.power);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> pos(-5, 5);
    constexpr int kDraws = 200000;
    for (int point = 0; point < 20; ++point) {
        Vec3 p(pos(rng), pos(rng), pos(rng));
        std::vector<int> count(set.lights.size(), 0);
        int none = 0;
        for (int i = 0; i < kDraws; ++i) {
            float pmf;
            int light = sampler.sample(p, (i + 0.5f) / kDraws, &pmf);  // stratified: frequencies exact to ~depth / kDraws
            if (light < 0) {
                ++none;
                continue;
            }
            ++count[size_t(light)];
            ASSERT_FLOAT_EQ(pmf, sampler.pmf(p, light)) << "light " << light;
        }
        double total = 0;
        for (size_t light = 0; light < count.size(); ++light) {
            double pmf = sampler.pmf(p, int(light));
            total += pmf;
            // Stratified u: each of the <= 7 levels' cuts moves a count by at most one draw.
            EXPECT_NEAR(double(count[light]) / kDraws, pmf, 8.0 / kDraws) << "light " << light << " point " << point;
        }
        EXPECT_NEAR(total + double(none) / kDraws, 1.0, 1e-3);
    }
}

TEST(LightSampler, NeverLeavesOutALightThatReachesThePoint) {
    Lights set = manyLights();
    LightSampler sampler(set.lights, set.power);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> pos(-6, 6);
    int reaching = 0;
    for (int point = 0; point < 2000; ++point) {
        Vec3 p(pos(rng), pos(rng), pos(rng));
        for (size_t light = 0; light < set.lights.size(); ++light) {
            // A light reaches p when a sample of it can arrive (p in front of a one-sided rect).
            bool reaches = false;
            for (int s = 0; s < 16 && !reaches; ++s) {
                LightSample ls = set.lights[light]->sample(p, Vec2((s % 4 + 0.5f) / 4, (s / 4 + 0.5f) / 4), 0);
                reaches = ls.pdf > 0 && !isBlack(ls.Li);
            }
            if (!reaches) continue;
            ++reaching;
            EXPECT_GT(sampler.pmf(p, int(light)), 0.0f) << "light " << light << " at " << p.x << " " << p.y << " " << p.z;
        }
    }
    EXPECT_GT(reaching, 20000);  // the check saw many pairs
}

TEST(LightSampler, DirectLightFromManyLightsMatchesLambertsFormula) {
    // Eight rect lights on a circle over a floor, half facing the floor's centre and half facing
    // away; the floor's radiance at the centre is albedo / pi * the facing ones' irradiance.
    for (const char* integrator : {"direct", "path"}) {
        Scene scene;
        const float albedo = 0.5f;
        int m = scene.addMaterial(lambert(Color(albedo)));
        addQuad(scene, "/Floor", {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, m);
        double expected = 0;
        for (int k = 0; k < 8; ++k) {
            float angle = float(k) * kPi / 4;
            Vec3 c(1.5f * std::cos(angle), 1.0f + 0.15f * float(k), 1.5f * std::sin(angle));
            Vec3 n = k % 2 == 0 ? -c : c;  // towards the origin, or away
            float intensity = 4.0f + 3.0f * float(k);
            LightDesc d = rectFacing("/Light" + std::to_string(k), c, n, 0.5f, 0.3f, intensity);
            scene.addLight(d);
            if (k % 2) continue;
            Vec3 nn = normalize(n);
            Vec3 u = normalize(std::fabs(nn.y) < 0.9f ? cross(Vec3(0, 1, 0), nn) : cross(Vec3(1, 0, 0), nn));
            Vec3 v = cross(nn, u);
            std::vector<Vec3> corners = {c - u * 0.25f - v * 0.15f, c + u * 0.25f - v * 0.15f, c + u * 0.25f + v * 0.15f,
                                         c - u * 0.25f + v * 0.15f};
            expected += albedo / kPi * polygonIrradiance(corners, Vec3(0, 1, 0), intensity);
        }
        scene.setCamera(lookingDown({0, 0.5f, 0}, true, 0.01f));
        std::vector<float> rgb = renderImage(scene, integrator, 8, 256, takenBy(integrator, {{"pathDepth", 2}}));
        // 64 pixels, each an independent estimate of the same radiance (a 1 mm window).
        double sum = 0, sum2 = 0;
        for (size_t i = 0; i < rgb.size(); i += 3) sum += rgb[i], sum2 += double(rgb[i]) * rgb[i];
        double n = double(rgb.size() / 3), mean = sum / n, stdError = std::sqrt((sum2 / n - mean * mean) / (n - 1));
        EXPECT_LT(stdError, 0.01 * expected) << integrator;  // precise enough to mean something
        EXPECT_NEAR(mean, expected, 4 * stdError + 1e-3 * expected) << integrator;  // 4 sigma; the formula's float sum
    }
}
