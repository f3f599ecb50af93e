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

namespace {

constexpr int kTiles = 6;
// Floor, four walls, the tiles; the ball is tested beside the BVH (Scene::kDirectSpheres), unless
// the room has extra balls.
constexpr size_t kRoomPrimitives = 2 * 5 + 2 * kTiles;

// A room of static shapes alone (no instances): its top level is the next scene's static BVH.
// `raised` lifts one tile by 0.3, `hidden` leaves one out (-1: none); `floorY` moves the floor.
std::unique_ptr<Scene> tiledRoom(const Scene* previous, int raised = -1, int hidden = -1, float floorY = 0,
                                 bool ball = true, Scene::BvhReuse reuse = Scene::BvhReuse::Edits, int extraBalls = 0) {
    auto s = std::make_unique<Scene>();
    if (previous) s->reuseBvhOf(*previous, reuse);
    int white = s->addMaterial(lambert(Color(0.7f)));
    int red = s->addMaterial(lambert(Color(0.7f, 0.2f, 0.2f)));
    addQuad(*s, "/Floor", {-1, floorY, -1}, {-1, floorY, 1}, {1, floorY, 1}, {1, floorY, -1}, white);
    addQuad(*s, "/Back", {-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}, white);
    addQuad(*s, "/Front", {-1, 0, 1}, {-1, 2, 1}, {1, 2, 1}, {1, 0, 1}, white);
    addQuad(*s, "/Left", {-1, 0, -1}, {-1, 2, -1}, {-1, 2, 1}, {-1, 0, 1}, red);
    addQuad(*s, "/Right", {1, 0, -1}, {1, 0, 1}, {1, 2, 1}, {1, 2, -1}, red);
    for (int t = 0; t < kTiles; ++t) {
        if (t == hidden) continue;
        float x = -0.9f + 0.22f * float(t), y = 0.05f + (t == raised ? 0.3f : 0.0f);
        const std::string name = "/Tile" + std::to_string(t);
        addQuad(*s, name.c_str(), {x, y, -0.1f}, {x, y, 0.1f}, {x + 0.15f, y, 0.1f}, {x + 0.15f, y, -0.1f}, red);
    }
    if (ball) s->addSphere("/Ball", Vec3(0.3f, 0.4f, 0.4f), 0.25f, white, nullptr, -1);
    for (int b = 0; b < extraBalls; ++b)  // small, in a corner by the back wall
        s->addSphere("/Extra" + std::to_string(b), Vec3(-0.9f + 0.1f * float(b), 0.05f, -0.9f), 0.04f, red, nullptr, -1);
    s->addLight(sphereLight("/Light", {0, 1.7f, 0}, 0.2f, 30));
    s->setCamera(lookingDown({0, 1.9f, 0}, false, 70));
    return s;
}

// The scene built after `previous` renders, and bounds itself, as the same scene built alone.
void expectAsBuiltAlone(Scene& reused, Scene& alone) {
    for (auto bound : {&Scene::boundsMin, &Scene::boundsMax}) {
        Vec3 a = (reused.*bound)(), b = (alone.*bound)();
        EXPECT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z);
    }
    EXPECT_EQ(image(reused), image(alone));
    EXPECT_EQ(renderImage(reused, "progressivePhotonMap", 16, 2), renderImage(alone, "progressivePhotonMap", 16, 2));
}

}  // namespace

TEST(SceneReuse, AnEditBuildsOnlyWhatChangedAndMasksItsOldSelf) {
    auto first = tiledRoom(nullptr);
    first->commit();
    EXPECT_EQ(first->stats().primitivesBuilt, kRoomPrimitives);
    // The first edit: the previous top level becomes the static BVH, the raised tile's old self
    // masked in it; only the tile is built.
    auto second = tiledRoom(first.get(), 3);
    second->commit();
    EXPECT_EQ(second->stats().primitivesBuilt, 2u);
    EXPECT_EQ(second->stats().primitivesReused, kRoomPrimitives - 2);
    EXPECT_EQ(second->stats().primitivesMasked, 2u);
    first.reset();  // the BVH taken outlives the scene it came from
    auto alone = tiledRoom(nullptr, 3);
    alone->commit();
    expectAsBuiltAlone(*second, *alone);
    // Hiding another tile builds nothing new but the raised tile (in the top level); a ray where
    // the hidden tile was reaches the floor.
    auto third = tiledRoom(second.get(), 3, 5);
    third->commit();
    EXPECT_EQ(third->stats().primitivesBuilt, 2u);
    EXPECT_EQ(third->stats().primitivesMasked, 4u);
    RayStats st;
    const float x5 = -0.9f + 0.22f * 5 + 0.07f;
    Intersection hit = third->intersect(Ray{Vec3(x5, 1, 0), Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(hit.kind, Intersection::Kind::Surface);
    EXPECT_EQ(third->shapeName(hit.si.shapeId), "/Floor");
    Intersection occluder = third->intersect(Ray{Vec3(x5 - 0.22f, 1, 0), Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(occluder.kind, Intersection::Kind::Surface);
    EXPECT_EQ(third->shapeName(occluder.si.shapeId), "/Tile4");
    EXPECT_FALSE(third->occluded(Vec3(x5, 1, 0), Vec3(0, -1, 0), 0.98f, st));  // only the floor, 1 below
    auto thirdAlone = tiledRoom(nullptr, 3, 5);
    thirdAlone->commit();
    expectAsBuiltAlone(*third, *thirdAlone);
    // Both back as they were: their old selves in the static BVH are theirs again.
    auto fourth = tiledRoom(third.get());
    fourth->commit();
    EXPECT_EQ(fourth->stats().primitivesBuilt, 0u);
    EXPECT_EQ(fourth->stats().primitivesMasked, 0u);
    EXPECT_EQ(fourth->stats().primitivesReused, kRoomPrimitives);
    auto fourthAlone = tiledRoom(nullptr);
    fourthAlone->commit();
    expectAsBuiltAlone(*fourth, *fourthAlone);
}

TEST(SceneReuse, AStaticBvhMaskingMoreThanItsShareIsRebuilt) {
    auto first = tiledRoom(nullptr);
    first->commit();
    // The floor moved, a tile raised, another gone: 2 + 2 + 2 = 6 of the 22 primitives would be
    // masked, over a quarter (the ball, gone too, is in no BVH).
    auto second = tiledRoom(first.get(), 1, 2, -0.01f, false);
    second->commit();
    EXPECT_EQ(second->stats().primitivesMasked, 0u);
    EXPECT_EQ(second->stats().primitivesReused, 0u);
    EXPECT_EQ(second->stats().primitivesBuilt, kRoomPrimitives - 2);  // all it has: a new static BVH and the rest
    auto alone = tiledRoom(nullptr, 1, 2, -0.01f, false);
    alone->commit();
    expectAsBuiltAlone(*second, *alone);
}

TEST(SceneReuse, FramesRebuildAStaticBvhRatherThanMaskIt) {
    auto first = tiledRoom(nullptr);
    first->commit();
    // Nothing changed: the first frame's top level is kept whole as the static BVH.
    auto second = tiledRoom(first.get(), -1, -1, 0, true, Scene::BvhReuse::Frames);
    second->commit();
    EXPECT_EQ(second->stats().primitivesBuilt, 0u);
    EXPECT_EQ(second->stats().primitivesReused, kRoomPrimitives);
    // A tile moves: a frame rebuilds the static BVH without it (no masks slowing its rays).
    auto third = tiledRoom(second.get(), 3, -1, 0, true, Scene::BvhReuse::Frames);
    third->commit();
    EXPECT_EQ(third->stats().primitivesMasked, 0u);
    EXPECT_EQ(third->stats().primitivesBuilt, kRoomPrimitives);
    auto alone = tiledRoom(nullptr, 3);
    alone->commit();
    expectAsBuiltAlone(*third, *alone);
}

// The ball (a sphere: user geometry, sphere_geometry.h, with five spheres in the room) hidden by an
// edit stays in the kept static BVH, masked: rays where it was reach the floor, shadow rays pass,
// and its data outlives the scene that built it.
TEST(SceneReuse, AHiddenSphereIsMaskedInTheKeptBvh) {
    auto first = tiledRoom(nullptr, -1, -1, 0, true, Scene::BvhReuse::Edits, 4);
    first->commit();
    const Vec3 ballTop(0.3f, 1, 0.4f);
    RayStats st;
    Intersection before = first->intersect(Ray{ballTop, Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(before.kind, Intersection::Kind::Surface);
    EXPECT_EQ(first->shapeName(before.si.shapeId), "/Ball");
    EXPECT_NEAR(before.si.p.y, 0.65f, 1e-5f);
    auto second = tiledRoom(first.get(), -1, -1, 0, false, Scene::BvhReuse::Edits, 4);
    second->commit();
    EXPECT_EQ(second->stats().primitivesMasked, 1u);
    EXPECT_EQ(second->stats().primitivesBuilt, 0u);
    first.reset();
    Intersection after = second->intersect(Ray{ballTop, Vec3(0, -1, 0), 0, kInf}, st);
    ASSERT_EQ(after.kind, Intersection::Kind::Surface);
    EXPECT_EQ(second->shapeName(after.si.shapeId), "/Floor");
    EXPECT_FALSE(second->occluded(ballTop, Vec3(0, -1, 0), 0.98f, st));
    auto alone = tiledRoom(nullptr, -1, -1, 0, false, Scene::BvhReuse::Edits, 4);  // its four spheres beside the BVH
    alone->commit();
    expectAsBuiltAlone(*second, *alone);
}
