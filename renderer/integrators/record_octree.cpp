#include "record_octree.h"

namespace gi {

void RecordOctree::reset(const Vec3& center, float radius) {
    float r = std::isfinite(radius) && radius > 0 ? radius * 1.01f : 1.0f;
    lo_ = center - Vec3(r);
    hi_ = center + Vec3(r);
    nodes_.assign(1, Node());
}

void RecordOctree::insert(uint32_t id, const Vec3& center, float radius) {
    if (nodes_.empty()) reset(center, radius);
    Vec3 boxLo = center - Vec3(radius), boxHi = center + Vec3(radius);
    bool inside = boxLo.x >= lo_.x && boxLo.y >= lo_.y && boxLo.z >= lo_.z && boxHi.x <= hi_.x &&
                  boxHi.y <= hi_.y && boxHi.z <= hi_.z;
    if (!inside || !std::isfinite(radius)) {
        nodes_[0].ids.push_back(id);  // the root is visited by every lookup
        return;
    }
    insert(0, lo_, hi_, 0, id, boxLo, boxHi, lengthSquared(boxHi - boxLo));
}

void RecordOctree::insert(int node, Vec3 lo, Vec3 hi, int depth, uint32_t id, const Vec3& boxLo, const Vec3& boxHi,
                          float boxDiagonal2) {
    if (depth == kMaxDepth || lengthSquared(hi - lo) < boxDiagonal2) {
        nodes_[node].ids.push_back(id);
        return;
    }
    if (nodes_[node].firstChild < 0) {
        nodes_[node].firstChild = int32_t(nodes_.size());
        nodes_.resize(nodes_.size() + 8);  // invalidates references into nodes_: none are held
    }
    Vec3 mid = (lo + hi) * 0.5f;
    for (int octant = 0; octant < 8; ++octant) {
        Vec3 childLo, childHi;
        bool overlaps = true;
        for (int axis = 0; axis < 3; ++axis) {
            bool upper = octant & (1 << axis);
            childLo[axis] = upper ? mid[axis] : lo[axis];
            childHi[axis] = upper ? hi[axis] : mid[axis];
            overlaps = overlaps && boxLo[axis] <= childHi[axis] && boxHi[axis] >= childLo[axis];
        }
        if (overlaps) insert(nodes_[node].firstChild + octant, childLo, childHi, depth + 1, id, boxLo, boxHi, boxDiagonal2);
    }
}

size_t RecordOctree::memoryBytes() const {
    size_t bytes = nodes_.capacity() * sizeof(Node);
    for (const Node& n : nodes_) bytes += n.ids.capacity() * sizeof(uint32_t);
    return bytes;
}

}  // namespace gi
