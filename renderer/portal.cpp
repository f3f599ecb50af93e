#include "portal.h"

#include "scene.h"

namespace gi {

float Portal::intersect(const Vec3& o, const Vec3& d) const {
    Vec3 n = cross(e1, e2);
    float denom = dot(d, n);
    if (!(std::fabs(denom) > 0)) return kInf;
    float t = dot(corner - o, n) / denom;
    if (!(t > 0)) return kInf;
    Vec3 q = o + d * t - corner;
    float s = dot(q, e1) / dot(e1, e1), v = dot(q, e2) / dot(e2, e2);
    return s >= 0 && s <= 1 && v >= 0 && v <= 1 ? t : kInf;
}

PortalSet::PortalSet(std::vector<Portal> portals) : portals_(std::move(portals)) {
    std::vector<float> areas;
    for (const Portal& p : portals_) {
        areas.push_back(p.area);
        totalArea_ += p.area;
    }
    if (!areas.empty()) byArea_ = Distribution1D(areas.data(), int(areas.size()));
}

bool PortalSet::guides(const Vec3& p) const {
    if (portals_.empty()) return false;
    for (const Portal& portal : portals_)
        if (!portal.behind(p)) return false;
    return true;
}

bool PortalSet::sampleDirection(const Vec3& p, Vec2 u, Vec3* wi, float* pdfOut) const {
    float pmf, ux;
    int i = byArea_.sample(u.x, &pmf, &ux);
    if (i < 0 || !(pmf > 0)) return false;
    const Portal& portal = portals_[size_t(i)];
    Vec3 q = portal.corner + portal.e1 * ux + portal.e2 * u.y;
    Vec3 d = q - p;
    float distance2 = lengthSquared(d);
    if (!(distance2 > 0)) return false;
    *wi = d / std::sqrt(distance2);
    *pdfOut = pdf(p, *wi);
    return *pdfOut > 0;
}

float PortalSet::pdf(const Vec3& p, const Vec3& wi) const {
    float total = 0;
    for (size_t i = 0; i < portals_.size(); ++i) {
        const Portal& portal = portals_[i];
        float t = portal.intersect(p, wi);
        if (!std::isfinite(t)) continue;
        float cosine = std::fabs(dot(wi, portal.travel));
        if (!(cosine > 1e-6f)) continue;
        total += byArea_.pmf(int(i)) * t * t / (portal.area * cosine);
    }
    return total;
}

int PortalSet::samplePoint(const Distribution1D& weights, Vec2 u, Vec3* point, float* pdfArea) const {
    float pmf, ux;
    if (weights.size() != int(portals_.size()) || !(weights.total() > 0)) return -1;
    int i = weights.sample(u.x, &pmf, &ux);
    if (i < 0 || !(pmf > 0)) return -1;
    const Portal& portal = portals_[size_t(i)];
    *point = portal.corner + portal.e1 * ux + portal.e2 * u.y;
    *pdfArea = pmf / portal.area;
    return i;
}

// A portal over an opening, checked: finite, of positive size, light on its +Z side reaching
// the sky more often than on its -Z (interior) side, which shows it faces the right way.
bool makePortal(const Scene& scene, const LightDesc& d, Portal& portal) {
    const Mat4& m = d.transform;
    portal.name = d.name;
    portal.corner = m.point(Vec3(-d.width / 2, -d.height / 2, 0));
    portal.e1 = m.vector(Vec3(d.width, 0, 0));
    portal.e2 = m.vector(Vec3(0, d.height, 0));
    Vec3 n = cross(portal.e1, portal.e2);
    portal.area = length(n);
    if (!isFinite(portal.corner) || !isFinite(n) || !(portal.area > 0) || !std::isfinite(portal.area)) {
        scene.warn("portal " + d.name + ": zero size, or NaN/Inf in its size or transform; ignored");
        return false;
    }
    n = n / portal.area;
    portal.travel = dot(n, m.vector(Vec3(0, 0, -1))) < 0 ? -n : n;  // UsdLux: light passes along -Z
    constexpr int kProbes = 32;
    int escapesOutward = 0, escapesInward = 0;
    Frame frame(portal.travel);
    RayStats stats;
    Vec3 c = portal.center();
    float lift = 1e-4f * (1 + length(c)) + 1e-3f * std::sqrt(portal.area);
    for (int i = 0; i < kProbes; ++i) {
        Vec2 u((i + 0.5f) / kProbes, std::fmod(i * 0.618034f, 1.0f));
        Vec3 dir = frame.toWorld(sampleCosineHemisphere(u));  // into the interior side
        escapesInward += !scene.occluded(c + dir * lift, dir, kInf, stats);
        escapesOutward += !scene.occluded(c - dir * lift, -dir, kInf, stats);
    }
    // Clearly: where both sides are walled in (a window onto a narrow courtyard) one stray ray
    // would decide, so the portal as authored is kept unless a few more rays escape inside
    // (Sibenik's Portal_19 was left out on 1 ray against 0 of 32; its glass is 5 cm inside it).
    if (escapesInward > escapesOutward + kProbes / 8) {
        scene.warn("portal " + d.name + ": faces the wrong way (its -Z side, where the light would go, sees more sky than its "
             "+Z side: " + std::to_string(escapesInward) + " and " + std::to_string(escapesOutward) + " of " +
             std::to_string(kProbes) + " rays); ignored");
        return false;
    }
    return true;
}

}  // namespace gi
