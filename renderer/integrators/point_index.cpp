#include "point_index.h"

#include <tbb/parallel_sort.h>

namespace gi {

namespace {
// Spreads the low 10 bits of v to every third bit.
uint32_t spreadBits(uint32_t v) {
    v &= 0x3ff;
    v = (v | (v << 16)) & 0x030000ff;
    v = (v | (v << 8)) & 0x0300f00f;
    v = (v | (v << 4)) & 0x030c30c3;
    v = (v | (v << 2)) & 0x09249249;
    return v;
}
}  // namespace

void PointIndex::build(const std::vector<Vec3>& points) {
    size_t n = points.size();
    sorted_.clear();
    order_.clear();
    boxes_.clear();
    if (n == 0) return;
    Vec3 lo(kInf), hi(-kInf);
    for (const Vec3& p : points) lo = vmin(lo, p), hi = vmax(hi, p);
    Vec3 scale = Vec3(1023.0f) / vmax(hi - lo, Vec3(1e-20f));
    // (Morton code, index) pairs: a total order, so the sort's result is unique.
    std::vector<uint64_t> keys(n);
    for (size_t i = 0; i < n; ++i) {
        Vec3 q = (points[i] - lo) * scale;
        uint32_t code = spreadBits(uint32_t(q.x)) | (spreadBits(uint32_t(q.y)) << 1) | (spreadBits(uint32_t(q.z)) << 2);
        keys[i] = (uint64_t(code) << 32) | uint64_t(i);
    }
    tbb::parallel_sort(keys.begin(), keys.end());
    sorted_.resize(n);
    order_.resize(n);
    for (size_t i = 0; i < n; ++i) {
        order_[i] = uint32_t(keys[i]);
        sorted_[i] = points[order_[i]];
    }
    // Halving ranges until they hold at most kLeafSize points: depth ceil(log2(n / leaf)).
    int depth = 0;
    for (size_t range = n; range > kLeafSize; range = (range + 1) / 2) ++depth;
    boxes_.resize((size_t(2) << depth) - 1);
    buildBoxes(0, 0, uint32_t(n));
}

void PointIndex::buildBoxes(uint32_t node, uint32_t begin, uint32_t end) {
    Box box{Vec3(kInf), Vec3(-kInf)};
    if (end - begin <= kLeafSize) {
        for (uint32_t i = begin; i < end; ++i) box.lo = vmin(box.lo, sorted_[i]), box.hi = vmax(box.hi, sorted_[i]);
    } else {
        uint32_t mid = begin + (end - begin) / 2;
        buildBoxes(2 * node + 1, begin, mid);
        buildBoxes(2 * node + 2, mid, end);
        const Box &a = boxes_[2 * node + 1], &b = boxes_[2 * node + 2];
        box.lo = vmin(a.lo, b.lo);
        box.hi = vmax(a.hi, b.hi);
    }
    boxes_[node] = box;
}

}  // namespace gi
