#include "disc_area.h"

#include <cmath>

#include "lighting.h"
#include "path.h"
#include "specular_chain.h"

namespace gi {

float discArea(const PhotonLookup& at, float radius, Sampler& sampler, RayStats& stats) {
    const float full = kPi * radius * radius;
    if (!at.scene || !(radius > 0)) return full;
    const Scene& scene = *at.scene;
    Vec3 plane = at.discNormal();
    if (dot(plane, at.n) < 0) plane = -plane;
    const Frame disc(plane);
    // The flattened disc reaches r / kDiscFlattening off its plane (photon_map.cpp).
    const float band = radius / kDiscFlattening;
    const float lift = 0.05f * radius;
    const float stretch = kDiscFlattening * kDiscFlattening - 1;
    const Vec2 shift = sampler.get2D();
    // Whether the surface a probe meets would hold photons the lookup counts.
    auto counts = [&](int j) {
        float angle = 2 * kPi * std::fmod(shift.x + float(j) / kDiscProbes, 1.0f);
        float along = radius * std::sqrt(std::fmod(shift.y + float(j) * 13 / kDiscProbes, 1.0f));
        Vec3 onDisc = at.p + (disc.s * std::cos(angle) + disc.t * std::sin(angle)) * along;
        Ray ray{onDisc + plane * band, -plane, 0.0f, 2 * band};
        Intersection hit = intersectVisible(scene, ray, sampler, stats, false);
        if (hit.kind != Intersection::Kind::Surface) return false;
        Vec3 d = hit.si.p - at.p;
        float off = std::min(std::abs(dot(d, at.n)), std::abs(dot(d, plane)));
        if (lengthSquared(d) + stretch * off * off > radius * radius) return false;
        ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
        if (!sp.bsdf.hasNonDelta() || isBlack(sp.bsdf.albedo())) return false;  // stores no photon
        Vec3 n = recordNormal(sp);
        if (dot(n, at.n) < kPhotonNormalAgreement) return false;
        uint32_t surface = photonSurface(hit.si.shapeId, hit.si.instanceId);
        if (at.surface != kAnySurface && surface != at.surface && !clearBetween(scene, at.p, at.n, hit.si.p, n, lift))
            return false;
        return true;
    };
    // The even probes are the 8-point lattice (generator 5/8): if all of them count, the disc is full.
    int counted = 0;
    for (int j = 0; j < kDiscProbes; j += 2) counted += counts(j);
    if (counted == kDiscProbes / 2) return full;
    for (int j = 1; j < kDiscProbes; j += 2) counted += counts(j);
    return full * std::max(float(counted) / kDiscProbes, kMinDiscShare);
}

Color overSurfaceInDisc(const PhotonEstimate& e, int k, const PhotonLookup& at, Sampler& sampler, RayStats& stats) {
    if (e.photons == 0) return Color(0.0f);
    if (e.photons >= k - 1) return e.coverageCorrected();  // the k-th photon set the radius
    if (e.fillsDisc()) return e.value;  // many photons, spread over the whole disc: no probe needed
    return e.value * (kPi * e.radius * e.radius / discArea(at, e.radius, sampler, stats));
}

}  // namespace gi
