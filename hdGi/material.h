// Hydra material networks to the renderer's MaterialDesc: translated into renderer/shader_network.h's
// description and resolved by renderer/preview_surface.h, the rules `gi render` shares. Textures
// are only named here; the renderer reads them when a visible prim uses the material.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "pxr/imaging/hd/material.h"
#include "pxr/pxr.h"
#include "renderer/material.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderParam;

class HdGiMaterial final : public HdMaterial {
public:
    explicit HdGiMaterial(SdfPath const& id);
    void Sync(HdSceneDelegate* sceneDelegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    HdDirtyBits GetInitialDirtyBitsMask() const override;
    void Finalize(HdRenderParam* renderParam) override;
};

// The network's surface as a MaterialDesc (nullptr, after a warning, when it is not a
// UsdPreviewSurface); warnings name the material, node and input. `readerVarnames`
// receives the primvars its textures' UsdPrimvarReader_float2 nodes read, in input order.
std::shared_ptr<gi::MaterialDesc> HdGiMaterialFromNetwork(SdfPath const& id, HdMaterialNetwork2 const& network,
                                                          HdGiRenderParam* param, std::vector<std::string>* readerVarnames);

PXR_NAMESPACE_CLOSE_SCOPE
