// Each UsdLux light type against its analytic irradiance at a point on a Lambertian floor
// (pixel value = albedo/pi * E), and light sampling against BSDF sampling for the others.
#include <gtest/gtest.h>

#include <random>

#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

constexpr float kAlbedo = 0.5f;

// Renders a tiny orthographic window around the origin of a floor at y = 0.
double floorValue(LightDesc light, const char* integrator, int spp, std::map<std::string, double> params = {}) {
    Scene scene;
    int m = scene.addMaterial(lambert(Color(kAlbedo)));
    addQuad(scene, "/Floor", {-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, m);
    scene.addLight(light);
    scene.setCamera(lookingDown({0, 0.05f, 0}, true, 0.01f));
    return channelMean(renderImage(scene, integrator, 4, spp, params), 1);
}

Mat4 translateY(float y) {
    Mat4 m;
    m.m[3][1] = y;
    return m;
}

Mat4 facingDown(float y) {  // rotate -90 degrees about X: local -Z -> world -Y
    Mat4 m = translateY(y);
    m.m[1][1] = 0, m.m[1][2] = -1, m.m[2][1] = 1, m.m[2][2] = 0;
    return m;
}

}  // namespace

TEST(Lights, SphereLightIrradiance) {
    LightDesc l = sphereLight("/Sphere", {0, 1.5f, 0}, 0.3f, 2);
    double sinAlpha = 0.3 / 1.5;
    double expected = kAlbedo / kPi * kPi * 2 * sinAlpha * sinAlpha;
    EXPECT_NEAR(floorValue(l, "direct", 256, {{"lightSamples", 4}}), expected, 0.005 * expected);
}

TEST(Lights, DiskLightIrradiance) {
    LightDesc l;
    l.name = "/Disk";
    l.kind = "disk";
    l.radius = 0.5f;
    l.intensity = 3;
    l.transform = facingDown(1.0f);
    double expected = kAlbedo / kPi * kPi * 3 * 0.25 / (0.25 + 1.0);
    EXPECT_NEAR(floorValue(l, "direct", 256, {{"lightSamples", 4}}), expected, 0.005 * expected);
}

TEST(Lights, NormalizedLightKeepsPowerWhenResized) {
    LightDesc small;
    small.name = "/Rect";
    small.kind = "rect";
    small.normalize = true;
    small.width = small.height = 0.1f;
    small.intensity = 1;
    small.transform = facingDown(3.0f);
    LightDesc big = small;
    big.width = big.height = 0.2f;
    double a = floorValue(small, "direct", 64), b = floorValue(big, "direct", 64);
    EXPECT_NEAR(a, b, 0.01 * a);  // far away, the same power gives (almost) the same irradiance
}

TEST(Lights, ConstantDomeGivesPiL) {
    LightDesc l;
    l.name = "/Dome";
    l.kind = "dome";
    l.intensity = 0.7f;
    double expected = kAlbedo * 0.7;  // albedo/pi * (pi L)
    EXPECT_NEAR(floorValue(l, "path", 512, {{"pathDepth", 1}}), expected, 0.01 * expected);
}

TEST(Lights, NormalizedDistantLightKeepsItsIrradiance) {
    LightDesc l;
    l.name = "/Sun";
    l.kind = "distant";
    l.angle = 10;  // degrees: a wide normalized sun still delivers `intensity` at normal incidence
    l.intensity = 2;
    l.normalize = true;
    l.transform = facingDown(0);
    // The cone's radiance is E / (pi sin^2(half angle)), whose cosine-weighted integral is E again.
    double expected = kAlbedo / kPi * 2;
    EXPECT_NEAR(floorValue(l, "direct", 256), expected, 0.005 * expected);
}

TEST(Lights, DistantLightIntensityIsTheRadianceOfItsDisc) {
    LightDesc l;
    l.name = "/Sun";
    l.kind = "distant";
    l.angle = 10;
    l.intensity = 2;  // radiance; irradiance = 2 * pi sin^2(5 degrees)
    l.transform = facingDown(0);
    double s = std::sin(5 * kPi / 180);
    double expected = kAlbedo / kPi * 2 * kPi * s * s;
    EXPECT_NEAR(floorValue(l, "direct", 256), expected, 0.005 * expected);
}

// Light sampling (direct) and BSDF sampling with MIS (path, one bounce) estimate the same
// integral; agreement checks each light's sample(), pdf() and radiance() together.
TEST(Lights, CylinderLightSamplingAgreesWithBsdfSampling) {
    LightDesc l;
    l.name = "/Tube";
    l.kind = "cylinder";
    l.radius = 0.1f;
    l.length = 1.0f;
    l.intensity = 4;
    l.transform = translateY(0.7f);
    double viaLights = floorValue(l, "direct", 1024, {{"lightSamples", 4}});
    double viaPaths = floorValue(l, "path", 2048, {{"pathDepth", 1}});
    EXPECT_GT(viaLights, 0);
    EXPECT_NEAR(viaLights, viaPaths, 0.02 * viaLights);
}

TEST(Camera, ThinLensFocusesAtFocusDistance) {
    CameraDesc c;
    c.focalLength = 50;
    c.horizontalAperture = c.verticalAperture = 36;
    c.fStop = 2;
    c.focusDistance = 4;
    Camera camera(c, 64, 64);
    // Every lens sample of the centre pixel passes through the same point on the focus plane.
    for (Vec2 lens : {Vec2(0.1f, 0.2f), Vec2(0.9f, 0.5f), Vec2(0.4f, 0.8f)}) {
        Ray r = camera.generateRay(32, 32, lens);
        float t = -4.0f / r.d.z;
        Vec3 p = r.o + r.d * t;
        EXPECT_NEAR(p.x, 0, 1e-4f);
        EXPECT_NEAR(p.y, 0, 1e-4f);
    }
    Ray a = camera.generateRay(32, 32, Vec2(0.1f, 0.2f)), b = camera.generateRay(32, 32, Vec2(0.9f, 0.5f));
    EXPECT_GT(length(a.o - b.o), 1e-3f);  // the lens has an aperture (f/2 at 50 mm = 1.25 units)
}

TEST(Camera, OrthographicRaysAreParallelAndApertureSized) {
    CameraDesc c;
    c.projection = "orthographic";
    c.horizontalAperture = c.verticalAperture = 20;  // tenths of a unit: a 2x2 window
    Camera camera(c, 10, 10);
    Ray left = camera.generateRay(0, 5, Vec2()), right = camera.generateRay(10, 5, Vec2());
    EXPECT_NEAR(right.o.x - left.o.x, 2.0f, 1e-5f);
    EXPECT_NEAR(dot(left.d, right.d), 1.0f, 1e-6f);
}

TEST(Camera, PerspectiveMatchesTheCornellSpec) {
    CameraDesc c;
    c.focalLength = 50;
    c.horizontalAperture = c.verticalAperture = 35.71429f;
    Camera camera(c, 512, 512);
    Ray r = camera.generateRay(0, 0, Vec2());  // the top-left corner of the film
    EXPECT_NEAR(r.d.x / -r.d.z, -0.357143f, 1e-5f);
    EXPECT_NEAR(r.d.y / -r.d.z, 0.357143f, 1e-5f);
}

namespace {

// Twelve lights of every analytic kind in a 4 x 3 grid on the plane y = 0, facing a camera above;
// `only` >= 0 keeps just that one. The third is hidden from the camera.
void addLightGrid(Scene& scene, int only) {
    const char* kinds[] = {"rect", "disk", "sphere", "cylinder"};
    for (int i = 0; i < 12; ++i) {
        if (only >= 0 && i != only) continue;
        LightDesc d;
        d.name = "/Light" + std::to_string(i);
        d.kind = kinds[i % 4];
        d.color = Color(0.2f + 0.05f * i, 1.0f - 0.05f * i, 0.5f);
        d.width = d.height = 0.8f;
        d.radius = 0.4f;
        d.length = 0.8f;
        d.visibleToCamera = i != 2;
        // Rotate -Z (where rect and disk lights emit) to +Y, towards the camera; then place.
        d.transform.m[1][1] = 0, d.transform.m[1][2] = 1;
        d.transform.m[2][1] = -1, d.transform.m[2][2] = 0;
        d.transform.m[3][0] = -3 + 2.0f * float(i % 4);
        d.transform.m[3][2] = -2 + 2.0f * float(i / 4);
        scene.addLight(d);
    }
    scene.setCamera(lookingDown({0, 10, 0}, true, 90));
}

}  // namespace

// More than a few analytic lights go into a BVH of their own; what a ray hits must not change.
TEST(AnalyticLights, BvhHitsWhatOneByOneTestsHit) {
    Scene all;
    addLightGrid(all, -1);
    std::vector<float> together = renderImage(all, "direct", 48, 4);
    std::vector<double> sum(together.size(), 0.0);
    for (int i = 0; i < 12; ++i) {
        Scene one;
        addLightGrid(one, i);
        std::vector<float> alone = renderImage(one, "direct", 48, 4);
        ASSERT_EQ(alone.size(), sum.size());
        for (size_t k = 0; k < sum.size(); ++k) sum[k] += alone[k];
    }
    double lit = 0;
    for (size_t k = 0; k < sum.size(); ++k) {
        EXPECT_NEAR(together[k], sum[k], 1e-5 * (1 + sum[k])) << "value " << k;
        lit += sum[k] > 0;
    }
    EXPECT_GT(lit, 0.05 * double(sum.size()));  // eleven lights in view, about a tenth of the frame
}

TEST(Lights, RectLightSamplesUniformlyInSolidAngle) {
    // A 2 x 1 rect light seen from beside it (a wall next to a window), from near its edge, sideways
    // and from afar: each sample lands on the rect, its pdf is pdf()'s, and E[1/pdf] is the solid
    // angle the rect subtends, counted independently as the share of uniform sphere directions that
    // hit it. Within a diagonal (sqrt 5) of its centre the samples are uniform in solid angle;
    // farther they are uniform by area (light.cpp's RectLight::near).
    LightDesc d;
    d.name = "/Window";
    d.kind = "rect";
    d.width = 2;
    d.height = 1;
    std::string warning;
    std::unique_ptr<Light> light = createLight(d, warning);  // in the z = 0 plane, emitting towards -z
    ASSERT_TRUE(light) << warning;
    for (Vec3 ref : {Vec3(0.9f, 0.4f, -0.05f), Vec3(1.5f, -1, -0.5f), Vec3(3, -2, -1), Vec3(0.2f, 0.1f, -40)}) {
        const bool near = length(ref) < std::sqrt(5.0f);
        double sumInversePdf = 0, minPdf = kInf, maxPdf = 0;
        const int n = 4096;
        for (int i = 0; i < n; ++i) {
            LightSample ls = light->sample(ref, Vec2((i % 64 + 0.5f) / 64, (i / 64 + 0.5f) / 64), 0);
            ASSERT_GT(ls.pdf, 0) << i;
            Vec3 p = ref + ls.wi * ls.distance;
            ASSERT_NEAR(p.z, 0, 1e-4f);
            ASSERT_LE(std::fabs(p.x), 1 + 1e-4f);
            ASSERT_LE(std::fabs(p.y), 0.5f + 1e-4f);
            ASSERT_NEAR(ls.pdf, light->pdf(ref, ls.wi, ls.distance, 0), 1e-4f * ls.pdf);
            sumInversePdf += 1 / ls.pdf;
            minPdf = std::min(minPdf, double(ls.pdf)), maxPdf = std::max(maxPdf, double(ls.pdf));
        }
        const int directions = 1 << 21;
        int hits = 0;
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> uniform(0, 1);
        for (int i = 0; i < directions; ++i) {
            Ray ray{ref, sampleUniformSphere(Vec2(uniform(rng), uniform(rng))), 0, kInf};
            hits += light->intersect(ray) < kInf;
        }
        double solidAngle = 4 * kPi * hits / directions;
        double sd = 4 * kPi * std::sqrt(double(hits)) / directions;  // binomial, hits << directions
        EXPECT_NEAR(sumInversePdf / n, solidAngle, 4 * sd + 1e-3 * solidAngle) << "from z = " << ref.z;
        if (near) {
            EXPECT_NEAR(minPdf, maxPdf, 1e-4 * maxPdf) << "uniform in solid angle, from z = " << ref.z;
        } else {  // by area: between the density d^2 / (A cos) = d^3 / (A |z|) of the rect's point
                  // nearest to ref and of its farthest corner
            auto density = [&](Vec3 q) { double d = length(q - ref); return d * d * d / (2 * std::fabs(ref.z)); };
            double nearest = density(Vec3(std::clamp(ref.x, -1.0f, 1.0f), std::clamp(ref.y, -0.5f, 0.5f), 0));
            double farthest = 0;
            for (float x : {-1.0f, 1.0f})
                for (float y : {-0.5f, 0.5f}) farthest = std::max(farthest, density(Vec3(x, y, 0)));
            EXPECT_GT(maxPdf, minPdf * (1 + 1e-3)) << "by area, from z = " << ref.z;
            EXPECT_GE(minPdf, 0.999 * nearest) << "from z = " << ref.z;
            EXPECT_LE(maxPdf, 1.001 * farthest) << "from z = " << ref.z;
        }
    }
    // Behind the one-sided light: nothing.
    EXPECT_EQ(light->sample(Vec3(0, 0, 1), Vec2(0.5f, 0.5f), 0).pdf, 0.0f);
    EXPECT_EQ(light->pdf(Vec3(0, 0, 1), Vec3(0, 0, -1), 1, 0), 0.0f);
}
