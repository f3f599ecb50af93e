// A static index over many points for sphere queries: which shading points does a record
// reach? The points are sorted along a Morton curve and an implicit binary tree of bounding
// boxes is laid over the sorted array (node i's children are 2i+1 and 2i+2, each covering
// half of its range), so the index costs 16 bytes a point plus a box per eight points.
#pragma once
#include <cstdint>
#include <vector>

#include "../math.h"

namespace gi {

class PointIndex {
public:
    void build(const std::vector<Vec3>& points);

    // Calls visit(index) for every point within `radius` of `center`, in index-tree order.
    template <class Visit>
    void forEachInSphere(const Vec3& center, float radius, Visit&& visit) const {
        if (sorted_.empty()) return;
        float r2 = radius * radius;
        struct Entry {
            uint32_t node, begin, end;
        };
        Entry stack[64];
        int top = 0;
        stack[top++] = {0, 0, uint32_t(sorted_.size())};
        while (top > 0) {
            Entry e = stack[--top];
            const Box& box = boxes_[e.node];
            float d2 = 0;
            for (int axis = 0; axis < 3; ++axis) {
                float d = std::max(std::max(box.lo[axis] - center[axis], center[axis] - box.hi[axis]), 0.0f);
                d2 += d * d;
            }
            if (d2 > r2) continue;
            if (e.end - e.begin <= kLeafSize) {
                for (uint32_t i = e.begin; i < e.end; ++i)
                    if (lengthSquared(sorted_[i] - center) <= r2) visit(order_[i]);
                continue;
            }
            uint32_t mid = e.begin + (e.end - e.begin) / 2;
            stack[top++] = {2 * e.node + 2, mid, e.end};
            stack[top++] = {2 * e.node + 1, e.begin, mid};
        }
    }

    size_t memoryBytes() const {
        return sorted_.capacity() * sizeof(Vec3) + order_.capacity() * sizeof(uint32_t) + boxes_.capacity() * sizeof(Box);
    }

private:
    static constexpr uint32_t kLeafSize = 8;
    struct Box {
        Vec3 lo, hi;
    };
    void buildBoxes(uint32_t node, uint32_t begin, uint32_t end);

    std::vector<Vec3> sorted_;
    std::vector<uint32_t> order_;  // sorted position -> original index
    std::vector<Box> boxes_;
};

}  // namespace gi
