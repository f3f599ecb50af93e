#include "sampling.h"

#include <algorithm>

namespace gi {

Distribution1D::Distribution1D(const float* weights, int n) : func_(weights, weights + n), cdf_(n + 1) {
    for (float& f : func_)
        if (!(f > 0) || !std::isfinite(f)) f = 0;  // NaN, Inf and negatives carry no probability
    double sum = 0;
    cdf_[0] = 0;
    for (int i = 0; i < n; ++i) {
        sum += func_[i];
        cdf_[i + 1] = float(sum);
    }
    total_ = float(sum);
    if (!(total_ > 0)) {
        std::fill(func_.begin(), func_.end(), 1.0f);
        for (int i = 0; i <= n; ++i) cdf_[i] = float(i);
        total_ = float(n);
    }
}

int Distribution1D::sample(float u, float* pmfOut, float* remapped) const {
    float target = u * total_;
    int index = int(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin()) - 1;
    index = std::clamp(index, 0, int(func_.size()) - 1);
    while (func_[index] == 0 && index + 1 < int(func_.size())) ++index;  // never pick an empty bin
    if (pmfOut) *pmfOut = func_[index] / total_;
    if (remapped) {
        float width = cdf_[index + 1] - cdf_[index];
        *remapped = width > 0 ? std::min((target - cdf_[index]) / width, 0.99999994f) : 0.5f;
    }
    return index;
}

SphericalRectangle::SphericalRectangle(const Vec3& p, const Vec3& s, const Vec3& ex, const Vec3& ey) : p_(p) {
    float exLength = length(ex), eyLength = length(ey);
    x_ = ex / exLength;
    y_ = ey / eyLength;
    z_ = cross(x_, y_);
    Vec3 d = s - p;
    x0_ = dot(d, x_), y0_ = dot(d, y_), z0_ = dot(d, z_);
    if (z0_ > 0) {  // z_ towards p's side, so that z0 < 0
        z_ = -z_;
        z0_ = -z0_;
    }
    if (!(z0_ < 0)) return;  // p in the plane: no solid angle
    x1_ = x0_ + exLength, y1_ = y0_ + eyLength;
    Vec3 v00(x0_, y0_, z0_), v01(x0_, y1_, z0_), v10(x1_, y0_, z0_), v11(x1_, y1_, z0_);
    Vec3 n0 = normalize(cross(v00, v10)), n1 = normalize(cross(v10, v11));
    Vec3 n2 = normalize(cross(v11, v01)), n3 = normalize(cross(v01, v00));
    float g0 = angleBetween(-n0, n1), g1 = angleBetween(-n1, n2);
    float g2 = angleBetween(-n2, n3), g3 = angleBetween(-n3, n0);
    solidAngle = std::max(0.0f, g0 + g1 + g2 + g3 - 2 * kPi);
    b0_ = n0.z, b1_ = n2.z;
    g0g1_ = g0 + g1 - 2 * kPi;
    g2g3_ = g2 + g3;
}

Vec3 SphericalRectangle::sample(Vec2 u) const {
    // The x at which the sampled direction's sub-rectangle [x0, x] holds u.x of the solid angle.
    float au = u.x * g0g1_ + (u.x - 1) * g2g3_;
    float fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
    float cu = std::copysign(1 / std::sqrt(fu * fu + b0_ * b0_), fu);
    cu = std::clamp(cu, -0x1.fffffep-1f, 0x1.fffffep-1f);
    float xu = std::clamp(-(cu * z0_) / safeSqrt(1 - cu * cu), x0_, x1_);
    // Then y, uniform in the height's sine along that x.
    float dd = std::sqrt(xu * xu + z0_ * z0_);
    float h0 = y0_ / std::sqrt(dd * dd + y0_ * y0_), h1 = y1_ / std::sqrt(dd * dd + y1_ * y1_);
    float hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
    float yv = hv2 < 1 - 1e-4f ? hv * dd / std::sqrt(1 - hv2) : y1_;
    return p_ + x_ * xu + y_ * yv + z_ * z0_;
}

}  // namespace gi
