// Auto's pilots (auto_select.h): the render's own pixels in tiles, each technique's batches in its
// share of the pilot time, and the choice predicted from them.
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "auto_select.h"
#include "render.h"
#include "sampler.h"

namespace gi {

namespace {

// The share of the progressive photon map's pilot that renders its ray-traced part alone
// (AutoPilot::rayTracedBatches: no photons, so a sample costs a fraction of the technique's).
constexpr double kRayTracedShare = 0.1;

// A pilot's share of the pilot time: the path tracer's noise shows in few samples (but each of
// its batches needs a sample in every pixel, and its heavy tail a few); the photon
// techniques must first trace and index their photons, and the progressive photon map, which
// traces a photon map for every sample, is the consistent technique that sees light the path
// tracer misses (a sun through glass), so its pilot must complete.
double pilotWeight(const std::string& integrator) {
    if (integrator == "path") return 1;
    if (integrator == "progressivePhotonMap") return 2 / (1 - kRayTracedShare);
    if (integrator == "photonMapIrradianceCache" || integrator == "photonMapFinalGather") return 1.5;
    return 1;
}

// The parameters of the render that `integrator` takes (sampleClamp, say), under the preset.
ParamSet paramsFor(const std::string& integrator, const RenderSettings& settings) {
    const IntegratorInfo* info = findIntegrator(integrator);
    ParamSet chosen;
    for (const auto& [name, value] : settings.params.values())
        for (const ParamInfo& p : info->params)
            if (p.name == name) chosen.set(name, value);
    return withPreset(settings.preset, integrator, chosen);
}

// A photon technique's photon counts, scaled with the pilot's pixels, so that its photon tracing
// costs as much per pixel as the render's. The progressive photon map's radii, in pixel
// footprints, grow by the inverse square root: each of its discs holds the render's photons, so a
// pass is as noisy as the render's (its blur, wider, is scaled back in predictFromPilots).
void scalePhotonCounts(const IntegratorInfo& info, double pixelRatio, ParamSet& params) {
    constexpr double kMinPilotPhotons = 2000;
    for (const char* name : {"photons", "causticPhotons", "photonsPerPass"})
        for (const ParamInfo& p : info.params)
            if (p.name == name) {
                double full = paramValue(info, params, name);
                params.set(name, std::min(full, std::max(kMinPilotPhotons, std::round(full * pixelRatio))));
            }
    for (const ParamInfo& p : info.params)
        if (p.name == "initialRadius" && pixelRatio < 1)
            params.set(p.name, paramValue(info, params, p.name) / std::sqrt(pixelRatio));
}

// The second cache of a photon technique's pilot traces `factor` times the first's photons (at
// most the render's), so that the two caches' noise gives its law in the photon count.
void growPhotonCounts(const IntegratorInfo& info, const ParamSet& renderParams, double factor, ParamSet& params) {
    for (const char* name : {"photons", "causticPhotons"})
        for (const ParamInfo& p : info.params)
            if (p.name == name)
                params.set(name, std::min(paramValue(info, renderParams, name),
                                          std::round(paramValue(info, params, name) * factor)));
}

RenderSettings pilotSettings(const RenderSettings& settings, const std::string& integrator, const PixelMosaic& mosaic,
                             uint32_t seed) {
    RenderSettings ps;
    ps.width = mosaic.tile > 0 ? mosaic.width() : settings.width;
    ps.height = mosaic.tile > 0 ? mosaic.height() : settings.height;
    ps.mosaic = mosaic;
    ps.imageWidth = settings.width;
    ps.imageHeight = settings.height;
    ps.spp = 1 << 24;  // the deadline ends a pilot
    ps.integrator = integrator;
    ps.params = paramsFor(integrator, settings);
    scalePhotonCounts(*findIntegrator(integrator),
                      double(ps.width) * ps.height / (double(settings.width) * settings.height), ps.params);
    ps.seed = seed;
    ps.threads = settings.threads;
    ps.filter = settings.filter;
    ps.framing = settings.framing;
    return ps;
}

// An integrator statistic (Renderer::integratorStatistics, which walks the cache: take it once),
// 0 where the integrator has none.
double statistic(const std::map<std::string, double>& statistics, const char* name) {
    const auto it = statistics.find(name);
    return it == statistics.end() ? 0.0 : it->second;
}

// What a batch cost, from the renderer's counters before and after it (AutoPilot's rates):
// thread-seconds sampling pixels and making records where none covered a sample (a cache's
// start-up), wall seconds setting passes up, rays the passes traced and those of the start-up's
// records.
struct BatchCost {
    double sampleThreadSeconds = 0, startupThreadSeconds = 0, setupSeconds = 0;
    double rays = 0, startupRays = 0;
    static BatchCost of(const Renderer& renderer) {
        const auto statistics = renderer.integratorStatistics();
        return {renderer.stats().sampleThreadSeconds, statistic(statistics, "renderTimeRecordSeconds"),
                renderer.stats().passSetupSeconds, double(renderer.stats().rays),
                statistic(statistics, "renderTimeRecordRays")};
    }
    BatchCost operator-(const BatchCost& o) const {
        return {sampleThreadSeconds - o.sampleThreadSeconds, startupThreadSeconds - o.startupThreadSeconds,
                setupSeconds - o.setupSeconds, rays - o.rays, startupRays - o.startupRays};
    }
};

// A refined-record cache's records after one of its batches (AutoPilot::recordPaths...): the
// first batch's records and samples per pixel go to `first`, from which the later ones' growth.
void recordRecords(const Renderer& renderer, bool firstBatch, std::pair<double, double>& first, AutoPilot& pilot) {
    const auto statistics = renderer.integratorStatistics();
    auto stat = [&](const char* name) { return statistic(statistics, name); };
    const double pixels = double(renderer.film().width()) * renderer.film().height();
    // The photon cache's path-traced records (its photon records' noise falls with its photons).
    const double records =
        statistics.count("pathTracedRecordsInCache") ? stat("pathTracedRecordsInCache") : stat("records");
    const double paths = stat("recordPathsMean");
    const double samples = double(renderer.stats().cameraSamples) / pixels;
    if (firstBatch) first = {records, samples};
    if (!(records > 0 && paths > 0 && samples > 0)) return;
    pilot.recordPaths = paths;
    pilot.recordsPerPixel = records / pixels;
    pilot.recordRaysPerPath = stat("recordRays") / (records * paths);
    pilot.passRaysPerSample = double(renderer.stats().rays) / double(renderer.stats().cameraSamples);
    pilot.cacheSamples = samples;
    pilot.recordGrowth = first.first > 0 && samples > first.second
                             ? std::log(records / first.first) / std::log(samples / first.second)
                             : 0.0;
}

// A pilot batch's seed: batches are independent (AutoPilot::batches), a cache's two caches take the
// same ones (their batches' camera samples are paired).
uint32_t pilotBatchSeed(uint32_t seed, int batch) { return hashCombine(seed, uint32_t(batch)); }

// The renderer's progressive passes of `seed`'s samples from index 0: the first (one sample per
// pixel) until `lastDeadline`, the others until `deadline`. The image, or false if some pixel has
// no sample; `samples` its samples per pixel, a last pass cut at the deadline counted for the
// pixels it finished. Its passes' sample counts are appended to `passes`, or, with `replay`,
// those passes are rendered (a second cache's batch takes the first's samples).
bool renderBatch(Renderer& renderer, uint32_t seed, double deadline, double lastDeadline,
                 const std::atomic<bool>* cancel, std::vector<float>& image, double& samples,
                 std::vector<int>& passes, const std::vector<int>* replay = nullptr) {
    constexpr int firstSample = 0;
    renderer.reset(firstSample, seed);
    PassEnd end = PassEnd::Complete;
    for (size_t pass = 0; !replay || pass < replay->size(); ++pass) {
        const double passDeadline = renderer.samplesTaken() == 0 ? lastDeadline : deadline;
        const int taken = renderer.samplesTaken();
        end = replay ? renderer.renderPass(firstSample + taken, (*replay)[pass], passDeadline, cancel)
                     : renderer.renderNextPass(Renderer::kMaxPassSamples, passDeadline, cancel);
        if (end == PassEnd::Cancelled) return false;
        if (!replay)
            passes.push_back(end == PassEnd::Complete ? renderer.samplesTaken() - taken
                                                      : renderer.stats().partialPassSamples);
        if (end != PassEnd::Complete || steadySeconds() >= deadline) break;
    }
    if (renderer.samplesTaken() == 0) return false;  // the first pass did not reach every pixel
    samples = renderer.samplesTaken();
    if (end == PassEnd::Deadline) {
        const double pixels = double(renderer.film().width()) * renderer.film().height();
        samples += double(renderer.stats().partialPassPixels) * renderer.stats().partialPassSamples / pixels;
    }
    image = renderer.film().color();
    return true;
}

// The progressive photon map's ray-traced part (AutoPilot::rayTracedBatches): up to
// kAutoPilotBatches batches of the technique's batch seeds with no photons, until `end`.
void renderRayTracedPart(const Scene& scene, const RenderSettings& ps, const CameraDesc& camera, uint32_t seed,
                         double end, const std::atomic<bool>* cancel, AutoPilot& pilot) {
    RenderSettings rs = ps;
    rs.params.set("photonsPerPass", 0);
    Renderer renderer(scene, rs, &camera);
    if (!renderer.preprocess(cancel, end)) return;
    for (int k = 0; k < kAutoPilotBatches; ++k) {
        const double now = steadySeconds();
        std::vector<float> image;
        std::vector<int> passes;
        double samples = 0;
        if (!renderBatch(renderer, pilotBatchSeed(seed, k), now + std::max(0.0, end - now) / (kAutoPilotBatches - k),
                         end, cancel, image, samples, passes))
            break;
        pilot.rayTracedBatches.push_back(std::move(image));
        pilot.rayTracedBatchSamples.push_back(samples);
    }
    if (pilot.rayTracedBatches.size() < 2) {
        pilot.rayTracedBatches.clear();
        pilot.rayTracedBatchSamples.clear();
    }
}

// The pilot of `integrator` in `seconds`: one preprocessing, then up to kAutoPilotBatches batches,
// each of its own seed's samples (pilotBatchSeed) and with an equal share of the time left, or one
// sample per pixel if that takes longer (an expensive technique's pilot makes fewer batches: as
// many as fit). A batch that cannot take a sample in every pixel before the pilot's end ends the
// pilot; it is complete with two batches or more, and incomplete when cancelled. A technique with a
// cache (records, photon maps) preprocesses twice, with two seeds, each with half the time and half
// the batches, so that the two caches' difference measures the cache's own noise; a second cache
// that makes fewer than two batches is dropped, and the pilot is as with one.
AutoPilot renderPilot(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                      const std::string& integrator, const PixelMosaic& mosaic, double seconds, uint32_t seed,
                      const std::atomic<bool>* cancel) {
    AutoPilot pilot;
    pilot.integrator = integrator;
    pilot.seconds = seconds;
    const double start = steadySeconds();
    const double rayTracedSeconds = integrator == "progressivePhotonMap" ? kRayTracedShare * seconds : 0;
    const double ownSeconds = seconds - rayTracedSeconds;
    const RenderSettings ps = pilotSettings(settings, integrator, mosaic, seed);
    pilot.width = ps.width;
    pilot.height = ps.height;
    pilot.tile = mosaic.tile;
    const int width = ps.width, height = ps.height;
    const IntegratorInfo& info = *findIntegrator(integrator);
    if (integrator == "progressivePhotonMap") pilot.radiusAlpha = paramValue(info, ps.params, "alpha");
    for (const ParamInfo& p : info.params) {
        if (p.name == "photons" && !isConsistentTechnique(integrator))
            pilot.photonShare = paramValue(info, ps.params, "photons") /
                                std::max(1.0, paramValue(info, paramsFor(integrator, settings), "photons"));
        if (p.name == "refineRecords") {
            pilot.records = true;
            pilot.refinesRecords = paramValue(info, ps.params, "refineRecords") != 0;
        }
    }
    int caches = isConsistentTechnique(integrator) ? 1 : 2;
    double batchSeconds = 0;  // the latest batch's wall time
    const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
    std::vector<size_t> cacheBatches;
    // Over all batches: seconds with every thread busy past the start-up, samples (per pixel),
    // rays besides the start-up's; the start-up's thread-seconds and rays.
    double busySeconds = 0, steadySamples = 0, steadyRays = 0, startupThreadSeconds = 0, startupRays = 0;
    // The first cache's start-up: in all (thread-seconds) and after its first batch, and its
    // samples per pixel after its first batch and after its last.
    double firstStartup = 0, laterStartup = 0, firstCacheSamples = 0, firstBatchSamples = 0;
    double fillRays = 0;  // the first cache's fill's record rays
    double preprocessSeconds = 0, firstPreprocessSeconds = 0;
    int preprocesses = 0;
    bool grew = false;  // the second cache traced more photons than the first
    std::pair<double, double> firstRecords;  // its records and samples per pixel after the first batch
    // The first cache's batches' passes (their samples), for the second's.
    std::vector<std::vector<int>> firstPasses;
    for (int c = 0; c < caches; ++c) {
        double end = start + ownSeconds * (c + 1) / caches;
        RenderSettings cs = ps;
        // Both caches take the same camera samples (common random numbers): their difference is
        // then the caches' own, not the samples' (cacheSeed, fixed while the batches' seeds change;
        // the next technique starts 2 seeds on). A consistent technique has no cache: its
        // per-pass work (a progressive photon map's photons) takes each batch's seed.
        cs.seed = seed;
        if (!isConsistentTechnique(integrator)) cs.cacheSeed = seed + uint32_t(c);
        // A photon technique's second cache traces more photons, as many as a third of its time
        // allows at the first's preprocessing rate (at most the render's), if that is 2x or more.
        double grownShare = 0;
        if (c == 1 && pilot.photonShare > 0 && pilot.photonShare < 1) {
            const double affordable = kPhotonGrowthPreprocessShare * std::max(0.0, end - steadySeconds()) /
                                      std::max(preprocessSeconds, 1e-4);
            const double factor = std::min(affordable, 1.0 / pilot.photonShare);
            if (factor >= 2) {
                const ParamSet renderParams = paramsFor(integrator, settings);
                growPhotonCounts(info, renderParams, factor, cs.params);
                grownShare = paramValue(info, cs.params, "photons") /
                             std::max(1.0, paramValue(info, renderParams, "photons"));
            }
        }
        Renderer renderer(scene, cs, &camera);
        bool preprocessed = renderer.preprocess(cancel, end);
        preprocessSeconds += renderer.stats().preprocessSeconds;
        if (c == 0) firstPreprocessSeconds = renderer.stats().preprocessSeconds;
        grew = grew || grownShare > 0;
        ++preprocesses;
        if (!preprocessed) break;
        if (c == 0) fillRays = statistic(renderer.integratorStatistics(), "preprocessRecordRays");
        // Photons cut short by the deadline stand for those asked: their count is not known.
        if (grownShare > 0 && renderer.stats().preprocessScaledDown == 0) pilot.secondPhotonShare = grownShare;
        int batches = c == 0 ? kAutoPilotBatches / caches : int(firstPasses.size());
        size_t made = 0;
        for (int k = 0; k < batches; ++k) {
            std::vector<float> image;
            const double before = renderer.stats().renderSeconds;
            const BatchCost costBefore = BatchCost::of(renderer);
            double samples = 0;
            const double now = steadySeconds();
            // The first cache's first pass may run to the pilot's end (see below).
            const double lastDeadline = caches == 2 && c == 0 && k == 0 ? start + ownSeconds : end;
            std::vector<int> passes;
            // The second cache renders the first's batches, pass for pass, until its end.
            if (!renderBatch(renderer, pilotBatchSeed(seed, k),
                             c == 1 ? end : now + std::max(0.0, end - now) / (batches - k), lastDeadline, cancel,
                             image, samples, passes, c == 1 ? &firstPasses[size_t(k)] : nullptr))
                break;
            if (c == 0) firstPasses.push_back(std::move(passes));
            batchSeconds = renderer.stats().renderSeconds - before;
            // Records made where the batch's samples first needed them are the cache's start-up,
            // which a longer render spreads over many samples: apart from its steady rate.
            const BatchCost cost = BatchCost::of(renderer) - costBefore;
            // Records are made inside the samples' time, so the rest is the samples' own: in a
            // cache's first batch on Sibenik under its sky 1.4 of 39 thread-ms (a floor at a fifth
            // of it, kept once for the counters' error, made the samples look 5.5 times as dear).
            const double startup = std::min(cost.startupThreadSeconds, cost.sampleThreadSeconds);
            busySeconds += (cost.sampleThreadSeconds - startup) / threads +
                           (pilot.refinesRecords ? 0.0 : cost.setupSeconds);
            steadySamples += samples;
            steadyRays += cost.rays - cost.startupRays;
            startupThreadSeconds += startup;
            startupRays += cost.startupRays;
            if (c == 0 || caches == 1) {
                firstStartup += startup;
                if (k > 0) laterStartup += startup;
                firstCacheSamples += samples;
                if (k == 0) firstBatchSamples = samples;
            }
            pilot.batchSamples.push_back(samples);
            pilot.batches.push_back(std::move(image));
            if (c == 0 && pilot.refinesRecords) recordRecords(renderer, k == 0, firstRecords, pilot);
            ++made;
            // Where two caches could not each make two batches (the first cache's preprocessing and
            // two batches like its first would take over half the pilot: on Sponza at 37x28 a
            // cache's first samples cost 6x its later ones), the first cache takes the whole
            // pilot: one cache, whose own noise then counts as bias, is better than no pilot.
            if (caches == 2 && c == 0 && k == 0 && 2 * (steadySeconds() - start + batchSeconds) > ownSeconds) {
                caches = 1;
                end = start + ownSeconds;
                batches = kAutoPilotBatches;
            }
        }
        cacheBatches.push_back(made);
        if (made < 2) break;
    }
    if (caches == 2 && cacheBatches.size() == 2 && cacheBatches[1] >= 2)
        pilot.firstCacheBatches = int(cacheBatches[0]);
    else {
        pilot.secondPhotonShare = 0;
        if (caches == 2 && !cacheBatches.empty()) {
            pilot.batches.resize(cacheBatches[0]);  // the second cache's lone batch, if any, goes
            pilot.batchSamples.resize(cacheBatches[0]);
        }
    }
    // The render's photons per pixel are the first cache's: its preprocessing is the one to scale.
    pilot.preprocessSeconds = grew ? firstPreprocessSeconds : preprocessSeconds / std::max(1, preprocesses);
    if (cancel && cancel->load()) return pilot;
    if (rayTracedSeconds > 0 && pilot.batches.size() >= 2)
        renderRayTracedPart(scene, ps, camera, seed, start + seconds, cancel, pilot);
    if (cancel && cancel->load()) return pilot;
    const double pilotPixels = double(width) * height;
    pilot.startupSeconds = firstStartup / threads;
    if (laterStartup > 0 && firstCacheSamples > firstBatchSamples && firstBatchSamples > 0) {
        pilot.startupGrowthSeconds = laterStartup / threads / std::log(firstCacheSamples / firstBatchSamples);
        pilot.startupSamples = firstCacheSamples;
    }
    if (steadySamples > 0) pilot.steadySecondsPerSample = busySeconds / (steadySamples * pilotPixels);
    if (pilot.refinesRecords && steadySamples > 0 && startupRays > 0) {
        pilot.steadyRaysPerSample = steadyRays / (steadySamples * pilotPixels);
        pilot.recordRaySeconds = startupThreadSeconds / threads / startupRays;
        pilot.fillRays = fillRays;
    }
    pilot.complete = pilot.batches.size() >= 2;
    return pilot;
}

}  // namespace

const std::vector<std::string>& autoCandidates() {
    // In order of their fixed cost (preprocessing) on the project's scenes: cheap pilots first.
    static const std::vector<std::string> candidates = {"path",
                                                        "irradianceCache",
                                                        "adaptiveIrradianceCache",
                                                        "progressivePhotonMap",
                                                        "photonMapIrradianceCache",
                                                        "photonMapFinalGather"};
    return candidates;
}

PixelMosaic pilotMosaic(int width, int height) {
    PixelMosaic mosaic;
    if (double(width) * height <= 2.0 * kAutoPilotPixels) return mosaic;  // the whole image
    // About kAutoPilotTiles tiles, as many across as the image's aspect asks, evenly spread.
    const int across = std::clamp(int(std::lround(std::sqrt(kAutoPilotTiles * double(width) / height))), 1,
                                  std::min(width, kAutoPilotTiles));
    const int down = std::clamp(int(std::lround(double(kAutoPilotTiles) / across)), 1, height);
    mosaic.across = across;
    mosaic.tile = std::max(1, std::min({int(std::lround(std::sqrt(double(kAutoPilotPixels) / (across * down)))),
                                        width / across, height / down}));
    for (int j = 0; j < down; ++j)
        for (int i = 0; i < across; ++i) {
            mosaic.x0.push_back(std::clamp(int(std::lround((i + 0.5) * width / across - 0.5 * mosaic.tile)), 0,
                                           width - mosaic.tile));
            mosaic.y0.push_back(std::clamp(int(std::lround((j + 0.5) * height / down - 0.5 * mosaic.tile)), 0,
                                           height - mosaic.tile));
        }
    return mosaic;
}

AutoChoice chooseIntegrator(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                            double budgetSeconds, double pilotSeconds, const std::atomic<bool>* cancel) {
    AutoChoice choice;
    choice.budgetSeconds = budgetSeconds;
    const double pixels = double(settings.width) * settings.height;
    const PixelMosaic mosaic = pilotMosaic(settings.width, settings.height);
    choice.pilotTile = mosaic.tile;
    choice.pilotTiles = mosaic.tiles();
    const double pilotPixels = mosaic.tile > 0 ? double(mosaic.width()) * mosaic.height() : pixels;

    // Pilots in order of their fixed cost, each with its weight's share of the time still left, so
    // the time one does not use goes to the next and the pilots end with their share.
    const std::vector<std::string>& candidates = autoCandidates();
    const double start = steadySeconds(), end = start + pilotSeconds;
    const size_t warningsBefore = scene.warningCount();
    std::vector<AutoPilot> pilots;
    for (size_t k = 0; k < candidates.size(); ++k) {
        double weightLeft = 0;
        for (size_t j = k; j < candidates.size(); ++j) weightLeft += pilotWeight(candidates[j]);
        double seconds = (end - steadySeconds()) * pilotWeight(candidates[k]) / weightLeft;
        AutoPilot pilot;  // no time left: incomplete
        pilot.integrator = candidates[k];
        if (seconds > 0)
            pilot = renderPilot(scene, settings, camera, candidates[k], mosaic, seconds,
                                settings.seed + 1 + 2 * uint32_t(k), cancel);
        pilots.push_back(std::move(pilot));
        if (cancel && cancel->load()) {
            scene.dropWarningsAfter(warningsBefore);
            choice.cancelled = true;
            return choice;
        }
    }
    double pilotsTook = steadySeconds() - start;
    scene.dropWarningsAfter(warningsBefore);
    AutoChoice predicted = predictFromPilots(pilots, pilotPixels, pixels, budgetSeconds);
    predicted.pilotSeconds = pilotsTook;
    predicted.pilotTile = choice.pilotTile;
    predicted.pilotTiles = choice.pilotTiles;
    return predicted;
}

}  // namespace gi
