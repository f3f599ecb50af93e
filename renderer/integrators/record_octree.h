// The irradiance cache's spatial index (thesis 2.4.5: an octree with the scene's extent). Each
// record is stored, pbrt-v1 style, in every node its influence box overlaps at the first depth
// whose nodes are smaller than the box; all of a record's nodes are then at one depth, so a
// lookup that walks the single root-to-leaf path containing the query point meets each
// candidate record exactly once.
//
// Lookups are const and run concurrently; insertion is not thread-safe and happens between
// parallel phases, so the index never serialises the render.
#pragma once
#include <cstdint>
#include <vector>

#include "../math.h"

namespace gi {

class RecordOctree {
public:
    // Forgets every record; the root is the cube around the given centre and radius.
    void reset(const Vec3& center, float radius);
    void insert(uint32_t id, const Vec3& center, float radius);

    // Calls visit(id) for every record whose influence box may contain p.
    template <class Visit>
    void forEachCandidate(const Vec3& p, Visit&& visit) const {
        if (nodes_.empty()) return;
        for (uint32_t id : nodes_[0].ids) visit(id);
        // Outside the root only the root's records (those too big or out of bounds) can apply.
        if (!(p.x >= lo_.x && p.y >= lo_.y && p.z >= lo_.z && p.x <= hi_.x && p.y <= hi_.y && p.z <= hi_.z)) return;
        Vec3 lo = lo_, hi = hi_;
        int node = 0;
        while (nodes_[node].firstChild >= 0) {
            Vec3 mid = (lo + hi) * 0.5f;
            int octant = 0;
            for (int axis = 0; axis < 3; ++axis) {
                if (p[axis] >= mid[axis]) {
                    octant |= 1 << axis;
                    lo[axis] = mid[axis];
                } else {
                    hi[axis] = mid[axis];
                }
            }
            node = nodes_[node].firstChild + octant;
            for (uint32_t id : nodes_[node].ids) visit(id);
        }
    }

    size_t nodeCount() const { return nodes_.size(); }
    size_t memoryBytes() const;

private:
    struct Node {
        int32_t firstChild = -1;  // eight consecutive children, or -1 for a leaf
        std::vector<uint32_t> ids;
    };
    void insert(int node, Vec3 lo, Vec3 hi, int depth, uint32_t id, const Vec3& boxLo, const Vec3& boxHi,
                float boxDiagonal2);

    static constexpr int kMaxDepth = 20;
    std::vector<Node> nodes_;
    Vec3 lo_, hi_;
};

}  // namespace gi
