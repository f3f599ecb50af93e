// A data window (RenderSettings::window) renders pixels equal to the whole image's, bit for bit:
// what farm tiles and RenderProducts' dataWindowNDC rely on.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

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

// dataWindowNDC to pixels (pixel_window.h), the rule both hosts follow: a pixel is in when its
// centre is, the low edges included and the high ones not; NDC y runs up.
TEST(DataWindow, NdcHoldsThePixelsWhoseCentresItContains) {
    std::string problem;
    // Low edges on pixel centres (x 2.5 of 10 columns: column 2's; the top edge (1 - 0.8125) x 8 =
    // 1.5: row 1's), high edges inside pixels (x 7.2, y 7.1); rounding the edges half up would
    // start at column 3 and row 2.
    PixelWindow w = dataWindowPixels(0.25f, 1 - 7.1f / 8, 0.72f, 0.8125f, 10, 8, &problem);
    EXPECT_EQ(w, (PixelWindow{2, 1, 7, 7})) << w.x0 << " " << w.y0 << " " << w.x1 << " " << w.y1;
    EXPECT_TRUE(problem.empty()) << problem;
    EXPECT_EQ(dataWindowPixels(0, 0, 1, 1, 10, 8, &problem), (PixelWindow{0, 0, 10, 8}));
    EXPECT_TRUE(problem.empty());
    // The bottom-left quarter: the last rows.
    EXPECT_EQ(dataWindowPixels(0, 0, 0.5f, 0.5f, 10, 8, &problem), (PixelWindow{0, 4, 5, 8}));
}

TEST(DataWindow, NdcOutsideTheImageIsClippedAndAnEmptyOrBrokenOneIsTheWholeImage) {
    std::string problem;
    EXPECT_EQ(dataWindowPixels(-0.5f, -1e30f, 0.5f, 2, 10, 8, &problem), (PixelWindow{0, 0, 5, 8}));
    EXPECT_NE(problem.find("reaches outside the image"), std::string::npos) << problem;
    const PixelWindow whole{0, 0, 10, 8};
    // Narrower than a pixel between two centres; reversed; beside the image; NaN.
    for (auto ndc : std::vector<std::array<float, 4>>{{0.11f, 0, 0.14f, 1}, {0.8f, 0, 0.2f, 1}, {1.5f, 0, 2, 1},
                                                      {0, std::nanf(""), 1, 1}}) {
        EXPECT_EQ(dataWindowPixels(ndc[0], ndc[1], ndc[2], ndc[3], 10, 8, &problem), whole) << ndc[0];
        EXPECT_NE(problem.find("the whole image is rendered"), std::string::npos) << problem;
    }
}
