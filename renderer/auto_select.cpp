#include "auto_select.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "render.h"

namespace gi {

namespace {


double srgbCode(float linear) {
    double x = std::clamp(double(linear), 0.0, 1.0);
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return 255.0 * v;
}

bool isConsistent(const std::string& integrator) {
    return integrator == "path" || integrator == "progressivePhotonMap";
}

// Where a cache's second pilot image starts its sample indices: far from the first's.
constexpr int kSecondPilotSample = 1 << 16;

// A pilot's share of the pilot time: the path tracer's noise shows in few samples; the photon
// techniques must first trace and index their photons, and the progressive photon map, which
// traces a photon map for every sample, is the consistent technique that sees light the path
// tracer misses (a sun through glass), so its pilot must complete.
double pilotWeight(const std::string& integrator) {
    if (integrator == "path") return 0.5;
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

// The renderer's progressive passes until `deadline`; the image, or none if some pixel has no sample.
bool renderUntil(Renderer& renderer, double deadline, const std::atomic<bool>* cancel, std::vector<double>& codes) {
    if (!renderer.preprocess(cancel, deadline)) return false;
    for (;;) {
        PassEnd end = renderer.renderNextPass(Renderer::kMaxPassSamples, deadline, cancel);
        if (end == PassEnd::Cancelled) return false;
        if (end != PassEnd::Complete || steadySeconds() >= deadline) break;
    }
    if (renderer.samplesTaken() == 0) return false;  // the first pass did not reach every pixel
    std::vector<float> color = renderer.film().color();
    codes.resize(color.size());
    for (size_t i = 0; i < color.size(); ++i) codes[i] = srgbCode(color[i]);
    return true;
}

// Two images of `integrator` in `seconds`. Techniques that preprocess a cache or a photon map
// preprocess once and render two disjoint ranges of sample indices: the two differ by the
// camera samples' noise, and the noise of the cache or map they share, which no number of
// camera samples removes, counts with their bias. The path tracer and the progressive photon map
// (whose maps belong to sample indices) render two seeds. Incomplete when cancelled, or when
// the time ran out before an image had a sample in every pixel.
AutoPilot renderPilot(const Scene& scene, const RenderSettings& settings, const CameraDesc& camera,
                  const std::string& integrator, int width, int height, double seconds, uint32_t seed,
                  const std::atomic<bool>* cancel) {
    AutoPilot pilot;
    pilot.integrator = integrator;
    const double start = steadySeconds(), end = start + seconds;
    if (isConsistent(integrator)) {
        for (int s = 0; s < 2; ++s) {
            Renderer renderer(scene, pilotSettings(settings, integrator, width, height, seed + uint32_t(s)), &camera);
            double deadline = s == 0 ? start + 0.5 * seconds : end;
            if (!renderUntil(renderer, deadline, cancel, pilot.codes[s])) return pilot;
            pilot.renderSeconds += 0.5 * renderer.stats().renderSeconds;
            pilot.preprocessSeconds += 0.5 * renderer.stats().preprocessSeconds;
        }
    } else {
        Renderer renderer(scene, pilotSettings(settings, integrator, width, height, seed), &camera);
        if (!renderer.preprocess(cancel, end)) return pilot;
        double half = steadySeconds() + 0.5 * std::max(0.0, end - steadySeconds());
        if (!renderUntil(renderer, half, cancel, pilot.codes[0])) return pilot;
        renderer.reset(kSecondPilotSample);
        if (!renderUntil(renderer, end, cancel, pilot.codes[1])) return pilot;
        pilot.renderSeconds = 0.5 * renderer.stats().renderSeconds;
        pilot.preprocessSeconds = renderer.stats().preprocessSeconds;
    }
    pilot.complete = true;
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
        char buffer[128];
        if (p.complete)
            std::snprintf(buffer, sizeof buffer, " %s %.2f%s", p.integrator.c_str(), p.predictedRmse,
                          &p == &predictions.back() ? "" : ",");
        else  // its pilot rendered no complete image in its share (preprocessing alone took longer)
            std::snprintf(buffer, sizeof buffer, " %s (no pilot in time)%s", p.integrator.c_str(),
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
        double each = (end - steadySeconds()) * pilotWeight(candidates[k]) / weightLeft / 2;
        AutoPilot pilot;  // no time left: incomplete
        pilot.integrator = candidates[k];
        if (each > 0)
            pilot = renderPilot(scene, settings, camera, candidates[k], choice.pilotWidth, choice.pilotHeight, each,
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

AutoChoice predictFromPilots(const std::vector<AutoPilot>& pilots, double pilotPixels, double pixels,
                             double budgetSeconds) {
    AutoChoice choice;
    choice.budgetSeconds = budgetSeconds;
    // Noise of one render of each technique, and the consistent techniques' inverse-variance mean.
    size_t n = 0;
    for (const AutoPilot& p : pilots)
        if (p.complete) n = p.codes[0].size();
    std::vector<std::vector<double>> means(pilots.size(), std::vector<double>(n));
    std::vector<double> noise(pilots.size());
    for (size_t k = 0; k < pilots.size(); ++k) {
        if (!pilots[k].complete) continue;
        noise[k] = 0.5 * meanSquaredDifference(pilots[k].codes[0], pilots[k].codes[1]);
        for (size_t i = 0; i < n; ++i) means[k][i] = 0.5 * (pilots[k].codes[0][i] + pilots[k].codes[1][i]);
    }
    // A floor on the variance keeps a noiseless pilot from taking all the weight.
    constexpr double kNoiseFloor = 1e-3;
    std::vector<double> reference(n, 0.0);
    double weightSum = 0;
    for (size_t k = 0; k < pilots.size(); ++k) {
        if (!pilots[k].complete || !isConsistent(pilots[k].integrator)) continue;
        double w = 1.0 / (0.5 * noise[k] + kNoiseFloor);
        weightSum += w;
        for (size_t i = 0; i < n; ++i) reference[i] += w * means[k][i];
    }
    choice.integrator = "path";
    // Without a consistent technique's pilot there is nothing to measure bias against: every
    // prediction is left out, and the choice is the unbiased technique.
    const bool compared = weightSum > 0;
    for (double& r : reference) r /= compared ? weightSum : 1;
    const double referenceVariance = compared ? 1.0 / weightSum : 0;

    double pathMse = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < pilots.size(); ++k) {
        AutoPrediction p;
        p.integrator = pilots[k].integrator;
        p.consistent = isConsistent(p.integrator);
        p.complete = pilots[k].complete && compared;
        if (p.complete) {
            p.renderSeconds = pilots[k].renderSeconds;
            p.preprocessSeconds = pilots[k].preprocessSeconds;
            p.noise = noise[k];
            double error = meanSquaredDifference(means[k], reference) - referenceVariance;
            p.bias = std::max(0.0, error - 0.5 * noise[k]);
            // The final render's time per pixel against the pilot's: its preprocessing, as the
            // pilot's grown with the pixel count, takes at most its share of the budget.
            double finalPreprocess = std::min(kPreprocessShare * budgetSeconds,
                                              p.preprocessSeconds * pixels / pilotPixels);
            double finalSecondsPerPixel = std::max(budgetSeconds - finalPreprocess, 1e-3) / pixels;
            double pilotSecondsPerPixel = std::max(p.renderSeconds, 1e-6) / pilotPixels;
            double ratio = std::min(1.0, pilotSecondsPerPixel / finalSecondsPerPixel);
            double mse = (p.consistent ? p.bias * ratio : p.bias) + p.noise * ratio;
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
