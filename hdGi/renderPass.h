// The render pass returns at once: it restarts the render thread when the scene, the
// settings, the camera, the framing or the AOV bindings changed, and reports convergence.
#pragma once
#include <atomic>
#include <optional>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/base/gf/rect2i.h"
#include "pxr/imaging/hd/renderPass.h"
#include "pxr/pxr.h"
#include "renderSession.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderPass final : public HdRenderPass {
public:
    HdGiRenderPass(HdRenderIndex* index, HdRprimCollection const& collection, HdRenderThread* thread,
                   HdGiRenderSession* session, HdGiRenderParam* param, std::atomic<bool>* cancel);
    ~HdGiRenderPass() override;
    bool IsConverged() const override;

protected:
    void _Execute(HdRenderPassStateSharedPtr const& renderPassState, TfTokenVector const& renderTags) override;

private:
    HdRenderThread* _thread;
    HdGiRenderSession* _session;
    HdGiRenderParam* _param;
    std::atomic<bool>* _cancel;
    int _sceneVersion = -1, _settingsVersion = -1;
    GfMatrix4d _view{0.0}, _projection{0.0};
    GfRect2i _dataWindow;
    gi::PixelWindow _window;
    std::optional<double> _frame;
    bool _warnedNoCamera = false;
    HdRenderPassAovBindingVector _aovs;
    bool _started = false;
};

PXR_NAMESPACE_CLOSE_SCOPE
