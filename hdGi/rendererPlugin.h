// The entry point Hydra's plugin system finds ("Gi" in usdview's renderer menu).
#pragma once
#include "pxr/imaging/hd/rendererPlugin.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRendererPlugin final : public HdRendererPlugin {
public:
    HdGiRendererPlugin() = default;
    ~HdGiRendererPlugin() override = default;

    HdRenderDelegate* CreateRenderDelegate() override;
    HdRenderDelegate* CreateRenderDelegate(HdRenderSettingsMap const& settingsMap) override;
    void DeleteRenderDelegate(HdRenderDelegate* renderDelegate) override;
    // A CPU renderer: supported with or without a GPU.
    bool IsSupported(bool gpuEnabled = true) const override;
};

PXR_NAMESPACE_CLOSE_SCOPE
