// UsdLux PortalLight: a rectangle over an opening (a window) through which a dome light and a
// sun shine into an interior; light passes it along its -Z. As in Cycles, Karma and RenderMan:
// - next-event estimation of the dome from a point on the interior side of every portal samples
//   the portals (uniform by area, converted to solid angle) instead of the whole sphere; other
//   points sample the dome as before. BSDF-sampled rays still find the sky anywhere (MIS), so
//   the path tracer stays unbiased even where the portals do not cover every opening;
// - photons of dome and distant lights start on the portals instead of a disc over the whole
//   scene, so all of them enter the interior. Where a photon's way back to the sky is blocked
//   outside the portal (a roof, a window reveal), the sky's and the sun's own light do not come
//   in along it, but what that outside surface reflects does: a photon of the (first) dome
//   carries that radiance, estimated by a path traced from the surface (all lights; the
//   dome's photons leave the portal in every direction; a quarter of them, weighted by 4, so
//   that the paths cost the photon map 20% of its samples, not 40%), and the others carry
//   nothing. Karma carries nothing there: on Sibenik with portals the progressive photon map
//   then read 0.948 of its image without portals, where light comes in off the aisles' roofs
//   and the window reveals. That still assumes the portals cover every opening the light comes through (light
//   through others is not emitted as photons), as in Karma.
// A portal is a rectangle: corner + s e1 + t e2, s, t in [0, 1); `travel` is its unit -Z.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "math.h"
#include "sampling.h"

namespace gi {

struct Portal {
    std::string name;
    Vec3 corner, e1, e2, travel;
    float area = 0;
    Vec3 center() const { return corner + e1 * 0.5f + e2 * 0.5f; }
    // Whether p lies on the side the light travels to (the interior).
    bool behind(const Vec3& p) const { return dot(p - center(), travel) > 0; }
    // Distance along d from o to the portal's rectangle, or inf.
    float intersect(const Vec3& o, const Vec3& d) const;
};

class Scene;
struct LightDesc;
// A portal from a UsdLux PortalLight's descriptor, checked against the committed geometry:
// finite, of positive size, and not clearly facing the wrong way (its -Z side, where the light
// goes, seeing more sky than its +Z side by a few probe rays). Otherwise warns on the scene,
// naming the prim, and returns false.
bool makePortal(const Scene& scene, const LightDesc& desc, Portal& portal);

class PortalSet {
public:
    PortalSet() = default;
    explicit PortalSet(std::vector<Portal> portals);
    bool empty() const { return portals_.empty(); }
    const std::vector<Portal>& portals() const { return portals_; }
    float totalArea() const { return totalArea_; }

    // Whether next-event estimation from p goes through the portals: p is behind every one.
    bool guides(const Vec3& p) const;
    // A direction from p through a portal chosen by area (u.x picks it, then is reused); its
    // solid-angle pdf (the sum over every portal the ray crosses). False if none was found.
    bool sampleDirection(const Vec3& p, Vec2 u, Vec3* wi, float* pdf) const;
    float pdf(const Vec3& p, const Vec3& wi) const;

    // Photon origins: a portal picked by `weights` (one per portal; e.g. area or projected area
    // towards the sun) with u.x, then a uniform point on it (u.x reused). Returns the portal's
    // index, or -1; pdfArea is the point's density per unit area.
    int samplePoint(const Distribution1D& weights, Vec2 u, Vec3* point, float* pdfArea) const;
    const Distribution1D& byArea() const { return byArea_; }

private:
    std::vector<Portal> portals_;
    Distribution1D byArea_;
    float totalArea_ = 0;
};

}  // namespace gi
