#include "camera.h"

#include <algorithm>
#include <cmath>

#include "motion.h"
#include "ray_cone.h"
#include "sampling.h"

namespace gi {

Camera::Camera(const CameraDesc& desc, int width, int height, const ImageFraming& framing,
               const PixelMosaic& mosaic)
    : desc_(desc), mosaic_(mosaic), width_(width), height_(height) {
    // NaN/Inf lens values fall back to UsdGeomCamera's defaults in cameraLens (the renderer warns
    // about them; see Renderer); no setting may turn into a NaN ray.
    const CameraLens lens = cameraLens(desc);
    const FilmWindow window = filmWindow(lens, framing, width, height);
    orthographic_ = lens.orthographic;
    halfWidth_ = float(window.halfWidth);
    halfHeight_ = float(window.halfHeight);
    offsetX_ = float(window.centerX);
    offsetY_ = float(window.centerY);
    desc_.clipNear = desc.clipNear >= 0 && std::isfinite(desc.clipNear) ? desc.clipNear : 0.0f;
    desc_.clipFar = desc.clipFar > desc_.clipNear ? desc.clipFar : CameraDesc().clipFar;  // NaN too
    if (!desc.transform.isFinite()) desc_.transform = Mat4();
    Mat4 inverse;
    for (const Mat4& m : desc.motionTransforms)
        if (!m.isFinite() || !m.inverse(inverse)) desc_.motionTransforms.clear();  // the renderer warns
    if (desc_.motionTransforms.size() < 2) desc_.motionTransforms.clear();
    // A pixel's cone (ray_cone.h), as one spread for every ray (the ray cones' own
    // simplification) or, orthographic, its width in the world.
    const float pixel = kConeSpreadScale * 2 * halfHeight_ / float(height_);
    pixelCone_ = orthographic_ ? pixel * length(desc_.transform.vector(Vec3(1, 0, 0))) : pixel;
    auto positive = [](float v) { return v > 0 && std::isfinite(v); };
    if (positive(desc.fStop) && positive(desc.focusDistance) && !orthographic_) {
        lensRadius_ = lens.focalLength / (2 * desc.fStop);
        focusDistance_ = desc.focusDistance;
    }
    position_ = desc_.transform.point(Vec3(0.0f));
    forward_ = normalize(desc_.transform.vector(Vec3(0, 0, -1)));
}

Ray Camera::generateRay(float filmX, float filmY, Vec2 lens, float time) const {
    if (mosaic_.tile <= 0) return generateImageRay(filmX, filmY, lens, time);
    // A film position's tile is its pixel's (a pixel's samples lie in the pixel).
    const int column = std::clamp(int(std::floor(filmX)) / mosaic_.tile, 0, mosaic_.across - 1);
    const int row = std::clamp(int(std::floor(filmY)) / mosaic_.tile, 0, mosaic_.tiles() / mosaic_.across - 1);
    const int t = row * mosaic_.across + column;
    return generateImageRay(float(mosaic_.x0[size_t(t)]) + (filmX - float(column * mosaic_.tile)),
                            float(mosaic_.y0[size_t(t)]) + (filmY - float(row * mosaic_.tile)), lens, time);
}

Ray Camera::generateImageRay(float filmX, float filmY, Vec2 lens, float time) const {
    float sx = (2 * filmX / width_ - 1) * halfWidth_ + offsetX_;
    float sy = (1 - 2 * filmY / height_) * halfHeight_ + offsetY_;
    Vec3 o(0.0f), d;
    if (orthographic_) {
        o = Vec3(sx, sy, 0);
        d = Vec3(0, 0, -1);
    } else {
        d = Vec3(sx, sy, -1);
        if (lensRadius_ > 0) {
            Vec2 l = sampleConcentricDisk(lens) * lensRadius_;
            Vec3 focus = d * focusDistance_;  // d.z = -1, so this lies on the focus plane
            o = Vec3(l.x, l.y, 0);
            d = focus - o;
        }
    }
    Ray r;
    const Mat4 toWorld = desc_.motionTransforms.empty() ? desc_.transform : atTime(desc_.motionTransforms, time);
    r.o = toWorld.point(o);
    Vec3 wd = toWorld.vector(d);
    r.time = time;
    float len = length(wd);
    r.d = wd / len;
    (orthographic_ ? r.coneWidth : r.coneSpread) = pixelCone_;
    // Clipping planes are distances along the view axis; convert to distances along the ray.
    float axial = std::fabs(d.z) / length(d);
    r.tMin = std::max(0.0f, desc_.clipNear) / std::max(axial, 1e-6f);
    r.tMax = desc_.clipFar >= 1e29f ? kInf : desc_.clipFar / std::max(axial, 1e-6f);
    return r;
}

}  // namespace gi
