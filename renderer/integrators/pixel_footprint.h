// The world-space size of one pixel at a point, for the record spacing limits that Tabellion
// and Lamorlette express in pixels (R- and R+ of formula 2.33).
#pragma once
#include "../camera.h"

namespace gi {

struct PixelFootprint {
    Vec3 origin;
    float spread = 0;  // between neighbouring pixels' rays at the camera (orthographic cameras)
    float angle = 0;   // between neighbouring pixels' rays, radians (perspective cameras)

    // Measured from the rays through two neighbouring pixels at the image centre (the image's,
    // not a mosaic's: pilots of the render's pixels have the render's footprints). Points seen
    // through mirrors use their straight distance to the camera, which can only underestimate
    // the footprint: records there are denser than needed, never sparser.
    static PixelFootprint of(const Camera& camera) {
        const float x = 0.5f * camera.imageWidth(), y = 0.5f * camera.imageHeight();
        Ray a = camera.generateImageRay(x, y, Vec2(0.5f, 0.5f));
        Ray b = camera.generateImageRay(x + 1, y, Vec2(0.5f, 0.5f));
        PixelFootprint f;
        f.origin = a.o;
        f.spread = length(b.o - a.o);
        f.angle = 2 * std::asin(std::min(1.0f, 0.5f * length(b.d - a.d)));
        return f;
    }

    float at(const Vec3& p) const {
        float size = spread + angle * length(p - origin);
        return std::isfinite(size) && size > 1e-7f ? size : 1e-7f;
    }
};

}  // namespace gi
