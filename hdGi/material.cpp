#include "material.h"

#include <array>
#include <optional>

#include "pxr/base/gf/vec2d.h"
#include "pxr/base/gf/vec2f.h"
#include "pxr/base/gf/vec3d.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/gf/vec4d.h"
#include "pxr/base/gf/vec4f.h"
#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/usd/sdf/assetPath.h"
#include "gprim.h"
#include "renderParam.h"
#include "renderer/preview_surface.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiMaterial::HdGiMaterial(SdfPath const& id) : HdMaterial(id) {}

HdDirtyBits HdGiMaterial::GetInitialDirtyBitsMask() const { return AllDirty; }

namespace {

// A Hydra parameter as the network description holds it (renderer/shader_network.h); nothing for a
// type that description has no place for (the input then reads as unauthored).
std::optional<gi::ShaderValue> ShaderValueOf(VtValue const& v) {
    if (v.IsHolding<float>()) return v.UncheckedGet<float>();
    if (v.IsHolding<double>()) return float(v.UncheckedGet<double>());
    if (v.IsHolding<int>()) return float(v.UncheckedGet<int>());
    if (v.IsHolding<bool>()) return float(v.UncheckedGet<bool>());
    if (v.IsHolding<TfToken>()) return v.UncheckedGet<TfToken>().GetString();
    if (v.IsHolding<std::string>()) return v.UncheckedGet<std::string>();
    if (v.IsHolding<SdfAssetPath>()) {
        SdfAssetPath const& asset = v.UncheckedGet<SdfAssetPath>();
        return gi::ShaderAsset{asset.GetAssetPath(), asset.GetResolvedPath()};
    }
    auto floats = [](auto const& vec) {
        std::array<float, std::decay_t<decltype(vec)>::dimension> out;
        for (size_t i = 0; i < out.size(); ++i) out[i] = float(vec[i]);
        return gi::ShaderValue(out);
    };
    if (v.IsHolding<GfVec2f>()) return floats(v.UncheckedGet<GfVec2f>());
    if (v.IsHolding<GfVec2d>()) return floats(v.UncheckedGet<GfVec2d>());
    if (v.IsHolding<GfVec3f>()) return floats(v.UncheckedGet<GfVec3f>());
    if (v.IsHolding<GfVec3d>()) return floats(v.UncheckedGet<GfVec3d>());
    if (v.IsHolding<GfVec4f>()) return floats(v.UncheckedGet<GfVec4f>());
    if (v.IsHolding<GfVec4d>()) return floats(v.UncheckedGet<GfVec4d>());
    return std::nullopt;
}

gi::ShaderNetwork ShaderNetworkOf(HdMaterialNetwork2 const& network) {
    gi::ShaderNetwork out;
    for (auto const& [path, node] : network.nodes) {
        gi::ShaderNode& n = out.nodes[path.GetString()];
        n.id = node.nodeTypeId.GetString();
        for (auto const& [name, value] : node.parameters)
            if (std::optional<gi::ShaderValue> v = ShaderValueOf(value)) n.parameters[name.GetString()] = *v;
        for (auto const& [input, connections] : node.inputConnections)
            if (!connections.empty())
                n.connections[input.GetString()] = {connections[0].upstreamNode.GetString(),
                                                    connections[0].upstreamOutputName.GetString()};
    }
    return out;
}

}  // namespace

std::shared_ptr<gi::MaterialDesc> HdGiMaterialFromNetwork(SdfPath const& id, HdMaterialNetwork2 const& network,
                                                          HdGiRenderParam* param, std::vector<std::string>* readerVarnames) {
    auto terminal = network.terminals.find(HdMaterialTerminalTokens->surface);
    std::string surface = terminal == network.terminals.end() ? "" : terminal->second.upstreamNode.GetString();
    std::optional<gi::PreviewSurface> resolved = gi::resolvePreviewSurface(
        id.GetString(), ShaderNetworkOf(network), surface,
        [&](std::string const& path, std::string const& message) { param->Warn(path + ": " + message); });
    if (!resolved) return nullptr;
    *readerVarnames = std::move(resolved->readerVarnames);
    return std::make_shared<gi::MaterialDesc>(std::move(resolved->material));
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
