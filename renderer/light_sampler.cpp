#include "light_sampler.h"

#include <algorithm>
#include <cmath>

#include "light.h"

namespace gi {

namespace {

constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// cos(max(0, a - b)) and sin(max(0, a - b)) from the angles' sines and cosines (pbrt-v4).
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
    return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}

// The smallest cone (pbrt-v4's DirectionCone union) holding cones (wa, cosA) and (wb, cosB).
void unionCone(Vec3 wa, float cosA, Vec3 wb, float cosB, Vec3* w, float* cosTheta) {
    float thetaA = std::acos(std::clamp(cosA, -1.0f, 1.0f)), thetaB = std::acos(std::clamp(cosB, -1.0f, 1.0f));
    float thetaD = angleBetween(wa, wb);
    if (std::min(thetaD + thetaB, kPi) <= thetaA) {
        *w = wa, *cosTheta = cosA;
        return;
    }
    if (std::min(thetaD + thetaA, kPi) <= thetaB) {
        *w = wb, *cosTheta = cosB;
        return;
    }
    float thetaO = (thetaA + thetaD + thetaB) / 2;
    Vec3 axis = cross(wa, wb);
    if (thetaO >= kPi || !(lengthSquared(axis) > 0)) {
        *w = wa, *cosTheta = -1;
        return;
    }
    // wa rotated towards wb by thetaO - thetaA about their common normal (Rodrigues; wa is
    // perpendicular to the axis).
    float thetaR = thetaO - thetaA;
    Vec3 k = normalize(axis);
    *w = normalize(wa * std::cos(thetaR) + cross(k, wa) * std::sin(thetaR));
    *cosTheta = std::cos(thetaO);
}

}  // namespace

LightImportance::LightImportance(const LightBounds& b)
    : center((b.lo + b.hi) * 0.5f), w(b.w), radius(length(b.hi - b.lo) / 2), phi(b.phi), cosThetaO(b.cosThetaO),
      sinThetaO(safeSqrt(1 - b.cosThetaO * b.cosThetaO)), cosThetaE(b.cosThetaE), twoSided(b.twoSided) {
    radiusSquared = radius * radius;
}

float LightImportance::operator()(const Vec3& p) const {
    if (!(phi > 0)) return 0;
    Vec3 toPoint = p - center;
    float d2 = lengthSquared(toPoint);
    // Not below the box's half diagonal: a point inside or next to the lights gets no infinity.
    float clamped = std::max(d2, radius);
    float cosThetaW = d2 > 0 ? dot(w, toPoint) / std::sqrt(d2) : 1.0f;
    if (twoSided) cosThetaW = std::fabs(cosThetaW);
    float sinThetaW = safeSqrt(1 - cosThetaW * cosThetaW);
    // The directions from the box's bounding sphere towards p lie within thetaB of toPoint.
    float cosThetaB = d2 > radiusSquared ? safeSqrt(1 - radiusSquared / d2) : -1.0f;
    float sinThetaB = safeSqrt(1 - cosThetaB * cosThetaB);
    // The smallest angle between a normal of the lights and a direction from them to p.
    float cosThetaX = cosSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
    float sinThetaX = sinSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
    float cosThetaP = cosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
    if (cosThetaP <= cosThetaE) return 0;  // every light below faces away from p
    return phi * cosThetaP / clamped;
}

LightBounds unionOf(const LightBounds& a, const LightBounds& b) {
    if (!(a.phi > 0)) return b;
    if (!(b.phi > 0)) return a;
    LightBounds u;
    u.lo = vmin(a.lo, b.lo);
    u.hi = vmax(a.hi, b.hi);
    u.phi = a.phi + b.phi;
    unionCone(a.w, a.cosThetaO, b.w, b.cosThetaO, &u.w, &u.cosThetaO);
    u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
    u.twoSided = a.twoSided || b.twoSided;
    return u;
}

LightSampler::LightSampler(const std::vector<const Light*>& lights, const std::vector<float>& power) {
    trail_.assign(lights.size(), 0);
    infiniteSlot_.assign(lights.size(), -1);
    std::vector<std::pair<int, LightBounds>> bounded;
    std::vector<float> infinitePower;
    for (size_t i = 0; i < lights.size(); ++i) {
        if (!(power[i] > 0)) continue;  // emits nothing: never picked
        LightBounds b;
        if (lights[i]->isInfinite()) {
            infiniteSlot_[i] = int(infiniteIndex_.size());
            infiniteIndex_.push_back(int(i));
            infinitePower.push_back(power[i]);
        } else if (lights[i]->emissionBounds(&b) && b.phi > 0) {
            bounded.emplace_back(int(i), b);
        }
    }
    if (!infinitePower.empty()) infinite_ = Distribution1D(infinitePower.data(), int(infinitePower.size()));
    LightBounds all;
    if (!bounded.empty()) build(bounded, 0, bounded.size(), 0, 0, all);
    // pbrt-v4's split: each infinite light counts as much as all the bounded ones together (their
    // power over the whole scene's disc says nothing about what reaches a point inside).
    size_t groups = infiniteIndex_.size() + (nodes_.empty() ? 0 : 1);
    pInfinite_ = groups ? float(infiniteIndex_.size()) / float(groups) : 0;
}

int LightSampler::build(std::vector<std::pair<int, LightBounds>>& lights, size_t begin, size_t end, uint64_t trail,
                        int depth, LightBounds& bounds) {
    int index = int(nodes_.size());
    nodes_.emplace_back();
    if (end - begin == 1) {  // median splits: log2(lights) levels, far below the trail's 64 bits
        bounds = lights[begin].second;
        nodes_[index].importance = LightImportance(bounds);
        nodes_[index].light = lights[begin].first;
        trail_[size_t(lights[begin].first)] = trail;
        return index;
    }
    // Split at the median centroid along the widest axis of the centroids.
    Vec3 lo(kInf), hi(-kInf);
    for (size_t i = begin; i < end; ++i) {
        Vec3 c = (lights[i].second.lo + lights[i].second.hi) * 0.5f;
        lo = vmin(lo, c), hi = vmax(hi, c);
    }
    Vec3 extent = hi - lo;
    int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    size_t mid = (begin + end) / 2;
    std::nth_element(lights.begin() + long(begin), lights.begin() + long(mid), lights.begin() + long(end),
                     [axis](const auto& a, const auto& b) {
                         float ca = a.second.lo[axis] + a.second.hi[axis];
                         float cb = b.second.lo[axis] + b.second.hi[axis];
                         return ca < cb || (ca == cb && a.first < b.first);
                     });
    LightBounds firstBounds, secondBounds;
    build(lights, begin, mid, trail, depth + 1, firstBounds);
    int second = build(lights, mid, end, trail | (uint64_t(1) << depth), depth + 1, secondBounds);
    nodes_[index].child1 = second;
    bounds = unionOf(firstBounds, secondBounds);
    nodes_[index].importance = LightImportance(bounds);
    return index;
}

int LightSampler::sample(const Vec3& p, float u, float* pmf) const {
    *pmf = 0;
    if (u < pInfinite_) {
        float infinitePmf;
        int k = infinite_.sample(std::min(u / pInfinite_, kOneMinusEpsilon), &infinitePmf);
        *pmf = pInfinite_ * infinitePmf;
        return infiniteIndex_[size_t(k)];
    }
    if (nodes_.empty()) return -1;
    u = std::min((u - pInfinite_) / (1 - pInfinite_), kOneMinusEpsilon);
    float prob = 1 - pInfinite_;
    size_t node = 0;
    while (nodes_[node].child1 >= 0) {
        size_t first = node + 1, second = size_t(nodes_[node].child1);
        float i0 = nodes_[first].importance(p), i1 = nodes_[second].importance(p);
        if (!(i0 + i1 > 0)) return -1;
        float p0 = i0 / (i0 + i1);
        if (u < p0) {
            u = std::min(u / p0, kOneMinusEpsilon);
            prob *= p0;
            node = first;
        } else {
            u = std::min((u - p0) / (1 - p0), kOneMinusEpsilon);
            prob *= i1 / (i0 + i1);  // as pmf() computes it
            node = second;
        }
    }
    // A light that cannot reach p is not drawn; a lone light is not tested: its own sample()
    // rejects what it cannot reach as cheaply (one-sided rects and disks) as the importance would.
    if (nodes_.size() > 1 && !(nodes_[node].importance(p) > 0)) return -1;
    *pmf = prob;
    return nodes_[node].light;
}

float LightSampler::pmf(const Vec3& p, int light) const {
    if (light < 0 || size_t(light) >= infiniteSlot_.size()) return 0;
    if (infiniteSlot_[size_t(light)] >= 0) return pInfinite_ * infinite_.pmf(infiniteSlot_[size_t(light)]);
    if (nodes_.empty()) return 0;
    float prob = 1 - pInfinite_;
    uint64_t trail = trail_[size_t(light)];
    size_t node = 0;
    while (nodes_[node].child1 >= 0) {
        size_t first = node + 1, second = size_t(nodes_[node].child1);
        float i0 = nodes_[first].importance(p), i1 = nodes_[second].importance(p);
        if (!(i0 + i1 > 0)) return 0;
        bool takeSecond = trail & 1;
        prob *= (takeSecond ? i1 : i0) / (i0 + i1);
        node = takeSecond ? second : first;
        trail >>= 1;
    }
    if (nodes_[node].light != light || (nodes_.size() > 1 && !(nodes_[node].importance(p) > 0))) return 0;
    return prob;
}

}  // namespace gi
