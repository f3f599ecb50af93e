#include "renderDelegate.h"

#include "camera.h"
#include "instancer.h"
#include "light.h"
#include "material.h"
#include "mesh.h"
#include "pxr/imaging/hd/camera.h"
#include "pxr/imaging/hd/extComputation.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderBuffer.h"
#include "renderParam.h"
#include "renderPass.h"
#include "renderSession.h"
#include "renderSettings.h"
#include "sphere.h"

PXR_NAMESPACE_OPEN_SCOPE

namespace {

TfTokenVector const kRprimTypes = {HdPrimTypeTokens->mesh, HdPrimTypeTokens->sphere};
TfTokenVector const kSprimTypes = {HdPrimTypeTokens->camera,        HdPrimTypeTokens->material,
                                   HdPrimTypeTokens->rectLight,     HdPrimTypeTokens->diskLight,
                                   HdPrimTypeTokens->sphereLight,   HdPrimTypeTokens->cylinderLight,
                                   HdPrimTypeTokens->distantLight,  HdPrimTypeTokens->domeLight,
                                   HdPrimTypeTokens->light,         HdPrimTypeTokens->extComputation};
TfTokenVector const kBprimTypes = {HdPrimTypeTokens->renderBuffer, HdPrimTypeTokens->renderSettings};

bool IsLight(TfToken const& type) {
    return type == HdPrimTypeTokens->rectLight || type == HdPrimTypeTokens->diskLight ||
           type == HdPrimTypeTokens->sphereLight || type == HdPrimTypeTokens->cylinderLight ||
           type == HdPrimTypeTokens->distantLight || type == HdPrimTypeTokens->domeLight ||
           type == HdPrimTypeTokens->light;  // generic: PortalLight (light.cpp)
}

}  // namespace

HdGiRenderDelegate::HdGiRenderDelegate() { _Initialize(); }

HdGiRenderDelegate::HdGiRenderDelegate(HdRenderSettingsMap const& settingsMap) : HdRenderDelegate(settingsMap) {
    _Initialize();
}

void HdGiRenderDelegate::_Initialize() {
    for (HdRenderSettingDescriptor const& d : HdGiSettingDescriptors())
        if (_settingsMap.find(d.key) == _settingsMap.end()) _settingsMap[d.key] = d.defaultValue;
    _renderParam = std::make_unique<HdGiRenderParam>(&_renderThread, &_cancel);
    _session = std::make_unique<HdGiRenderSession>(&_renderThread, _renderParam.get(), &_cancel);
    _renderThread.SetRenderCallback([this] { _session->Run(); });
    _renderThread.StartThread();
    _resourceRegistry = std::make_shared<HdResourceRegistry>();
}

HdGiRenderDelegate::~HdGiRenderDelegate() {
    _cancel = true;
    _renderThread.StopThread();
    _session.reset();
    _renderParam.reset();
}

HdRenderParam* HdGiRenderDelegate::GetRenderParam() const { return _renderParam.get(); }
TfTokenVector const& HdGiRenderDelegate::GetSupportedRprimTypes() const { return kRprimTypes; }
TfTokenVector const& HdGiRenderDelegate::GetSupportedSprimTypes() const { return kSprimTypes; }
TfTokenVector const& HdGiRenderDelegate::GetSupportedBprimTypes() const { return kBprimTypes; }
HdResourceRegistrySharedPtr HdGiRenderDelegate::GetResourceRegistry() const { return _resourceRegistry; }
HdRenderSettingDescriptorList HdGiRenderDelegate::GetRenderSettingDescriptors() const { return HdGiSettingDescriptors(); }

VtDictionary HdGiRenderDelegate::GetRenderStats() const {
    HdGiSessionStats s = _session->Stats();
    VtDictionary stats;
    stats["sceneBuildSeconds"] = s.sceneBuildSeconds;
    stats["firstPixelSeconds"] = s.firstPixelSeconds;  // a low-resolution preview's, in a large view
    stats["firstPassSeconds"] = s.firstPassSeconds;
    stats["renderSeconds"] = s.renderSeconds;
    stats["samples"] = s.samples;
    stats["rays"] = double(s.rays);
    stats["nonFiniteSamples"] = double(s.nonFiniteSamples);  // must stay 0 (tests/hydra assert it)
    stats["converged"] = s.converged;
    stats["lastTileTime"] = s.lastTileTime;
    // Of the textures the current scene binds, how many its build read from disk (an edit
    // rebuilds the scene; unchanged files come from the session's image cache).
    stats["textures"] = s.textures;
    stats["texturesRead"] = s.texturesRead;
    // The last build's BVH work: an edit builds only what it changed (gi::Scene::reuseBvhOf), and
    // masks the old selves of what it changed in the BVH it keeps.
    stats["primitivesBuilt"] = s.primitivesBuilt;
    stats["primitivesReused"] = s.primitivesReused;
    stats["primitivesMasked"] = s.primitivesMasked;
    stats["portals"] = s.portals;
    // usdview's HUD shows this key.
    stats["percentDone"] = s.targetSamples > 0 ? 100.0 * s.samples / s.targetSamples : 0.0;
    return stats;
}

bool HdGiRenderDelegate::Pause() {
    // The pass in flight is abandoned (and redone on resume) so work stops within a tile.
    _cancel = true;
    _renderThread.PauseRender();
    return true;
}

bool HdGiRenderDelegate::Resume() {
    _cancel = false;
    _renderThread.ResumeRender();
    return true;
}

bool HdGiRenderDelegate::Stop(bool blocking) {
    _cancel = true;
    if (blocking) _renderThread.StopRender();
    return true;
}

bool HdGiRenderDelegate::Restart() {
    _cancel = false;
    _renderThread.StartRender();
    return true;
}

HdRenderPassSharedPtr HdGiRenderDelegate::CreateRenderPass(HdRenderIndex* index, HdRprimCollection const& collection) {
    return std::make_shared<HdGiRenderPass>(index, collection, &_renderThread, _session.get(), _renderParam.get(),
                                            &_cancel);
}

HdInstancer* HdGiRenderDelegate::CreateInstancer(HdSceneDelegate* delegate, SdfPath const& id) {
    return new HdGiInstancer(delegate, id);
}

void HdGiRenderDelegate::DestroyInstancer(HdInstancer* instancer) { delete instancer; }

HdRprim* HdGiRenderDelegate::CreateRprim(TfToken const& typeId, SdfPath const& rprimId) {
    if (typeId == HdPrimTypeTokens->mesh) return new HdGiMesh(rprimId);
    if (typeId == HdPrimTypeTokens->sphere) return new HdGiSphere(rprimId);
    TF_CODING_ERROR("hdGi: unknown rprim type %s", typeId.GetText());
    return nullptr;
}

void HdGiRenderDelegate::DestroyRprim(HdRprim* rprim) { delete rprim; }

HdSprim* HdGiRenderDelegate::CreateSprim(TfToken const& typeId, SdfPath const& sprimId) {
    if (typeId == HdPrimTypeTokens->camera) return new HdGiCamera(sprimId);
    if (typeId == HdPrimTypeTokens->material) return new HdGiMaterial(sprimId);
    if (IsLight(typeId)) return new HdGiLight(sprimId, typeId);
    if (typeId == HdPrimTypeTokens->extComputation) return new HdExtComputation(sprimId);
    TF_CODING_ERROR("hdGi: unknown sprim type %s", typeId.GetText());
    return nullptr;
}

HdSprim* HdGiRenderDelegate::CreateFallbackSprim(TfToken const& typeId) { return CreateSprim(typeId, SdfPath::EmptyPath()); }

void HdGiRenderDelegate::DestroySprim(HdSprim* sprim) { delete sprim; }

HdBprim* HdGiRenderDelegate::CreateBprim(TfToken const& typeId, SdfPath const& bprimId) {
    if (typeId == HdPrimTypeTokens->renderBuffer) return new HdGiRenderBuffer(bprimId);
    if (typeId == HdPrimTypeTokens->renderSettings) return new HdGiRenderSettings(bprimId, this);
    TF_CODING_ERROR("hdGi: unknown bprim type %s", typeId.GetText());
    return nullptr;
}

HdBprim* HdGiRenderDelegate::CreateFallbackBprim(TfToken const& typeId) { return CreateBprim(typeId, SdfPath::EmptyPath()); }

void HdGiRenderDelegate::DestroyBprim(HdBprim* bprim) { delete bprim; }

HdAovDescriptor HdGiRenderDelegate::GetDefaultAovDescriptor(TfToken const& name) const {
    // Color is linear float: the host applies its color correction.
    if (name == HdAovTokens->color) return HdAovDescriptor(HdFormatFloat32Vec4, false, VtValue(GfVec4f(0.0f)));
    if (name == HdAovTokens->depth) return HdAovDescriptor(HdFormatFloat32, false, VtValue(1.0f));
    if (name == HdAovTokens->cameraDepth) return HdAovDescriptor(HdFormatFloat32, false, VtValue(0.0f));
    if (name == HdAovTokens->normal || name == TfToken("albedo"))
        return HdAovDescriptor(HdFormatFloat32Vec3, false, VtValue(GfVec3f(0.0f)));
    if (name == HdAovTokens->primId || name == HdAovTokens->instanceId || name == HdAovTokens->elementId)
        return HdAovDescriptor(HdFormatInt32, false, VtValue(-1));
    return HdAovDescriptor();
}

PXR_NAMESPACE_CLOSE_SCOPE
