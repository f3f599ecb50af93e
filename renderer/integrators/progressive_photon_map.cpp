#include "progressive_photon_map.h"

#include <chrono>
#include <cmath>

#include "disc_area.h"
#include "photon_maps.h"
#include "photon_tracer.h"
#include "seen_surfaces.h"

namespace gi {

namespace {
constexpr uint32_t kPassStream = 0x5990000u;  // + sample index: one photon stream per iteration
// Density estimates take every photon within the radius; past this many (a dense caustic at
// an early iteration) the k nearest, whose radius is smaller still.
constexpr int kMaxLookupPhotons = 512;
using Clock = std::chrono::steady_clock;
}  // namespace

ProgressivePhotonMapIntegrator::ProgressivePhotonMapIntegrator(const ProgressivePhotonMapSettings& settings)
    : DirectIntegrator(settings.rayDepth, settings.lightSamples), settings_(settings) {
    // Glossy lobes are traced (a density estimate through a sharp lobe is blotches); every
    // photon that came through specular surfaces is in the maps, domes' too, so glossy rays
    // count no emitter they reach through them (radianceBesideGlossyRays reads those photons).
    tracesGlossy_ = true;
    glossyBranchEmitters_ = BranchEmitters::None;
}

float ProgressivePhotonMapIntegrator::radiusScale(uint32_t sampleIndex, float alpha) {
    // prod_{k=1}^{i-1} (k + alpha) / (k + 1) = Gamma(i + alpha) / (Gamma(1 + alpha) Gamma(i + 1)).
    double i = double(sampleIndex) + 1;
    double logScale2 = std::lgamma(i + alpha) - std::lgamma(1 + double(alpha)) - std::lgamma(i + 1);
    return float(std::exp(0.5 * logScale2));
}

void ProgressivePhotonMapIntegrator::preprocess(const PreprocessContext& context) {
    seed_ = context.seed;
    footprint_ = PixelFootprint::of(context.camera);
    const Scene& scene = context.scene;
    if (settings_.photonsPerPass < 1) return;  // the ray-traced part alone: no photon emitters
    if (scene.lights().empty()) {
        scene.warn("progressivePhotonMap: the scene has no light to emit photons; only emission is rendered");
        return;
    }
    SeenSurfaces seen = SeenSurfaces::trace(scene, context.camera, context.width, context.height, settings_.rayDepth,
                                            context.seed);
    uint32_t pilot = std::clamp<uint32_t>(uint32_t(std::min(settings_.photonsPerPass, 1e9)) / 8, 4096, 65536);
    emitters_ = choosePhotonEmitters(scene, seen, pilot, settings_.photonDepth, context.seed,
                                     context.deadline > 0 ? steadySeconds() + 0.5 * context.secondsLeft() : 0);
}

void ProgressivePhotonMapIntegrator::beginPass(const PreprocessContext& context, int firstSample, int count) {
    auto start = Clock::now();
    firstSample_ = firstSample;
    maps_.assign(size_t(std::max(0, count)), PhotonMap());
    radiusScales_.resize(maps_.size());
    uint32_t photons = uint32_t(std::clamp(settings_.photonsPerPass, 0.0, kMaxPhotonsPerMap));
    PhotonTracer tracer(context.scene, emitters_.distribution, context.seed, &emitters_.guide);
    PhotonTraceSettings trace;
    trace.maxBounces = settings_.photonDepth;
    trace.keepDirect = false;  // light sampling has it
    for (int i = 0; i < count; ++i) {
        uint32_t sample = uint32_t(firstSample + i);
        radiusScales_[size_t(i)] = radiusScale(sample, settings_.alpha);
        if (emitters_.empty() || photons == 0) continue;
        PhotonTracer::Counters counters;
        uint32_t traced = photons;
        std::vector<Photon> stored =
            tracer.tracePass(kPassStream + sample, photons, trace, counters, context.cancel, context.deadline, &traced);
        // Cut short by a time limit: the photons traced stand for all of them (each photon's
        // power was divided by the count asked for), so the estimate stays unbiased.
        if (traced > 0 && traced < photons)
            for (Photon& p : stored) p.power = p.power * (float(photons) / float(traced));
        photonsTraced_ += traced;
        photonsStored_ += stored.size();
        photonsAtDepthCap_ += counters.depthCapped.load();
        maps_[size_t(i)].build(std::move(stored));
    }
    passes_++;
    photonSeconds_ += std::chrono::duration<double>(Clock::now() - start).count();
}

Color ProgressivePhotonMapIntegrator::indirect(const Scene& scene, const ShadingPoint& sp, Sampler& sampler,
                                               RayStats& stats) const {
    size_t iteration = size_t(sampler.sampleIndex() - uint32_t(firstSample_));
    if (iteration >= maps_.size() || maps_[iteration].empty()) return Color(0.0f);
    float radius = settings_.initialRadius * footprint_.at(sp.si.p) * radiusScales_[iteration];
    lookups_.fetch_add(1, std::memory_order_relaxed);
    PhotonEstimate e = maps_[iteration].radianceBesideGlossyRays(sp, scene, kMaxLookupPhotons, radius);
    photonsFound_.fetch_add(uint64_t(e.photons), std::memory_order_relaxed);
    return overSurfaceInDisc(e, kMaxLookupPhotons, PhotonLookup::at(sp, scene), sampler, stats);
}

std::map<std::string, double> ProgressivePhotonMapIntegrator::statistics() const {
    std::map<std::string, double> s;
    s["photonsTraced"] = double(photonsTraced_);
    s["photonsStored"] = double(photonsStored_);
    s["photonsAtDepthCap"] = double(photonsAtDepthCap_);
    s["photonPasses"] = passes_;
    s["photonSeconds"] = photonSeconds_;
    s["photonLookups"] = double(lookups_.load());
    s["photonsPerLookup"] = lookups_.load() ? double(photonsFound_.load()) / double(lookups_.load()) : 0.0;
    s["photonLightsSkipped"] = double(emitters_.skipped.size());
    s["lastRadiusScale"] = radiusScales_.empty() ? 1.0 : radiusScales_.back();
    return s;
}

}  // namespace gi
