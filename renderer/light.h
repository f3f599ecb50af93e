// UsdLux lights and emissive triangles. Radiance follows UsdLux: color * intensity *
// 2^exposure, divided by the world-space area when `normalize` is on. A distant light's
// intensity is its irradiance at normal incidence, whatever its angular size.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "light_sampler.h"
#include "math.h"
#include "portal.h"
#include "sampling.h"
#include "texture.h"

namespace gi {

struct LightDesc {
    std::string name;
    std::string kind = "rect";  // rect | disk | sphere | cylinder | distant | dome | portal
    Color color{1.0f};
    float intensity = 1;
    float exposure = 0;
    bool normalize = false;
    float width = 1, height = 1, radius = 0.5f, length = 1, angle = 0.53f;
    std::string textureFile;
    Mat4 transform;  // at the time rendered (the frame)
    // The transform over the shutter at evenly spaced steps (motion.h: the first at shutter open,
    // the last at close) when it moves; empty: the light stands at `transform`. Only the kinds
    // lightKindMoves() names are blurred; the Scene warns about the others and places them by
    // `transform`.
    std::vector<Mat4> motionTransforms;
    bool visibleToCamera = true;
};

// Whether a light of this kind moves with its motionTransforms (the area lights: rect, disk,
// sphere, cylinder); distant and dome lights shine as at the frame.
bool lightKindMoves(const std::string& kind);

struct SceneBounds {
    Vec3 center{0.0f};
    float radius = 1;
};

struct LightSample {
    Vec3 wi;         // unit direction from the reference point to the light
    float distance;  // to the sampled point (infinite for distant/dome)
    Color Li;        // radiance arriving along -wi
    float pdf = 0;   // solid angle; for delta lights 1 with `delta` set
    bool delta = false;
};

struct PhotonEmission {
    Ray ray;
    Color power;  // flux carried, already divided by the sampling pdfs
    // Started on a portal inside the scene (portal.h): the light reaches the origin only if the
    // way back along -ray.d is clear, which the photon tracer tests.
    bool fromPortal = false;
    // A dome's portal photon: its power per unit of the radiance arriving along -ray.d (where the
    // sky is hidden outside the portal, the photon tracer puts what an outside surface sends there).
    float powerPerRadiance = 0;
};

class Light {
public:
    virtual ~Light() = default;
    // `time` (sample, pdf, radiance; a ray's Ray::time for intersect): the instant within the
    // shutter (motion.h) the light is seen at; only a moving light's answers depend on it. A path
    // keeps its camera ray's time, so its light samples see the light where its rays would hit it.
    virtual LightSample sample(const Vec3& ref, Vec2 u, float time) const = 0;
    // Solid-angle pdf that sample() would produce wi from ref, reaching the light at distance t.
    virtual float pdf(const Vec3& ref, const Vec3& wi, float t, float time) const = 0;
    // Radiance leaving the light towards -wi at a ray-light intersection (or escaping, for infinite lights).
    virtual Color radiance(const Vec3& wi, float time) const = 0;
    // Analytic ray intersection for area lights (they are not in the surface BVH); returns t or inf.
    virtual float intersect(const Ray&) const { return kInf; }
    // World-space box around an analytic shape (what intersect() can hit at any time); false for
    // lights without one (infinite lights, emissive triangles, which the surface BVH holds).
    virtual bool shapeBounds(Vec3* lo, Vec3* hi) const { return false; }
    // Where and how the light emits (over the whole shutter), for light selection
    // (light_sampler.h); false for infinite lights.
    virtual bool emissionBounds(LightBounds*) const { return false; }
    virtual Color power(const SceneBounds&) const = 0;
    // A photon leaving the light at `time` (the photon ray's instant in the shutter, as for
    // sample()): a moving light emits from where it is then, so the photon maps hold its light
    // spread over the shutter as camera rays see it.
    virtual PhotonEmission emit(Vec2 uPos, Vec2 uDir, const SceneBounds&, float time) const = 0;
    virtual bool isInfinite() const { return false; }
    // Whether emit()'s uPos names a fixed place in the scene (a point on the light, or on the
    // disc a sun shines through), so that an emission guide can learn which of them pay.
    virtual bool emitsFromFixedPositions() const { return true; }
    // Light from the whole sky (a dome): a BSDF-sampled ray finds it through window glass as
    // easily as a photon does, where a small light (a sun) is found only by photons.
    virtual bool isDome() const { return false; }
    virtual void preprocess(const SceneBounds& bounds) { bounds_ = bounds; }
    // Portals over the openings an infinite light shines through (portal.h); others ignore them.
    virtual void setPortals(std::shared_ptr<const PortalSet>) {}

    std::string name;
    bool visibleToCamera = true;

protected:
    SceneBounds bounds_;
};

// Builds the light for a descriptor; returns nullptr and a message for unusable input
// (NaN parameters, zero area, non-positive or non-finite radiance).
std::unique_ptr<Light> createLight(const LightDesc& desc, std::string& warning);

// One emissive triangle of a mesh (world space); radiance from the material at the sampled uv.
class Material;
std::unique_ptr<Light> createTriangleLight(const Vec3 p[3], const Vec2 uv[3], const Material* material,
                                           bool doubleSided, const std::string& name);
// One emissive triangle that moves during the shutter (triangle_light.cpp): its points per step of
// its own motion (one entry when only its transform moves), placed by `toWorld` per step of its
// instance's motion (one entry: a still instance; empty: the points are in world space).
std::unique_ptr<Light> createMovingTriangleLight(std::vector<std::array<Vec3, 3>> points, std::vector<Mat4> toWorld,
                                                 const Vec2 uv[3], const Material* material, bool doubleSided,
                                                 const std::string& name);

}  // namespace gi
