// How a UsdGeomCamera frames the image: its apertures, offsets and focal length, conformed to
// the image by UsdRenderSettings' aspectRatioConformPolicy and pixelAspectRatio, give the window
// on the image plane that the pixels span. One rule for both hosts: `gi render` fills the
// framing from the stage's render settings or render product, hdGi from the render product or
// from Hydra's framing (its window policy and display window), and both hand over the camera's
// attributes, so the same camera gives the same rays, bit for bit.
#pragma once
#include <array>
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

// The camera that frames a scene given no camera of its own: usdrecord's free camera (OpenUSD 24.11,
// UsdAppUtilsFrameRecorder's _ComputeCameraToFrameStage), so that a stage without a camera shows
// the same view in `gi render` as in usdrecord. A default camera (CameraDesc's defaults are
// GfCamera's: 50 mm, 20.955 x 15.2908 mm, clipping 1 to 1e6) looks down -Z (`zUp`: along +Y, its up
// +Z) at the box's centre from the distance at which the box's half-diagonal across the image plane
// fills half the horizontal field of view, backed off by half the box's depth; a distance under the
// near clipping plane (1) is lengthened by it, so small scenes are not clipped. An empty or
// non-finite box (a stage with nothing to bound) frames the origin as a point.
// `gi render` passes the stage's bounding box (UsdGeomBBoxCache with extents hints, as usdrecord);
// the renderer, given a scene without a camera, its geometry's box with Y up; hdGi never needs it,
// as Hydra hosts (usdrecord included) always hand it a camera.
CameraDesc framingCamera(std::array<double, 3> center, std::array<double, 3> size, bool zUp);

}  // namespace gi
