// The renderer (thesis 3.1): preprocess the integrator, then sample the image in tiles on all
// threads, in passes, so that a render can be progressive, time-limited and cancelled.
#pragma once
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "auto_select.h"
#include "film.h"
#include "integrator.h"
#include "pixel_window.h"

namespace gi {

struct RenderSettings {
    int width = 512, height = 512;
    // The pixels to render (a data window: a farm tile, a RenderProduct's dataWindowNDC); the
    // rest of the film stays empty. Each pixel's samples depend only on its position and the
    // seed, and the camera, the passes and preprocessing are those of the whole image, so the
    // pixels inside equal the whole image's bit for bit (for integrators that keep no state
    // across pixels during a pass; see gi.job). Empty: the whole image.
    PixelWindow window;
    // Auto's pilots (auto_select.h): the film, width x height, is this mosaic of tiles of an
    // imageWidth x imageHeight image, the one the camera frames. Empty: the film is the image.
    PixelMosaic mosaic;
    int imageWidth = 0, imageHeight = 0;
    // How the camera's aperture fits the image (UsdRenderSettings' aspectRatioConformPolicy and
    // pixelAspectRatio, or a Hydra host's framing): camera_framing.h.
    ImageFraming framing;
    int spp = 16;
    std::string integrator = "path";
    ParamSet params;
    std::string preset;  // a named parameter set (integrator.h) under `params`; empty = the defaults
    // Integrator "auto" only: the technique an earlier render chose (AutoChoice::integrator), taken
    // without pilots. Pilots are timed, so two renders may choose apart where two techniques come
    // close; a sequence's frames, a command's render products and a Hydra session's restarts keep
    // the first render's choice instead, so that they do not switch (flicker) between techniques.
    // Empty: the pilots choose.
    std::string keptAutoChoice;
    uint32_t seed = 0;
    // The seed of the integrator's preprocessing and caches (records, photon maps), where it
    // differs from the camera samples' `seed`: auto's pilots render two caches from the same
    // camera samples, so that their difference is the caches' own (auto_pilots.cpp).
    std::optional<uint32_t> cacheSeed;
    int threads = 0;         // 0 = all hardware threads
    // Seconds for the whole render, preprocessing included; 0 = none. Preprocessing gets about
    // half (kPreprocessShare) and scales itself down to fit; passes are sized from the measured
    // sample rate and the last one stops at the deadline, pixel by pixel.
    double timeLimit = 0;
    std::string filter = "box";
    // Benchmarks only: every ray the render casts is appended here (in tile order, so the same
    // settings record the same rays).
    std::vector<RecordedRay>* recordRays = nullptr;
};

struct RenderStats {
    double seconds = 0, preprocessSeconds = 0, renderSeconds = 0;
    uint64_t rays = 0, cameraSamples = 0, nonFiniteSamples = 0;
    uint64_t clampedSamples = 0;  // samples the sampleClamp parameter scaled down
    uint64_t depthCappedPaths = 0;  // paths the safety depth cap ended (kDepthCap; warned about)
    int spp = 0;  // complete passes' samples per pixel
    // A time-limited render's last pass, stopped at the deadline: the pixels it finished (they
    // have more samples than spp) and the samples per pixel that pass was rendering.
    uint64_t partialPassPixels = 0;
    int partialPassSamples = 0;
    int preprocessScaledDown = 0;  // times preprocessing did less than asked, to keep the time limit
    size_t peakMemoryBytes = 0;
    // Where the passes' time went: thread-seconds sampling pixels (the tiles' own time, summed over
    // threads: a pass's wall time also holds its threads' idle ends, which on a small image such as
    // auto's pilots is a fifth to most of it), and wall seconds in the integrator's setup of each
    // pass (a progressive photon map's photons, a cache's record refinement).
    double sampleThreadSeconds = 0, passSetupSeconds = 0;
    std::map<std::string, double> integrator;
};

// The share of a time limit preprocessing may use (the rest is for sampling the image).
inline constexpr double kPreprocessShare = 0.5;

// How a pass with a deadline ended.
enum class PassEnd { Complete, Deadline, Cancelled };

class Renderer {
public:
    // Throws std::invalid_argument for an unknown integrator or a bad resolution. `camera`
    // overrides the scene's camera (a host's view); by default the scene's, else one framing it.
    Renderer(const Scene& scene, const RenderSettings& settings, const CameraDesc* camera = nullptr);
    // Returns false if cancelled; a cancelled preprocess is discarded and redone by the next call.
    // `deadline` (steadySeconds(); 0 = none): when the render must end; the integrator's
    // preprocessing is given kPreprocessShare of the time left before it.
    bool preprocess(const std::atomic<bool>* cancel = nullptr, double deadline = 0);
    bool preprocessed() const { return preprocessed_; }
    // Adds samples [first, first + count) of every pixel to the film. Returns false if cancelled;
    // a cancelled pass leaves the film as it was, so the same pass can be rendered again.
    bool renderPass(int firstSample, int count, const std::atomic<bool>* cancel = nullptr);
    // renderPass with a deadline (steadySeconds(); 0 = none): once it passes, no further pixel is
    // started, and the pixels finished keep the pass's samples (the film is a per-pixel weighted
    // mean, so pixels with fewer samples than others stay unbiased). Cancelled: as renderPass.
    // After a Deadline end the samples [firstSample, firstSample + count) are in part of the
    // image: samplesTaken() stays at firstSample, and any further pass must start at
    // firstSample + count (a time-limited render just stops).
    PassEnd renderPass(int firstSample, int count, double deadline, const std::atomic<bool>* cancel = nullptr);
    // The samples per pixel, at most `wanted`, that the next pass can take in half the time left
    // before `deadline`, from the rate measured in the passes so far (`wanted` before any; at
    // least 1): passes shrink to one sample per pixel near the deadline, which cuts one of those.
    int passSamplesBefore(double deadline, int wanted) const;
    // The next pass of a progressive render towards settings.spp: passes start at one sample
    // per pixel and double up to `maxPassSamples` (amortising each pass's overhead while the
    // image still refreshes); with a deadline each is cut to what passSamplesBefore fits. A
    // cancelled pass is discarded and the next call renders the same samples again, so a
    // render paused (cancelled) and resumed is bit-identical to an uninterrupted one. Returns
    // Complete without rendering once settings.spp are taken.
    PassEnd renderNextPass(int maxPassSamples, double deadline = 0, const std::atomic<bool>* cancel = nullptr);
    // render()'s cap on a pass: long enough to amortise a pass's overhead, short enough that a
    // progressive image refreshes.
    static constexpr int kMaxPassSamples = 64;
    bool finished() const { return samplesTaken_ >= std::max(1, settings_.spp); }
    // Called after every pass: returns whether to go on. A host shows the image there; after a
    // Cancelled pass (a paused viewport) it may wait until the cancel is cleared and return true:
    // the same pass is then rendered again.
    using PassHook = std::function<bool(PassEnd)>;
    // Preprocess plus passes up to settings.spp (renderNextPass up to `maxPassSamples`), or until
    // settings.timeLimit (measured from this call) with the last pass cut at the deadline. After
    // a cancel, calling it again resumes the render where it stopped. Both hosts render through
    // it (`gi render`, hdGi's render thread with its `afterPass`), so a time limit, the
    // statistics and the warnings mean the same in both.
    // `startedAt` (steadySeconds(); 0 = now): when the budget began, for a host whose own work
    // before this call (committing the scene, building it) counts against the time limit;
    // stats().seconds is measured from it too.
    void render(const std::atomic<bool>* cancel = nullptr, double startedAt = 0, const PassHook& afterPass = {},
                int maxPassSamples = kMaxPassSamples);
    // Fraction of settings.spp done, updated after every tile; safe to read from any thread.
    double progress() const { return progress_.load(std::memory_order_relaxed); }
    // steady_clock time (seconds since its epoch) when the last tile finished: lets a host check
    // that a stop or pause request actually stopped the work.
    double lastTileTime() const { return lastTileTime_.load(std::memory_order_relaxed); }

    // With integrator "auto": the pilots' choice, made in preprocess() (empty integrator before).
    const AutoChoice& autoChoice() const { return autoChoice_; }
    // The integrator that renders: the settings', or the one "auto" chose.
    const std::string& integratorName() const { return settings_.integrator; }

    const Film& film() const { return film_; }
    const RenderStats& stats() const { return stats_; }
    // The integrator's counters now (stats().integrator holds them as render() ended).
    std::map<std::string, double> integratorStatistics() const {
        return integrator_ ? integrator_->statistics() : std::map<std::string, double>{};
    }
    int samplesTaken() const { return samplesTaken_; }
    const Camera& camera() const { return camera_; }
    // Clears the film, keeps the preprocessed integrator. The next passes take sample indices
    // from `firstSample` on, and with `seed` that seed's samples (and, where no cacheSeed is set,
    // the integrator's per-pass work: a progressive photon map's photons): an image independent
    // of the first one from the same preprocessing (auto's pilots measure their noise so).
    void reset(int firstSample = 0, std::optional<uint32_t> seed = std::nullopt);

private:
    // Integrator "auto": runs the pilots in part of the time before `deadline` (or of the
    // autoHorizon without one) and creates the integrator they choose. False if cancelled.
    bool chooseAutomatically(const std::atomic<bool>* cancel, double deadline);

    const Scene& scene_;
    RenderSettings settings_;
    Camera camera_;
    CameraDesc cameraDesc_;
    const IntegratorInfo* info_ = nullptr;
    AutoChoice autoChoice_;
    std::unique_ptr<Integrator> integrator_;
    Film film_;
    RenderStats stats_;
    int samplesTaken_ = 0;
    int firstSample_ = 0;      // of the passes since reset()
    int nextPassSamples_ = 1;  // renderNextPass's schedule
    bool preprocessed_ = false;
    std::atomic<double> progress_{0};
    std::atomic<double> lastTileTime_{0};
};

size_t peakResidentMemoryBytes();

}  // namespace gi
