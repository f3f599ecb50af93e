#include "render.h"

#include <sys/resource.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>

namespace gi {

namespace {
constexpr int kTileSize = 16;
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
bool past(double deadline) { return deadline > 0 && steadySeconds() >= deadline; }

// A scene given no camera is framed as usdrecord frames a stage without one (camera_framing.h), from
// its geometry's box, Y up (the scene does not know the stage's up axis; `gi render` frames stages
// itself, with their bounding box and up axis).
CameraDesc defaultCamera(const Scene& scene) {
    Vec3 lo = scene.boundsMin(), hi = scene.boundsMax();
    CameraDesc c = framingCamera({0.5 * (double(lo.x) + hi.x), 0.5 * (double(lo.y) + hi.y), 0.5 * (double(lo.z) + hi.z)},
                                 {double(hi.x) - lo.x, double(hi.y) - lo.y, double(hi.z) - lo.z}, false);
    c.name = "<default camera>";
    return c;
}
}  // namespace

double steadySeconds() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

double PreprocessContext::secondsLeft() const {
    return deadline > 0 ? std::max(0.0, deadline - steadySeconds()) : std::numeric_limits<double>::infinity();
}

void PreprocessContext::scaledDown(const std::string& what) const {
    scene.warn("time limit: " + what);
    if (scaledDownCount) scaledDownCount->fetch_add(1, std::memory_order_relaxed);
}

size_t peakResidentMemoryBytes() {
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    return size_t(usage.ru_maxrss) * 1024;  // Linux reports kilobytes
}

Renderer::Renderer(const Scene& scene, const RenderSettings& settings, const CameraDesc* camera)
    : scene_(scene), settings_(settings), film_(std::max(1, settings.width), std::max(1, settings.height),
                                                  Filter::byName(settings.filter)) {
    if (settings.width <= 0 || settings.height <= 0 || settings.width > 65536 || settings.height > 65536)
        throw std::invalid_argument("resolution " + std::to_string(settings.width) + "x" +
                                    std::to_string(settings.height) + " is out of range");
    if (!scene.committed()) throw std::logic_error("the scene must be committed before rendering");
    const PixelWindow& win = settings.window;
    if (!(win.x0 == 0 && win.y0 == 0 && win.x1 == 0 && win.y1 == 0) &&
        (win.empty() || win.x0 < 0 || win.y0 < 0 || win.x1 > settings.width || win.y1 > settings.height))
        throw std::invalid_argument("data window [" + std::to_string(win.x0) + ", " + std::to_string(win.x1) + ") x [" +
                                    std::to_string(win.y0) + ", " + std::to_string(win.y1) + ") is not inside the " +
                                    std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
    if (win.empty()) settings_.window = PixelWindow{0, 0, settings.width, settings.height};
    const PixelMosaic& mosaic = settings.mosaic;
    if (mosaic.tile > 0) {
        bool fits = mosaic.across > 0 && mosaic.x0.size() == mosaic.y0.size() && mosaic.tiles() % mosaic.across == 0 &&
                    mosaic.tiles() > 0 && mosaic.width() == settings.width && mosaic.height() == settings.height;
        for (size_t t = 0; fits && t < mosaic.x0.size(); ++t)
            fits = mosaic.x0[t] >= 0 && mosaic.y0[t] >= 0 && mosaic.x0[t] + mosaic.tile <= settings.imageWidth &&
                   mosaic.y0[t] + mosaic.tile <= settings.imageHeight;
        if (!fits) throw std::invalid_argument("the pixel mosaic does not tile the film inside its image");
    }
    const IntegratorInfo* info = findIntegrator(settings.integrator);
    if (!info) {
        std::string names;
        for (const auto& i : integratorRegistry()) names += (names.empty() ? "" : ", ") + i.name;
        throw std::invalid_argument("unknown integrator '" + settings.integrator + "' (have: " + names + ")");
    }
    info_ = info;
    // A name the integrator does not take is a typo or meant for another one: rendering
    // something else silently (with that parameter at its default) is worse than refusing.
    for (const auto& [name, value] : settings.params.values()) {
        bool takes = false;
        for (const ParamInfo& p : info->params) takes = takes || p.name == name;
        if (takes) continue;
        std::string names;
        for (const ParamInfo& p : info->params) names += (names.empty() ? "" : ", ") + p.name;
        throw std::invalid_argument("integrator " + info->name + " has no parameter '" + name + "' (it takes: " +
                                    (names.empty() ? "none" : names) + ")");
    }
    if (!settings.keptAutoChoice.empty()) {
        const auto& candidates = autoCandidates();
        if (settings.integrator != kAutoIntegrator)
            throw std::invalid_argument("a kept auto choice ('" + settings.keptAutoChoice + "') is for integrator " +
                                        kAutoIntegrator + ", not " + settings.integrator);
        if (std::find(candidates.begin(), candidates.end(), settings.keptAutoChoice) == candidates.end())
            throw std::invalid_argument("'" + settings.keptAutoChoice + "' is not a technique auto chooses");
    }
    settings_.params = withPreset(settings.preset, settings.integrator, settings.params);
    if (settings.integrator != kAutoIntegrator) integrator_ = info->create(settings_.params);
    CameraDesc desc = camera ? *camera : scene.hasCamera() ? scene.cameraDesc() : defaultCamera(scene);
    if (!desc.transform.isFinite() || desc.transform.det3() == 0) {
        scene.warn("camera " + desc.name + ": NaN, Inf or singular transform; using a camera that frames the scene");
        desc = defaultCamera(scene);
    }
    for (float v : {desc.focalLength, desc.horizontalAperture, desc.verticalAperture, desc.horizontalApertureOffset,
                    desc.verticalApertureOffset, desc.fStop, desc.focusDistance, desc.clipNear})
        if (!std::isfinite(v)) {
            scene.warn("camera " + desc.name + ": NaN or Inf in its lens or clipping settings; defaults used there");
            break;
        }
    if (desc.shutterClose < desc.shutterOpen || std::isnan(desc.shutterOpen) || std::isnan(desc.shutterClose))
        scene.warn("camera " + desc.name + ": shutter:close (" + std::to_string(desc.shutterClose) +
                   ") is before shutter:open (" + std::to_string(desc.shutterOpen) +
                   ") or not a number; rendered without motion blur");
    Mat4 inverse;
    for (const Mat4& m : desc.motionTransforms)
        if (!m.isFinite() || !m.inverse(inverse)) {
            scene.warn("camera " + desc.name + ": NaN, Inf or singular transform among its motion steps; rendered "
                       "without camera motion");
            break;
        }
    cameraDesc_ = desc;
    camera_ = mosaic.tile > 0 ? Camera(desc, settings.imageWidth, settings.imageHeight, settings.framing, mosaic)
                              : Camera(desc, settings.width, settings.height, settings.framing);
}

bool Renderer::chooseAutomatically(const std::atomic<bool>* cancel, double deadline) {
    const IntegratorInfo& automatic = *info_;
    double share = paramValue(automatic, settings_.params, "autoPilotShare");
    double budget = deadline > 0 ? std::max(0.0, deadline - steadySeconds())
                                 : paramValue(automatic, settings_.params, "autoHorizon");
    if (!settings_.keptAutoChoice.empty()) {  // an earlier render's choice: no pilots, the whole budget
        autoChoice_ = AutoChoice();
        autoChoice_.integrator = settings_.keptAutoChoice;
        autoChoice_.kept = true;
        autoChoice_.budgetSeconds = budget;
    } else {
        autoChoice_ = chooseIntegrator(scene_, settings_, cameraDesc_, (1 - share) * budget, share * budget, cancel);
    }
    if (autoChoice_.cancelled) return false;
    // The chosen technique takes the render's preset and the parameters every integrator takes.
    ParamSet shared;
    for (const auto& [name, value] : settings_.params.values())
        if (name == "sampleClamp") shared.set(name, value);
    info_ = findIntegrator(autoChoice_.integrator);
    settings_.integrator = autoChoice_.integrator;
    settings_.params = withPreset(settings_.preset, settings_.integrator, shared);
    integrator_ = info_->create(settings_.params);
    return true;
}

bool Renderer::preprocess(const std::atomic<bool>* cancel, double deadline) {
    if (preprocessed_) return true;
    auto start = Clock::now();
    if (!integrator_ && !chooseAutomatically(cancel, deadline)) {
        stats_.preprocessSeconds += secondsSince(start);
        return false;
    }
    std::atomic<int> scaledDown{0};
    PreprocessContext context{scene_, camera_, settings_.width, settings_.height,
                              settings_.cacheSeed.value_or(settings_.seed), cancel};
    if (deadline > 0) {
        double now = steadySeconds();
        context.deadline = now + kPreprocessShare * std::max(0.0, deadline - now);
    }
    context.scaledDownCount = &scaledDown;
    tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
    arena.execute([&] { integrator_->preprocess(context); });
    stats_.preprocessSeconds += secondsSince(start);
    stats_.preprocessScaledDown += scaledDown.load();
    if (cancel && cancel->load()) {
        integrator_ = info_->create(settings_.params);  // a half-built cache must not be used
        return false;
    }
    preprocessed_ = true;
    return true;
}

void Renderer::reset(int firstSample, std::optional<uint32_t> seed) {
    if (seed) settings_.seed = *seed;
    film_.clear();
    samplesTaken_ = 0;
    firstSample_ = firstSample;
    nextPassSamples_ = 1;
    progress_ = 0;
}

bool Renderer::renderPass(int firstSample, int count, const std::atomic<bool>* cancel) {
    return renderPass(firstSample, count, 0.0, cancel) == PassEnd::Complete;
}

int Renderer::passSamplesBefore(double deadline, int wanted) const {
    wanted = std::max(1, wanted);
    if (deadline <= 0 || stats_.cameraSamples == 0 || !(stats_.renderSeconds > 0)) return wanted;
    // Seconds per sample per pixel over the whole image, passes' overheads included.
    double pixels = double(settings_.window.area());
    double secondsPerSpp = stats_.renderSeconds * pixels / double(stats_.cameraSamples);
    // Half the time left: passes shrink towards the deadline, so the one it cuts has one sample
    // per pixel (unless the rate halves) and every pixel ends with n or n + 1.
    double fit = 0.5 * (deadline - steadySeconds()) / secondsPerSpp;
    return fit >= wanted ? wanted : std::max(1, int(fit));
}

PassEnd Renderer::renderPass(int firstSample, int count, double deadline, const std::atomic<bool>* cancel) {
    if (!preprocess(cancel, deadline)) return PassEnd::Cancelled;
    // Integrators that hold state per sample index take the pass in chunks; a cancel discards
    // only the chunk it cut (the ones before are complete passes of their own), and so does a
    // deadline.
    const int most = integrator_->maxSamplesPerPass();
    if (most > 0 && count > most) {
        for (int done = 0; done < count; done += most) {
            PassEnd end = renderPass(firstSample + done, std::min(most, count - done), deadline, cancel);
            if (end != PassEnd::Complete) return end;
        }
        return PassEnd::Complete;
    }
    if (past(deadline)) {  // no time for the pass's own setup either
        stats_.partialPassPixels = 0;
        stats_.partialPassSamples = count;
        return PassEnd::Deadline;
    }
    auto start = Clock::now();
    {
        PreprocessContext context{scene_, camera_, settings_.width, settings_.height,
                                  settings_.cacheSeed.value_or(settings_.seed), cancel};
        context.deadline = deadline;  // the pass's setup stops with the render
        context.passRays = stats_.rays;
        tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
        arena.execute([&] { integrator_->beginPass(context, firstSample, count); });
        stats_.passSetupSeconds += secondsSince(start);
        if (cancel && cancel->load()) return PassEnd::Cancelled;
    }
    int w = settings_.width, h = settings_.height;
    int tilesX = (w + kTileSize - 1) / kTileSize, tilesY = (h + kTileSize - 1) / kTileSize;
    int tileCount = tilesX * tilesY;
    // The pixels sampled: the window grown by the filter's reach, so that a window pixel gets
    // every sample the whole image gives it. Tiles keep the whole image's grid (and merge in its
    // order), so the sums in each pixel are added in the same order as in the whole image.
    const int reach = film_.filter().name == "box" ? 0 : int(std::ceil(film_.filter().radius - 0.5f));
    const PixelWindow sampled{std::max(0, settings_.window.x0 - reach), std::max(0, settings_.window.y0 - reach),
                              std::min(w, settings_.window.x1 + reach), std::min(h, settings_.window.y1 + reach)};
    std::vector<std::unique_ptr<FilmTile>> tiles(tileCount);
    struct ThreadCounters {
        RayStats rays;
        uint64_t samples = 0, nonFinite = 0, clamped = 0;
        double tileSeconds = 0;
    };
    // Opt-in firefly clamp: a sample brighter than this luminance is scaled down to it (hue kept).
    const float clampLuminance = float(paramValue(*info_, settings_.params, "sampleClamp"));
    tbb::enumerable_thread_specific<ThreadCounters> counters;
    std::vector<std::vector<RecordedRay>> tileRays(settings_.recordRays ? tileCount : 0);
    std::atomic<int> done{0};
    std::atomic<bool> cut{false};
    std::atomic<uint64_t> pixelsDone{0};
    Vec3 forward = camera_.forward();
    tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, tileCount, [&](int t) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            if (past(deadline)) {
                cut = true;
                return;
            }
            int x0 = (t % tilesX) * kTileSize, y0 = (t / tilesX) * kTileSize;
            if (x0 >= sampled.x1 || y0 >= sampled.y1 || x0 + kTileSize <= sampled.x0 || y0 + kTileSize <= sampled.y0) {
                ++done;  // outside the window: nothing to sample, nothing to merge
                return;
            }
            auto tile = std::make_unique<FilmTile>(x0, y0, std::min(x0 + kTileSize, w), std::min(y0 + kTileSize, h),
                                                   film_.filter());
            ThreadCounters& c = counters.local();
            const auto tileStart = Clock::now();
            c.rays.record = settings_.recordRays ? &tileRays[t] : nullptr;
            Sampler sampler(settings_.seed);
            uint64_t tilePixels = 0;
            for (int y = tile->y0; y < tile->y1 && !(deadline > 0 && cut.load(std::memory_order_relaxed)); ++y)
                for (int x = tile->x0; x < tile->x1; ++x) {
                    // Checked per pixel, so the deadline is kept to within one pixel's samples.
                    if (past(deadline)) {
                        cut = true;
                        break;
                    }
                    if (!sampled.contains(x, y)) continue;
                    ++tilePixels;
                    for (int s = firstSample; s < firstSample + count; ++s) {
                        sampler.start(x, y, uint32_t(s));
                        Vec2 pixel = sampler.get2D();
                        Vec2 lens = sampler.get2D();
                        float fx = x + pixel.x, fy = y + pixel.y;
                        float time = camera_.hasShutterInterval() ? sampler.shutterTime() : 0.0f;
                        Ray ray = camera_.generateRay(fx, fy, lens, time);
                        SampleAovs aovs;
                        Color L = integrator_->Li(ray, scene_, sampler, c.rays, &aovs);
                        if (!isFinite(L) || L.x < 0 || L.y < 0 || L.z < 0) {
                            ++c.nonFinite;  // never let one bad sample poison the image
                            L = isFinite(L) ? vmax(L, Color(0.0f)) : Color(0.0f);
                        }
                        if (clampLuminance > 0) {
                            float y = luminance(L);
                            if (y > clampLuminance) {
                                L = L * (clampLuminance / y);
                                ++c.clamped;
                            }
                        }
                        aovs.depth *= dot(ray.d, forward);  // distance along the view axis, as EXR Z
                        tile->addSample(fx, fy, L, aovs);
                        ++c.samples;
                    }
                }
            pixelsDone += tilePixels;
            c.tileSeconds += secondsSince(tileStart);
            tiles[t] = std::move(tile);
            int finished = ++done;
            lastTileTime_.store(std::chrono::duration<double>(Clock::now().time_since_epoch()).count(),
                                std::memory_order_relaxed);
            double target = std::max(1, settings_.spp);
            progress_.store(std::min(1.0, (firstSample + double(finished) / tileCount * count) / target),
                            std::memory_order_relaxed);
        });
    });
    bool complete = !cut && done.load() == tileCount;  // every tile sampled (or outside the window)
    bool cancelled = !complete && cancel && cancel->load();
    // Merged in tile order after the pass: the image does not depend on thread timing. A pass
    // cut by the deadline keeps the pixels it finished; a cancelled one is discarded.
    if (!cancelled)
        for (auto& tile : tiles)
            if (tile) film_.merge(*tile);
    for (auto& rays : tileRays) settings_.recordRays->insert(settings_.recordRays->end(), rays.begin(), rays.end());
    for (const ThreadCounters& c : counters) {
        stats_.rays += c.rays.rays;
        stats_.cameraSamples += c.samples;
        stats_.nonFiniteSamples += c.nonFinite;
        stats_.clampedSamples += c.clamped;
        stats_.depthCappedPaths += c.rays.depthCapped;
        stats_.sampleThreadSeconds += c.tileSeconds;
    }
    stats_.renderSeconds += secondsSince(start);
    if (complete) samplesTaken_ = std::max(samplesTaken_, firstSample - firstSample_ + count);
    stats_.spp = samplesTaken_;
    if (complete) return PassEnd::Complete;
    if (cancelled) return PassEnd::Cancelled;
    stats_.partialPassPixels = pixelsDone.load();
    stats_.partialPassSamples = count;
    return PassEnd::Deadline;
}

PassEnd Renderer::renderNextPass(int maxPassSamples, double deadline, const std::atomic<bool>* cancel) {
    if (finished()) return PassEnd::Complete;
    int count = passSamplesBefore(deadline, std::min(nextPassSamples_, std::max(1, settings_.spp) - samplesTaken_));
    // A pass split into chunks (maxSamplesPerPass) keeps the chunks it finished: samplesTaken_
    // moves past them, and the chunks after start where they would have.
    PassEnd end = renderPass(firstSample_ + samplesTaken_, count, deadline, cancel);
    if (end == PassEnd::Complete) nextPassSamples_ = std::min(nextPassSamples_ * 2, std::max(1, maxPassSamples));
    return end;
}

void Renderer::render(const std::atomic<bool>* cancel, double startedAt, const PassHook& afterPass, int maxPassSamples) {
    double start = startedAt > 0 ? startedAt : steadySeconds();
    double deadline = settings_.timeLimit > 0 ? start + settings_.timeLimit : 0;
    while (!finished()) {
        PassEnd end = renderNextPass(maxPassSamples, deadline, cancel);  // preprocesses first
        bool goOn = afterPass ? afterPass(end) : end != PassEnd::Cancelled;
        if (!goOn || end == PassEnd::Deadline || past(deadline)) break;
    }
    const uint64_t windowPixels = uint64_t(settings_.window.area());
    if (deadline > 0 && samplesTaken_ == 0 && stats_.partialPassPixels < windowPixels &&
        !(cancel && cancel->load()))
        scene_.warn("time limit: " + std::to_string(settings_.timeLimit) + " s ran out before every pixel had a sample (" +
                    std::to_string(stats_.partialPassPixels) + " of " +
                    std::to_string(windowPixels) + " have one)");
    stats_.seconds = steadySeconds() - start;
    stats_.peakMemoryBytes = peakResidentMemoryBytes();
    stats_.integrator = integrator_->statistics();
    if (stats_.nonFiniteSamples > 0)  // the film never shows them: this is their only trace
        scene_.warn(settings_.integrator + ": " + std::to_string(stats_.nonFiniteSamples) +
                    " non-finite samples (NaN, Inf or negative) were replaced by zero");
    if (stats_.depthCappedPaths > 0)
        scene_.warn(settings_.integrator + ": " + std::to_string(stats_.depthCappedPaths) +
                    " paths reached the safety depth cap of " + std::to_string(kDepthCap) +
                    " vertices and were ended there (light trapped between specular surfaces?)");
}

}  // namespace gi
