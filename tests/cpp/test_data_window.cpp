// A data window (RenderSettings::window) renders pixels equal to the whole image's, bit for bit:
// what farm tiles and RenderProducts' dataWindowNDC rely on.
#include <gtest/gtest.h>

#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

void litFloorAndBall(Scene& scene) {
    int grey = scene.addMaterial(lambert(Color(0.6f)));
    addQuad(scene, "/Floor", {-3, 0, -3}, {3, 0, -3}, {3, 0, 3}, {-3, 0, 3}, grey);
    Mat4 up;
    up.m[3][1] = 1;
    scene.addSphere("/Ball", {0, 0, 0}, 0.8f, grey, &up, -1);
    scene.addLight(sphereLight("/Light", {1, 4, 1}, 0.5f, 40));
    scene.setCamera(lookingDown({0, 6, 0}, false, 36));
    scene.commit();
}

Film renderWindow(const Scene& scene, const std::string& filter, PixelWindow window, int threads) {
    RenderSettings settings;
    settings.width = 37, settings.height = 29;  // not multiples of the 16-pixel tiles
    settings.spp = 3;
    settings.seed = 9;
    settings.filter = filter;
    settings.window = window;
    settings.threads = threads;
    Renderer renderer(scene, settings);
    renderer.render();
    return renderer.film();
}

}  // namespace

TEST(DataWindow, WindowsEqualTheWholeImageBitForBit) {
    Scene scene;
    litFloorAndBall(scene);
    for (const char* filter : {"box", "gaussian"}) {
        std::vector<float> whole = renderWindow(scene, filter, {}, 0).color();
        // Windows across tile boundaries and the image's edges, rendered on one thread and on all.
        for (PixelWindow w : {PixelWindow{0, 0, 19, 13}, PixelWindow{19, 13, 37, 29}, PixelWindow{5, 17, 33, 18}}) {
            for (int threads : {1, 0}) {
                std::vector<float> part = renderWindow(scene, filter, w, threads).color();
                for (int y = 0; y < 29; ++y)
                    for (int x = 0; x < 37; ++x)
                        for (int c = 0; c < 3; ++c) {
                            size_t i = (size_t(y) * 37 + x) * 3 + c;
                            if (w.contains(x, y))
                                ASSERT_EQ(part[i], whole[i]) << filter << " pixel " << x << "," << y;
                            else if (std::string(filter) == "box")  // the gaussian also samples its reach around
                                ASSERT_EQ(part[i], 0.0f) << "outside the window: " << x << "," << y;
                        }
            }
        }
        double mean = 0;
        for (float v : whole) mean += v;
        EXPECT_GT(mean / whole.size(), 0.01) << "the scene must be lit for the comparison to mean anything";
    }
}

TEST(DataWindow, AWindowOutsideTheImageIsRefused) {
    Scene scene;
    litFloorAndBall(scene);
    EXPECT_THROW(renderWindow(scene, "box", PixelWindow{30, 0, 40, 5}, 0), std::invalid_argument);
    EXPECT_THROW(renderWindow(scene, "box", PixelWindow{-1, 0, 5, 5}, 0), std::invalid_argument);
}
