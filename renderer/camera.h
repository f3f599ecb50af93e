// UsdGeomCamera: perspective or orthographic projection from focal length and apertures,
// thin-lens depth of field from fStop and focusDistance. The aperture is expanded to the
// image's aspect ratio (UsdRenderSettings' default conform policy, "expandAperture").
#pragma once
#include <string>
#include <vector>

#include "math.h"

namespace gi {

struct CameraDesc {
    std::string name;
    std::string projection = "perspective";
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
    // A host that has already conformed the camera to its viewport (Hydra) gives its projection
    // matrix instead (OpenGL convention, row vectors: NDC [-1,1]^2 spans the image); the
    // apertures are then unused. Read as the same window the apertures give, so both front ends
    // trace bit-identical camera rays for the same camera.
    bool useProjection = false;
    Mat4 projectionMatrix;
};

class Camera {
public:
    Camera() = default;
    Camera(const CameraDesc& desc, int width, int height);
    // filmX, filmY in pixels (x right, y down); lens sample in [0,1)^2; time within the shutter
    // (Ray::time; it places a moving camera and is the ray's time).
    Ray generateRay(float filmX, float filmY, Vec2 lens, float time = 0) const;
    bool moves() const { return !desc_.motionTransforms.empty(); }
    Vec3 position() const { return position_; }
    bool hasShutterInterval() const { return desc_.shutterClose > desc_.shutterOpen; }  // false for NaN
    Vec3 forward() const { return forward_; }

private:
    CameraDesc desc_;
    int width_ = 1, height_ = 1;
    float halfWidth_ = 1, halfHeight_ = 1;  // of the film window, at unit distance (perspective) or in scene units
    float offsetX_ = 0, offsetY_ = 0;
    float lensRadius_ = 0, focusDistance_ = 1;
    bool orthographic_ = false;
    Vec3 position_, forward_;
};

}  // namespace gi
