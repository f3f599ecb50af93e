#include "light.h"

#include "pxr/base/gf/vec3f.h"
#include "pxr/imaging/hd/material.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/imaging/hd/timeSampleArray.h"
#include "pxr/imaging/hd/tokens.h"
#include "pxr/usd/sdf/assetPath.h"
#include "renderParam.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiLight::HdGiLight(SdfPath const& id, TfToken const& lightType) : HdLight(id), _lightType(lightType) {}

HdDirtyBits HdGiLight::GetInitialDirtyBitsMask() const { return AllDirty; }

namespace {

// The shader id of a generic `light` sprim (UsdImaging's scene index gives UsdLux lights that
// have no Hydra type of their own, such as PortalLight, this type; their light network's
// terminal node names the schema).
TfToken GenericLightShaderId(HdSceneDelegate* delegate, SdfPath const& id) {
    VtValue resource = delegate->GetMaterialResource(id);
    if (!resource.IsHolding<HdMaterialNetworkMap>()) return TfToken();
    auto const& networks = resource.UncheckedGet<HdMaterialNetworkMap>().map;
    auto network = networks.find(HdMaterialTerminalTokens->light);
    if (network == networks.end() || network->second.nodes.empty()) return TfToken();
    return network->second.nodes.back().identifier;
}

std::string Kind(TfToken const& type, HdSceneDelegate* delegate, SdfPath const& id) {
    if (type == HdPrimTypeTokens->light) return GenericLightShaderId(delegate, id) == "PortalLight" ? "portal" : "";
    if (type == HdPrimTypeTokens->rectLight) return "rect";
    if (type == HdPrimTypeTokens->diskLight) return "disk";
    if (type == HdPrimTypeTokens->sphereLight) return "sphere";
    if (type == HdPrimTypeTokens->cylinderLight) return "cylinder";
    if (type == HdPrimTypeTokens->distantLight) return "distant";
    if (type == HdPrimTypeTokens->domeLight) return "dome";
    return "";
}

template <typename T>
bool Param(HdSceneDelegate* delegate, SdfPath const& id, TfToken const& name, T* out) {
    VtValue v = delegate->GetLightParamValue(id, name);
    if (v.IsHolding<T>()) {
        *out = v.UncheckedGet<T>();
        return true;
    }
    if constexpr (std::is_same_v<T, float>) {
        if (v.IsHolding<double>()) return *out = float(v.UncheckedGet<double>()), true;
    }
    return false;
}

}  // namespace

void HdGiLight::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) {
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    SdfPath const& id = GetId();
    if (!(*dirtyBits & (DirtyTransform | DirtyParams | DirtyResource | DirtyShadowParams | DirtyCollection))) {
        *dirtyBits = Clean;
        return;
    }
    std::string kind = Kind(_lightType, delegate, id);
    auto record = std::make_shared<HdGiLightRecord>();
    gi::LightDesc* light = &record->desc;
    light->name = id.GetString();
    light->kind = kind;
    GfVec3f color(1.0f);
    if (Param(delegate, id, HdLightTokens->color, &color)) light->color = gi::Color(color[0], color[1], color[2]);
    Param(delegate, id, HdLightTokens->intensity, &light->intensity);
    Param(delegate, id, HdLightTokens->exposure, &light->exposure);
    Param(delegate, id, HdLightTokens->normalize, &light->normalize);
    Param(delegate, id, HdLightTokens->width, &light->width);
    Param(delegate, id, HdLightTokens->height, &light->height);
    Param(delegate, id, HdLightTokens->radius, &light->radius);
    Param(delegate, id, HdLightTokens->length, &light->length);
    Param(delegate, id, HdLightTokens->angle, &light->angle);
    bool visibleInPrimaryRay = true;
    if (Param(delegate, id, TfToken("visibleInPrimaryRay"), &visibleInPrimaryRay))
        light->visibleToCamera = visibleInPrimaryRay;
    SdfAssetPath texture;
    if ((kind == "dome" || kind == "rect") && Param(delegate, id, HdLightTokens->textureFile, &texture) &&
        !texture.GetAssetPath().empty()) {
        light->textureFile = texture.GetResolvedPath();
        if (light->textureFile.empty())
            param->Warn(id, "texture file '" + texture.GetAssetPath() + "' was not found; using the light's color");
    }
    light->transform = HdGiToMat4(delegate->GetTransform(id));
    // The transform's motion for blur, over the cameras' shutters (HdGiRenderParam's sampling
    // interval: cameras sync before lights) and at least a frame either side of the frame. A light
    // is an sprim, which 24.11's scene index emulation gives no way to mark for resampling when a
    // shutter is edited later (gprim.h's HdGiDirtyShutter reaches rprims only); the wider interval
    // keeps such an edit within a frame of the frame blurred right.
    GfVec2f const interval = param->SamplingInterval();
    HdTimeSampleArray<GfMatrix4d, 4> samples;
    delegate->SampleTransform(id, std::min(interval[0], -1.0f), std::max(interval[1], 1.0f), &samples);
    record->transformTimes.assign(samples.times.begin(), samples.times.begin() + samples.count);
    record->transformSamples.assign(samples.values.begin(), samples.values.begin() + samples.count);
    bool visible = delegate->GetVisible(id);

    HdGiSceneStore& store = param->EditScene();
    if (kind.empty()) {
        std::string what = _lightType == HdPrimTypeTokens->light
                               ? "a light of shader '" + GenericLightShaderId(delegate, id).GetString() + "'"
                               : std::string(_lightType.GetText());
        param->Warn(id, what + " is not supported; ignored");
        store.SetLight(id, nullptr);
    } else {
        store.SetLight(id, visible ? std::shared_ptr<const HdGiLightRecord>(record) : nullptr);
    }
    *dirtyBits = Clean;
}

void HdGiLight::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->EditScene().Remove(GetId());
}

PXR_NAMESPACE_CLOSE_SCOPE
