// What Hydra has synced, translated to the renderer's descriptions: one record per rprim,
// light and material. Sync calls (in parallel, from Hydra's threads) replace records; the
// render thread builds a gi::Scene from a consistent snapshot when the version has changed.
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/base/gf/vec2f.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/pxr.h"
#include "pxr/usd/sdf/path.h"
#include "renderer/scene.h"

PXR_NAMESPACE_OPEN_SCOPE

// Triangles in object space: per-vertex data, three indices per triangle.
struct HdGiTriangleMesh {
    std::vector<gi::Vec3> points, normals;
    std::vector<gi::Vec2> uvs;
    std::vector<uint32_t> indices;
    // Deformation over the shutter (SamplePrimvar of points): times relative to the frame, and
    // the points at each, as many as `points`. Fewer than two: the mesh does not deform.
    std::vector<float> pointTimes;
    std::vector<std::vector<gi::Vec3>> pointSamples;
};

struct HdGiGeometry {
    std::string name;
    bool isSphere = false;
    float radius = 0;  // spheres
    // Meshes: one piece per material (the prim's own, then each GeomSubset's); an empty
    // material path means the prim's binding. Each piece is named by its prim's path (the mesh's,
    // else the subset's), as `gi render` names it: the renderer orders emissive pieces' lights by
    // name, so both hosts pick the same light for the same sample.
    std::vector<std::shared_ptr<const HdGiTriangleMesh>> pieces;
    std::vector<SdfPath> pieceMaterials;
    std::vector<std::string> pieceNames;
    GfMatrix4d transform{1.0};
    // Transform motion over the shutter (SampleTransform): times relative to the frame, with the
    // shutter's boundaries among them. Fewer than two: the transform does not move.
    std::vector<float> transformTimes;
    std::vector<GfMatrix4d> transformSamples;
    // Instancer transforms (world = transform * instance). Empty and !instanced: one copy.
    bool instanced = false;
    std::vector<GfMatrix4d> instanceTransforms;
    // Their motion: sample times as transformTimes', and per time one transform per instance.
    std::vector<float> instanceTimes;
    std::vector<std::vector<GfMatrix4d>> instanceSamples;
    SdfPath material;
    bool hasDisplayColor = false;
    GfVec3f displayColor{0.0f};  // read only when hasDisplayColor (else the spec's default diffuse)
    bool doubleSided = true;
    int primId = -1;  // Hydra's id for picking
};

// A light as Hydra synced it: its description at the frame, and its transform's motion samples
// (SampleTransform: times relative to the frame; fewer than two: it does not move), turned into
// the description's motion steps over the rendering camera's shutter when the scene is built.
struct HdGiLightRecord {
    gi::LightDesc desc;
    std::vector<float> transformTimes;
    std::vector<GfMatrix4d> transformSamples;
};

// Ids the film reports, mapped back to Hydra's: shape -> primId, scene instance -> index.
struct HdGiIdMap {
    std::vector<int> shapePrimId;
    std::vector<int> instanceIndex;
};

class HdGiSceneStore {
public:
    void SetGeometry(SdfPath const& id, std::shared_ptr<const HdGiGeometry> geometry);
    void SetLight(SdfPath const& id, std::shared_ptr<const HdGiLightRecord> light);
    // `readerVarnames`: the primvars the material's textures read (UsdPrimvarReader_float2's
    // varname). True when they changed: meshes then pick their texture coordinates again.
    bool SetMaterial(SdfPath const& id, std::shared_ptr<const gi::MaterialDesc> material,
                     std::vector<std::string> readerVarnames = {});
    std::vector<std::string> ReaderVarnames(SdfPath const& material) const;
    void Remove(SdfPath const& id);

    // A committed scene of everything visible now, with the id maps for the film's AOVs.
    // `domeLightCameraVisibility` false hides dome lights from camera rays (a render setting);
    // `shutter`: the rendering camera's, relative to the frame (motion is sampled over it).
    // `previous`: the last scene built (no longer rendering), whose BVHs are kept where nothing
    // changed since (gi::Scene::reuseBvhOf): an edit rebuilds only the BVH of what it changed.
    std::unique_ptr<gi::Scene> Build(HdGiIdMap* ids, bool domeLightCameraVisibility = true,
                                     GfVec2f shutter = GfVec2f(0.0f), gi::Scene const* previous = nullptr) const;

    size_t GeometryCount() const;

    // Sends the scene's warnings to TF_WARN, each once per session: those of building it (Build
    // does) and those of rendering it (a camera's shutter closing before it opens, ...).
    void ReportWarnings(gi::Scene const& scene) const;

private:
    mutable std::mutex _mutex;
    mutable std::set<std::string> _reported;
    std::map<SdfPath, std::shared_ptr<const HdGiGeometry>> _geometry;
    std::map<SdfPath, std::shared_ptr<const HdGiLightRecord>> _lights;
    std::map<SdfPath, std::shared_ptr<const gi::MaterialDesc>> _materials;
    std::map<SdfPath, std::vector<std::string>> _readerVarnames;
    // Textures outlive the scene rebuilt on every edit: an unchanged file is read once.
    std::shared_ptr<gi::ImageCache> _images = std::make_shared<gi::ImageCache>();
};

gi::Mat4 HdGiToMat4(GfMatrix4d const& m);
// Matrices between motion samples, entry by entry (as Embree interpolates instance transforms).
inline GfMatrix4d HdGiLerp(GfMatrix4d const& a, GfMatrix4d const& b, float f) { return a * double(1 - f) + b * double(f); }
// A transform's motion samples (times relative to the frame) at the renderer's even steps over
// the shutter [open, close] (gi::shutterStepTimes: the first at open, the last at close); empty
// when fewer than two samples or the shutter does not open.
std::vector<GfMatrix4d> HdGiTransformSteps(std::vector<float> const& times, std::vector<GfMatrix4d> const& samples,
                                           float open, float close);

PXR_NAMESPACE_CLOSE_SCOPE
