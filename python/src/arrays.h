// numpy <-> std::vector<float> conversions the gi._core bindings share.
#pragma once
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <initializer_list>
#include <stdexcept>
#include <vector>

namespace gi::bindings {

namespace nb = nanobind;

using ImageArray = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;

// A numpy array owning `v`, of N dimensions `shape`.
template <size_t N>
nb::ndarray<nb::numpy, float> toNumpy(std::vector<float> v, std::initializer_list<size_t> shape) {
    auto* heap = new std::vector<float>(std::move(v));
    nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
    return nb::ndarray<nb::numpy, float>(heap->data(), N, shape.begin(), owner);
}

// The first three channels of an (H, W, C >= 3) image as W*H*3 values; sets w and h.
inline std::vector<float> toVector(const ImageArray& a, size_t& w, size_t& h) {
    if (a.ndim() != 3 || a.shape(2) < 3) throw std::invalid_argument("expected an (H, W, 3) float32 array");
    h = a.shape(0), w = a.shape(1);
    size_t c = a.shape(2);
    std::vector<float> out(w * h * 3);
    for (size_t p = 0; p < w * h; ++p)
        for (size_t k = 0; k < 3; ++k) out[p * 3 + k] = a.data()[p * c + k];
    return out;
}

}  // namespace gi::bindings
