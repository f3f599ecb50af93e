// UsdLux lights (rect, disk, sphere, cylinder, distant, dome) to the renderer's LightDesc.
// A light's edit re-syncs only that light; the scene is rebuilt on the next render start.
#pragma once
#include "pxr/imaging/hd/light.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiLight final : public HdLight {
public:
    HdGiLight(SdfPath const& id, TfToken const& lightType);
    void Sync(HdSceneDelegate* sceneDelegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    HdDirtyBits GetInitialDirtyBitsMask() const override;
    void Finalize(HdRenderParam* renderParam) override;

private:
    TfToken _lightType;
};

PXR_NAMESPACE_CLOSE_SCOPE
