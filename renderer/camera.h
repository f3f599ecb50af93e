// UsdGeomCamera's rays: perspective or orthographic through the window camera_framing.h gives
// (apertures and offsets conformed to the image), thin-lens depth of field from fStop and
// focusDistance, clipping planes as ray extents, a moving camera over the shutter.
#pragma once
#include "camera_desc.h"
#include "camera_framing.h"

namespace gi {

class Camera {
public:
    Camera() = default;
    Camera(const CameraDesc& desc, int width, int height, const ImageFraming& framing = {});
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
