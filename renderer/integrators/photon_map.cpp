#include "photon_map.h"

#include "specular_chain.h"

namespace gi {

PhotonLookup PhotonLookup::at(const ShadingPoint& sp, const Scene& scene) {
    return PhotonLookup{sp.si.p, recordNormal(sp), photonSurface(sp.si.shapeId, sp.si.instanceId), &scene, sp.si.ng};
}

void PhotonMap::gather(const PhotonLookup& at, int k, float maxRadius, std::vector<Neighbour>& out) const {
    const float stretch = kDiscFlattening * kDiscFlattening - 1;
    const Vec3 plane = at.discNormal();
    auto discDistance2 = [&](const Vec3& position) {
        Vec3 d = position - at.p;
        float along = std::min(std::abs(dot(d, at.n)), std::abs(dot(d, plane)));
        return lengthSquared(d) + stretch * along * along;
    };
    auto agrees = [&](const Photon& photon) { return octahedral::agrees(photon.normal, at.n, kPhotonNormalAgreement); };
    tree_.nearest(at.p, size_t(std::max(k, 1)), maxRadius * maxRadius, discDistance2, agrees, out);
}

bool clearBetween(const Scene& scene, const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb, float lift) {
    float scale = lift + 64 * std::max(pointErrorBound(a), pointErrorBound(b));
    Vec3 from = a + na * scale, d = b + nb * scale - from;
    float distance = length(d);
    if (!(distance > 0)) return true;
    RayStats stats;
    return !scene.occluded(from, d / distance, distance, stats);
}

bool PhotonMap::reaches(const Photon& photon, const PhotonLookup& at, float lift) const {
    if (!at.scene || at.surface == kAnySurface || photon.surface == at.surface) return true;
    // Lifted by a share of the disc's radius: clears the bumps of a tessellated floor.
    return clearBetween(*at.scene, at.p, at.n, photon.p, photon.n(), lift);
}

template <class Weight>
PhotonEstimate PhotonMap::estimate(const PhotonLookup& at, int k, float maxRadius, Weight&& weight,
                                   float coneFilter) const {
    PhotonEstimate e;
    if (tree_.empty() || k < 2 || !(maxRadius > 0)) return e;
    std::vector<Neighbour> found;
    found.reserve(size_t(k));
    gather(at, k, maxRadius, found);
    if (found.empty()) return e;
    float radius2 = maxRadius * maxRadius;
    size_t first = 0;
    if (found.size() == size_t(k)) {
        // The k-th photon (the heap's front) only sets the radius.
        radius2 = found.front().distance2;
        first = 1;
    }
    if (!(radius2 > 0)) return e;  // k photons on one spot: no area to divide by
    const float lift = 0.05f * std::sqrt(radius2);
    Color sum(0.0f);
    const Frame tangent(at.n);
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;  // the photons' places in the tangent plane
    for (size_t i = first; i < found.size(); ++i) {
        const Photon& photon = tree_[found[i].index];
        if (!reaches(photon, at, lift)) continue;
        float filter = coneFilter > 0 ? 1 - std::sqrt(found[i].distance2 / radius2) / coneFilter : 1.0f;
        // A photon on a face tilted from the query's plane stands for cos(tilt) of its power per
        // area of that plane (the face's area projects onto it shrunk by cos): the disc's pi r^2
        // is an area of the plane.
        float tilt = std::max(0.0f, dot(photon.n(), at.n));
        sum += weight(photon) * (std::max(0.0f, filter) * tilt);
        e.photons++;
        Vec3 d = tangent.toLocal(photon.p - at.p);
        sx += d.x, sy += d.y, sxx += double(d.x) * d.x, syy += double(d.y) * d.y, sxy += double(d.x) * d.y;
    }
    if (e.photons > 1) {
        double n = e.photons, mx = sx / n, my = sy / n;
        double cxx = sxx / n - mx * mx, cyy = syy / n - my * my, cxy = sxy / n - mx * my;
        double smaller = 0.5 * (cxx + cyy) - std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
        e.coverage = float(std::max(0.0, smaller) * 4 / radius2);
    }
    // A uniform density over the disc averages a cone's weight to 1 - 2 / (3 k).
    float normalisation = coneFilter > 0 ? 1 - 2 / (3 * coneFilter) : 1.0f;
    e.value = sum / (kPi * radius2 * normalisation);
    e.radius = std::sqrt(radius2);
    return e;
}

PhotonEstimate PhotonMap::irradiance(const PhotonLookup& at, int k, float maxRadius, float coneFilter) const {
    return estimate(at, k, maxRadius, [](const Photon& photon) { return photon.power; }, coneFilter);
}

PhotonEstimate PhotonMap::radiance(const ShadingPoint& sp, const Scene& scene, int k, float maxRadius,
                                   float coneFilter) const {
    return estimate(PhotonLookup::at(sp, scene), k, maxRadius, [&](const Photon& photon) {
        Vec3 wi = sp.frame.toLocal(photon.wi());
        // A photon that passed the normal test can still sit a hair below this point's
        // shading hemisphere (neighbouring facets, interpolated normals); mirrored into it,
        // a Lambertian surface keeps its whole irradiance instead of losing grazing photons.
        if (sp.woLocal.z * wi.z < 0) wi.z = -wi.z;
        return sp.bsdf.eval(sp.woLocal, wi) * photon.power;
    }, coneFilter);
}

PhotonEstimate PhotonMap::radianceBesideGlossyRays(const ShadingPoint& sp, const Scene& scene, int k,
                                                   float maxRadius) const {
    if (!sp.bsdf.hasGlossy()) return radiance(sp, scene, k, maxRadius);
    const Color lambertian = sp.bsdf.diffuseLobe(sp.woLocal);
    return estimate(PhotonLookup::at(sp, scene), k, maxRadius, [&](const Photon& photon) {
        if (!photon.caustic) return lambertian * photon.power;
        Vec3 wi = sp.frame.toLocal(photon.wi());
        if (sp.woLocal.z * wi.z < 0) wi.z = -wi.z;  // as in radiance()
        return sp.bsdf.eval(sp.woLocal, wi) * photon.power;
    });
}

bool PhotonMap::nearest(const PhotonLookup& at, float maxRadius, Photon* found) const {
    std::vector<Neighbour> candidates;
    candidates.reserve(kNearestCandidates);
    gather(at, kNearestCandidates, maxRadius, candidates);
    std::sort(candidates.begin(), candidates.end());
    for (const Neighbour& candidate : candidates) {
        const Photon& photon = tree_[candidate.index];
        if (reaches(photon, at, 0.05f * std::sqrt(candidate.distance2))) {
            *found = photon;
            return true;
        }
    }
    return false;
}

}  // namespace gi
