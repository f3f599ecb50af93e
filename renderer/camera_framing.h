// How a UsdGeomCamera frames the image: its apertures, offsets and focal length, conformed to
// the image by UsdRenderSettings' aspectRatioConformPolicy and pixelAspectRatio, give the window
// on the image plane that the pixels span. One rule for both hosts: `gi render` fills the
// framing from the stage's render settings or render product, hdGi from the render product or
// from Hydra's framing (its window policy and display window), and both hand over the camera's
// attributes, so the same camera gives the same rays, bit for bit.
#pragma once
#include <string>

#include "camera_desc.h"

namespace gi {

// UsdRenderSettingsBase's aspectRatioConformPolicy: what gives way when the aperture's aspect
// ratio is not the image's. The aperture is conformed about its centre (offsets are kept).
enum class ApertureConform {
    ExpandAperture,         // the schema's default: the aperture too small for the image grows
    CropAperture,           // the aperture too large for the image shrinks
    AdjustApertureWidth,    // the vertical aperture is kept
    AdjustApertureHeight,   // the horizontal aperture is kept
    AdjustPixelAspectRatio  // both are kept; the pixels are stretched instead
};
// USD's token for each (e.g. "expandAperture"); false for a token that is none of them.
bool parseApertureConform(const std::string& token, ApertureConform* conform);
const char* apertureConformToken(ApertureConform conform);

struct ImageFraming {
    ApertureConform conform = ApertureConform::ExpandAperture;
    float pixelAspectRatio = 1;  // a pixel's width over its height; not positive and finite: 1
    // The part of the rendered image the conformed aperture fills, as fractions of its width and
    // height from its top-left corner (Hydra's display window within its data window: a host's
    // viewport may show more than the camera's frame, or less). Empty: the whole image.
    float displayLeft = 0, displayTop = 0, displayRight = 1, displayBottom = 1;
};

// The camera's lengths in scene units: UsdGeomCamera's tenths converted as UsdImaging converts
// them for Hydra (v * float(0.1), in float), so that both hosts start from the same floats;
// unusable values (not positive, NaN, Inf) replaced by the schema's defaults (camera_desc.h).
struct CameraLens {
    bool orthographic = false;
    float focalLength, horizontalAperture, verticalAperture, horizontalApertureOffset, verticalApertureOffset;
};
CameraLens cameraLens(const CameraDesc& camera);

// The window the image spans on the image plane, y up: at unit distance in front of a
// perspective camera, in scene units for an orthographic one.
struct FilmWindow {
    double centerX = 0, centerY = 0, halfWidth = 1, halfHeight = 1;
};
FilmWindow filmWindow(const CameraLens& lens, const ImageFraming& framing, int width, int height);

}  // namespace gi
