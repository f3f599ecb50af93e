// UsdGeomCamera's rays: perspective or orthographic through the window camera_framing.h gives
// (apertures and offsets conformed to the image), thin-lens depth of field from fStop and
// focusDistance, clipping planes as ray extents, a moving camera over the shutter.
#pragma once
#include <vector>

#include "camera_desc.h"
#include "camera_framing.h"

namespace gi {

// Square tiles of the image laid side by side, row by row, as an image of their own: auto's
// pilots render the render's own pixels in a few places (auto_select.h). Mosaic pixel (x, y)
// is the image's pixel (x0[t] + x % tile, y0[t] + y % tile) of tile t = (y / tile) * across +
// x / tile; the tiles fill whole rows. Empty (tile 0): the image itself. (A pixel filter wider
// than the box spreads a tile's edge samples into its neighbour in the mosaic: a pilot's error.)
struct PixelMosaic {
    int tile = 0, across = 1;
    std::vector<int> x0, y0;  // each tile's top-left pixel in the image
    int tiles() const { return int(x0.size()); }
    int width() const { return tile * across; }
    int height() const { return tile * (tiles() / across); }
};

class Camera {
public:
    Camera() = default;
    // A width x height image; with a mosaic, its film is the mosaic's tiles of that image.
    Camera(const CameraDesc& desc, int width, int height, const ImageFraming& framing = {},
           const PixelMosaic& mosaic = {});
    // filmX, filmY in pixels of the film (x right, y down); lens sample in [0,1)^2; time within
    // the shutter (Ray::time; it places a moving camera and is the ray's time).
    Ray generateRay(float filmX, float filmY, Vec2 lens, float time = 0) const;
    // The same through the image's pixels, whatever the mosaic (footprints, seen surfaces).
    Ray generateImageRay(float imageX, float imageY, Vec2 lens, float time = 0) const;
    int imageWidth() const { return width_; }
    int imageHeight() const { return height_; }
    bool moves() const { return !desc_.motionTransforms.empty(); }
    Vec3 position() const { return position_; }
    bool hasShutterInterval() const { return desc_.shutterClose > desc_.shutterOpen; }  // false for NaN
    Vec3 forward() const { return forward_; }

private:
    CameraDesc desc_;
    PixelMosaic mosaic_;
    int width_ = 1, height_ = 1;
    float halfWidth_ = 1, halfHeight_ = 1;  // of the film window, at unit distance (perspective) or in scene units
    float pixelCone_ = 0;  // a camera ray's cone: its spread, or its width when orthographic
    float offsetX_ = 0, offsetY_ = 0;
    float lensRadius_ = 0, focusDistance_ = 1;
    bool orthographic_ = false;
    Vec3 position_, forward_;
};

}  // namespace gi
