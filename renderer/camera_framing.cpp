#include "camera_framing.h"

#include <cmath>

namespace gi {

namespace {

struct ConformToken {
    ApertureConform conform;
    const char* token;
};
constexpr ConformToken kConformTokens[] = {{ApertureConform::ExpandAperture, "expandAperture"},
                                           {ApertureConform::CropAperture, "cropAperture"},
                                           {ApertureConform::AdjustApertureWidth, "adjustApertureWidth"},
                                           {ApertureConform::AdjustApertureHeight, "adjustApertureHeight"},
                                           {ApertureConform::AdjustPixelAspectRatio, "adjustPixelAspectRatio"}};

bool usable(float v) { return v > 0 && std::isfinite(v); }

}  // namespace

bool parseApertureConform(const std::string& token, ApertureConform* conform) {
    for (const ConformToken& t : kConformTokens)
        if (token == t.token) {
            *conform = t.conform;
            return true;
        }
    return false;
}

const char* apertureConformToken(ApertureConform conform) {
    for (const ConformToken& t : kConformTokens)
        if (t.conform == conform) return t.token;
    return kConformTokens[0].token;
}

CameraLens cameraLens(const CameraDesc& camera) {
    // UsdImaging's conversion (cameraAdapter.cpp, dataSourceCamera.cpp): a float times
    // float(GfCamera::APERTURE_UNIT), rounded to float.
    auto sceneUnits = [&](float v) {
        return camera.lengthUnit == CameraLengthUnit::TenthsOfSceneUnit ? v * float(0.1) : v;
    };
    auto tenthsToSceneUnits = [](float v) { return v * float(0.1); };
    const CameraDesc defaults;
    auto length = [&](float v, float fallbackTenths) {
        float s = sceneUnits(v);
        return usable(s) ? s : tenthsToSceneUnits(fallbackTenths);
    };
    auto offset = [&](float v) { return std::isfinite(v) ? sceneUnits(v) : 0.0f; };
    CameraLens lens;
    lens.orthographic = camera.projection == "orthographic";
    lens.focalLength = length(camera.focalLength, defaults.focalLength);
    lens.horizontalAperture = length(camera.horizontalAperture, defaults.horizontalAperture);
    lens.verticalAperture = length(camera.verticalAperture, defaults.verticalAperture);
    lens.horizontalApertureOffset = offset(camera.horizontalApertureOffset);
    lens.verticalApertureOffset = offset(camera.verticalApertureOffset);
    return lens;
}

FilmWindow filmWindow(const CameraLens& lens, const ImageFraming& framing, int width, int height) {
    // The aperture on the image plane: at unit distance (perspective), or as is (orthographic).
    double scale = lens.orthographic ? 1.0 : 1.0 / double(lens.focalLength);
    double halfWidth = 0.5 * double(lens.horizontalAperture) * scale;
    double halfHeight = 0.5 * double(lens.verticalAperture) * scale;
    double centerX = double(lens.horizontalApertureOffset) * scale;
    double centerY = double(lens.verticalApertureOffset) * scale;

    double left = framing.displayLeft, top = framing.displayTop;
    double right = framing.displayRight, bottom = framing.displayBottom;
    if (!(right > left && bottom > top) || !std::isfinite(right - left) || !std::isfinite(bottom - top))
        left = top = 0, right = bottom = 1;
    double pixelAspect = usable(framing.pixelAspectRatio) ? framing.pixelAspectRatio : 1.0;
    double displayAspect = pixelAspect * (right - left) * width / ((bottom - top) * height);

    // CameraUtilConformedWindow's resolution of the policies (Hydra's, for the same floats).
    bool wider = halfWidth / halfHeight > displayAspect;
    switch (framing.conform) {
        case ApertureConform::ExpandAperture:
            if (wider) halfHeight = halfWidth / displayAspect;
            else halfWidth = halfHeight * displayAspect;
            break;
        case ApertureConform::CropAperture:
            if (wider) halfWidth = halfHeight * displayAspect;
            else halfHeight = halfWidth / displayAspect;
            break;
        case ApertureConform::AdjustApertureWidth: halfWidth = halfHeight * displayAspect; break;
        case ApertureConform::AdjustApertureHeight: halfHeight = halfWidth / displayAspect; break;
        case ApertureConform::AdjustPixelAspectRatio: break;
    }

    // From the display window to the whole image: image fraction u maps to
    // centerX + (2 (u - left) / (right - left) - 1) halfWidth; y runs down in the image, up on the
    // plane. For the whole image (left 0, right 1) these leave the window as it is, exactly.
    FilmWindow window;
    window.halfWidth = halfWidth / (right - left);
    window.halfHeight = halfHeight / (bottom - top);
    window.centerX = centerX + ((1 - 2 * left) / (right - left) - 1) * halfWidth;
    window.centerY = centerY + (1 - (1 - 2 * top) / (bottom - top)) * halfHeight;
    return window;
}

CameraDesc framingCamera(std::array<double, 3> center, std::array<double, 3> size, bool zUp) {
    bool finite = true;
    for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(center[i]) && std::isfinite(size[i]) && size[i] >= 0;
    if (!finite) center = size = {0, 0, 0};
    CameraDesc c;
    c.name = "<framing camera>";
    c.clipNear = 1;  // GfCamera's clipping range, as usdrecord hands it to Hydra
    c.clipFar = 1e6f;
    int up = zUp ? 2 : 1, depth = zUp ? 1 : 2;
    // In float where usdrecord computes in float; tan(half fov) is the aperture over twice the
    // focal length (GfCamera's atan, then tan, gives it back to within a float's rounding).
    float planeRadius = float(std::sqrt(size[0] * size[0] / 4 + size[up] * size[up] / 4));
    float distance = planeRadius / (c.horizontalAperture / (2 * c.focalLength));
    distance = float(distance + size[depth] / 2);
    if (distance < c.clipNear) distance += c.clipNear;
    if (zUp) {  // rotated 90 degrees about X: the camera's -Z looks along +Y, its +Y is +Z
        c.transform.m[1][1] = 0;
        c.transform.m[1][2] = 1;
        c.transform.m[2][1] = -1;
        c.transform.m[2][2] = 0;
    }
    c.transform.m[3][0] = center[0];
    c.transform.m[3][1] = center[1] - (zUp ? distance : 0);
    c.transform.m[3][2] = center[2] + (zUp ? 0 : distance);
    return c;
}

}  // namespace gi
