// What a host (the Hydra delegate) relies on: the film reports which shape and instance each
// pixel sees, a cancelled pass leaves the film untouched, and a paused render resumes exactly.
// (The camera both hosts share: test_camera_framing.cpp.)
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "renderer/render.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {
// A white floor lit by an overhead delta sun, seen from above: returns the floor's shape id.
int litFloor(Scene& scene, int material) {
    int floor = addQuad(scene, "/Floor", {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, material);
    LightDesc sun;
    sun.kind = "distant";
    sun.angle = 0;
    scene.addLight(sun);
    scene.setCamera(lookingDown({0, 5, 0}, true, 40));
    return floor;
}

// The lit floor alone, in grey, committed.
void commitLitFloor(Scene& scene) {
    litFloor(scene, scene.addMaterial(lambert(Color(0.5f))));
    scene.commit();
}

// A grey floor under a small sphere light, committed: its samples differ, so a pixel's
// second sample changes its mean.
void commitFloorUnderSphereLight(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.5f)));
    addQuad(scene, "/Floor", {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, white);
    scene.addLight(sphereLight("/Light", {0, 2, 0}, 0.5f, 10));
    scene.setCamera(lookingDown({0, 5, 0}, true, 40));
    scene.commit();
}

RenderSettings smallImage(int size, int spp) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.spp = spp;
    return settings;
}
}  // namespace

TEST(Host, FilmReportsShapeAndInstanceIds) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.5f)));
    int floor = litFloor(scene, white);
    int prototype = scene.addPrototype("/Proto");
    int sphere = scene.addSphere("/Proto/Ball", Vec3(0.0f), 0.5f, white, nullptr, prototype);
    Mat4 at;
    at.m[3][1] = 1;
    int instance = scene.addInstance(prototype, at, "/Proto[0]");
    scene.commit();
    Renderer renderer(scene, smallImage(16, 2));
    renderer.render();
    std::vector<int32_t> shapes = renderer.film().shapeIds(), instances = renderer.film().instanceIds();
    // Centre: the instanced sphere; corner: the floor.
    size_t centre = 8 * 16 + 8, corner = 0;
    EXPECT_EQ(shapes[centre], sphere);
    EXPECT_EQ(instances[centre], instance);
    EXPECT_EQ(shapes[corner], floor);
    EXPECT_EQ(instances[corner], -1);
}

TEST(Host, CancelledPassLeavesTheFilmAsItWas) {
    Scene scene;
    commitLitFloor(scene);
    Renderer renderer(scene, smallImage(32, 4));
    ASSERT_TRUE(renderer.renderPass(0, 1));
    std::vector<float> before = renderer.film().color();
    std::atomic<bool> cancel{true};
    EXPECT_FALSE(renderer.renderPass(1, 1, &cancel));
    EXPECT_EQ(renderer.samplesTaken(), 1);
    EXPECT_EQ(renderer.film().color(), before);
    EXPECT_TRUE(renderer.renderPass(1, 1));
    EXPECT_EQ(renderer.samplesTaken(), 2);
}

// A time-limited host renders its last pass with a deadline: the pixels finished by then keep
// the pass's samples, each one exactly as a render with that many samples would have it.
TEST(Host, DeadlineCutPassKeepsFinishedPixelsUnbiased) {
    Scene scene;
    commitFloorUnderSphereLight(scene);
    const int size = 128;
    Renderer two(scene, smallImage(size, 2));
    ASSERT_TRUE(two.renderPass(0, 2));
    std::vector<float> twoSpp = two.film().color();
    bool partial = false;
    // The deadline halfway through the second pass, as the first one timed it; retried with
    // other fractions if thread timing makes the pass finish or not start.
    for (double fraction : {0.5, 0.25, 0.75, 0.1, 0.9}) {
        Renderer renderer(scene, smallImage(size, 2));
        ASSERT_TRUE(renderer.renderPass(0, 1));
        std::vector<float> oneSpp = renderer.film().color();
        double passSeconds = renderer.stats().renderSeconds;
        PassEnd end = renderer.renderPass(1, 1, steadySeconds() + fraction * passSeconds);
        uint64_t finished = renderer.stats().partialPassPixels;
        if (end != PassEnd::Deadline || finished == 0) continue;
        partial = true;
        EXPECT_EQ(renderer.samplesTaken(), 1);
        EXPECT_LT(finished, uint64_t(size * size));
        std::vector<float> cut = renderer.film().color();
        uint64_t withTwo = 0;
        for (size_t p = 0; p < cut.size() / 3; ++p) {
            bool isOne = true, isTwo = true;
            for (int c = 0; c < 3; ++c) {
                isOne = isOne && cut[p * 3 + c] == oneSpp[p * 3 + c];
                isTwo = isTwo && cut[p * 3 + c] == twoSpp[p * 3 + c];
            }
            EXPECT_TRUE(isOne || isTwo) << "pixel " << p;
            withTwo += isTwo && !isOne;
        }
        // Pixels whose second sample happens to leave the mean unchanged count as "one".
        EXPECT_LE(withTwo, finished);
        EXPECT_GT(withTwo, finished / 2);
        break;
    }
    EXPECT_TRUE(partial) << "no deadline cut the pass part way";
}

// README: a render paused part way through a pass and resumed gives the same image as an
// uninterrupted one. The pause cancels the pass in flight after some of its tiles finished;
// the host then asks for the next pass again (hdGi's render thread, renderNextPass). Bit for bit:
// the same seed, pixels and sample indices give the same samples, summed in the same passes.
TEST(Host, ResumedRenderIsBitIdenticalToAnUninterruptedOne) {
    Scene scene;
    commitFloorUnderSphereLight(scene);  // every sample differs: a lost, repeated or shifted one shows
    const int size = 128, maxPassSamples = 8;  // hdGi's passes: 1, 2, 4, 8, 8 ... samples
    RenderSettings settings = smallImage(size, 23);  // 1 + 2 + 4 + 8 + 8: the last pass is cut to 8
    Renderer uninterrupted(scene, settings);
    while (!uninterrupted.finished()) ASSERT_EQ(uninterrupted.renderNextPass(maxPassSamples), PassEnd::Complete);
    const std::vector<float> expected = uninterrupted.film().color();

    // Every pass is paused once, a quarter of its tiles in (as progress() reports them); the
    // watcher spins, so a pass that ends before it sees the quarter just completes.
    Renderer resumed(scene, settings);
    int passes = 0, cutPartWay = 0;
    while (!resumed.finished()) {
        const double target = settings.spp, first = resumed.samplesTaken();
        const double count = std::min<double>(1 << std::min(passes, 3), target - first);
        std::atomic<bool> cancel{false}, passOver{false};
        std::thread pauser([&] {
            while (!passOver.load() && resumed.progress() < (first + 0.25 * count) / target) std::this_thread::yield();
            cancel = true;
        });
        std::vector<float> before = resumed.film().color();
        PassEnd end = resumed.renderNextPass(maxPassSamples, 0, &cancel);
        passOver = true;
        pauser.join();
        if (end == PassEnd::Cancelled) {
            double reached = resumed.progress();
            cutPartWay += reached > first / target && reached < (first + count) / target;
            EXPECT_EQ(resumed.samplesTaken(), int(first));
            EXPECT_EQ(resumed.film().color(), before) << "a cancelled pass must leave the film as it was";
            ASSERT_EQ(resumed.renderNextPass(maxPassSamples), PassEnd::Complete);  // resumed
        }
        ++passes;
    }
    EXPECT_GE(cutPartWay, 3) << "too few passes were paused part way to test anything";
    EXPECT_EQ(resumed.samplesTaken(), uninterrupted.samplesTaken());
    const std::vector<float> got = resumed.film().color();
    size_t differing = 0;
    for (size_t i = 0; i < got.size(); ++i) differing += got[i] != expected[i];
    EXPECT_EQ(differing, 0u) << "of " << got.size() << " values";

    // The same through Renderer::render (its own pass sizes): cancelled mid-pass, then again.
    Renderer whole(scene, settings);
    whole.render();
    Renderer viaRender(scene, settings);
    std::atomic<bool> cancel{false};
    std::thread pauser([&] {
        while (viaRender.progress() < 0.5) std::this_thread::yield();
        cancel = true;
    });
    viaRender.render(&cancel);
    pauser.join();
    EXPECT_LT(viaRender.samplesTaken(), settings.spp);
    viaRender.render();
    EXPECT_EQ(viaRender.film().color(), whole.film().color());
}

TEST(Host, DeadlinePassedRendersNothingAndCancelStillDiscards) {
    Scene scene;
    commitLitFloor(scene);
    Renderer renderer(scene, smallImage(32, 4));
    ASSERT_TRUE(renderer.renderPass(0, 1));
    std::vector<float> before = renderer.film().color();
    EXPECT_EQ(renderer.renderPass(1, 1, steadySeconds()), PassEnd::Deadline);
    EXPECT_EQ(renderer.stats().partialPassPixels, 0u);
    EXPECT_EQ(renderer.film().color(), before);
    std::atomic<bool> cancel{true};
    EXPECT_EQ(renderer.renderPass(1, 1, steadySeconds() + 100, &cancel), PassEnd::Cancelled);
    EXPECT_EQ(renderer.film().color(), before);
    EXPECT_EQ(renderer.renderPass(1, 1, 0.0), PassEnd::Complete);
    EXPECT_EQ(renderer.samplesTaken(), 2);
    // Without a deadline a pass is as large as asked; with one, as large as the rate allows.
    EXPECT_EQ(renderer.passSamplesBefore(0, 64), 64);
    EXPECT_EQ(renderer.passSamplesBefore(steadySeconds() + 1e-9, 64), 1);
}

TEST(Host, TimeLimitIsKept) {
    Scene scene;
    commitLitFloor(scene);
    RenderSettings settings = smallImage(64, 1 << 24);
    settings.timeLimit = 0.5;
    double start = steadySeconds();
    Renderer renderer(scene, settings);
    renderer.render(nullptr, start);
    double elapsed = steadySeconds() - start;
    // The bound: within 5% + 0.2 s of the budget (issue 16).
    EXPECT_LE(elapsed, 0.5 * 1.05 + 0.2);
    EXPECT_GE(elapsed, 0.5 * 0.95 - 0.2);
    EXPECT_NEAR(renderer.stats().seconds, elapsed, 0.05);
    EXPECT_GT(renderer.samplesTaken(), 1);
}
