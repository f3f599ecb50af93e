// The render thread's work: (re)build the renderer's scene when Hydra changed it, then render
// passes of the requested integrator into the bound AOV buffers until the samples or the time
// limit are done. Stop and pause reach the renderer through `cancel`, checked between tiles.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/base/gf/rect2i.h"
#include "pxr/imaging/hd/renderPassState.h"
#include "pxr/imaging/hd/renderThread.h"
#include "pxr/pxr.h"
#include "renderParam.h"
#include "renderer/denoiser.h"
#include "renderer/render.h"

PXR_NAMESPACE_OPEN_SCOPE

// One image a batch host's render products ask for: the products that share a camera,
// resolution, framing and data window, written from one render (renderPass.cpp's ProductImages).
struct HdGiProductImage {
    std::optional<gi::CameraDesc> camera;
    gi::ImageFraming framing;
    GfRect2i dataWindow;
    gi::PixelWindow window;  // empty: all of dataWindow
    HdRenderSettings::RenderProducts products;
    bool productFramed = false;  // false: the host's camera and image size (the product cannot say)
};

// Everything one render depends on besides the scene.
struct HdGiRenderJob {
    gi::RenderSettings settings;
    std::optional<gi::CameraDesc> camera;  // none: the renderer's camera framing the whole scene
    GfMatrix4d projection{1.0};  // for the depth AOV (clip-space depth)
    GfRect2i dataWindow;
    HdRenderPassAovBindingVector aovs;
    bool domeLightCameraVisibility = true;
    bool denoise = false;  // gi:denoise: the colour AOV denoised after each pass
    HdRenderSettings::RenderProducts products;  // written when the render converges
    std::optional<double> frame;  // the host's current frame (names the products' files); none: not set
    // Rendered at the products' camera and resolution (a batch host): the AOV buffers, sized for
    // the host's viewport, are only marked converged.
    bool productMode = false;
    // Products whose camera, resolution, framing or data window differ from `products`': each
    // image rendered after this job's, in turn, as `gi render` renders each product; the AOVs
    // are converged when the last one is.
    std::vector<HdGiProductImage> moreImages;
};

struct HdGiSessionStats {
    // firstPixelSeconds: the first pixels shown, a preview's when there is one (_RenderPreview);
    // firstPassSeconds: the end of the first real pass.
    double sceneBuildSeconds = 0, firstPixelSeconds = 0, firstPassSeconds = 0, renderSeconds = 0;
    double lastTileTime = 0;  // steady_clock seconds: when the renderer last finished a tile
    int textures = 0, texturesRead = 0;  // bound by the last scene build; of them read from disk
    // The last scene build's BVH work: triangles and spheres built, and kept from the scene before.
    double primitivesBuilt = 0, primitivesReused = 0, primitivesMasked = 0;
    int portals = 0;  // UsdLux portal lights in use (renderer/portal.h)
    int samples = 0, targetSamples = 0;
    uint64_t rays = 0;
    // Samples the renderer replaced because they were NaN, Inf or negative (a renderer bug;
    // the film never shows them, so this count is the only trace).
    uint64_t nonFiniteSamples = 0;
    bool converged = false;
};

// AOVs the film fills (color, depth, cameraDepth, normal, albedo, primId, instanceId).
bool HdGiIsSupportedAov(TfToken const& name);

class HdGiRenderSession {
public:
    HdGiRenderSession(HdRenderThread* thread, HdGiRenderParam* param, std::atomic<bool>* cancel);
    // Called with the render thread stopped.
    void SetJob(HdGiRenderJob const& job);
    void Run();  // the render thread's callback
    bool IsConverged() const { return _converged.load(); }
    HdGiSessionStats Stats() const;

private:
    // One image of the job: the scene (re)built for its camera's shutter, then its passes until
    // its samples or time limit are done; `showsAovs`: its film goes to the AOVs (the job's first
    // image), which are marked converged when `last` converges. True when it converged.
    bool _Render(HdGiRenderJob const& job, bool showsAovs, bool last);
    void _WriteAovs(gi::Renderer const& renderer, HdGiRenderJob const& job, bool converged);
    // A quick low-resolution image into the AOVs before the first pass; false if none was shown.
    bool _RenderPreview(HdGiRenderJob const& job, gi::RenderSettings const& settings);
    // The film's colour, denoised when the job asks for it and Open Image Denoise is there.
    // The job's render products, written from the converged film (products.h).
    void _WriteProducts(gi::Renderer const& renderer, HdGiRenderJob const& job);
    std::vector<float> _Color(gi::Film const& film, HdGiRenderJob const& job, bool converged);

    HdRenderThread* _thread;
    HdGiRenderParam* _param;
    std::atomic<bool>* _cancel;
    HdGiRenderJob _job;
    std::unique_ptr<gi::Scene> _scene;
    HdGiIdMap _ids;
    int _sceneVersion = -1;
    bool _sceneDomeVisible = true;
    GfVec2f _sceneShutter{0.0f};
    std::atomic<bool> _converged{false};
    mutable std::mutex _statsMutex;
    HdGiSessionStats _stats;
    gi::Renderer const* _active = nullptr;  // guarded by _statsMutex
    // Used on the render thread only; loaded on the first denoised pass. _denoiserMissing: it
    // could not be loaded (warned once; colour stays raw).
    std::unique_ptr<gi::Denoiser> _denoiser;
    bool _denoiserMissing = false;
    // Integrator "auto": the session's choice, kept for its later renders (restarts after a
    // camera move or an edit, later frames and render products) while auto's settings are those it
    // was made for (_autoChoiceFor), as `gi render` keeps it for its frames
    // (RenderSettings::keptAutoChoice); a render with another technique drops it. Render thread only.
    std::string _autoChoice, _autoChoiceFor;
};

PXR_NAMESPACE_CLOSE_SCOPE
