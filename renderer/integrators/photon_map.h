// A photon map (thesis 2.4.7): photons in a kd-tree, and the density estimates read from it.
//
// The thesis's Sibenik renders came out too bright because photons stored on the outside of
// thin walls were counted on the inside. Three guards keep a query on its own surface:
// - a photon counts only if the normal it was stored with (the side it arrived at) agrees
//   with the query's normal, cos >= kPhotonNormalAgreement (60 degrees): the two faces of a wall
//   face opposite ways, so no photon crosses it, whatever its thickness;
// - the search region is a disc, not a sphere (Jensen 2001, 7.2): distance along the normal
//   (PhotonLookup says which) counts kDiscFlattening times, so photons on a nearby parallel
//   surface (a step, a shelf) drop out long before those in the query's plane. The area divided
//   by stays pi r^2, exact on a plane; on a sphere of radius R it shrinks by
//   (kDiscFlattening^2 - 1) r^2 / (4 R^2), 0.2% at r = R / 20;
// - a photon that agrees but landed on another surface (the ground outside a wall, level with
//   the floor inside) counts only if nothing blocks the line between it and the query, both
//   lifted off their surfaces. At most k shadow rays, and only where surfaces meet: photons
//   from the query's own surface are never tested. An occluded photon is dropped from the
//   sum but not from the disc, so the estimate there reads like the edge of a lit area
//   (slightly dark) rather than the light on the other side.
//
// With k photons found the estimate divides the flux of the k - 1 nearest by pi r_k^2:
// given r_k, the k - 1 inner photons are uniform over the disc, so for locally uniform
// density this is unbiased, where dividing all k by pi r_k^2 is k / (k - 1) too bright.
// With fewer than k within maxRadius, all of them over pi maxRadius^2 (a fixed-radius
// estimate, unbiased too).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "kd_tree.h"
#include "lighting.h"
#include "photon.h"

namespace gi {

// 60 degrees: enough to keep the two faces of a wall (and a wall from the floor it stands on)
// apart. Faceted geometry needs the room: Sibenik has face normals only, and 85% of its area lies
// on faces with a neighbour bent 26-80 degrees away (moldings, columns, ribs); at 0.9 (26 degrees)
// a disc on one face lost its neighbours' photons but not their area, and final gathering read
// darker the more photons it had (Sibenik under its sky, map read at the gather hit, 0.5 / 8
// million photons: 0.961 / 0.911 of the path tracer; 0.996 / 0.970 now). The photons of a tilted
// face count by cos(tilt) (PhotonMap::estimate), so 60 degrees does not count them per their own,
// larger area: with the agreement alone the progressive photon map read 2-3% bright.
inline constexpr float kPhotonNormalAgreement = 0.5f;
inline constexpr float kDiscFlattening = 3.0f;
inline constexpr uint32_t kAnySurface = 0xffffffffu;

// Whether nothing blocks the line between two surface points, both lifted off their surfaces
// along their normals by `lift` (plus the usual ray offset), so that the line runs through
// the open space in front of them: clear along a floor, blocked by a wall standing on it.
bool clearBetween(const Scene& scene, const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb, float lift);

struct PhotonEstimate {
    Color value{0.0f};
    int photons = 0;   // photons the estimate used
    float radius = 0;  // of the disc it covered (maxRadius when fewer than k were found)
    // How much of the disc the photons' surface covers: the smaller variance of their places in
    // the tangent plane (about their mean) over a full disc's, r^2 / 4. About 1 where the surface
    // fills the disc; a strip of width w across it gives w^2 / 3r^2, a half disc (an edge, a
    // corner) 0.28: there the estimate, which divides by the whole disc's area, reads dark.
    float coverage = 0;

    // Whether the photons say the surface does not fill the disc (the threshold below).
    bool partlyCovered() const { return coverage < std::min(0.7f, 1 - 2.9f / std::sqrt(float(photons))); }
    // Whether enough photons spread over the whole disc to say the surface fills it.
    bool fillsDisc() const { return photons >= 16 && !partlyCovered(); }

    // The estimate divided by the share of its disc the surface covers, where the photons say it
    // does not cover it all: coverage below 0.7 and below what 99% of estimates over a full disc
    // reach with this many photons (1 - 2.9 / sqrt(n), fitted to simulation: 0.59 for 50, 0.71 for
    // 100), from 16 photons on. The share is that of a strip across the disc with that coverage,
    // 2 sqrt(3 c) / pi (a half disc, 0.28, reads 0.58 for 0.5; never below 0.25). The density an
    // estimate divides by is then the surface's, not the disc's, at edges, corners and thin or
    // curved geometry; where the surface fills the disc (every point but edges, as the radius
    // shrinks) nothing changes.
    Color coverageCorrected() const {
        if (photons < 16 || !partlyCovered()) return value;
        float covered = std::clamp(2 * std::sqrt(3 * coverage) / kPi, 0.25f, 1.0f);
        return value / covered;
    }
};

// Where light is wanted: a point, the unit normal on the side it is wanted (the shading normal,
// which the photons' normals are compared with), its surface, the scene for the visibility guard
// (none: photons from other surfaces count unchecked), and the geometric normal, either side
// (zero: n). A photon's distance off the disc is the smaller of its offsets along n and along ng.
// Photons land on the flat facets of a smooth-shaded mesh, which the interpolated normal tilts
// away from: along n alone the facet's own photons counted as off the disc, and on Sponza's
// coarse columns and arches the progressive photon map lost 11% of the indirect light whatever
// its radius. Along ng alone, a wide disc on a curved surface loses the neighbouring facets.
struct PhotonLookup {
    Vec3 p, n;
    uint32_t surface = kAnySurface;
    const Scene* scene = nullptr;
    Vec3 ng = Vec3(0.0f);

    Vec3 discNormal() const { return lengthSquared(ng) > 0 ? ng : n; }
    static PhotonLookup at(const ShadingPoint& sp, const Scene& scene);
};

class PhotonMap {
public:
    using Neighbour = KdTree<Photon>::Neighbour;

    void build(std::vector<Photon> photons) { tree_.build(std::move(photons)); }
    bool empty() const { return tree_.empty(); }
    size_t size() const { return tree_.size(); }
    size_t memoryBytes() const { return tree_.memoryBytes(); }
    const KdTree<Photon>& tree() const { return tree_; }

    // The k nearest photons on the disc around the lookup whose normals agree with it, within
    // maxRadius (the visibility guard is not applied here).
    void gather(const PhotonLookup& at, int k, float maxRadius, std::vector<Neighbour>& out) const;
    // Whether a photon passes the visibility guard of a lookup (lift: how far both ends are
    // raised off their surfaces).
    bool reaches(const Photon& photon, const PhotonLookup& at, float lift) const;

    // Irradiance arriving at the lookup (coneFilter as for radiance()).
    PhotonEstimate irradiance(const PhotonLookup& at, int k, float maxRadius, float coneFilter = 0) const;
    // Radiance that sp's BSDF reflects towards sp.wo: sum of f(wo, wi_p) flux_p over the disc.
    // coneFilter > 0 weights photon p by 1 - d_p / (coneFilter r) (Jensen's cone filter, for
    // caustics: sharper edges, less of a halo), normalised so a uniform density reads the same.
    PhotonEstimate radiance(const ShadingPoint& sp, const Scene& scene, int k, float maxRadius,
                            float coneFilter = 0) const;
    // The same for an integrator that traces sp's glossy lobes itself (DirectIntegrator's
    // glossyIndirect): photons are read through the Lambertian lobe alone, except those that came
    // through specular surfaces alone (Photon::caustic), which its glossy rays do not count. A
    // density estimate through a sharp lobe has few photons in it: a near-mirror ball (roughness
    // 0.21) reflected the room as blotches. Without glossy lobes, radiance() itself.
    PhotonEstimate radianceBesideGlossyRays(const ShadingPoint& sp, const Scene& scene, int k, float maxRadius) const;
    // The nearest photon around the lookup that passes all three guards, among the
    // kNearestCandidates nearest; false if none does within maxRadius. (For maps of
    // precomputed irradiance, which keep it in `power`.)
    bool nearest(const PhotonLookup& at, float maxRadius, Photon* found) const;
    static constexpr int kNearestCandidates = 4;

private:
    template <class Weight>
    PhotonEstimate estimate(const PhotonLookup& at, int k, float maxRadius, Weight&& weight, float coneFilter = 0) const;

    KdTree<Photon> tree_;
};

}  // namespace gi
