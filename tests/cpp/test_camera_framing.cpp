// renderer/camera_framing.h, the camera rule both USD hosts follow: UsdGeomCamera's defaults
// for unusable values, each aspectRatioConformPolicy, the pixel aspect ratio, a host's display
// window, and lengths given in Hydra's scene units giving the very window USD's tenths give.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "renderer/camera.h"

using namespace gi;

namespace {

// A 36 x 24 aperture (aspect 1.5) with a 50 focal length, in USD's tenths, offset 2 right.
CameraDesc filmCamera() {
    CameraDesc c;
    c.focalLength = 50;
    c.horizontalAperture = 36, c.verticalAperture = 24;
    c.horizontalApertureOffset = 2;
    return c;
}

FilmWindow windowOf(const CameraDesc& camera, ApertureConform conform, int width, int height, float pixelAspect = 1) {
    ImageFraming framing;
    framing.conform = conform;
    framing.pixelAspectRatio = pixelAspect;
    return filmWindow(cameraLens(camera), framing, width, height);
}

// The aperture's half extents and offset at unit distance, in double, from USD's tenths.
constexpr double kHalfWidth = 0.5 * 36 / 50.0, kHalfHeight = 0.5 * 24 / 50.0, kOffsetX = 2 / 50.0;
constexpr double kTolerance = 1e-6;  // the float rounding of lengths in scene units (2^-24 relative)

void expectWindow(const FilmWindow& w, double halfWidth, double halfHeight) {
    EXPECT_NEAR(w.halfWidth, halfWidth, kTolerance);
    EXPECT_NEAR(w.halfHeight, halfHeight, kTolerance);
    EXPECT_NEAR(w.centerX, kOffsetX, kTolerance);  // conformed about the offset window's centre
    EXPECT_NEAR(w.centerY, 0, kTolerance);
}

}  // namespace

TEST(CameraFraming, TokensRoundTripAndAnUnknownOneIsRefused) {
    for (auto conform : {ApertureConform::ExpandAperture, ApertureConform::CropAperture,
                         ApertureConform::AdjustApertureWidth, ApertureConform::AdjustApertureHeight,
                         ApertureConform::AdjustPixelAspectRatio}) {
        ApertureConform parsed = ApertureConform::ExpandAperture;
        ASSERT_TRUE(parseApertureConform(apertureConformToken(conform), &parsed));
        EXPECT_EQ(parsed, conform);
    }
    ApertureConform untouched = ApertureConform::CropAperture;
    EXPECT_FALSE(parseApertureConform("fit", &untouched));
    EXPECT_EQ(untouched, ApertureConform::CropAperture);
    EXPECT_STREQ(apertureConformToken(ApertureConform::ExpandAperture), "expandAperture");
}

TEST(CameraFraming, EachPolicyOnAWiderAndANarrowerImage) {
    // Image aspect 3 (wider than the aperture's 1.5) and 1 (narrower).
    CameraDesc c = filmCamera();
    expectWindow(windowOf(c, ApertureConform::ExpandAperture, 300, 100), 3 * kHalfHeight, kHalfHeight);
    expectWindow(windowOf(c, ApertureConform::ExpandAperture, 100, 100), kHalfWidth, kHalfWidth);
    expectWindow(windowOf(c, ApertureConform::CropAperture, 300, 100), kHalfWidth, kHalfWidth / 3);
    expectWindow(windowOf(c, ApertureConform::CropAperture, 100, 100), kHalfHeight, kHalfHeight);
    expectWindow(windowOf(c, ApertureConform::AdjustApertureWidth, 300, 100), 3 * kHalfHeight, kHalfHeight);
    expectWindow(windowOf(c, ApertureConform::AdjustApertureWidth, 100, 100), kHalfHeight, kHalfHeight);
    expectWindow(windowOf(c, ApertureConform::AdjustApertureHeight, 300, 100), kHalfWidth, kHalfWidth / 3);
    expectWindow(windowOf(c, ApertureConform::AdjustApertureHeight, 100, 100), kHalfWidth, kHalfWidth);
    expectWindow(windowOf(c, ApertureConform::AdjustPixelAspectRatio, 300, 100), kHalfWidth, kHalfHeight);
    expectWindow(windowOf(c, ApertureConform::AdjustPixelAspectRatio, 100, 100), kHalfWidth, kHalfHeight);
}

TEST(CameraFraming, PixelAspectRatioWidensTheImage) {
    // 150 x 100 pixels twice as wide as tall frame what 300 x 100 square pixels frame.
    CameraDesc c = filmCamera();
    for (auto conform : {ApertureConform::ExpandAperture, ApertureConform::CropAperture}) {
        FilmWindow wide = windowOf(c, conform, 300, 100), stretched = windowOf(c, conform, 150, 100, 2);
        EXPECT_DOUBLE_EQ(stretched.halfWidth, wide.halfWidth);
        EXPECT_DOUBLE_EQ(stretched.halfHeight, wide.halfHeight);
    }
    // An unusable pixel aspect ratio is 1.
    FilmWindow square = windowOf(c, ApertureConform::CropAperture, 150, 100);
    for (float bad : {0.0f, -2.0f, std::numeric_limits<float>::quiet_NaN()})
        EXPECT_DOUBLE_EQ(windowOf(c, ApertureConform::CropAperture, 150, 100, bad).halfWidth, square.halfWidth);
}

TEST(CameraFraming, DisplayWindowMapsTheFrameIntoTheImage) {
    // A 200 x 100 image whose right half (100 x 100) shows the camera's frame, conformed to that
    // square: the image spans twice the frame's width, its centre one frame-width left of the frame's.
    CameraDesc c = filmCamera();
    FilmWindow frame = windowOf(c, ApertureConform::ExpandAperture, 100, 100);
    ImageFraming framing;
    framing.displayLeft = 0.5f;
    FilmWindow image = filmWindow(cameraLens(c), framing, 200, 100);
    EXPECT_NEAR(image.halfWidth, 2 * frame.halfWidth, kTolerance);
    EXPECT_NEAR(image.halfHeight, frame.halfHeight, kTolerance);
    EXPECT_NEAR(image.centerX, frame.centerX - frame.halfWidth, kTolerance);
    // The bottom half of a 100 x 200 image: the image's centre lies one frame-height above.
    framing = ImageFraming();
    framing.displayTop = 0.5f;
    image = filmWindow(cameraLens(c), framing, 100, 200);
    EXPECT_NEAR(image.halfHeight, 2 * frame.halfHeight, kTolerance);
    EXPECT_NEAR(image.centerY, frame.halfHeight, kTolerance);
    // A whole-image display window leaves the window exactly as it is; an empty one is the whole image.
    framing = ImageFraming();
    FilmWindow whole = filmWindow(cameraLens(c), framing, 100, 100);
    EXPECT_EQ(whole.halfWidth, frame.halfWidth);
    EXPECT_EQ(whole.centerX, frame.centerX);
    framing.displayRight = 0;
    EXPECT_EQ(filmWindow(cameraLens(c), framing, 100, 100).halfWidth, frame.halfWidth);
}

TEST(CameraFraming, UnusableLengthsFallBackToTheSchemaDefaults) {
    CameraDesc defaults;  // UsdGeomCamera's: 50, 20.955 x 15.2908, no offsets
    FilmWindow expected = windowOf(defaults, ApertureConform::AdjustPixelAspectRatio, 64, 64);
    EXPECT_NEAR(expected.halfWidth, 0.5 * 20.955 / 50, kTolerance);
    EXPECT_NEAR(expected.halfHeight, 0.5 * 15.2908 / 50, kTolerance);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    CameraDesc bad;
    bad.focalLength = nan, bad.horizontalAperture = 0, bad.verticalAperture = -inf;
    bad.horizontalApertureOffset = nan, bad.verticalApertureOffset = inf;
    FilmWindow w = windowOf(bad, ApertureConform::AdjustPixelAspectRatio, 64, 64);
    EXPECT_EQ(w.halfWidth, expected.halfWidth);
    EXPECT_EQ(w.halfHeight, expected.halfHeight);
    EXPECT_EQ(w.centerX, 0);
    EXPECT_EQ(w.centerY, 0);
}

TEST(CameraFraming, HydraSceneUnitsGiveTheWindowOfUsdTenths) {
    // hdGi hands over HdCamera's lengths as UsdImaging made them, float(v * float(0.1)); the
    // window must equal, bit for bit, the one `gi render` computes from the USD values v. (Scaling
    // Hydra's back by 10 does not: 20.955 comes back as 20.955002, and about a fifth of values
    // 0.01..2000 miss by an ulp.)
    int sameAfterTimesTen = 0, values = 0;
    for (float v = 0.37f; v < 2000; v *= 1.37f) {
        CameraDesc usd = filmCamera();
        usd.projection = values % 2 ? "orthographic" : "perspective";
        usd.horizontalAperture = v, usd.verticalAperture = 0.7f * v, usd.focalLength = 1.3f * v;
        usd.horizontalApertureOffset = -0.2f * v;
        CameraDesc hydra = usd;
        hydra.lengthUnit = CameraLengthUnit::SceneUnit;
        for (float* length : {&hydra.horizontalAperture, &hydra.verticalAperture, &hydra.focalLength,
                              &hydra.horizontalApertureOffset, &hydra.verticalApertureOffset})
            *length = *length * float(0.1);
        for (auto conform : {ApertureConform::ExpandAperture, ApertureConform::CropAperture}) {
            FilmWindow a = windowOf(usd, conform, 240, 162), b = windowOf(hydra, conform, 240, 162);
            EXPECT_EQ(a.halfWidth, b.halfWidth) << v;
            EXPECT_EQ(a.halfHeight, b.halfHeight) << v;
            EXPECT_EQ(a.centerX, b.centerX) << v;
        }
        sameAfterTimesTen += float(double(hydra.horizontalAperture) * 10) == usd.horizontalAperture;
        ++values;
    }
    EXPECT_LT(sameAfterTimesTen, values);  // the round trip this rule avoids does lose values
}

TEST(CameraFraming, RaysGoThroughTheWindow) {
    // The camera's ray through the image's top-right corner points at the window's corner.
    CameraDesc c = filmCamera();
    ImageFraming framing;
    framing.conform = ApertureConform::CropAperture;
    FilmWindow w = filmWindow(cameraLens(c), framing, 300, 100);
    Camera camera(c, 300, 100, framing);
    Ray r = camera.generateRay(300, 0, Vec2(0.5f, 0.5f));
    EXPECT_NEAR(r.d.x / -r.d.z, w.centerX + w.halfWidth, 1e-6);
    EXPECT_NEAR(r.d.y / -r.d.z, w.centerY + w.halfHeight, 1e-6);
    c.projection = "orthographic";
    Camera ortho(c, 300, 100, framing);
    FilmWindow ow = filmWindow(cameraLens(c), framing, 300, 100);
    r = ortho.generateRay(0, 100, Vec2(0.5f, 0.5f));
    EXPECT_NEAR(r.o.x, ow.centerX - ow.halfWidth, 1e-6);
    EXPECT_NEAR(r.o.y, ow.centerY - ow.halfHeight, 1e-6);
}

// A mosaic's film is the image's pixels in tiles (auto's pilots): a film position's ray is the
// image's ray at the same place in the same pixel of its tile, bit for bit.
TEST(CameraFraming, AMosaicsPixelsAreTheImagesPixels) {
    PixelMosaic mosaic;
    mosaic.tile = 5;
    mosaic.across = 2;
    mosaic.x0 = {0, 40, 7, 290};
    mosaic.y0 = {0, 3, 80, 95};
    Camera camera(filmCamera(), 300, 100, {}, mosaic);
    ASSERT_EQ(mosaic.width(), 10);
    ASSERT_EQ(mosaic.height(), 10);
    for (int y = 0; y < mosaic.height(); ++y)
        for (int x = 0; x < mosaic.width(); ++x) {
            const int t = (y / 5) * 2 + x / 5;
            const Ray a = camera.generateRay(x + 0.25f, y + 0.75f, Vec2(0.5f, 0.5f));
            const Ray b = camera.generateImageRay(float(mosaic.x0[size_t(t)] + x % 5) + 0.25f,
                                                  float(mosaic.y0[size_t(t)] + y % 5) + 0.75f, Vec2(0.5f, 0.5f));
            for (int i = 0; i < 3; ++i) {
                EXPECT_EQ(a.d[i], b.d[i]) << x << ", " << y;
                EXPECT_EQ(a.o[i], b.o[i]) << x << ", " << y;
            }
        }
    EXPECT_EQ(camera.imageWidth(), 300);
    EXPECT_EQ(camera.imageHeight(), 100);
}

// framingCamera: usdrecord's camera for a stage without one (its 24.11 _ComputeCameraToFrameStage).
namespace {
constexpr double kTanHalfFov = 20.955 / (2 * 50.0);  // GfCamera's default horizontal aperture and focal length
constexpr double kFloat = 1e-5;                      // the rule computes its distance in float, as usdrecord

Vec3 viewDirection(const CameraDesc& c) { return c.transform.vector(Vec3(0, 0, -1)); }
Vec3 upDirection(const CameraDesc& c) { return c.transform.vector(Vec3(0, 1, 0)); }
Vec3 position(const CameraDesc& c) { return c.transform.point(Vec3(0.0f)); }
void ExpectVec(Vec3 actual, Vec3 expected) {
    for (int i = 0; i < 3; ++i) EXPECT_EQ(actual[i], expected[i]) << "component " << i;
}
}  // namespace

TEST(FramingCamera, YUpLooksDownZAndTheBoxsImagePlaneDiagonalFillsTheHorizontalFov) {
    CameraDesc c = framingCamera({1, 2, 3}, {4, 2, 6}, false);
    ExpectVec(viewDirection(c), Vec3(0, 0, -1));
    ExpectVec(upDirection(c), Vec3(0, 1, 0));
    Vec3 p = position(c);
    EXPECT_EQ(p.x, 1);
    EXPECT_EQ(p.y, 2);
    // The front face (z = 6) is where the half-diagonal sqrt(2^2 + 1^2) spans half the field of view.
    EXPECT_NEAR(std::sqrt(5.0) / (p.z - 6), kTanHalfFov, kFloat);
    EXPECT_EQ(c.focalLength, CameraDesc().focalLength);
    EXPECT_EQ(c.horizontalAperture, CameraDesc().horizontalAperture);
    EXPECT_EQ(c.clipNear, 1);
    EXPECT_EQ(c.clipFar, 1e6f);
}

TEST(FramingCamera, ZUpLooksAlongYWithZUp) {
    CameraDesc c = framingCamera({1, 2, 3}, {4, 6, 2}, true);
    ExpectVec(viewDirection(c), Vec3(0, 1, 0));
    ExpectVec(upDirection(c), Vec3(0, 0, 1));
    Vec3 p = position(c);
    EXPECT_EQ(p.x, 1);
    EXPECT_EQ(p.z, 3);
    EXPECT_NEAR(std::sqrt(5.0) / (2 - 3 - p.y), kTanHalfFov, kFloat);  // front face at y = -1
}

TEST(FramingCamera, ASmallBoxIsBackedOffByTheNearPlaneAndAnEmptyOneFramesTheOrigin) {
    CameraDesc small = framingCamera({0, 0, 0}, {0.02, 0.02, 0.02}, false);
    EXPECT_NEAR(position(small).z, std::sqrt(2e-4) / kTanHalfFov + 0.01 + 1, kFloat);
    double inf = std::numeric_limits<double>::infinity(), lowest = -std::numeric_limits<float>::max();
    // GfRange3d's empty box has a negative size; a NaN or Inf anywhere is no box either.
    for (auto size : {std::array<double, 3>{2 * lowest, 2 * lowest, 2 * lowest}, std::array<double, 3>{inf, 1, 1}}) {
        Vec3 p = position(framingCamera({0, 0, 0}, size, false));
        EXPECT_EQ(p.x, 0);
        EXPECT_EQ(p.y, 0);
        EXPECT_EQ(p.z, 1);  // distance 0, lengthened by the near plane
    }
}
