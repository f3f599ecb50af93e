#include "auto_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "render.h"

namespace gi {

namespace {


double srgbCode(double linear) {
    double x = std::clamp(linear, 0.0, 1.0);
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return 255.0 * v;
}

bool isConsistent(const std::string& integrator) {
    return integrator == "path" || integrator == "progressivePhotonMap";
}

// The per-pixel-value mean of images.
std::vector<double> meanImage(const std::vector<std::vector<float>>& images) {
    std::vector<double> mean(images.empty() ? 0 : images[0].size(), 0.0);
    for (const auto& image : images)
        for (size_t i = 0; i < mean.size(); ++i) mean[i] += image[i];
    for (double& m : mean) m /= double(images.size());
    return mean;
}

std::vector<double> srgbCodes(const std::vector<double>& linear) {
    std::vector<double> codes(linear.size());
    for (size_t i = 0; i < linear.size(); ++i) codes[i] = srgbCode(linear[i]);
    return codes;
}

// A pilot's share of the pilot time: the path tracer's noise shows in few samples (but each of
// its batches needs a sample in every pixel, and its heavy tail a few); the photon
// techniques must first trace and index their photons, and the progressive photon map, which
// traces a photon map for every sample, is the consistent technique that sees light the path
// tracer misses (a sun through glass), so its pilot must complete.
double pilotWeight(const std::string& integrator) {
    if (integrator == "path") return 1;
    if (integrator == "progressivePhotonMap") return 2;
    if (integrator == "photonMapIrradianceCache" || integrator == "photonMapFinalGather") return 1.5;
    return 1;
}

double meanSquaredDifference(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
    return a.empty() ? 0 : sum / double(a.size());
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

// A photon technique's photon counts, scaled with the pilot's pixels: the same photons per pixel
// footprint, so that density estimates blur over as many pixels in the pilot as in the final
// render, and its photon tracing costs as much per pixel.
void scalePhotonCounts(const IntegratorInfo& info, double pixelRatio, ParamSet& params) {
    constexpr double kMinPilotPhotons = 2000;
    for (const char* name : {"photons", "causticPhotons", "photonsPerPass"})
        for (const ParamInfo& p : info.params)
            if (p.name == name) {
                double full = paramValue(info, params, name);
                params.set(name, std::min(full, std::max(kMinPilotPhotons, std::round(full * pixelRatio))));
            }
}

RenderSettings pilotSettings(const RenderSettings& settings, const std::string& integrator, int width, int height,
                             uint32_t seed) {
    RenderSettings ps;
    ps.width = width;
    ps.height = height;
    ps.spp = 1 << 24;  // the deadline ends a pilot
    ps.integrator = integrator;
    ps.params = paramsFor(integrator, settings);
    scalePhotonCounts(*findIntegrator(integrator), double(width) * height / (double(settings.width) * settings.height),
                      ps.params);
    ps.seed = seed;
    ps.threads = settings.threads;
    ps.filter = settings.filter;
    ps.framing = settings.framing;  // in fractions of the image: the pilot's window is the image's
    return ps;
}

// The renderer's progressive passes from sample index `firstSample`: the first (one sample per
// pixel) until `lastDeadline`, the others until `deadline`. The image, or false if some pixel has
// no sample. `nextSample` is where the next batch starts: past every sample index this one used,
// its last pass cut at the deadline included.
bool renderBatch(Renderer& renderer, int firstSample, double deadline, double lastDeadline,
                 const std::atomic<bool>* cancel, std::vector<float>& image, int& nextSample) {
    renderer.reset(firstSample);
    PassEnd end;
    do {
        end = renderer.renderNextPass(Renderer::kMaxPassSamples,
                                      renderer.samplesTaken() == 0 ? lastDeadline : deadline, cancel);
        if (end == PassEnd::Cancelled) return false;
    } while (end == PassEnd::Complete && steadySeconds() < deadline);
    // Right after the last index used: the progressive photon map's radii go on shrinking as in
    // one render (a gap would give its later batches the radii of a longer render).
    nextSample = firstSample + renderer.samplesTaken() +
                 (end == PassEnd::Deadline ? renderer.stats().partialPassSamples : 0);
    if (renderer.samplesTaken() == 0) return false;  // the first pass did not reach every pixel
    image = renderer.film().color();
    return true;
}

// The pilot of `integrator` in `seconds`: one preprocessing, then up to kAutoPilotBatches batches
// of consecutive sample indices, each with an equal share of the time left, or one sample per
// pixel if that takes longer (an expensive technique's pilot makes fewer batches: as many as
// fit). A batch that cannot take a sample in every pixel before the pilot's end ends the pilot;
// it is complete with two batches or more, and incomplete when cancelled.
AutoPilot renderPilot(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                      const std::string& integrator, int width, int height, double seconds, uint32_t seed,
                      const std::atomic<bool>* cancel) {
    AutoPilot pilot;
    pilot.integrator = integrator;
    pilot.seconds = seconds;
    pilot.width = width;
    pilot.height = height;
    const double end = steadySeconds() + seconds;
    Renderer renderer(scene, pilotSettings(settings, integrator, width, height, seed), &camera);
    bool preprocessed = renderer.preprocess(cancel, end);
    pilot.preprocessSeconds = renderer.stats().preprocessSeconds;
    if (!preprocessed) return pilot;
    const double renderStart = steadySeconds(), slice = std::max(0.0, end - renderStart) / kAutoPilotBatches;
    int firstSample = 0;
    double batchSeconds = 0;  // of the batches kept
    for (int k = 0; k < kAutoPilotBatches; ++k) {
        std::vector<float> image;
        double before = renderer.stats().renderSeconds;
        if (!renderBatch(renderer, firstSample, renderStart + (k + 1) * slice, end, cancel, image, firstSample))
            break;
        batchSeconds += renderer.stats().renderSeconds - before;
        pilot.batches.push_back(std::move(image));
    }
    if (cancel && cancel->load()) return pilot;
    pilot.renderSeconds = batchSeconds / std::max<size_t>(1, pilot.batches.size());
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

std::string AutoChoice::summary() const {
    std::string text = "auto: chose " + integrator + " for " + std::to_string(int(std::lround(budgetSeconds))) +
                       " s after " + std::to_string(pilotSeconds).substr(0, 4) + " s of pilots at " +
                       std::to_string(pilotWidth) + "x" + std::to_string(pilotHeight) +
                       "; predicted RMSE (sRGB codes):";
    for (const AutoPrediction& p : predictions) {
        char buffer[192];
        if (p.complete)
            std::snprintf(buffer, sizeof buffer, " %s %.2f%s", p.integrator.c_str(), p.predictedRmse,
                          &p == &predictions.back() ? "" : ",");
        else  // its pilot rendered fewer than two batches in its share
            std::snprintf(buffer, sizeof buffer,
                          " %s (no pilot in time: %d of %d batches in %.2f s, %.2f s of it preprocessing)%s",
                          p.integrator.c_str(), p.batches, kAutoPilotBatches, p.pilotSeconds, p.preprocessSeconds,
                          &p == &predictions.back() ? "" : ",");
        text += buffer;
    }
    return text;
}

AutoChoice chooseIntegrator(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                            double budgetSeconds, double pilotSeconds, const std::atomic<bool>* cancel) {
    AutoChoice choice;
    choice.budgetSeconds = budgetSeconds;
    const double pixels = double(settings.width) * settings.height;
    const double scale = std::max(1.0, std::sqrt(pixels / kAutoPilotPixels));
    choice.pilotWidth = std::max(1, int(std::lround(settings.width / scale)));
    choice.pilotHeight = std::max(1, int(std::lround(settings.height / scale)));
    const double pilotPixels = double(choice.pilotWidth) * choice.pilotHeight;

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
            pilot = renderPilot(scene, settings, camera, candidates[k], choice.pilotWidth, choice.pilotHeight, seconds,
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
    predicted.pilotWidth = choice.pilotWidth;
    predicted.pilotHeight = choice.pilotHeight;
    return predicted;
}

double predictedNoise(const AutoPilot& pilot, double q) {
    const auto& batches = pilot.batches;
    const size_t K = batches.size();
    if (K < 2 || !(q > 0)) return 0;
    const size_t n = batches[0].size();
    std::vector<double> total(n, 0.0);
    for (const auto& batch : batches)
        for (size_t i = 0; i < n; ++i) total[i] += batch[i];
    const double unbias = std::sqrt(double(K - 1) / double(K));
    double sum = 0;
    for (int y = 0; y < pilot.height; ++y)
        for (int x = 0; x < pilot.width; ++x)
            for (int channel = 0; channel < 3; ++channel) {
                // The window's values in every batch, and how many there are.
                double window = 0;
                int count = 0;
                for (int v = std::max(0, y - 1); v <= std::min(pilot.height - 1, y + 1); ++v)
                    for (int u = std::max(0, x - 1); u <= std::min(pilot.width - 1, x + 1); ++u, ++count)
                        window += total[(size_t(v) * size_t(pilot.width) + size_t(u)) * 3 + size_t(channel)];
                const size_t i = (size_t(y) * size_t(pilot.width) + size_t(x)) * 3 + size_t(channel);
                double pixel = 0;
                for (size_t k = 0; k < K; ++k) {
                    double value = batches[k][i];
                    double center = (window - value) / double(size_t(count) * K - 1);
                    double deviation = unbias * (value - (total[i] - value) / double(K - 1));
                    double e = srgbCode(center + q * deviation) - srgbCode(center);
                    pixel += e * e;
                }
                double meanCode = srgbCode(total[i] / double(K)), farthest = std::max(meanCode, 255.0 - meanCode);
                sum += std::min(pixel / (double(K) * q), farthest * farthest);
            }
    return n ? sum / double(n) : 0;
}

AutoChoice predictFromPilots(const std::vector<AutoPilot>& pilots, double pilotPixels, double pixels,
                             double budgetSeconds) {
    AutoChoice choice;
    choice.budgetSeconds = budgetSeconds;
    // Each technique's mean image (in codes) and its noise; the consistent techniques'
    // inverse-variance mean R.
    size_t n = 0;
    for (const AutoPilot& p : pilots)
        if (p.complete) n = p.batches[0].size();
    std::vector<std::vector<double>> means(pilots.size());
    std::vector<double> meanNoise(pilots.size());  // noise(1 / K): of the mean of its K batches
    // A floor on the variance keeps a noiseless pilot from taking all the weight.
    constexpr double kNoiseFloor = 1e-3;
    std::vector<double> reference(n, 0.0);
    double weightSum = 0;
    for (size_t k = 0; k < pilots.size(); ++k) {
        if (!pilots[k].complete) continue;
        means[k] = meanImage(pilots[k].batches);
        meanNoise[k] = predictedNoise(pilots[k], 1.0 / double(pilots[k].batches.size()));
        if (!isConsistent(pilots[k].integrator)) continue;
        double w = 1.0 / (meanNoise[k] + kNoiseFloor);
        weightSum += w;
        for (size_t i = 0; i < n; ++i) reference[i] += w * means[k][i];
    }
    choice.integrator = "path";
    // Without a consistent technique's pilot there is nothing to measure bias against: every
    // prediction is left out, and the choice is the unbiased technique.
    const bool compared = weightSum > 0;
    for (double& r : reference) r /= compared ? weightSum : 1;
    const std::vector<double> referenceCodes = srgbCodes(reference);
    const double referenceVariance = compared ? 1.0 / weightSum : 0;

    double pathMse = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < pilots.size(); ++k) {
        AutoPrediction p;
        p.integrator = pilots[k].integrator;
        p.consistent = isConsistent(p.integrator);
        p.complete = pilots[k].complete && compared;
        p.batches = int(pilots[k].batches.size());
        p.pilotSeconds = pilots[k].seconds;
        p.renderSeconds = pilots[k].renderSeconds;
        p.preprocessSeconds = pilots[k].preprocessSeconds;
        if (p.complete) {
            const double batches = double(pilots[k].batches.size());
            p.noise = predictedNoise(pilots[k], 1.0);
            double error = meanSquaredDifference(srgbCodes(means[k]), referenceCodes) - referenceVariance;
            p.bias = std::max(0.0, error - meanNoise[k]);
            // The final render's time per pixel against one batch's: its preprocessing, as the
            // pilot's grown with the pixel count, takes at most its share of the budget.
            double finalPreprocess = std::min(kPreprocessShare * budgetSeconds,
                                              p.preprocessSeconds * pixels / pilotPixels);
            double finalSecondsPerPixel = std::max(budgetSeconds - finalPreprocess, 1e-3) / pixels;
            double batchSecondsPerPixel = std::max(p.renderSeconds, 1e-6) / pilotPixels;
            double ratio = std::min(1.0, batchSecondsPerPixel / finalSecondsPerPixel);
            double mse = (p.consistent ? p.bias * std::min(1.0, batches * ratio) : p.bias) +
                         predictedNoise(pilots[k], ratio);
            p.predictedRmse = std::sqrt(mse);
            if (p.integrator == "path") pathMse = mse;
        }
        choice.predictions.push_back(p);
    }
    double best = pathMse * kAutoMargin;
    for (const AutoPrediction& p : choice.predictions) {
        double mse = p.predictedRmse * p.predictedRmse;
        if (p.complete && p.integrator != "path" && mse < best) {
            best = mse;
            choice.integrator = p.integrator;
        }
    }
    return choice;
}

}  // namespace gi
