// A balanced kd-tree over items stored in place (after Jensen's photon map, 2001, 6.3): the
// items of a range [lo, hi) are partitioned around their median, the lower half going to
// the left child and the rest to the right, down to leaves of at most kLeafSize items. Each
// node splits its cell (a box that starts as the items' bounds) along the cell's longest
// axis, so a query re-derives every node's axis and cell while it descends; only the split
// coordinates are stored, in heap order (4 bytes per node, so the upper levels stay in
// cache), and a leaf's items are contiguous. The items' positions are kept apart as well
// (12 bytes each): a query measures distances there and touches an item only when it is near
// enough to enter the result, which matters because queries are bound by cache misses.
//
// The build is parallel (tbb::parallel_invoke over the halves) and deterministic: the median
// partition depends only on the items' order. Queries are const and run on all threads.
// T must have a public `Vec3 p`.
#pragma once
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "../math.h"

namespace gi {

// Squared distance from p to the box [lo, hi] (zero inside).
inline float boxDistanceSquared(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    float d2 = 0;
    for (int axis = 0; axis < 3; ++axis) {
        float d = std::max(std::max(lo[axis] - p[axis], p[axis] - hi[axis]), 0.0f);
        d2 += d * d;
    }
    return d2;
}

inline int longestAxis(const Vec3& lo, const Vec3& hi) {
    Vec3 e = hi - lo;
    return e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
}

template <class T>
class KdTree {
public:
    struct Neighbour {
        float distance2;
        uint32_t index;
        bool operator<(const Neighbour& b) const { return distance2 < b.distance2; }
    };

    // Takes the items and reorders them into the tree. Positions must be finite.
    void build(std::vector<T> items) {
        items_ = std::move(items);
        lo_ = hi_ = Vec3(0.0f);
        splits_.clear();
        positions_.clear();
        if (items_.empty()) return;
        lo_ = hi_ = items_[0].p;
        for (const T& item : items_) lo_ = vmin(lo_, item.p), hi_ = vmax(hi_, item.p);
        // Heap indices of a tree whose leaves hold at most kLeafSize items: below 2^(depth+1).
        size_t nodes = 1;
        for (size_t n = items_.size(); n > kLeafSize; n = (n + 1) / 2) nodes = nodes * 2 + 1;
        splits_.assign(nodes, 0.0f);
        buildRange(0, 0, uint32_t(items_.size()), lo_, hi_);
        positions_.resize(items_.size());
        for (size_t i = 0; i < items_.size(); ++i) positions_[i] = items_[i].p;
    }

    const std::vector<T>& items() const { return items_; }
    const T& operator[](uint32_t i) const { return items_[i]; }
    size_t size() const { return items_.size(); }
    bool empty() const { return items_.empty(); }
    size_t memoryBytes() const {
        return items_.capacity() * sizeof(T) + positions_.capacity() * sizeof(Vec3) + splits_.capacity() * sizeof(float);
    }

    // The (at most) k items nearest to q under `distance2(position)` that `accept(item)`
    // admits (asked only of items near enough to enter). The pruning uses the Euclidean
    // distance to a node's cell, so distance2 must never be smaller than the Euclidean squared
    // distance (an ellipsoid stretched along some axis qualifies). Only items below
    // maxDistance2 count.
    // `out` is left as a max-heap on distance2: out.front() is the farthest.
    template <class Distance2, class Accept>
    void nearest(const Vec3& q, size_t k, float maxDistance2, Distance2&& distance2, Accept&& accept,
                 std::vector<Neighbour>& out) const {
        out.clear();
        if (k == 0 || items_.empty()) return;
        float radius2 = maxDistance2;
        traverse(q, radius2, [&](uint32_t i) {
            float d2 = distance2(positions_[i]);
            if (!(d2 < radius2) || !accept(items_[i])) return;
            if (out.size() < k) {
                out.push_back({d2, i});
                std::push_heap(out.begin(), out.end());
            } else {
                std::pop_heap(out.begin(), out.end());
                out.back() = {d2, i};
                std::push_heap(out.begin(), out.end());
            }
            if (out.size() == k) radius2 = out.front().distance2;  // only nearer items can still enter
        });
    }

    // The k nearest items by Euclidean distance.
    void nearest(const Vec3& q, size_t k, float maxDistance2, std::vector<Neighbour>& out) const {
        nearest(q, k, maxDistance2, [&](const Vec3& p) { return lengthSquared(p - q); }, [](const T&) { return true; },
                out);
    }

    // Calls visit(item, index, squaredDistance) for every item nearer than sqrt(radius2) to q.
    template <class Visit>
    void forEachWithin(const Vec3& q, float radius2, Visit&& visit) const {
        float r2 = radius2;
        traverse(q, r2, [&](uint32_t i) {
            float d2 = lengthSquared(positions_[i] - q);
            if (d2 < r2) visit(items_[i], i, d2);
        });
    }

private:
    static constexpr uint32_t kLeafSize = 16;         // ranges this small stay unsorted and are scanned
    static constexpr uint32_t kParallelSize = 32768;  // ranges this large build their halves in parallel

    void buildRange(size_t node, uint32_t lo, uint32_t hi, Vec3 cellLo, Vec3 cellHi) {
        if (hi - lo <= kLeafSize) return;
        int axis = longestAxis(cellLo, cellHi);
        uint32_t mid = lo + (hi - lo) / 2;
        std::nth_element(items_.begin() + lo, items_.begin() + mid, items_.begin() + hi,
                         [axis](const T& a, const T& b) { return a.p[axis] < b.p[axis]; });
        float split = items_[mid].p[axis];
        splits_[node] = split;
        Vec3 leftHi = cellHi, rightLo = cellLo;
        leftHi[axis] = split;
        rightLo[axis] = split;
        auto left = [&] { buildRange(2 * node + 1, lo, mid, cellLo, leftHi); };
        auto right = [&] { buildRange(2 * node + 2, mid, hi, rightLo, cellHi); };
        if (hi - lo >= kParallelSize) {
            tbb::parallel_invoke(left, right);
        } else {
            left();
            right();
        }
    }

    // Visits every item of every node whose cell is nearer to q than sqrt(radius2); radius2
    // may shrink during the visit. Nearer children first, so that a k-nearest search shrinks
    // its radius early.
    template <class Visit>
    void traverse(const Vec3& q, const float& radius2, Visit&& visit) const {
        struct Entry {
            size_t node;
            uint32_t lo, hi;
            Vec3 cellLo, cellHi;
        };
        // A balanced tree over 2^32 items has 29 levels above its leaves; each level leaves
        // one entry behind at most.
        Entry stack[64];
        int top = 0;
        stack[top++] = {0, 0, uint32_t(items_.size()), lo_, hi_};
        while (top > 0) {
            const Entry e = stack[--top];
            if (!(boxDistanceSquared(q, e.cellLo, e.cellHi) < radius2)) continue;
            if (e.hi - e.lo <= kLeafSize) {
                for (uint32_t i = e.lo; i < e.hi; ++i) visit(i);
                continue;
            }
            int axis = longestAxis(e.cellLo, e.cellHi);
            uint32_t mid = e.lo + (e.hi - e.lo) / 2;
            float split = splits_[e.node];
            Entry left{2 * e.node + 1, e.lo, mid, e.cellLo, e.cellHi}, right{2 * e.node + 2, mid, e.hi, e.cellLo, e.cellHi};
            left.cellHi[axis] = split;
            right.cellLo[axis] = split;
            bool leftFirst = q[axis] < split;
            stack[top++] = leftFirst ? right : left;
            stack[top++] = leftFirst ? left : right;
        }
    }

    std::vector<T> items_;
    std::vector<Vec3> positions_;  // items_[i].p
    std::vector<float> splits_;    // per internal node, in heap order (children of i: 2i + 1, 2i + 2)
    Vec3 lo_, hi_;
};

}  // namespace gi
