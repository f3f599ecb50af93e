// Motion geometry: a moving shape is hit where it is at the ray's time, with the hit point and
// normal of that time; a host's uneven motion samples become even steps; bad motion is warned about.
#include <gtest/gtest.h>

#include "renderer/motion.h"
#include "renderer/scene.h"

using namespace gi;

namespace {

Mat4 translation(float x) {
    Mat4 m;
    m.m[3][0] = x;
    return m;
}

// A ray down -z through (x, 0) at `time`.
Intersection shoot(const Scene& s, float x, float time) {
    Ray ray{Vec3(x, 0, 10), Vec3(0, 0, -1), 0, kInf};
    ray.time = time;
    RayStats stats;
    return s.intersect(ray, stats);
}

}  // namespace

// A unit sphere moving from x = -2 (shutter open) to x = +2 (close) with 3 steps: at time t it is
// at x = 4t - 2, and the hit point lies on it there (the ray along z hits its top at z = 1).
TEST(Motion, MovingSphereIsHitWhereItIsAtTheRaysTime) {
    Scene s;
    MotionSteps motion;
    motion.transforms = {translation(-2), translation(0), translation(2)};
    ASSERT_GE(s.addSphere("/Ball", Vec3(0.0f), 1, -1, &motion.transforms[0], -1, motion), 0);
    s.commit();
    EXPECT_EQ(s.stats().movingShapes, 1u);
    for (float t : {0.0f, 0.3f, 0.5f, 0.85f, 1.0f}) {
        float centre = 4 * t - 2;
        Intersection hit = shoot(s, centre, t);
        ASSERT_EQ(hit.kind, Intersection::Kind::Surface) << t;
        EXPECT_NEAR(hit.si.p.x, centre, 1e-4f) << t;
        EXPECT_NEAR(hit.si.p.z, 1, 1e-4f) << t;
        EXPECT_NEAR(hit.si.ng.z, 1, 1e-4f) << t;
        EXPECT_EQ(hit.si.time, t);
        EXPECT_EQ(shoot(s, centre + 1.5f, t).kind, Intersection::Kind::None) << t;  // beside it at that time
    }
}

// A deforming triangle mesh and a moving instance: hit points and normals follow the geometry.
TEST(Motion, DeformingMeshAndMovingInstanceFollowTheirSteps) {
    Scene s;
    std::vector<Vec3> quad = {{-0.5f, -5, 0}, {0.5f, -5, 0}, {0.5f, 5, 0}, {-0.5f, 5, 0}};
    std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
    MotionSteps deformation;
    for (float dx : {-2.0f, 2.0f}) {
        std::vector<Vec3> step = quad;
        for (Vec3& p : step) p = p + Vec3(dx, 0, float(dx > 0));  // and up by 1 at shutter close
        deformation.points.push_back(step);
    }
    ASSERT_GE(s.addMesh("/Deforming", quad, indices, {}, {}, -1, nullptr, true, -1, deformation), 0);
    int prototype = s.addPrototype("/Proto");
    ASSERT_GE(s.addMesh("/Proto/Quad", quad, indices, {}, {}, -1, nullptr, true, prototype), 0);
    MotionSteps instanceMotion;
    instanceMotion.transforms = {translation(10), translation(14)};
    ASSERT_GE(s.addInstance(prototype, instanceMotion.transforms[0], "/Instance", instanceMotion), 0);
    s.commit();
    EXPECT_EQ(s.stats().movingShapes, 1u);
    EXPECT_EQ(s.stats().movingInstances, 1u);
    for (float t : {0.0f, 0.25f, 0.75f, 1.0f}) {
        Intersection deforming = shoot(s, -2 + 4 * t, t);
        ASSERT_EQ(deforming.kind, Intersection::Kind::Surface) << t;
        EXPECT_NEAR(deforming.si.p.z, t, 1e-4f) << t;
        EXPECT_EQ(shoot(s, -2 + 4 * t + 0.75f, t).kind, Intersection::Kind::None) << t;
        Intersection instance = shoot(s, 10 + 4 * t, t);
        ASSERT_EQ(instance.kind, Intersection::Kind::Surface) << t;
        EXPECT_NEAR(instance.si.p.x, 10 + 4 * t, 1e-4f) << t;
        EXPECT_EQ(shoot(s, 10 + 4 * t + 0.75f, t).kind, Intersection::Kind::None) << t;
    }
}

TEST(Motion, StepsThatAreAllEqualBuildStaticGeometry) {
    Scene s;
    MotionSteps still;
    still.transforms = {translation(1), translation(1)};
    s.addSphere("/Still", Vec3(0.0f), 1, -1, &still.transforms[0], -1, still);
    s.commit();
    EXPECT_EQ(s.stats().movingShapes, 0u);
    EXPECT_FALSE(s.hasMotion());
}

TEST(Motion, UnusableMotionIsWarnedAboutNamingThePrim) {
    Scene s;
    std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    MotionSteps wrongCount;
    wrongCount.points = {triangle, {{0, 0, 0}}};
    EXPECT_GE(s.addMesh("/Shrinking", triangle, {0, 1, 2}, {}, {}, -1, nullptr, true, -1, wrongCount), 0);
    MotionSteps singular;
    Mat4 flat;
    flat.m[2][2] = 0;
    singular.transforms = {Mat4(), flat};
    EXPECT_GE(s.addInstance(s.addPrototype("/P"), Mat4(), "/Flattened", singular), -1);
    s.commit();
    std::vector<std::string> w = s.warnings();
    auto warned = [&](const std::string& what) {
        return std::any_of(w.begin(), w.end(), [&](const std::string& m) {
            return m.find(what) != std::string::npos && m.find("without motion blur") != std::string::npos;
        });
    };
    EXPECT_TRUE(warned("/Shrinking"));
    EXPECT_TRUE(warned("/Flattened"));
    EXPECT_EQ(s.stats().movingShapes + s.stats().movingInstances, 0u);
}

TEST(Motion, UnevenHostSamplesBecomeEvenStepsThatKeepThem) {
    // Hydra's samples: the shutter's boundaries and the authored samples between them.
    EXPECT_EQ(evenStepTimes({-0.25f, 0.25f}), (std::vector<float>{-0.25f, 0.25f}));
    EXPECT_EQ(evenStepTimes({-0.25f, 0.0f, 0.25f}), (std::vector<float>{-0.25f, 0.0f, 0.25f}));
    std::vector<float> uneven = evenStepTimes({0.0f, 0.1f, 1.0f});
    ASSERT_EQ(uneven.size(), 11u);  // as fine as the closest pair
    EXPECT_FLOAT_EQ(uneven[1], 0.1f);
    EXPECT_TRUE(evenStepTimes({0.5f}).empty());
    EXPECT_EQ(evenStepTimes({0.0f, 1e-38f, 1e30f}).size(), kMaxMotionSteps);  // capped, and no overflow
    auto lerpFloat = [](float a, float b, float f) { return a + (b - a) * f; };
    EXPECT_FLOAT_EQ(sampleAt<float>({0.0f, 0.1f, 1.0f}, {0.0f, 1.0f, 10.0f}, 0.55f, lerpFloat), 5.5f);
    EXPECT_FLOAT_EQ(sampleAt<float>({0.0f, 1.0f}, {3.0f, 5.0f}, 2.0f, lerpFloat), 5.0f);
}

TEST(Motion, ADeformingMeshWithAnUnusableTransformKeepsItsDeformationAndIsWarnedAboutOnce) {
    Scene s;
    std::vector<Vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<Vec3> shifted = {{1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
    MotionSteps motion;
    motion.points = {triangle, shifted};
    Mat4 flat;
    flat.m[2][2] = 0;
    motion.transforms = {Mat4(), flat};
    EXPECT_GE(s.addMesh("/Deforming", triangle, {0, 1, 2}, {}, {}, -1, nullptr, true, -1, motion), 0);
    s.commit();
    std::vector<std::string> w = s.warnings();
    EXPECT_EQ(std::count_if(w.begin(), w.end(), [](const std::string& m) { return m.find("/Deforming") != std::string::npos; }), 1);
    EXPECT_EQ(s.stats().movingShapes, 1u);
}
