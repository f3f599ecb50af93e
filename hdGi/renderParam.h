// Shared state the prims reach through Sync: the scene store and the render thread, which
// must stop before the scene changes (the render pass restarts it on the new version).
#pragma once
#include <atomic>
#include <mutex>
#include <set>
#include <string>

#include "pxr/base/tf/diagnostic.h"
#include "pxr/imaging/hd/renderDelegate.h"
#include "pxr/imaging/hd/renderThread.h"
#include "pxr/pxr.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderParam final : public HdRenderParam {
public:
    HdGiRenderParam(HdRenderThread* renderThread, std::atomic<bool>* cancel)
        : _renderThread(renderThread), _cancel(cancel) {}

    // Stops the render (the renderer checks `cancel` between tiles, so this returns within a
    // tile's time) and marks the scene changed.
    HdGiSceneStore& EditScene() {
        StopRender();
        _sceneVersion.fetch_add(1);
        return _store;
    }
    void StopRender() {
        _cancel->store(true);
        _renderThread->StopRender();
    }
    HdGiSceneStore const& Store() const { return _store; }
    int SceneVersion() const { return _sceneVersion.load(); }

    // A warning once per prim and message (Sync runs again on every edit).
    void Warn(SdfPath const& id, std::string const& message) {
        std::lock_guard<std::mutex> lock(_warnedMutex);
        if (_warned.insert(id.GetString() + ": " + message).second)
            TF_WARN("hdGi: %s: %s", id.GetText(), message.c_str());
    }

private:
    HdRenderThread* _renderThread;
    std::atomic<bool>* _cancel;
    std::atomic<int> _sceneVersion{1};
    HdGiSceneStore _store;
    std::mutex _warnedMutex;
    std::set<std::string> _warned;
};

PXR_NAMESPACE_CLOSE_SCOPE
