// The Gi render delegate: creates the prims that translate Hydra's scene for the renderer,
// the render pass, and the render thread that renders progressively.
#pragma once
#include <atomic>
#include <memory>

#include "pxr/imaging/hd/renderDelegate.h"
#include "pxr/imaging/hd/renderThread.h"
#include "pxr/imaging/hd/resourceRegistry.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderParam;
class HdGiRenderSession;

class HdGiRenderDelegate final : public HdRenderDelegate {
public:
    HdGiRenderDelegate();
    explicit HdGiRenderDelegate(HdRenderSettingsMap const& settingsMap);
    ~HdGiRenderDelegate() override;

    HdRenderParam* GetRenderParam() const override;
    TfTokenVector const& GetSupportedRprimTypes() const override;
    TfTokenVector const& GetSupportedSprimTypes() const override;
    TfTokenVector const& GetSupportedBprimTypes() const override;
    HdResourceRegistrySharedPtr GetResourceRegistry() const override;
    HdRenderSettingDescriptorList GetRenderSettingDescriptors() const override;
    VtDictionary GetRenderStats() const override;

    bool IsPauseSupported() const override { return true; }
    bool Pause() override;
    bool Resume() override;
    bool IsStopSupported() const override { return true; }
    bool Stop(bool blocking = true) override;
    bool Restart() override;

    HdRenderPassSharedPtr CreateRenderPass(HdRenderIndex* index, HdRprimCollection const& collection) override;
    HdInstancer* CreateInstancer(HdSceneDelegate* delegate, SdfPath const& id) override;
    void DestroyInstancer(HdInstancer* instancer) override;
    HdRprim* CreateRprim(TfToken const& typeId, SdfPath const& rprimId) override;
    void DestroyRprim(HdRprim* rprim) override;
    HdSprim* CreateSprim(TfToken const& typeId, SdfPath const& sprimId) override;
    HdSprim* CreateFallbackSprim(TfToken const& typeId) override;
    void DestroySprim(HdSprim* sprim) override;
    HdBprim* CreateBprim(TfToken const& typeId, SdfPath const& bprimId) override;
    HdBprim* CreateFallbackBprim(TfToken const& typeId) override;
    void DestroyBprim(HdBprim* bprim) override;
    void CommitResources(HdChangeTracker* tracker) override {}
    HdAovDescriptor GetDefaultAovDescriptor(TfToken const& name) const override;
    TfTokenVector GetRenderSettingsNamespaces() const override { return {TfToken("gi")}; }

private:
    void _Initialize();

    std::atomic<bool> _cancel{false};
    HdRenderThread _renderThread;
    std::unique_ptr<HdGiRenderParam> _renderParam;
    std::unique_ptr<HdGiRenderSession> _session;
    HdResourceRegistrySharedPtr _resourceRegistry;
};

PXR_NAMESPACE_CLOSE_SCOPE
