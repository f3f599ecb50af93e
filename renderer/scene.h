// The scene: triangle meshes, exact spheres and instances in Embree 3, UsdPreviewSurface
// materials, UsdLux lights (intersected analytically, not in the BVH) and emissive triangles.
// Built through add* calls, then committed once; after commit it is read-only and all
// queries are thread-safe. Moving shapes and instances (motion.h) become Embree motion geometry;
// static ones stay static, so a scene where nothing moves is built as without motion blur.
#pragma once
#include <embree3/rtcore.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "camera.h"
#include "image_cache.h"
#include "light.h"
#include "sphere_geometry.h"
#include "material.h"
#include "motion.h"

namespace gi {

// A ray as the renderer handed it to Embree (bench/rays.py replays a render's rays through
// Embree alone to measure Embree's share of the render).
struct RecordedRay {
    Vec3 o, d;
    float tMin, tMax;
    bool occlusion;  // rtcOccluded1 (shadow ray) rather than rtcIntersect1
    float time = 0;  // within the shutter (Ray::time)
    bool camera = false;  // a camera ray: starts a path (wavefront-ordered replays use it)
};

struct RayStats {
    uint64_t rays = 0;
    uint64_t depthCapped = 0;  // paths ended by the safety depth cap (kDepthCap), not by Russian roulette
    std::vector<RecordedRay>* record = nullptr;  // when set, every ray is appended (benchmarks only)
};

struct SurfaceInteraction {
    Vec3 p;           // world position
    Vec3 ng;          // geometric normal, unit, world space (as wound; not face-forwarded)
    Vec3 ns;          // shading normal, unit, world space (same hemisphere as ng)
    Vec2 uv;
    float t = 0;
    float time = 0;   // the ray's time within the shutter (motion.h): rays leaving here keep it
    // The arriving ray's cone (ray_cone.h): its width here (world units) and its spread, and the
    // width in uv units that the textures here are read over (Image::lookup); 0 without a cone.
    float coneWidth = 0, coneSpread = 0, uvFootprint = 0;
    const Material* material = nullptr;
    int emissiveLight = -1;  // index into lights() when the surface is an emissive triangle
    uint32_t primId = 0, shapeId = 0, instanceId = 0xffffffffu;
    bool doubleSided = true;
};

struct Intersection {
    enum class Kind { None, Surface, Light } kind = Kind::None;
    SurfaceInteraction si;
    int light = -1;  // when kind == Light
    float t = kInf;
};

class Scene {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // --- building (not thread-safe) ---
    int addMaterial(const MaterialDesc& desc);
    int addPrototype(const std::string& name);
    // Returns the shape id, or -1 (with a warning) if nothing usable remained. `motion`: the
    // positions (deformation) and/or the transform over the shutter; a mesh whose steps are all
    // equal is static. Transform motion applies to top-level shapes (a prototype's shapes move
    // with their instances).
    int addMesh(const std::string& name, std::vector<Vec3> positions, std::vector<uint32_t> indices,
                std::vector<Vec3> normals, std::vector<Vec2> uvs, int material, const Mat4* transform,
                bool doubleSided, int prototype, const MotionSteps& motion = {});
    // motion.transforms only (a sphere does not deform; a changing radius is a scale).
    int addSphere(const std::string& name, Vec3 center, float radius, int material, const Mat4* transform,
                  int prototype, const MotionSteps& motion = {});
    // motion.transforms only: the instance's transform over the shutter.
    int addInstance(int prototype, const Mat4& transform, const std::string& name, const MotionSteps& motion = {});
    // The name of instance `index` of `count` that a host knows only by index (a point
    // instancer's point, Hydra's instance of an rprim): base[index], zero-padded to the count's
    // width, so that names sort as the indices do (the scene orders emissive instances by name).
    static std::string indexedName(const std::string& base, size_t index, size_t count);
    int addLight(const LightDesc& desc);
    void setCamera(const CameraDesc& desc) { cameraDesc_ = desc; hasCamera_ = true; }
    // Frame sequences and interactive edits: this scene, built after `previous` (the last frame's or
    // the last edit's, still alive), shares its Embree device and takes its BVHs where nothing
    // changed (scene_reuse.cpp). Top-level shapes that are the same as in `previous` (same name,
    // points and indices; not moving) go into one static BVH, built once and reused by every later
    // scene while they stay the same; a prototype whose shapes are all the same keeps its BVH. Only
    // what changed is built. The image is the one this scene gives built alone. Call before commit.
    // BvhReuse::Edits (an interactive host) also keeps a static BVH that holds shapes changed
    // since, masking their old selves (buildStaticBvh): an edit's first pixels come without a
    // rebuild; while masks stand, rays run up to 12% slower, and Embree's filtered traversal can
    // change a few pixels' bits from the scene built alone's (README, "Edits build only what they
    // change"). Frames (a sequence,
    // where a frame's render outweighs its build) rebuilds it instead, as soon as one changed.
    enum class BvhReuse { Frames, Edits };
    void reuseBvhOf(const Scene& previous, BvhReuse reuse = BvhReuse::Frames);
    void commit();
    bool committed() const { return committed_; }

    // --- queries (thread-safe after commit) ---
    // cameraRay: skip lights that are invisible to the camera.
    Intersection intersect(const Ray& ray, RayStats& stats, bool cameraRay = false) const;
    // intersect in two halves, for a caller with work to do while the hit's triangle data is
    // fetched from memory: trace finds the hit and starts loading its vertex indices;
    // prefetchSurface, once those have had time to arrive, starts loading its vertices, normals
    // and texture coordinates; finish reads them (intersect's result, bit for bit).
    struct PendingHit {
        Intersection hit;  // kind, t and light; si is filled by finish
        RTCRayHit rh;
        int shape = -1;    // the surface hit's shape
        int instance = -1; // the instance it is seen through (none: the top level or the static BVH)
    };
    PendingHit trace(const Ray& ray, RayStats& stats, bool cameraRay = false) const;
    void prefetchSurface(const PendingHit& pending) const;
    Intersection finish(const Ray& ray, const PendingHit& pending) const;
    // `time`: within the shutter (Ray::time); preprocessing tests (portals) see shutter open.
    bool occluded(const Vec3& origin, const Vec3& dir, float distance, RayStats& stats, float time = 0) const;
    // Shadow test between a surface point and a light sample, offsetting the origin (at si.time).
    bool visible(const SurfaceInteraction& si, const Vec3& wi, float distance, RayStats& stats) const;

    // In order of name, not of addLight (analytic lights, then emissive shapes' triangles, then
    // emissive instances'): the same for every host's insertion order.
    const std::vector<std::unique_ptr<Light>>& lights() const { return lights_; }
    // Light selection at a shading point (light_sampler.h), and the probability it picks `light` there.
    const LightSampler& lightSampler() const { return lightSampler_; }
    float lightPmf(const Vec3& p, int light) const { return lightSampler_.pmf(p, light); }
    const std::vector<int>& infiniteLights() const { return infiniteLights_; }
    const SceneBounds& bounds() const { return bounds_; }
    // The geometry's bounds and the bounded lights' shapes: where a distant or dome light's
    // photons start, so that a light outside the geometry (a lamp above a skylight) shades them
    // as it shades the sky from camera paths.
    const SceneBounds& photonBounds() const { return photonBounds_; }
    Vec3 boundsMin() const { return boundsMin_; }
    Vec3 boundsMax() const { return boundsMax_; }
    const CameraDesc& cameraDesc() const { return cameraDesc_; }
    bool hasCamera() const { return hasCamera_; }
    const Material& material(int id) const { return *materials_[id]; }
    int materialCount() const { return int(materials_.size()); }
    bool hasSpecularSurfaces() const { return hasSpecular_; }
    const std::string& shapeName(uint32_t shape) const { return shapes_[shape].name; }
    bool hasMotion() const { return stats_.movingShapes + stats_.movingInstances > 0; }

    void warn(const std::string& message) const;
    std::vector<std::string> warnings() const;
    // Pilot renders (auto_select.h) drop what they warned about: the technique chosen warns again.
    size_t warningCount() const;
    void dropWarningsAfter(size_t count) const;

    struct Stats {
        size_t triangles = 0, spheres = 0, instances = 0, prototypes = 0, lights = 0, emissiveTriangles = 0;
        size_t textureBytes = 0, textures = 0;
        size_t portals = 0;  // portal lights in use (portal.h)
        size_t movingShapes = 0, movingInstances = 0;  // built as Embree motion geometry
        size_t movingLights = 0;  // area lights moving during the shutter (moving_light.h)
        size_t texturesRead = 0;  // of `textures`, read from disk (the rest came from a shared ImageCache)
        double buildSeconds = 0;
        // BVH work of commit(): triangles and spheres built, and taken from the previous scene;
        // of those taken, the ones this scene masks (shapes it no longer has as they were).
        size_t primitivesBuilt = 0, primitivesReused = 0, primitivesMasked = 0;
    };
    const Stats& stats() const { return stats_; }
    // Textures come from (and go to) `images`, shared with other scenes, instead of this scene's
    // own reads. Call before commit().
    void shareImages(std::shared_ptr<ImageCache> images) { sharedImages_ = std::move(images); }
    RTCScene embreeScene() const { return top_; }
    RTCDevice embreeDevice() const;
    // Up to kDirectSpheres static spheres of the top level are not in embreeScene(): they are
    // tested one by one beside it, since Embree's call of a user geometry cost the Cornell box's
    // rays more than the test itself (its path tracer took 14% less time so, docs/performance.md); more go into
    // it. Whoever casts rays through embreeScene() must test them too: the nearest crossing in
    // (tMin, *tMax) lowers *tMax to it and returns the sphere's shape; -1 if none.
    static constexpr size_t kDirectSpheres = 4;
    int nearestDirectSphere(const Vec3& o, const Vec3& d, float tMin, float* tMax) const;
    // Whether one of them crosses the segment (0, distance) of the ray.
    bool directSphereBlocks(const Vec3& o, const Vec3& d, float distance) const;

private:
    struct Shape {
        std::string name;
        bool isSphere = false;
        std::vector<Vec3> positions, normals;
        std::vector<Vec2> uvs;
        std::vector<uint32_t> indices;
        Vec3 center;
        float radius = 0;
        // Motion (empty when static): per time step, step 0 equal to positions / center and radius.
        std::vector<std::vector<Vec3>> stepPositions, stepNormals;
        std::vector<Vec3> stepCenters;
        std::vector<float> stepRadii;
        int material = 0;
        bool doubleSided = true;
        int prototype = -1;
        int lightOffset = -1;  // first triangle light of this shape (top-level shapes)
    };
    struct Bvh;           // an Embree scene of shapes, shareable between consecutive scenes
    struct EmbreeDevice;  // a device, shared likewise, and the scene its errors are reported to
    struct Previous;      // what reuseBvhOf took from the previous scene
    struct Prototype {
        std::string name;
        std::vector<int> shapes;
        std::shared_ptr<const Bvh> bvh;
        RTCScene rtc = nullptr;  // bvh's
        std::vector<int> geomToShape;
        bool emissive = false;
        std::map<int, int> relativeLightOffset;  // emissive shape -> its first light within an instance
    };
    struct Instance {
        std::string name;
        int prototype;
        Mat4 toWorld;                 // at shutter open
        std::vector<Mat4> stepToWorld;  // per time step when it moves; empty when static
        int lightOffset = -1;  // first light of this instance's emissive triangles
    };

    void buildShapeGeometry(RTCScene target, std::vector<int>& geomToShape, int shapeId);
    // scene_reuse.cpp: a shape's BVH inputs (points, indices, sphere, motion steps) as one hash.
    static uint64_t fingerprint(const Shape& shape);
    // The BVH of `shapes` (geometry ids in their order), built, or taken from previous_ when
    // `previous` holds the same names and fingerprints in the same order.
    std::shared_ptr<const Bvh> shapesBvh(const std::vector<int>& shapes, const std::vector<uint64_t>& fingerprints,
                                         const std::shared_ptr<const Bvh>& previous);
    // commit()'s top level: the static BVH (reused or built) and the shapes left out of it.
    std::vector<int> buildStaticBvh(const std::vector<uint64_t>& fingerprints);
    std::vector<int> shapesOutside(const std::vector<int>& top, const std::vector<int>& inStatic) const;
    // Whether the static spheres among `shapes` are few enough to be tested beside the BVH (at
    // most kDirectSpheres), and moving those of `top` (the shapes the top level builds) there.
    bool isStaticSphere(int shape) const;
    bool spheresBesideBvh(const std::vector<int>& shapes) const;
    void chooseDirectSpheres(std::vector<int>& top);
    // A reused static BVH is rebuilt once the shapes it masks hold more than this share of its
    // primitives (their traversal is wasted work for every ray).
    static constexpr double kMaskedShare = 0.25;
    // This committed scene's top level as the next scene's static BVH, when it holds static
    // shapes alone (no instances, no static BVH of its own); null otherwise.
    std::shared_ptr<const Bvh> topLevelAsBvh() const;
    // Embree's context filter for rays that met masked geometry: skips hits on it.
    static void skipMasked(const RTCFilterFunctionNArguments* args);
    struct MaskContext {
        RTCIntersectContext embree;  // first: Embree hands the filter this pointer
        const Scene* scene;
    };
    void initMaskContext(MaskContext& context, bool skipsMasked) const;
    // Grows [lo, hi] by a static shape's primitives, as Embree bounds them.
    static void growByShape(const Shape& shape, Vec3& lo, Vec3& hi);
    struct Bounds {
        Vec3 lo{kInf}, hi{-kInf};
    };
    static Bounds shapeBounds(const Shape& shape) {
        Bounds b;
        growByShape(shape, b.lo, b.hi);
        return b;
    }
    // Whether the segment [origin, origin + distance dir] crosses a masked shape's bounds.
    bool mayHitMasked(const Vec3& origin, const Vec3& dir, float distance) const;
    void countShapes();
    // The validated steps of a mesh's motion, or empty (warned about when unusable); `transforms`:
    // the per-step transforms baked into them (empty when the static one was).
    std::vector<std::vector<Vec3>> meshMotion(const std::string& name, const std::vector<Vec3>& positions,
                                              const Mat4* transform, int prototype, const MotionSteps& motion,
                                              std::vector<Mat4>& transforms);
    // motion.transforms validated (finite, invertible, as many as motion's steps), or empty.
    std::vector<Mat4> transformMotion(const std::string& what, const MotionSteps& motion);
    void buildLights();
    void buildLightBvh();
    // The nearest analytic light (rect, disk, sphere, cylinder) along `ray` before its tMax.
    void intersectAnalyticLights(const Ray& ray, bool cameraRay, Intersection& result) const;
    static void intersectLightPrimitive(const struct RTCIntersectFunctionNArguments* args);
    void bindMaterials();
    // Fills `si` (default-constructed) in place: a returned copy, read back in 16-byte moves from
    // the fields' narrower stores just made, stalls on store forwarding (5% of the Cornell box's render).
    void makeInteraction(const Ray& ray, const PendingHit& hit, SurfaceInteraction& si) const;
    // The shape an Embree hit is on (in the top level, the static BVH or an instance's prototype);
    // *instance is set to the instance it is seen through, left alone for the top level's and the
    // static BVH's. Resolved once per hit, in trace.
    int hitShape(const RTCHit& hit, int* instance) const;
    Texture loadTexture(const TextureDesc& desc, const std::string& materialName, const std::string& input);
    // One file's image, read once per scene (nullptr with `error` when it cannot be read); *first
    // says whether this call read it (or tried to).
    std::shared_ptr<Image> loadImage(const std::string& file, const std::string& colorSpace, std::string& error,
                                     bool* first);
    int defaultMaterial();

    std::shared_ptr<EmbreeDevice> device_;
    // The static spheres' user-geometry data (sphere_geometry.h): also held by the BVHs later
    // scenes keep, whose geometries point into it.
    std::shared_ptr<SphereStore> sphereStore_ = std::make_shared<SphereStore>();
    // The top level's direct spheres (kDirectSpheres): never in a BVH a later scene keeps, so
    // never masked.
    struct DirectSphere {
        SphereData sphere;
        int shape;
    };
    std::vector<DirectSphere> directSpheres_;
    RTCScene top_ = nullptr;
    std::unique_ptr<Previous> previous_;
    std::map<std::string, uint64_t> topFingerprints_;  // static top-level shapes with a name of their own
    std::shared_ptr<const Bvh> staticBvh_;  // top-level shapes unchanged since the previous scene
    unsigned staticBvhGeom_ = RTC_INVALID_GEOMETRY_ID;  // its instance in top_
    std::vector<int> staticBvhToShape_;               // its geometry ids -> shapes (-1: masked)
    std::vector<uint8_t> staticMasked_;  // by its geometry id: 1 for a shape this scene does not have; empty if none
    std::vector<Bounds> maskedBounds_;   // the masked shapes' (their union past a few)
    std::vector<Shape> shapes_;
    std::vector<Prototype> prototypes_;
    std::vector<Instance> instances_;
    std::vector<int> topGeomToShape_;  // geomID -> shape, or -(instance+1) for instances
    std::vector<MaterialDesc> materialDescs_;
    std::vector<std::unique_ptr<Material>> materials_;
    std::map<std::string, std::shared_ptr<Image>> imageCache_;  // this scene's textures, by file and colour space
    std::shared_ptr<ImageCache> sharedImages_;
    std::vector<LightDesc> lightDescs_;
    std::vector<std::unique_ptr<Light>> lights_;
    std::vector<int> infiniteLights_;
    std::vector<int> analyticLights_;  // lights with a shape of their own (not in top_)
    RTCScene lightBvh_ = nullptr;      // over analyticLights_, when there are more than a few
    LightSampler lightSampler_;
    SceneBounds bounds_;
    Vec3 boundsMin_{0.0f}, boundsMax_{0.0f};
    SceneBounds photonBounds_;
    CameraDesc cameraDesc_;
    bool hasCamera_ = false;
    bool committed_ = false;
    bool hasSpecular_ = false;
    int defaultMaterial_ = -1;
    Stats stats_;
    mutable std::mutex warningsMutex_;
    mutable std::vector<std::string> warnings_;
};

}  // namespace gi
