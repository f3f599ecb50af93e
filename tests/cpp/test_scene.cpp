// Scene building: bad input is repaired or dropped with a warning naming the prim; exact
// spheres and instances intersect where they should.
#include <gtest/gtest.h>

#include "renderer/ray_benchmark.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

bool anyWarningContains(const Scene& s, const std::string& a, const std::string& b) {
    for (const std::string& w : s.warnings())
        if (w.find(a) != std::string::npos && w.find(b) != std::string::npos) return true;
    return false;
}

Ray rayDown(Vec3 from) { return Ray{from, Vec3(0, -1, 0), 0, kInf}; }

}  // namespace

TEST(Scene, DropsBadTrianglesWithWarningsNamingThePrim) {
    Scene s;
    float nan = std::nanf("");
    int id = s.addMesh("/World/Broken", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {nan, 0, 0}, {2, 0, 0}},
                       {0, 1, 2, 0, 1, 9, 0, 3, 1, 0, 1, 4}, {}, {}, -1, nullptr, true, -1);
    EXPECT_GE(id, 0);
    EXPECT_TRUE(anyWarningContains(s, "/World/Broken", "out-of-range"));
    EXPECT_TRUE(anyWarningContains(s, "/World/Broken", "NaN"));
    EXPECT_TRUE(anyWarningContains(s, "/World/Broken", "degenerate"));
    s.commit();
    EXPECT_EQ(s.stats().triangles, 1u);
}

TEST(Scene, MeshWithNothingUsableIsIgnored) {
    Scene s;
    EXPECT_EQ(s.addMesh("/Empty", {}, {}, {}, {}, -1, nullptr, true, -1), -1);
    EXPECT_TRUE(anyWarningContains(s, "/Empty", "no valid triangles"));
    s.commit();  // an empty scene still commits and renders black
    RayStats st;
    EXPECT_EQ(s.intersect(rayDown({0, 1, 0}), st).kind, Intersection::Kind::None);
}

TEST(Scene, ExactSphereHitAndNormal) {
    Scene s;
    s.addSphere("/Sphere", {0, -0.6f, 0}, 0.4f, -1, nullptr, -1);
    s.commit();
    RayStats st;
    Intersection hit = s.intersect(rayDown({0.1f, 5, 0}), st);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    float expectedY = -0.6f + std::sqrt(0.16f - 0.01f);
    EXPECT_NEAR(hit.si.p.y, expectedY, 1e-5f);
    EXPECT_NEAR(length(hit.si.ng), 1.0f, 1e-5f);
    EXPECT_NEAR(hit.si.ng.x, 0.1f / 0.4f, 1e-4f);
}

// Up to Scene::kDirectSpheres static spheres are tested beside the BVH, more go into it as user
// geometry: both ways give the same hits, bit for bit, and the same shadow-ray answers.
TEST(Scene, AFewSpheresBesideTheBvhHitAsInIt) {
    auto build = [](int extraSpheres) {
        auto s = std::make_unique<Scene>();
        addQuad(*s, "/Floor", {-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, -1);
        s->addSphere("/Ball", {0.2f, 0.5f, -0.1f}, 0.45f, -1, nullptr, -1);
        for (int i = 0; i < extraSpheres; ++i)  // far from every ray below
            s->addSphere("/Far" + std::to_string(i), {50.0f + 3 * float(i), 50, 50}, 1, -1, nullptr, -1);
        s->commit();
        return s;
    };
    auto beside = build(0), inside = build(int(Scene::kDirectSpheres));
    EXPECT_EQ(beside->stats().primitivesBuilt, 2u);  // the floor: the ball is not in the BVH
    EXPECT_EQ(inside->stats().primitivesBuilt, 2u + 1u + Scene::kDirectSpheres);
    Sampler sampler(7);
    RayStats st;
    int ballHits = 0, blocked = 0;
    for (uint32_t i = 0; i < 4000; ++i) {
        sampler.startStream(0, i);
        Vec2 u = sampler.get2D();
        // Origins around and inside the ball, directions everywhere; some rays start past the
        // ball's near side (tMin), and shadow rays end before, inside or past it.
        Ray ray{Vec3(-0.6f + 1.6f * u.x, 0.05f + 1.2f * u.y, -0.9f + 1.6f * sampler.get1D()),
                sampleUniformSphere(sampler.get2D()), 0, kInf};
        if (i % 3 == 0) ray.tMin = 0.5f * sampler.get1D();
        Intersection a = beside->intersect(ray, st), b = inside->intersect(ray, st);
        ASSERT_EQ(a.kind, b.kind) << i;
        if (a.kind == Intersection::Kind::Surface) {
            ballHits += beside->shapeName(a.si.shapeId) == "/Ball";
            EXPECT_EQ(beside->shapeName(a.si.shapeId), inside->shapeName(b.si.shapeId)) << i;
            EXPECT_EQ(a.t, b.t) << i;
            EXPECT_TRUE(a.si.p.x == b.si.p.x && a.si.p.y == b.si.p.y && a.si.p.z == b.si.p.z) << i;
            EXPECT_TRUE(a.si.ng.x == b.si.ng.x && a.si.ng.y == b.si.ng.y && a.si.ng.z == b.si.ng.z) << i;
        }
        float distance = 1.5f * sampler.get1D();
        bool occludedBeside = beside->occluded(ray.o, ray.d, distance, st);
        EXPECT_EQ(occludedBeside, inside->occluded(ray.o, ray.d, distance, st)) << i;
        blocked += occludedBeside;
    }
    EXPECT_GT(ballHits, 600);  // 819 of the 4,000 rays meet the ball first, 1,149 shadow rays are blocked
    EXPECT_GT(blocked, 800);
}

TEST(Scene, InstancesShareOnePrototype) {
    Scene s;
    int proto = s.addPrototype("/Proto");
    s.addMesh("/Proto/Quad", {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, {0, 1, 2, 0, 2, 3}, {}, {}, -1,
              nullptr, true, proto);
    for (int i = 0; i < 3; ++i) {
        Mat4 m;
        m.m[3][0] = 10.0 * i;
        m.m[0][0] = m.m[2][2] = 0.5;  // scaled: the hit normal must stay unit length
        s.addInstance(proto, m, "/Instance" + std::to_string(i));
    }
    s.commit();
    EXPECT_EQ(s.stats().triangles, 2u);  // geometry stored once
    EXPECT_EQ(s.stats().instances, 3u);
    RayStats st;
    Intersection hit = s.intersect(rayDown({20.2f, 1, 0.2f}), st);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    EXPECT_EQ(hit.si.instanceId, 2u);
    EXPECT_NEAR(hit.si.p.y, 0.0f, 1e-5f);
    EXPECT_NEAR(std::fabs(hit.si.ng.y), 1.0f, 1e-5f);
    EXPECT_EQ(s.intersect(rayDown({20.8f, 1, 0}), st).kind, Intersection::Kind::None);  // outside the scaled quad
}

TEST(Scene, BadLightsAreIgnoredWithWarnings) {
    Scene s;
    LightDesc zero;
    zero.name = "/Lights/Zero";
    zero.intensity = 0;
    s.addLight(zero);
    LightDesc nanLight;
    nanLight.name = "/Lights/NaN";
    nanLight.width = std::nanf("");
    s.addLight(nanLight);
    LightDesc flat;
    flat.name = "/Lights/Flat";
    flat.width = 0;
    s.addLight(flat);
    s.commit();
    EXPECT_TRUE(s.lights().empty());
    EXPECT_TRUE(anyWarningContains(s, "/Lights/Zero", "intensity"));
    EXPECT_TRUE(anyWarningContains(s, "/Lights/NaN", "NaN"));
    EXPECT_TRUE(anyWarningContains(s, "/Lights/Flat", "zero area"));
}

TEST(Scene, MissingTextureWarnsNamingMaterialAndFile) {
    Scene s;
    MaterialDesc m = lambert(Color(0.5f));
    m.name = "/Looks/Brick";
    m.diffuseColorTexture.file = "/nonexistent/brick.png";
    int id = s.addMaterial(m);
    addQuad(s, "/Wall", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, id);
    s.commit();
    EXPECT_TRUE(anyWarningContains(s, "/Looks/Brick", "/nonexistent/brick.png"));
}

TEST(Scene, UnusedMaterialsReadNoTextures) {
    Scene s;
    MaterialDesc m = lambert(Color(0.5f));
    m.name = "/Looks/Unused";
    m.diffuseColorTexture.file = "/nonexistent/unused.png";
    s.addMaterial(m);
    s.commit();
    EXPECT_FALSE(anyWarningContains(s, "/Looks/Unused", "unused.png"));
    EXPECT_EQ(s.stats().textures, 0u);
}

TEST(Scene, FarFromOriginDoesNotSelfIntersect) {
    Scene s;
    const float far = 1e5f;
    int m = s.addMaterial(lambert(Color(0.5f)));
    addQuad(s, "/Far", {far - 1, 0, -1}, {far - 1, 0, 1}, {far + 1, 0, 1}, {far + 1, 0, -1}, m);
    s.commit();
    RayStats st;
    Intersection hit = s.intersect(rayDown({far + 0.3f, 1, 0.1f}), st);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    // A ray leaving the surface upwards must not hit the surface it starts on.
    Vec3 o = offsetRayOrigin(hit.si.p, hit.si.ng, Vec3(0, 1, 0));
    EXPECT_EQ(s.intersect(Ray{o, Vec3(0, 1, 0), 0, kInf}, st).kind, Intersection::Kind::None);
}

// bench/rays.py's "Embree share": the recording render records every ray the timed render
// counted, and Embree alone casts them all.
TEST(RayReplay, RecordsEveryRayTheRenderCasts) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.7f)));
    addQuad(scene, "/Floor", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, white);
    addQuad(scene, "/Wall", {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, white);
    // A sphere: its geometry (sphere_geometry.h) then answers 8-wide packets too.
    scene.addSphere("/Ball", {0.3f, 0.3f, 0}, 0.3f, white, nullptr, -1);
    scene.addLight(sphereLight("/Light", {0, 1.5f, 0}, 0.2f, 5));
    scene.setCamera(lookingDown({0, 3, 0.5f}, false, 30));
    scene.commit();
    RenderSettings settings;
    settings.width = settings.height = 16;
    settings.spp = 4;
    RenderReplayResult r = replayRenderRays(scene, settings);
    EXPECT_GT(r.render.rays, uint64_t(16 * 16 * 4));  // camera rays and more
    EXPECT_EQ(r.replay.rays, r.render.rays);
    EXPECT_GT(r.replay.hits, 0u);
    EXPECT_LT(r.replay.hits, r.replay.rays);  // some shadow rays reach the light, some rays escape
    EXPECT_GT(r.replay.seconds, 0);
    // Reordered into waves, one by one or as packets, the same rays find the same hits.
    for (RayReplay order : {RayReplay::Wavefront, RayReplay::WavefrontPackets8}) {
        RenderReplayResult w = replayRenderRays(scene, settings, order);
        EXPECT_EQ(w.replay.rays, r.replay.rays);
        EXPECT_EQ(w.replay.hits, r.replay.hits);
    }
}

// bench/rays.py's baseline: every ray of its pool is a real ray. Cast from inside a closed box,
// every one hits (a pool left mostly unfilled, zero directions, hit almost nothing).
TEST(RayBenchmark, EveryIncoherentRayIsCast) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.7f)));
    addQuad(scene, "/Floor", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, white);
    addQuad(scene, "/Ceiling", {-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}, white);
    addQuad(scene, "/Back", {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, white);
    addQuad(scene, "/Front", {-1, 0, 1}, {-1, 2, 1}, {1, 2, 1}, {1, 0, 1}, white);
    addQuad(scene, "/Left", {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}, {-1, 0, 1}, white);
    addQuad(scene, "/Right", {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, white);
    scene.setCamera(lookingDown({0, 1.5f, 0}, false, 30));
    scene.commit();
    RayBenchmarkResult r = castIncoherentRays(scene, 20000, 1, 2);
    EXPECT_EQ(r.rays, 20000u);
    EXPECT_GE(r.hits, r.rays - r.rays / 1000);  // origins on a wall may leave through it
}

// From inside, a sphere's far side (glass: the ray refracted in); a ray starting past its near
// crossing hits the far one; a grazing ray beside it misses; shadow rays stop at it.
TEST(Scene, SphereFromInsideAndGrazing) {
    Scene s;
    s.addSphere("/Sphere", {0, 0, 0}, 0.5f, -1, nullptr, -1);
    s.commit();
    RayStats st;
    Intersection inside = s.intersect(Ray{Vec3(0.1f, 0, 0), Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(inside.kind, Intersection::Kind::Surface);
    EXPECT_NEAR(inside.si.p.y, -std::sqrt(0.25f - 0.01f), 1e-5f);
    EXPECT_NEAR(inside.t, std::sqrt(0.25f - 0.01f), 1e-5f);
    Intersection pastNear = s.intersect(Ray{Vec3(0, 2, 0), Vec3(0, -1, 0), 1.6f, kInf}, st);
    ASSERT_EQ(pastNear.kind, Intersection::Kind::Surface);
    EXPECT_NEAR(pastNear.t, 2.5f, 1e-5f);
    EXPECT_EQ(s.intersect(Ray{Vec3(0.5001f, 2, 0), Vec3(0, -1, 0), 0, kInf}, st).kind, Intersection::Kind::None);
    EXPECT_TRUE(s.occluded(Vec3(0, 2, 0), Vec3(0, -1, 0), 1.6f, st));
    EXPECT_FALSE(s.occluded(Vec3(0, 2, 0), Vec3(0, -1, 0), 1.4f, st));
    EXPECT_FALSE(s.occluded(Vec3(0.5001f, 2, 0), Vec3(0, -1, 0), 4, st));
}

TEST(Scene, ASceneThatEmitsNothingSaysItRendersBlack) {
    auto build = [](bool light, bool emissive) {
        auto s = std::make_unique<Scene>();
        int m = s->addMaterial(lambert(Color(0.5f), emissive ? Color(1.0f) : Color(0.0f)));
        addQuad(*s, "/Floor", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, m);
        if (light) s->addLight(sphereLight("/Lamp", {0, 1, 0}, 0.1f, 10));
        s->commit();
        return s;
    };
    EXPECT_TRUE(anyWarningContains(*build(false, false), "no lights and no emissive surfaces", "black"));
    EXPECT_FALSE(anyWarningContains(*build(true, false), "no lights", "black"));
    EXPECT_FALSE(anyWarningContains(*build(false, true), "no lights", "black"));
}
