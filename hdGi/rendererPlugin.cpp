#include "rendererPlugin.h"

#include "pxr/imaging/hd/rendererPluginRegistry.h"
#include "renderDelegate.h"

PXR_NAMESPACE_OPEN_SCOPE

TF_REGISTRY_FUNCTION(TfType) { HdRendererPluginRegistry::Define<HdGiRendererPlugin>(); }

HdRenderDelegate* HdGiRendererPlugin::CreateRenderDelegate() { return new HdGiRenderDelegate(); }

HdRenderDelegate* HdGiRendererPlugin::CreateRenderDelegate(HdRenderSettingsMap const& settingsMap) {
    return new HdGiRenderDelegate(settingsMap);
}

void HdGiRendererPlugin::DeleteRenderDelegate(HdRenderDelegate* renderDelegate) { delete renderDelegate; }

bool HdGiRendererPlugin::IsSupported(bool) const { return true; }

PXR_NAMESPACE_CLOSE_SCOPE
