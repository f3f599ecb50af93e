#include "renderSession.h"

#include <chrono>
#include <thread>

#include "pxr/base/tf/diagnostic.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/tokens.h"
#include "products.h"
#include "renderBuffer.h"

PXR_NAMESPACE_OPEN_SCOPE

namespace {
using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
// Passes grow to this many samples: large enough to amortise the per-pass resolve, small
// enough that the image refreshes often.
constexpr int kMaxPassSamples = 8;
HdGiRenderBuffer* BufferOf(HdRenderPassAovBinding const& aov) { return dynamic_cast<HdGiRenderBuffer*>(aov.renderBuffer); }
// What auto's choice depends on besides the scene and the view: the budget (time limit), the
// preset and parameters, the threads. Empty when the integrator is not "auto".
std::string AutoSettings(gi::RenderSettings const& settings) {
    if (settings.integrator != gi::kAutoIntegrator) return {};
    std::string text = settings.preset + ";" + std::to_string(settings.timeLimit) + ";" + std::to_string(settings.threads);
    for (auto const& [name, value] : settings.params.values()) text += ";" + name + "=" + std::to_string(value);
    return text;
}
}  // namespace

bool HdGiIsSupportedAov(TfToken const& name) {
    static TfToken const albedo("albedo");
    return name == HdAovTokens->color || name == HdAovTokens->depth || name == HdAovTokens->cameraDepth ||
           name == HdAovTokens->normal || name == albedo || name == HdAovTokens->primId ||
           name == HdAovTokens->instanceId || name == HdAovTokens->elementId;
}

HdGiRenderSession::HdGiRenderSession(HdRenderThread* thread, HdGiRenderParam* param, std::atomic<bool>* cancel)
    : _thread(thread), _param(param), _cancel(cancel) {}

void HdGiRenderSession::SetJob(HdGiRenderJob const& job) {
    _job = job;
    _converged = false;
}

HdGiSessionStats HdGiRenderSession::Stats() const {
    std::lock_guard<std::mutex> lock(_statsMutex);
    HdGiSessionStats stats = _stats;
    if (_active) stats.lastTileTime = std::max(stats.lastTileTime, _active->lastTileTime());
    return stats;
}

void HdGiRenderSession::Run() {
    HdGiRenderJob const job = _job;
    if (job.aovs.empty() || job.dataWindow.IsEmpty()) return;
    std::vector<HdGiRenderJob> images = {job};
    for (HdGiProductImage const& image : job.moreImages) {
        HdGiRenderJob& next = images.emplace_back(job);
        next.camera = image.camera;
        next.settings.framing = image.framing;
        next.settings.window = image.window;
        next.dataWindow = image.dataWindow;
        next.products = image.products;
        next.productMode = true;  // no preview: its pixels never reach the AOVs
        next.moreImages.clear();
    }
    bool converged = false;
    for (size_t i = 0; i < images.size(); ++i) {
        converged = _Render(images[i], i == 0, i + 1 == images.size());
        if (!converged) break;  // stopped, or the render failed
    }
    _converged = converged;
}

bool HdGiRenderSession::_Render(HdGiRenderJob const& job, bool showsAovs, bool last) {
    auto start = Clock::now();
    double const startSeconds = gi::steadySeconds();
    // The render ends by the time limit, the scene build included, as in `gi render`.
    double const deadline = job.settings.timeLimit > 0 ? startSeconds + job.settings.timeLimit : 0;
    HdGiSessionStats stats;

    int version = _param->SceneVersion();
    GfVec2f const shutter = job.camera ? GfVec2f(job.camera->shutterOpen, job.camera->shutterClose) : GfVec2f(0.0f);
    if (!_scene || version != _sceneVersion || job.domeLightCameraVisibility != _sceneDomeVisible ||
        shutter != _sceneShutter) {
        auto buildStart = Clock::now();
        _scene = _param->Store().Build(&_ids, job.domeLightCameraVisibility, shutter, _scene.get());
        _sceneVersion = version;
        _sceneDomeVisible = job.domeLightCameraVisibility;
        _sceneShutter = shutter;
        stats.sceneBuildSeconds = SecondsSince(buildStart);
    }
    stats.textures = int(_scene->stats().textures);
    stats.texturesRead = int(_scene->stats().texturesRead);
    stats.primitivesBuilt = double(_scene->stats().primitivesBuilt);
    stats.primitivesReused = double(_scene->stats().primitivesReused);
    stats.primitivesMasked = double(_scene->stats().primitivesMasked);
    stats.portals = int(_scene->stats().portals);

    gi::RenderSettings settings = job.settings;
    settings.width = job.dataWindow.GetWidth();
    settings.height = job.dataWindow.GetHeight();
    std::string const autoSettings = AutoSettings(settings);
    if (autoSettings.empty()) {  // another technique: choosing auto again chooses anew
        _autoChoice.clear();
        _autoChoiceFor.clear();
    } else if (autoSettings == _autoChoiceFor) {
        settings.keptAutoChoice = _autoChoice;
    }
    if (showsAovs && _RenderPreview(job, settings)) stats.firstPixelSeconds = SecondsSince(start);
    std::unique_ptr<gi::Renderer> renderer;
    try {
        renderer = std::make_unique<gi::Renderer>(*_scene, settings, job.camera ? &*job.camera : nullptr);
    } catch (std::exception const& e) {
        TF_RUNTIME_ERROR("hdGi: cannot render: %s", e.what());
        return false;
    }
    _param->Store().ReportWarnings(*_scene);  // the camera's (a shutter closing before it opens)
    {
        std::lock_guard<std::mutex> lock(_statsMutex);
        _active = renderer.get();
    }
    int const target = std::max(1, settings.spp);
    bool converged = false, reportedChoice = false;
    // Renderer::render's pass loop, as `gi render`'s; after each pass the image goes to the AOVs.
    // A pass cut by a pause is waited on here and rendered again on resume, so the image is the
    // uninterrupted one (render.h).
    auto afterPass = [&](gi::PassEnd end) {
        if (end == gi::PassEnd::Cancelled) {
            while (_thread->IsPauseRequested() && !_thread->IsStopRequested())
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            return !_thread->IsStopRequested();
        }
        if (!reportedChoice && !renderer->autoChoice().integrator.empty()) {  // "auto" chose in this pass's preprocess
            // A kept choice is said once, when it was made, not on every restart.
            if (!renderer->autoChoice().kept) TF_STATUS("hdGi: %s", renderer->autoChoice().summary().c_str());
            reportedChoice = true;
            _autoChoice = renderer->autoChoice().integrator;
            _autoChoiceFor = autoSettings;
        }
        int taken = renderer->samplesTaken();
        converged = taken >= target || end == gi::PassEnd::Deadline || (deadline > 0 && gi::steadySeconds() >= deadline);
        if (stats.firstPassSeconds == 0) stats.firstPassSeconds = SecondsSince(start);
        if (stats.firstPixelSeconds == 0) stats.firstPixelSeconds = stats.firstPassSeconds;  // no preview
        // Products first: usdrecord looks for their files once the AOVs say converged.
        if (converged && !job.products.empty()) _WriteProducts(*renderer, job);
        if (showsAovs) _WriteAovs(*renderer, job, converged && last);
        if (converged && last && !showsAovs)
            for (HdRenderPassAovBinding const& aov : job.aovs)
                if (HdGiRenderBuffer* buffer = BufferOf(aov)) buffer->SetConverged(true);
        stats.samples = taken;
        stats.targetSamples = target;
        stats.rays = renderer->stats().rays;
        stats.nonFiniteSamples = renderer->stats().nonFiniteSamples;
        stats.renderSeconds = SecondsSince(start);
        stats.converged = converged && last;
        {
            std::lock_guard<std::mutex> lock(_statsMutex);
            _stats = stats;
        }
        return !converged && !_thread->IsStopRequested();
    };
    renderer->render(_cancel, startSeconds, afterPass, kMaxPassSamples);
    stats.renderSeconds = SecondsSince(start);  // the scene build, preprocessing and every pass
    // The renderer's warnings (non-finite samples replaced, paths at the depth cap, a time limit
    // too short for one sample): tests/hydra look for them (hdgi_errors).
    _param->Store().ReportWarnings(*_scene);
    std::lock_guard<std::mutex> lock(_statsMutex);
    _stats.renderSeconds = stats.renderSeconds;
    _stats.lastTileTime = std::max(_stats.lastTileTime, renderer->lastTileTime());
    _active = nullptr;
    return converged;
}

bool HdGiRenderSession::_RenderPreview(HdGiRenderJob const& job, gi::RenderSettings const& settings) {
    // An interactive view's first pixels within a few tens of milliseconds of an edit, as
    // Cycles' start resolution gives them: one path-traced sample per pixel at 1/kPreviewScale of
    // the resolution, shown enlarged, before the first real pass (a 1-sample pass over a whole
    // 597x540 Sponza takes about a second on two cores). It is never accumulated: the image
    // after the first pass is the one without a preview, bit for bit. Batch output (products)
    // and small views, whose first pass is quick anyway, skip it.
    constexpr int kPreviewScale = 8, kPreviewFromPixels = 256 * 256;
    if (job.productMode || settings.width * settings.height < kPreviewFromPixels) return false;
    gi::RenderSettings preview = settings;
    preview.width = (settings.width + kPreviewScale - 1) / kPreviewScale;
    preview.height = (settings.height + kPreviewScale - 1) / kPreviewScale;
    preview.window = gi::PixelWindow();
    preview.integrator = "path";
    preview.keptAutoChoice.clear();
    preview.params = gi::ParamSet();
    preview.preset.clear();
    preview.spp = 1;
    preview.timeLimit = 0;
    preview.recordRays = nullptr;
    try {
        gi::Renderer renderer(*_scene, preview, job.camera ? &*job.camera : nullptr);
        if (renderer.renderNextPass(1, 0, _cancel) != gi::PassEnd::Complete) return false;
        _WriteAovs(renderer, job, false);
    } catch (std::exception const&) {
        return false;  // the real render reports what is wrong
    }
    return true;
}

namespace {

// A film's pixels (channels per pixel, row by row) enlarged to width x height, nearest pixel.
template <typename T>
std::vector<T> Enlarged(std::vector<T> const& pixels, int channels, gi::Film const& film, int width, int height) {
    if (film.width() == width && film.height() == height) return pixels;
    std::vector<T> out(size_t(width) * height * channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            size_t from = (size_t(y) * film.height() / height * film.width() + size_t(x) * film.width() / width) * channels;
            std::copy_n(pixels.begin() + from, channels, out.begin() + (size_t(y) * width + x) * channels);
        }
    return out;
}

// The film's shape or instance ids as Hydra's (prim ids, instance indices); -1 where none.
std::vector<int32_t> HydraIds(std::vector<int32_t> ids, std::vector<int> const& map) {
    for (int32_t& id : ids) id = id >= 0 && size_t(id) < map.size() ? map[size_t(id)] : -1;
    return ids;
}

// Camera-space depth to Hydra's clip-space depth in [0, 1] (row-vector projection matrix).
float ClipDepth(GfMatrix4d const& p, float viewDepth) {
    double z = -viewDepth;
    double clipZ = z * p[2][2] + p[3][2], clipW = z * p[2][3] + p[3][3];
    return clipW != 0 ? float(std::clamp((clipZ / clipW + 1) * 0.5, 0.0, 1.0)) : 1.0f;
}

}  // namespace

std::vector<float> HdGiRenderSession::_Color(gi::Film const& film, HdGiRenderJob const& job, bool converged) {
    if (!job.denoise || _denoiserMissing) return film.color();
    try {
        if (!_denoiser) _denoiser = std::make_unique<gi::Denoiser>(std::vector<std::string>{}, job.settings.threads);
        // The final pass gets OIDN's final-frame set-up (albedo and normal prefiltered); the
        // passes before it the one-filter preview set-up, to keep the viewport responsive.
        return _denoiser->denoise(film, converged);
    } catch (gi::DenoiserUnavailable const& e) {
        _denoiserMissing = true;
        TF_WARN("hdGi: gi:denoise is on, but %s; showing the raw colour", e.what());
    } catch (std::exception const& e) {
        TF_WARN("hdGi: denoising failed (%s); showing the raw colour", e.what());
    }
    return film.color();
}

void HdGiRenderSession::_WriteProducts(gi::Renderer const& renderer, HdGiRenderJob const& job) {
    gi::Film const& film = renderer.film();
    auto ids = [](std::vector<int32_t> const& hydraIds) { return std::vector<float>(hydraIds.begin(), hydraIds.end()); };
    HdGiOutputPixels pixels = [&](gi::RenderOutput output) -> std::vector<float> {
        switch (output) {
            case gi::RenderOutput::Color: return _Color(film, job, true);
            case gi::RenderOutput::Depth: return film.depth();
            case gi::RenderOutput::Normal: return film.normal();
            case gi::RenderOutput::Albedo: return film.albedo();
            case gi::RenderOutput::PrimId: return ids(HydraIds(film.shapeIds(), _ids.shapePrimId));
            case gi::RenderOutput::InstanceId: return ids(HydraIds(film.instanceIds(), _ids.instanceIndex));
        }
        return {};
    };
    std::map<std::string, std::string> metadata = {{"gi:integrator", job.settings.integrator},
                                                   {"gi:spp", std::to_string(renderer.samplesTaken())},
                                                   {"gi:seed", std::to_string(job.settings.seed)}};
    if (job.frame) {  // as `gi render --frames` records it
        char text[64];
        std::snprintf(text, sizeof text, "%g", *job.frame);
        metadata["gi:frame"] = text;
    }
    HdGiWriteProducts(job.products, job.dataWindow.GetWidth(), job.dataWindow.GetHeight(), job.settings.window,
                      job.frame, pixels, metadata, [this](std::string const& message) { _param->Warn(message); });
}

void HdGiRenderSession::_WriteAovs(gi::Renderer const& renderer, HdGiRenderJob const& job, bool converged) {
    gi::Film const& film = renderer.film();
    GfRect2i const& window = job.dataWindow;
    // A preview's film is smaller than the window (_RenderPreview).
    auto fit = [&](auto const& pixels, int channels) {
        return Enlarged(pixels, channels, film, window.GetWidth(), window.GetHeight());
    };
    for (HdRenderPassAovBinding const& aov : job.aovs) {
        HdGiRenderBuffer* buffer = BufferOf(aov);
        if (!buffer) continue;
        if (job.productMode) {
            buffer->SetConverged(converged);
            continue;
        }
        TfToken const& name = aov.aovName;
        if (name == HdAovTokens->color) {
            buffer->WriteFloats(fit(_Color(film, job, converged), 3).data(), 3, window, 1.0f);
        } else if (name == HdAovTokens->depth || name == HdAovTokens->cameraDepth) {
            std::vector<float> depth = fit(film.depth(), 1);
            for (float& d : depth) {
                bool hit = std::isfinite(d);
                if (name == HdAovTokens->depth) d = hit ? ClipDepth(job.projection, d) : 1.0f;
                else d = hit ? d : 0.0f;
            }
            buffer->WriteFloats(depth.data(), 1, window, 0.0f);
        } else if (name == HdAovTokens->normal) {
            buffer->WriteFloats(fit(film.normal(), 3).data(), 3, window, 0.0f);
        } else if (name == TfToken("albedo")) {
            buffer->WriteFloats(fit(film.albedo(), 3).data(), 3, window, 0.0f);
        } else if (name == HdAovTokens->primId) {
            buffer->WriteInts(fit(HydraIds(film.shapeIds(), _ids.shapePrimId), 1).data(), window);
        } else if (name == HdAovTokens->instanceId) {
            buffer->WriteInts(fit(HydraIds(film.instanceIds(), _ids.instanceIndex), 1).data(), window);
        }
        // Anything else (elementId, unsupported AOVs) keeps its clear value.
        buffer->SetConverged(converged);
    }
}

PXR_NAMESPACE_CLOSE_SCOPE
