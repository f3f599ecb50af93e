// Which light a shading point samples: a BVH over the lights that have a place in the scene (area
// lights, emissive triangles), each node weighted at the point by an importance bound (power over
// squared distance, zero where no light below it can face the point), as pbrt-v4's
// BVHLightSampler; infinite lights (distant, dome) share one probability among them by power.
// Light selection by power alone gave Sibenik's 53 window lights a probability of 0.0014 each
// beside the sun and sky that the glass hides from inside: rare, 700x-weighted samples that made
// the direct light speckle. The pmf depends on the point only (not its normal), so a BSDF-sampled
// ray that reaches a light evaluates the same pmf for MIS as the light sample would have used.
#pragma once
#include <cstdint>
#include <vector>

#include "sampling.h"

namespace gi {

class Light;

// What bounds a light's (or a group's) emission: its box, power, and a cone around `w` holding
// its surface normals (cosThetaO; -1: every direction) beyond which it emits up to cosThetaE
// (0: a hemisphere, as every UsdLux area light).
struct LightBounds {
    Vec3 lo{0.0f}, hi{0.0f};
    float phi = 0;  // luminance of the power
    Vec3 w{0, 0, 1};
    float cosThetaO = -1, cosThetaE = 0;
    bool twoSided = false;
};
LightBounds unionOf(const LightBounds& a, const LightBounds& b);

// A node's bounds as its importance at a point reads them: the box's centre and radius and the
// cone's sine computed once, not at each of the 2 log2(lights) calls a light sample makes (on
// Sibenik's 53 windows these calls were 6% of a path-traced render's time).
struct LightImportance {
    LightImportance() = default;
    explicit LightImportance(const LightBounds& b);
    // An upper bound of what the bounded lights can send to `p`, up to a common factor.
    float operator()(const Vec3& p) const;

    Vec3 center{0.0f}, w{0, 0, 1};
    float radius = 0, radiusSquared = 0, phi = 0;
    float cosThetaO = -1, sinThetaO = 0, cosThetaE = 0;
    bool twoSided = false;
};

class LightSampler {
public:
    LightSampler() = default;
    // `lights`: the scene's; `power`: each one's (luminance), the infinite lights' among them.
    LightSampler(const std::vector<const Light*>& lights, const std::vector<float>& power);
    // A light for point p with its probability in *pmf, or -1 when no light can reach p.
    int sample(const Vec3& p, float u, float* pmf) const;
    // The probability that sample(p, ...) picks `light`.
    float pmf(const Vec3& p, int light) const;
    bool empty() const { return infinite_.size() == 0 && nodes_.empty(); }

private:
    struct Node {
        LightImportance importance;
        int child1 = -1;  // second child (the first follows the node); -1 for a leaf
        int light = -1;   // a leaf's light
    };
    // Builds the subtree of lights [begin, end) at the next node; returns its index, its bounds in `bounds`.
    int build(std::vector<std::pair<int, LightBounds>>& lights, size_t begin, size_t end, uint64_t trail, int depth,
              LightBounds& bounds);

    std::vector<Node> nodes_;
    std::vector<uint64_t> trail_;      // per light: the child taken at each level (bit i = level i)
    Distribution1D infinite_;          // over infiniteIndex_, by power
    std::vector<int> infiniteIndex_;   // infinite lights' indices
    std::vector<int> infiniteSlot_;    // per light: its place in infiniteIndex_, or -1
    float pInfinite_ = 0;              // probability of picking an infinite light
};

}  // namespace gi
