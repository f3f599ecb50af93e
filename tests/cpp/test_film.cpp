#include <gtest/gtest.h>

#include "renderer/color.h"
#include "renderer/film.h"

using namespace gi;

TEST(Film, BoxFilterAveragesSamplesOfTheirOwnPixel) {
    Film film(2, 1);
    FilmTile tile(0, 0, 2, 1, film.filter());
    SampleAovs aovs;
    tile.addSample(0.2f, 0.5f, Color(1, 2, 3), aovs);
    tile.addSample(0.9f, 0.1f, Color(3, 2, 1), aovs);
    tile.addSample(1.5f, 0.5f, Color(7.0f), aovs);
    film.merge(tile);
    auto c = film.color();
    EXPECT_FLOAT_EQ(c[0], 2.0f);
    EXPECT_FLOAT_EQ(c[1], 2.0f);
    EXPECT_FLOAT_EQ(c[3], 7.0f);
}

TEST(Film, SampleAtTheFarEdgeOfALargeCoordinateStaysInItsPixel) {
    // 199 + 0.99999994f rounds to 200.0f: the sample still belongs to pixel 199.
    Film film(200, 1);
    FilmTile tile(192, 0, 200, 1, film.filter());
    tile.addSample(199.0f + 0.99999994f, 0.99999994f, Color(4.0f), SampleAovs());
    film.merge(tile);
    EXPECT_FLOAT_EQ(film.color()[199 * 3], 4.0f);
}

TEST(Film, GaussianFilterPreservesAConstantImage) {
    Film film(8, 8, Filter::byName("gaussian"));
    for (int ty = 0; ty < 8; ty += 4)
        for (int tx = 0; tx < 8; tx += 4) {
            FilmTile tile(tx, ty, tx + 4, ty + 4, film.filter());
            for (int y = ty; y < ty + 4; ++y)
                for (int x = tx; x < tx + 4; ++x)
                    for (int s = 0; s < 4; ++s) tile.addSample(x + 0.25f + 0.5f * (s % 2), y + 0.25f + 0.5f * (s / 2), Color(0.5f), SampleAovs());
            film.merge(tile);
        }
    for (float v : film.color()) EXPECT_NEAR(v, 0.5f, 1e-5f);
}

TEST(Color, ShippedConfigAppliesTheSrgbTransferFunction) {
    std::vector<float> linear = {0.0f, 0.0031308f, 0.18f, 1.0f, 4.0f, 0.5f};
    auto out = applyDisplayTransform(linear, 2, 1, GI_OCIO_CONFIG, "sRGB", "Standard", 0);
    auto srgb = [](float x) { return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1 / 2.4f) - 0.055f; };
    for (size_t i = 0; i < linear.size(); ++i) EXPECT_NEAR(out[i], std::min(1.0f, srgb(linear[i])), 2e-3f) << i;
}

TEST(Color, UnknownViewIsAClearError) {
    std::vector<float> px(3, 0.5f);
    EXPECT_THROW(applyDisplayTransform(px, 1, 1, GI_OCIO_CONFIG, "sRGB", "NoSuchView", 0), std::runtime_error);
}
