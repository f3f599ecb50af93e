// Scene::reuseBvhOf: consecutive scenes build only the BVHs of what changed, and render exactly
// what the same scene built alone renders.
#include <gtest/gtest.h>

#include <memory>

#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

constexpr size_t kStaticTriangles = 2 + 2 + 2;  // floor, back wall, the prototype's quad
constexpr size_t kBoxTriangles = 2;

// Frame `frame` of a small animation: a floor, a back wall and two instances of a prototype stay
// put; a quad ("/Box") rises with the frame; `floorY` moves the floor without renaming it.
std::unique_ptr<Scene> frameScene(int frame, float floorY = 0, const Scene* previous = nullptr) {
    auto s = std::make_unique<Scene>();
    if (previous) s->reuseBvhOf(*previous);
    int white = s->addMaterial(lambert(Color(0.7f)));
    int red = s->addMaterial(lambert(Color(0.7f, 0.2f, 0.2f)));
    addQuad(*s, "/Floor", {-2, floorY, -2}, {-2, floorY, 2}, {2, floorY, 2}, {2, floorY, -2}, white);
    addQuad(*s, "/Wall", {-2, 0, -2}, {2, 0, -2}, {2, 3, -2}, {-2, 3, -2}, white);
    int proto = s->addPrototype("/Rock");
    s->addMesh("/Rock/Quad", {{-0.2f, 0, -0.2f}, {-0.2f, 0, 0.2f}, {0.2f, 0, 0.2f}, {0.2f, 0, -0.2f}},
               {0, 1, 2, 0, 2, 3}, {}, {}, red, nullptr, true, proto);
    for (int i = 0; i < 2; ++i) {
        Mat4 m;
        m.m[3][0] = -1.0 + 2.0 * i, m.m[3][1] = 0.05;
        s->addInstance(proto, m, "/Rock" + std::to_string(i));
    }
    float y = 0.5f + 0.25f * float(frame);
    addQuad(*s, "/Box", {-0.5f, y, -0.5f}, {-0.5f, y, 0.5f}, {0.5f, y, 0.5f}, {0.5f, y, -0.5f}, red);
    s->addLight(sphereLight("/Light", {0, 2.5f, 1}, 0.3f, 40));
    s->setCamera(lookingDown({0, 4, 0}, false, 36));
    return s;
}

std::vector<float> image(Scene& s) { return renderImage(s, "path", 24, 4); }

}  // namespace

TEST(SceneReuse, BuildsOnlyWhatMovedAndRendersAsTheSceneBuiltAlone) {
    auto first = frameScene(0);
    first->commit();
    EXPECT_EQ(first->stats().primitivesReused, 0u);  // a scene built alone builds everything
    EXPECT_EQ(first->stats().primitivesBuilt, kStaticTriangles + kBoxTriangles);
    auto second = frameScene(1, 0, first.get());
    second->commit();
    // Frame 2 gathers what did not move into the static BVH (built once); the prototype is kept.
    EXPECT_EQ(second->stats().primitivesBuilt, kStaticTriangles - 2 + kBoxTriangles);
    EXPECT_EQ(second->stats().primitivesReused, 2u);
    first.reset();  // the BVHs taken outlive the scene they came from
    auto third = frameScene(2, 0, second.get());
    third->commit();
    EXPECT_EQ(third->stats().primitivesBuilt, kBoxTriangles);
    EXPECT_EQ(third->stats().primitivesReused, kStaticTriangles);
    EXPECT_EQ(third->stats().triangles, kStaticTriangles + kBoxTriangles);

    auto alone = frameScene(2);
    EXPECT_EQ(image(*third), image(*alone));
    // A hit in the static BVH is the top-level shape it is in the scene built alone.
    RayStats st;
    Ray down{Vec3(1.5f, 1, 1.5f), Vec3(0, -1, 0), 0, kInf};
    Intersection reused = third->intersect(down, st), built = alone->intersect(down, st);
    ASSERT_EQ(reused.kind, Intersection::Kind::Surface);
    EXPECT_EQ(third->shapeName(reused.si.shapeId), "/Floor");
    EXPECT_EQ(reused.si.shapeId, built.si.shapeId);
    EXPECT_EQ(reused.si.instanceId, built.si.instanceId);
    EXPECT_EQ(reused.si.primId, built.si.primId);
}

TEST(SceneReuse, AShapeEditedUnderTheSameNameIsRebuilt) {
    auto first = frameScene(0);
    first->commit();
    auto second = frameScene(0, 0, first.get());
    second->commit();
    EXPECT_EQ(second->stats().primitivesBuilt, kStaticTriangles - 2 + kBoxTriangles);  // the static BVH
    // The floor moves down: the static BVH it was in is rebuilt without it, the floor is built.
    auto third = frameScene(0, -0.5f, second.get());
    third->commit();
    EXPECT_EQ(third->stats().primitivesBuilt, kStaticTriangles - 2 + kBoxTriangles);
    RayStats st;
    Intersection hit = third->intersect(Ray{Vec3(1.5f, 1, 1.5f), Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    EXPECT_NEAR(hit.si.p.y, -0.5f, 1e-5f);
    auto alone = frameScene(0, -0.5f);
    EXPECT_EQ(image(*third), image(*alone));
    // It stays down: the static BVH is kept, and the floor, having moved once, stays in the top
    // level (rebuilt with it at each commit, as the instances are).
    auto fourth = frameScene(0, -0.5f, third.get());
    fourth->commit();
    EXPECT_EQ(fourth->stats().primitivesBuilt, 2u);
    EXPECT_EQ(fourth->stats().primitivesReused, kStaticTriangles + kBoxTriangles - 2);
}

TEST(SceneReuse, SharedNamesAndMovingShapesAreAlwaysBuilt) {
    auto build = [](const Scene* previous) {
        auto s = std::make_unique<Scene>();
        if (previous) s->reuseBvhOf(*previous);
        int m = s->addMaterial(lambert(Color(0.5f)));
        addQuad(*s, "/Same", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, m);
        addQuad(*s, "/Same", {-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, m);  // a second shape, same name
        MotionSteps motion;
        Mat4 open, close;
        close.m[3][0] = 0.5;
        motion.transforms = {open, close};
        s->addSphere("/Moving", Vec3(0, 2, 0), 0.5f, m, nullptr, -1, motion);
        s->commit();
        return s;
    };
    auto first = build(nullptr);
    auto second = build(first.get());
    auto third = build(second.get());
    EXPECT_EQ(third->stats().primitivesBuilt, 2u + 2u + 1u);
    EXPECT_EQ(third->stats().primitivesReused, 0u);
    EXPECT_EQ(third->stats().movingShapes, 1u);
}
