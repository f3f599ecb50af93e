// A camera as USD describes it: UsdGeomCamera's attributes, with the schema's defaults written
// once, here. renderer/camera_framing.h turns them into the window the image spans; camera.h
// into rays.
#pragma once
#include <string>
#include <vector>

#include "math.h"

namespace gi {

// The unit of a camera's focal length and apertures. UsdGeomCamera gives them in tenths of a
// scene unit; Hydra's HdCamera holds them in scene units (UsdImaging converts them, see
// camera_framing.h), so hdGi hands them over as Hydra has them.
enum class CameraLengthUnit { TenthsOfSceneUnit, SceneUnit };

struct CameraDesc {
    std::string name;
    std::string projection = "perspective";
    CameraLengthUnit lengthUnit = CameraLengthUnit::TenthsOfSceneUnit;  // of the next five
    float focalLength = 50;
    float horizontalAperture = 20.955f, verticalAperture = 15.2908f;
    float horizontalApertureOffset = 0, verticalApertureOffset = 0;
    float fStop = 0;
    float focusDistance = 0;
    float clipNear = 1e-4f, clipFar = 1e30f;
    // UsdGeomCamera's shutter:open and shutter:close, in frames relative to the rendered time.
    // Motion geometry (motion.h) spans [open, close]; when close > open each camera ray gets a
    // time in it, otherwise every ray sees shutter open (close < open is a host's mistake: warned).
    float shutterOpen = 0, shutterClose = 0;
    Mat4 transform;
    // A moving camera: camera-to-world at evenly spaced steps over the shutter (motion.h), step 0
    // at shutter open; empty (or unusable: NaN, singular) = `transform` at every time.
    std::vector<Mat4> motionTransforms;  // camera to world, USD convention
};

}  // namespace gi
