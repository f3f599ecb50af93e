#include "camera.h"

#include "motion.h"
#include "sampling.h"

namespace gi {

namespace {
// UsdGeomCamera lengths (focal length, apertures) are in tenths of a scene unit.
constexpr float kTenthOfUnit = 0.1f;
}

Camera::Camera(const CameraDesc& desc, int width, int height) : desc_(desc), width_(width), height_(height) {
    orthographic_ = desc.projection == "orthographic";
    float focal = desc.focalLength > 0 && std::isfinite(desc.focalLength) ? desc.focalLength : 50.0f;
    // NaN/Inf lens values fall back to UsdGeomCamera's defaults (the renderer warns about the
    // transform; see Renderer); no setting may turn into a NaN ray.
    auto positive = [](float v, float fallback) { return v > 0 && std::isfinite(v) ? v : fallback; };
    auto finiteOr = [](float v, float fallback) { return std::isfinite(v) ? v : fallback; };
    float ha = positive(desc.horizontalAperture, 20.955f);
    float va = positive(desc.verticalAperture, 15.2908f);
    float imageAspect = float(width) / float(height);
    // expandAperture: grow whichever aperture is too small for the image's aspect ratio.
    if (ha / va < imageAspect) ha = va * imageAspect;
    else va = ha / imageAspect;
    // In double, rounded once: a host's projection matrix (below) gives the same floats.
    double scale = orthographic_ ? double(kTenthOfUnit) : 1.0 / focal;
    halfWidth_ = float(0.5 * ha * scale);
    halfHeight_ = float(0.5 * va * scale);
    offsetX_ = float(finiteOr(desc.horizontalApertureOffset, 0) * scale);
    offsetY_ = float(finiteOr(desc.verticalApertureOffset, 0) * scale);
    const Mat4& p = desc.projectionMatrix;
    if (desc.useProjection && p.isFinite() && p.m[0][0] != 0 && p.m[1][1] != 0) {
        // Perspective: P00 = 2n/(r-l), P20 = (r+l)/(r-l) (the window at unit distance);
        // orthographic: P00 = 2/(r-l), P30 = -(r+l)/(r-l).
        orthographic_ = p.m[2][3] == 0;
        halfWidth_ = float(1.0 / p.m[0][0]);
        halfHeight_ = float(1.0 / p.m[1][1]);
        offsetX_ = float(orthographic_ ? -p.m[3][0] / p.m[0][0] : p.m[2][0] / p.m[0][0]);
        offsetY_ = float(orthographic_ ? -p.m[3][1] / p.m[1][1] : p.m[2][1] / p.m[1][1]);
    }
    desc_.clipNear = desc.clipNear >= 0 && std::isfinite(desc.clipNear) ? desc.clipNear : 0.0f;
    desc_.clipFar = desc.clipFar > desc_.clipNear ? desc.clipFar : 1e30f;  // NaN too
    if (!desc.transform.isFinite()) desc_.transform = Mat4();
    Mat4 inverse;
    for (const Mat4& m : desc.motionTransforms)
        if (!m.isFinite() || !m.inverse(inverse)) desc_.motionTransforms.clear();  // the renderer warns
    if (desc_.motionTransforms.size() < 2) desc_.motionTransforms.clear();
    if (positive(desc.fStop, 0) > 0 && positive(desc.focusDistance, 0) > 0 && !orthographic_) {
        lensRadius_ = focal * kTenthOfUnit / (2 * desc.fStop);
        focusDistance_ = desc.focusDistance;
    }
    position_ = desc_.transform.point(Vec3(0.0f));
    forward_ = normalize(desc_.transform.vector(Vec3(0, 0, -1)));
}

Ray Camera::generateRay(float filmX, float filmY, Vec2 lens, float time) const {
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
    // Clipping planes are distances along the view axis; convert to distances along the ray.
    float axial = std::fabs(d.z) / length(d);
    r.tMin = std::max(0.0f, desc_.clipNear) / std::max(axial, 1e-6f);
    r.tMax = desc_.clipFar >= 1e29f ? kInf : desc_.clipFar / std::max(axial, 1e-6f);
    return r;
}

}  // namespace gi
