// Shared state the prims reach through Sync: the scene store and the render thread, which
// must stop before the scene changes (the render pass restarts it on the new version).
#pragma once
#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "pxr/base/gf/vec2f.h"
#include "pxr/base/tf/diagnostic.h"
#include "pxr/imaging/hd/renderDelegate.h"
#include "pxr/imaging/hd/renderSettings.h"
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
    void Warn(SdfPath const& id, std::string const& message) { Warn(id.GetString() + ": " + message); }
    // A warning once per message (it names what it is about).
    void Warn(std::string const& message) {
        std::lock_guard<std::mutex> lock(_warnedMutex);
        if (_warned.insert(message).second) TF_WARN("hdGi: %s", message.c_str());
    }

    // The interval the gprims sample their motion over (times relative to the frame): the union of
    // the cameras' shutters, so that whichever camera renders finds its own inside. NoteShutter
    // returns whether the union changed (then every rprim's motion must be sampled again).
    bool NoteShutter(SdfPath const& camera, float open, float close) {
        std::lock_guard<std::mutex> lock(_shutterMutex);
        _shutters[camera] = GfVec2f(std::min(open, close), std::max(open, close));
        return _UpdateSamplingInterval();
    }
    void ForgetShutter(SdfPath const& camera) {
        std::lock_guard<std::mutex> lock(_shutterMutex);
        _shutters.erase(camera);
        _UpdateSamplingInterval();
    }
    GfVec2f SamplingInterval() const {
        std::lock_guard<std::mutex> lock(_shutterMutex);
        return _samplingInterval;
    }

    // The active render settings' products (empty: none), written when a render converges.
    void SetProducts(HdRenderSettings::RenderProducts const& products) {
        std::lock_guard<std::mutex> lock(_productsMutex);
        _products = products;
    }
    HdRenderSettings::RenderProducts Products() const {
        std::lock_guard<std::mutex> lock(_productsMutex);
        return _products;
    }

private:
    bool _UpdateSamplingInterval() {
        GfVec2f interval(0.0f);
        for (auto const& [camera, shutter] : _shutters)
            interval = GfVec2f(std::min(interval[0], shutter[0]), std::max(interval[1], shutter[1]));
        bool changed = interval != _samplingInterval;
        _samplingInterval = interval;
        return changed;
    }

    HdRenderThread* _renderThread;
    std::atomic<bool>* _cancel;
    std::atomic<int> _sceneVersion{1};
    HdGiSceneStore _store;
    std::mutex _warnedMutex;
    std::set<std::string> _warned;
    mutable std::mutex _shutterMutex;
    std::map<SdfPath, GfVec2f> _shutters;
    GfVec2f _samplingInterval{0.0f};  // always holds the frame (0)
    mutable std::mutex _productsMutex;
    HdRenderSettings::RenderProducts _products;
};

PXR_NAMESPACE_CLOSE_SCOPE
