// Render settings reflected from the renderer's integrator registry: one descriptor per
// integrator parameter ("gi:<integrator>:<param>"), plus the integrator, samples, seed and time
// limit. Nothing here lists an integrator or parameter by hand.
#pragma once
#include <string>

#include "pxr/imaging/hd/renderDelegate.h"
#include "pxr/imaging/hd/renderSettings.h"
#include "pxr/pxr.h"
#include "renderer/render.h"

PXR_NAMESPACE_OPEN_SCOPE

struct HdGiSettingsTokens {
    static TfToken const& Integrator();
    static TfToken const& Seed();
    static TfToken const& TimeLimit();
    static TfToken const& Preset();
    static TfToken const& Denoise();
    static TfToken Param(std::string const& integrator, std::string const& param);
};

HdRenderSettingDescriptorList HdGiSettingDescriptors();

// A UsdRenderSettings prim (the stage's renderSettingsPrimPath, e.g. usdrecord's): when active,
// its "gi:" attributes become the delegate's render settings, so a scene file can choose the
// integrator and its parameters ("gi:samples" sets the samples per pixel).
class HdGiRenderSettings final : public HdRenderSettings {
public:
    HdGiRenderSettings(SdfPath const& id, HdRenderDelegate* delegate) : HdRenderSettings(id), _delegate(delegate) {}

protected:
    void _Sync(HdSceneDelegate* sceneDelegate, HdRenderParam* renderParam, HdDirtyBits const* dirtyBits) override;

private:
    HdRenderDelegate* _delegate;
};

// The renderer's settings for the delegate's current values (resolution and camera aside).
// Unknown integrator names fall back to "path" with a warning.
gi::RenderSettings HdGiReadSettings(HdRenderDelegate const& delegate);

// Whether a "gi:" render setting names a setting of the delegate's (the fixed ones, or an
// integrator's parameter as gi:<integrator>:<param>); _Sync warns about the others.
bool HdGiIsKnownSetting(std::string const& key);

// gi:denoise: whether the colour AOV is denoised (Open Image Denoise) after each pass.
bool HdGiReadDenoise(HdRenderDelegate const& delegate);

PXR_NAMESPACE_CLOSE_SCOPE
