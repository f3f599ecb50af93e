#include "material.h"

#include <algorithm>

#include "pxr/base/gf/vec2f.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/gf/vec4f.h"
#include "pxr/base/tf/stringUtils.h"
#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/usd/sdf/assetPath.h"
#include "gprim.h"
#include "renderParam.h"
#include "renderer/usd_shading.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiMaterial::HdGiMaterial(SdfPath const& id) : HdMaterial(id) {}

HdDirtyBits HdGiMaterial::GetInitialDirtyBitsMask() const { return AllDirty; }

namespace {

float AsFloat(VtValue const& v, float fallback) {
    if (v.IsHolding<float>()) return v.UncheckedGet<float>();
    if (v.IsHolding<double>()) return float(v.UncheckedGet<double>());
    if (v.IsHolding<int>()) return float(v.UncheckedGet<int>());
    return fallback;
}

gi::Color AsColor(VtValue const& v, gi::Color fallback) {
    if (v.IsHolding<GfVec3f>()) {
        GfVec3f c = v.UncheckedGet<GfVec3f>();
        return gi::Color(c[0], c[1], c[2]);
    }
    return fallback;
}

void AsFloat4(VtValue const& v, float out[4]) {
    if (v.IsHolding<GfVec4f>()) {
        GfVec4f c = v.UncheckedGet<GfVec4f>();
        for (int i = 0; i < 4; ++i) out[i] = c[i];
    }
}

std::string AsToken(VtValue const& v, std::string fallback) {
    if (v.IsHolding<TfToken>()) return v.UncheckedGet<TfToken>().GetString();
    if (v.IsHolding<std::string>()) return v.UncheckedGet<std::string>();
    return fallback;
}

VtValue ParamOf(HdMaterialNode2 const& node, char const* name) {
    auto it = node.parameters.find(TfToken(name));
    return it == node.parameters.end() ? VtValue() : it->second;
}

HdMaterialConnection2 const* Upstream(HdMaterialNode2 const& node, char const* input) {
    auto it = node.inputConnections.find(TfToken(input));
    return it == node.inputConnections.end() || it->second.empty() ? nullptr : &it->second[0];
}

class NetworkReader {
public:
    NetworkReader(SdfPath const& id, HdMaterialNetwork2 const& network, HdGiRenderParam* param)
        : _id(id), _network(network), _param(param) {}

    HdMaterialNode2 const* Node(SdfPath const& path) const {
        auto it = _network.nodes.find(path);
        return it == _network.nodes.end() ? nullptr : &it->second;
    }

    // A UsdUVTexture feeding `input`, read into `texture`; false (and a warning for
    // unsupported nodes) when the input is a constant.
    bool Texture(HdMaterialNode2 const& surface, char const* input, gi::TextureDesc* texture,
                 std::vector<std::string>* readerVarnames) {
        HdMaterialConnection2 const* c = Upstream(surface, input);
        if (!c) return false;
        HdMaterialNode2 const* node = Node(c->upstreamNode);
        if (!node || node->nodeTypeId != TfToken("UsdUVTexture")) {
            _param->Warn(_id, std::string("inputs:") + input + " is driven by " + c->upstreamNode.GetString() +
                                  " (" + (node ? node->nodeTypeId.GetString() : "missing") +
                                  "), which is not supported there; using the default");
            return false;
        }
        VtValue file = ParamOf(*node, "file");
        if (file.IsHolding<SdfAssetPath>()) {
            SdfAssetPath const& asset = file.UncheckedGet<SdfAssetPath>();
            texture->file = asset.GetResolvedPath();
            if (texture->file.empty() && !asset.GetAssetPath().empty())
                _param->Warn(c->upstreamNode, "texture file '" + asset.GetAssetPath() + "' was not found; using its fallback");
        }
        // An unauthored parameter keeps TextureDesc's default, the spec's (renderer/texture.h).
        texture->wrapS = AsToken(ParamOf(*node, "wrapS"), texture->wrapS);
        texture->wrapT = AsToken(ParamOf(*node, "wrapT"), texture->wrapT);
        AsFloat4(ParamOf(*node, "scale"), texture->scale);
        AsFloat4(ParamOf(*node, "bias"), texture->bias);
        AsFloat4(ParamOf(*node, "fallback"), texture->fallback);
        texture->sourceColorSpace = AsToken(ParamOf(*node, "sourceColorSpace"), texture->sourceColorSpace);
        std::string output = c->upstreamOutputName.GetString();
        texture->channel = output == "r" || output == "g" || output == "b" || output == "a" ? output : "rgb";
        std::string varname = ReadStNetwork(*node, texture);
        if (!varname.empty() && std::find(readerVarnames->begin(), readerVarnames->end(), varname) == readerVarnames->end())
            readerVarnames->push_back(varname);
        return true;
    }

private:
    // The UsdTransform2d (optional) and UsdPrimvarReader_float2 feeding a texture's st: fills the
    // transform into `texture`, returns the reader's varname ("" without a reader).
    std::string ReadStNetwork(HdMaterialNode2 const& textureNode, gi::TextureDesc* texture) {
        HdMaterialConnection2 const* c = Upstream(textureNode, "st");
        HdMaterialNode2 const* node = c ? Node(c->upstreamNode) : nullptr;
        if (node && node->nodeTypeId == TfToken("UsdTransform2d")) {
            texture->stRotation = AsFloat(ParamOf(*node, "rotation"), texture->stRotation);
            VtValue scale = ParamOf(*node, "scale"), translation = ParamOf(*node, "translation");
            if (scale.IsHolding<GfVec2f>())
                texture->stScale = gi::Vec2(scale.UncheckedGet<GfVec2f>()[0], scale.UncheckedGet<GfVec2f>()[1]);
            if (translation.IsHolding<GfVec2f>())
                texture->stTranslation =
                    gi::Vec2(translation.UncheckedGet<GfVec2f>()[0], translation.UncheckedGet<GfVec2f>()[1]);
            c = Upstream(*node, "in");
            node = c ? Node(c->upstreamNode) : nullptr;
        }
        if (!node || !TfStringStartsWith(node->nodeTypeId.GetString(), "UsdPrimvarReader")) return "";
        return AsToken(ParamOf(*node, "varname"), "");
    }

    SdfPath const& _id;
    HdMaterialNetwork2 const& _network;
    HdGiRenderParam* _param;
};

}  // namespace

std::shared_ptr<gi::MaterialDesc> HdGiMaterialFromNetwork(SdfPath const& id, HdMaterialNetwork2 const& network,
                                                          HdGiRenderParam* param, std::vector<std::string>* readerVarnames) {
    auto terminal = network.terminals.find(HdMaterialTerminalTokens->surface);
    if (terminal == network.terminals.end()) return nullptr;
    auto surfaceIt = network.nodes.find(terminal->second.upstreamNode);
    if (surfaceIt == network.nodes.end() || surfaceIt->second.nodeTypeId != TfToken("UsdPreviewSurface")) {
        param->Warn(id, "no UsdPreviewSurface drives its surface output; using the prim's displayColor");
        return nullptr;
    }
    HdMaterialNode2 const& s = surfaceIt->second;
    NetworkReader reader(id, network, param);
    auto d = std::make_shared<gi::MaterialDesc>();
    d->name = id.GetString();
    // An unauthored input keeps MaterialDesc's default, the spec's (renderer/material.h).
    d->diffuseColor = AsColor(ParamOf(s, "diffuseColor"), d->diffuseColor);
    d->emissiveColor = AsColor(ParamOf(s, "emissiveColor"), d->emissiveColor);
    VtValue workflow = ParamOf(s, "useSpecularWorkflow");
    d->useSpecularWorkflow = workflow.IsHolding<int>() ? workflow.UncheckedGet<int>() != 0
                             : workflow.IsHolding<bool>() ? workflow.UncheckedGet<bool>()
                                                          : d->useSpecularWorkflow;
    d->specularColor = AsColor(ParamOf(s, "specularColor"), d->specularColor);
    d->metallic = AsFloat(ParamOf(s, "metallic"), d->metallic);
    d->roughness = AsFloat(ParamOf(s, "roughness"), d->roughness);
    d->clearcoat = AsFloat(ParamOf(s, "clearcoat"), d->clearcoat);
    d->clearcoatRoughness = AsFloat(ParamOf(s, "clearcoatRoughness"), d->clearcoatRoughness);
    d->opacity = AsFloat(ParamOf(s, "opacity"), d->opacity);
    d->opacityMode = AsToken(ParamOf(s, "opacityMode"), d->opacityMode);
    d->opacityThreshold = AsFloat(ParamOf(s, "opacityThreshold"), d->opacityThreshold);
    d->ior = AsFloat(ParamOf(s, "ior"), d->ior);

    // A textured input's constant becomes the texture's fallback (renderer/usd_shading.h).
    for (char const* input : {"diffuseColor", "emissiveColor", "specularColor", "metallic", "roughness", "opacity", "normal"}) {
        gi::TextureDesc texture;
        if (reader.Texture(s, input, &texture, readerVarnames)) gi::connectTexture(*d, input, texture);
    }
    if (Upstream(s, "displacement")) param->Warn(id, "displacement is not supported; ignored");
    return d;
}

void HdGiMaterial::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) {
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    SdfPath const& id = GetId();
    if (*dirtyBits & (DirtyResource | DirtyParams)) {
        VtValue resource = delegate->GetMaterialResource(id);
        std::shared_ptr<gi::MaterialDesc> desc;
        std::vector<std::string> readerVarnames;
        if (resource.IsHolding<HdMaterialNetworkMap>()) {
            HdMaterialNetwork2 network = HdConvertToHdMaterialNetwork2(resource.UncheckedGet<HdMaterialNetworkMap>());
            desc = HdGiMaterialFromNetwork(id, network, param, &readerVarnames);
        }
        // Meshes pick their texture coordinates by these names (HdGiMesh::Sync): when they change,
        // meshes read their primvars again (rprims sync after materials, in this same sync).
        if (param->EditScene().SetMaterial(id, desc, readerVarnames))
            delegate->GetRenderIndex().GetChangeTracker().MarkAllRprimsDirty(HdGiDirtyUvPrimvar);
    }
    *dirtyBits = Clean;
}

void HdGiMaterial::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->EditScene().Remove(GetId());
}

PXR_NAMESPACE_CLOSE_SCOPE
