#include "sceneStore.h"

#include "pxr/base/tf/diagnostic.h"
#include "renderer/usd_shading.h"

PXR_NAMESPACE_OPEN_SCOPE

gi::Mat4 HdGiToMat4(GfMatrix4d const& m) { return gi::Mat4::fromRowMajor(m.data()); }

void HdGiSceneStore::SetGeometry(SdfPath const& id, std::shared_ptr<const HdGiGeometry> geometry) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (geometry) _geometry[id] = std::move(geometry);
    else _geometry.erase(id);
}

std::vector<GfMatrix4d> HdGiTransformSteps(std::vector<float> const& times, std::vector<GfMatrix4d> const& samples,
                                           float open, float close) {
    std::vector<GfMatrix4d> steps;
    if (times.size() < 2) return steps;
    for (float t : gi::shutterStepTimes(open, close, {&times})) steps.push_back(gi::sampleAt(times, samples, t, HdGiLerp));
    return steps;
}

void HdGiSceneStore::SetLight(SdfPath const& id, std::shared_ptr<const HdGiLightRecord> light) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (light) _lights[id] = std::move(light);
    else _lights.erase(id);
}

bool HdGiSceneStore::SetMaterial(SdfPath const& id, std::shared_ptr<const gi::MaterialDesc> material,
                                 std::vector<std::string> readerVarnames) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (material) _materials[id] = std::move(material);
    else _materials.erase(id);
    auto it = _readerVarnames.find(id);
    bool changed = it == _readerVarnames.end() ? !readerVarnames.empty() : it->second != readerVarnames;
    if (readerVarnames.empty()) _readerVarnames.erase(id);
    else _readerVarnames[id] = std::move(readerVarnames);
    return changed;
}

std::vector<std::string> HdGiSceneStore::ReaderVarnames(SdfPath const& material) const {
    std::lock_guard<std::mutex> lock(_mutex);
    auto it = _readerVarnames.find(material);
    return it == _readerVarnames.end() ? std::vector<std::string>() : it->second;
}

void HdGiSceneStore::Remove(SdfPath const& id) {
    std::lock_guard<std::mutex> lock(_mutex);
    _geometry.erase(id);
    _lights.erase(id);
    _materials.erase(id);
    _readerVarnames.erase(id);
}

size_t HdGiSceneStore::GeometryCount() const {
    std::lock_guard<std::mutex> lock(_mutex);
    return _geometry.size();
}

namespace {

// Materials are added to the scene once each, on first use (textures of unused materials are
// never read); meshes without one use their displayColor (UsdImaging resolves its inheritance).
class MaterialBinder {
public:
    MaterialBinder(gi::Scene& scene, std::map<SdfPath, std::shared_ptr<const gi::MaterialDesc>> const& materials)
        : _scene(scene), _materials(materials) {}

    // `piece` overrides the prim's material (a GeomSubset's binding) when not empty.
    int Bind(HdGiGeometry const& g, SdfPath const& piece) {
        SdfPath const& path = piece.IsEmpty() ? g.material : piece;
        if (!path.IsEmpty()) {
            auto it = _materials.find(path);
            if (it != _materials.end()) {
                auto [slot, inserted] = _ids.emplace(path.GetString(), -1);
                if (inserted) slot->second = _scene.addMaterial(*it->second);
                if (slot->second >= 0) return slot->second;
            }
        }
        // No usable material: renderer/usd_shading.h's displayColor material (shared by equal colours).
        std::string key = "displayColor";
        gi::Color c(g.displayColor[0], g.displayColor[1], g.displayColor[2]);
        if (g.hasDisplayColor) key += ":" + std::to_string(c.x) + "," + std::to_string(c.y) + "," + std::to_string(c.z);
        auto [slot, inserted] = _ids.emplace(key, -1);
        if (inserted) slot->second = _scene.addMaterial(gi::displayColorMaterial(g.name, g.hasDisplayColor ? &c : nullptr));
        return slot->second;
    }

private:
    gi::Scene& _scene;
    std::map<SdfPath, std::shared_ptr<const gi::MaterialDesc>> const& _materials;
    std::map<std::string, int> _ids;
};

// The prim's motion over the rendering camera's shutter [open, close] as the renderer's even steps
// (renderer/motion.h): its transform's (top-level prims only: instances move by their instancer)
// and `mesh`'s deformation. Hydra's samples span every camera's shutter (HdGiRenderParam's
// sampling interval), so the steps are this shutter's ends and the samples between, the first at
// shutter open and the last at close, as the renderer's ray times 0 and 1.
gi::MotionSteps MotionOf(HdGiGeometry const& g, HdGiTriangleMesh const* mesh, int prototype, GfVec2f shutter) {
    bool moves = prototype < 0 && g.transformTimes.size() > 1;
    bool deforms = mesh && mesh->pointTimes.size() > 1;
    gi::MotionSteps motion;
    if (!moves && !deforms) return motion;
    for (float t : gi::shutterStepTimes(shutter[0], shutter[1], {moves ? &g.transformTimes : nullptr,
                                                                 deforms ? &mesh->pointTimes : nullptr})) {
        if (moves) motion.transforms.push_back(HdGiToMat4(gi::sampleAt(g.transformTimes, g.transformSamples, t, HdGiLerp)));
        if (deforms)
            motion.points.push_back(gi::sampleAt(mesh->pointTimes, mesh->pointSamples, t,
                                                 [](std::vector<gi::Vec3> const& a, std::vector<gi::Vec3> const& b, float f) {
                                                     std::vector<gi::Vec3> out(a.size());
                                                     for (size_t i = 0; i < a.size(); ++i) out[i] = gi::lerp(a[i], b[i], f);
                                                     return out;
                                                 }));
    }
    return motion;
}

// Each instance's motion over the rendering camera's shutter, as MotionOf's transform steps (empty
// when the instances do not move).
std::vector<gi::MotionSteps> InstanceMotionOf(HdGiGeometry const& g, GfVec2f shutter) {
    std::vector<gi::MotionSteps> motion(g.instanceTransforms.size());
    if (g.instanceTimes.size() < 2) return motion;
    std::vector<float> const steps = gi::shutterStepTimes(shutter[0], shutter[1], {&g.instanceTimes});
    std::vector<GfMatrix4d> path(g.instanceTimes.size());
    for (size_t i = 0; i < motion.size(); ++i) {
        for (size_t k = 0; k < path.size(); ++k)
            path[k] = i < g.instanceSamples[k].size() ? g.instanceSamples[k][i] : g.instanceTransforms[i];
        for (float t : steps) motion[i].transforms.push_back(HdGiToMat4(gi::sampleAt(g.instanceTimes, path, t, HdGiLerp)));
    }
    return motion;
}

// Adds the prim's shapes (a sphere, or one mesh per material piece); returns their ids.
std::vector<int> AddShapes(gi::Scene& scene, HdGiGeometry const& g, MaterialBinder& binder, gi::Mat4 const& transform,
                           int prototype, GfVec2f shutter) {
    std::vector<int> shapes;
    if (g.isSphere) {
        shapes.push_back(scene.addSphere(g.name, gi::Vec3(0.0f), g.radius, binder.Bind(g, SdfPath()), &transform,
                                         prototype, MotionOf(g, nullptr, prototype, shutter)));
        return shapes;
    }
    for (size_t i = 0; i < g.pieces.size(); ++i) {
        HdGiTriangleMesh const& m = *g.pieces[i];
        if (m.indices.empty()) continue;
        SdfPath material = i < g.pieceMaterials.size() ? g.pieceMaterials[i] : SdfPath();
        std::string const& name = i < g.pieceNames.size() ? g.pieceNames[i] : g.name;
        shapes.push_back(scene.addMesh(name, m.points, m.indices, m.normals, m.uvs, binder.Bind(g, material), &transform,
                                       g.doubleSided, prototype, MotionOf(g, &m, prototype, shutter)));
    }
    return shapes;
}

void Record(std::vector<int>& map, int index, int value) {
    if (index < 0) return;
    if (map.size() <= size_t(index)) map.resize(size_t(index) + 1, -1);
    map[size_t(index)] = value;
}

}  // namespace

void HdGiSceneStore::ReportWarnings(gi::Scene const& scene) const {
    // Every edit rebuilds the scene: report each of its warnings once per session.
    for (std::string const& w : scene.warnings()) {
        std::lock_guard<std::mutex> lock(_mutex);
        if (_reported.insert(w).second) TF_WARN("hdGi: %s", w.c_str());
    }
}

std::unique_ptr<gi::Scene> HdGiSceneStore::Build(HdGiIdMap* ids, bool domeLightCameraVisibility, GfVec2f shutter,
                                                 gi::Scene const* previous) const {
    // Snapshot under the lock (records are immutable once stored), build outside it.
    std::vector<std::shared_ptr<const HdGiGeometry>> geometry;
    std::vector<std::shared_ptr<const HdGiLightRecord>> lights;
    std::map<SdfPath, std::shared_ptr<const gi::MaterialDesc>> materials;
    {
        std::lock_guard<std::mutex> lock(_mutex);
        for (auto const& [path, g] : _geometry) geometry.push_back(g);
        for (auto const& [path, l] : _lights) lights.push_back(l);
        materials = _materials;
    }
    auto scene = std::make_unique<gi::Scene>();
    if (previous) scene->reuseBvhOf(*previous, gi::Scene::BvhReuse::Edits);
    scene->shareImages(_images);
    MaterialBinder binder(*scene, materials);
    HdGiIdMap map;
    for (auto const& g : geometry) {
        if (!g->instanced) {
            for (int shape : AddShapes(*scene, *g, binder, HdGiToMat4(g->transform), -1, shutter))
                Record(map.shapePrimId, shape, g->primId);
            continue;
        }
        if (g->instanceTransforms.empty()) continue;
        // Instances share one Embree prototype: the rprim's own transform inside it, the
        // instancer's on top (Hydra's order: world = transform * instance).
        int prototype = scene->addPrototype(g->name);
        std::vector<int> shapes = AddShapes(*scene, *g, binder, HdGiToMat4(g->transform), prototype, shutter);
        for (int shape : shapes) Record(map.shapePrimId, shape, g->primId);
        std::vector<gi::MotionSteps> const motion = InstanceMotionOf(*g, shutter);
        // Named by Hydra's index (Scene::indexedName): emissive instances keep Hydra's order, which is
        // the native instances' path order (`gi render` names them by path) and the points' order.
        for (size_t i = 0; i < g->instanceTransforms.size(); ++i) {
            int instance = scene->addInstance(prototype, HdGiToMat4(g->instanceTransforms[i]),
                                              gi::Scene::indexedName(g->name, i, g->instanceTransforms.size()), motion[i]);
            Record(map.instanceIndex, instance, int(i));
        }
    }
    for (auto const& l : lights) {
        gi::LightDesc light = l->desc;
        if (light.kind == "dome" && !domeLightCameraVisibility) light.visibleToCamera = false;
        for (GfMatrix4d const& m : HdGiTransformSteps(l->transformTimes, l->transformSamples, shutter[0], shutter[1]))
            light.motionTransforms.push_back(HdGiToMat4(m));
        scene->addLight(light);
    }
    scene->commit();
    ReportWarnings(*scene);
    if (ids) *ids = std::move(map);
    return scene;
}

PXR_NAMESPACE_CLOSE_SCOPE
