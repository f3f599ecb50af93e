#include "sampling.h"

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

}  // namespace gi
