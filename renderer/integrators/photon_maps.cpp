#include "photon_maps.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cstdio>

#include "disc_area.h"
#include "photon_emitters.h"
#include "photon_tracer.h"

namespace gi {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr uint32_t kGlobalStream = 0x6170001u, kCausticStream = 0x6170002u, kIrradianceStream = 0x6170003u;

// The requested count as a photon count, clamped to what a map can hold.
uint32_t photonCount(const Scene& scene, double requested, const char* parameter) {
    if (!std::isfinite(requested) || requested < 0) requested = 0;
    if (requested > kMaxPhotonsPerMap) {
        char text[256];
        std::snprintf(text, sizeof text, "photon mapping: %s = %.6g is more than a photon map can hold; clamped to %u",
                      parameter, requested, uint32_t(kMaxPhotonsPerMap));
        scene.warn(text);
        return uint32_t(kMaxPhotonsPerMap);
    }
    return uint32_t(std::llround(requested));
}

// Irradiance photons: every stride-th photon of the global map (in tree order, so spread
// like the photons), carrying the map's irradiance estimate at its position instead of its power.
// With a deadline (context.deadline), the first estimates are timed and the stride widened so
// that the rest end by it.
std::vector<Photon> irradiancePhotons(const PreprocessContext& context, const PhotonMap& global, int k, float maxRadius) {
    const Scene& scene = context.scene;
    size_t stride = std::max<size_t>(kMinIrradianceStride, (global.size() + kMaxIrradiancePhotons - 1) / kMaxIrradiancePhotons);
    std::vector<Photon> result;
    auto estimate = [&](size_t begin, size_t end) {
        tbb::parallel_for(tbb::blocked_range<size_t>(begin, end, 256), [&](const tbb::blocked_range<size_t>& r) {
            Sampler sampler(context.seed);
            RayStats stats;
            for (size_t i = r.begin(); i < r.end(); ++i) {
                Photon photon = global.tree()[uint32_t(i * stride)];
                PhotonLookup at{photon.p, photon.n(), photon.surface, &scene};
                sampler.startStream(kIrradianceStream, uint32_t(i));
                photon.power = overSurfaceInDisc(global.irradiance(at, k, maxRadius), k, at, sampler, stats);
                result[i] = photon;
            }
        });
    };
    result.resize((global.size() + stride - 1) / stride);
    size_t timed = 0;
    if (context.deadline > 0) {
        constexpr size_t kTimed = 2048;  // about 1% of a full irradiance map: a short, steady sample
        timed = std::min(result.size(), kTimed);
        auto start = Clock::now();
        estimate(0, timed);
        double perEstimate = secondsSince(start) / double(std::max<size_t>(1, timed));
        double fit = context.secondsLeft() / perEstimate;
        if (fit < double(result.size() - timed)) {
            size_t wanted = std::max<size_t>(timed, size_t(fit));
            size_t wider = (global.size() + wanted - 1) / wanted;
            context.scaledDown("photon mapping precomputed irradiance at every " + std::to_string(wider) +
                               "th photon instead of every " + std::to_string(stride) + "th");
            stride = wider;
            result.assign((global.size() + stride - 1) / stride, Photon());
            timed = 0;
        }
    }
    estimate(timed, result.size());
    return result;
}
}  // namespace

void buildPhotonMaps(const PreprocessContext& context, const PhotonMapSettings& settings, PhotonMaps& maps) {
    const Scene& scene = context.scene;
    auto traceStart = Clock::now();
    maps = PhotonMaps();
    maps.gatherRadius = settings.maxGatherRadius > 0 ? settings.maxGatherRadius : 0.1f * scene.bounds().radius;
    maps.causticRadius = std::min(maps.gatherRadius, 0.003f * scene.bounds().radius);
    uint32_t globalCount = photonCount(scene, settings.photons, "photons");
    uint32_t causticCount = photonCount(scene, settings.causticPhotons, "causticPhotons");
    if (causticCount > 0 && !scene.hasSpecularSurfaces()) {
        scene.warn("photon mapping: no caustic map, the scene has no specular or refractive surface to focus light");
        causticCount = 0;
    }
    std::map<std::string, double>& stats = maps.statistics;
    stats["gatherRadius"] = maps.gatherRadius;
    stats["pilotPhotons"] = 0;
    stats["photonLightsSkipped"] = 0;
    stats["photonLightsGuided"] = 0;

    auto source = std::make_shared<PhotonSource>();
    PhotonEmitters& emitters = source->emitters;
    auto pilotStart = Clock::now();
    if (globalCount + causticCount > 0) {
        if (scene.lights().empty()) {
            scene.warn("photon mapping: the scene has no light to emit photons; the photon maps stay empty");
        } else {
            // A pilot of 1/8 of the photons, between 4096 and 65536: enough to see where each
            // significant light's photons go, a small fraction of the real passes.
            uint32_t pilot = std::clamp<uint32_t>(std::max(globalCount, causticCount) / 8, 4096, 65536);
            SeenSurfaces seen = SeenSurfaces::trace(scene, context.camera, context.width, context.height,
                                                    settings.rayDepth, context.seed);
            // With a time limit, the pilot may take half the preprocessing share.
            double pilotDeadline = context.deadline > 0 ? steadySeconds() + 0.5 * context.secondsLeft() : 0;
            emitters = choosePhotonEmitters(scene, seen, pilot, settings.photonDepth, context.seed, pilotDeadline);
            stats["pilotSeconds"] = secondsSince(traceStart);
            stats["pilotPhotons"] = emitters.pilotPhotons;
            stats["photonLightsSkipped"] = double(emitters.skipped.size());
            stats["photonLightsGuided"] = settings.guideEmission ? double(emitters.guide.guidedLights()) : 0;
        }
    }
    if (emitters.empty()) globalCount = causticCount = 0;

    // A time limit: the two passes stop at their share of the preprocessing deadline (half the
    // time left after the pilot, split as their photon counts; the rest is for building the maps
    // and what the integrator does with them), and the photons traced stand for all requested.
    double globalDeadline = 0, causticDeadline = 0;
    if (context.deadline > 0) {
        double now = steadySeconds(), traceSeconds = 0.5 * context.secondsLeft();
        double total = std::max(1.0, double(globalCount) + double(causticCount));
        globalDeadline = now + traceSeconds * (globalCount / total);
        causticDeadline = now + traceSeconds;
        // A pilot that overran the whole share leaves the passes a chunk each.
        if (context.pastDeadline())
            context.scaledDown("photon mapping: the emitter pilot took " + std::to_string(secondsSince(pilotStart)) +
                               " s, the preprocessing share; tracing one chunk of photons per map");
    }
    auto scaleUp = [&](std::vector<Photon>& photons, uint32_t traced, uint32_t& count, const char* which) {
        if (traced >= count || traced == 0 || context.cancelled()) return;
        float scale = float(double(count) / traced);
        for (Photon& photon : photons) photon.power = photon.power * scale;
        context.scaledDown("photon mapping traced " + std::to_string(traced) + " of " + std::to_string(count) + " " +
                           which + " photons");
        count = traced;
    };

    PhotonTracer::Counters counters;
    PhotonTracer tracer(scene, emitters.distribution, context.seed, settings.guideEmission ? &emitters.guide : nullptr);
    std::vector<Photon> globalPhotons, causticPhotons;
    PhotonTraceSettings& global = source->global;
    if (globalCount > 0) {
        global.maxBounces = settings.photonDepth;
        global.keepDirect = global.keepCaustic = settings.globalKeepsDirectAndCaustic;
        if (settings.globalLeavesOutDirect) global.keepDirect = false;
        global.keepDomeCaustic = settings.globalKeepsDomeCaustics;
        uint32_t traced = globalCount;
        globalPhotons = tracer.tracePass(kGlobalStream, globalCount, global, counters, context.cancel, globalDeadline, &traced);
        scaleUp(globalPhotons, traced, globalCount, "global");
        source->globalRays = counters.rays.load();
        if (globalPhotons.empty())
            scene.warn("photon mapping: none of " + std::to_string(globalCount) +
                       " photons landed on a surface that reflects light diffusely; the global map is empty");
    }
    // The caustic pass's lights: all that emit photons, or all but the domes.
    Distribution1D causticEmitters = emitters.distribution;
    if (causticCount > 0 && settings.causticMapLeavesOutDomes) {
        std::vector<float> weights(size_t(emitters.distribution.size()));
        float kept = 0;
        for (int i = 0; i < emitters.distribution.size(); ++i) {
            weights[size_t(i)] = scene.lights()[size_t(i)]->isDome() ? 0.0f : emitters.distribution.func(i);
            kept += weights[size_t(i)];
        }
        if (kept > 0) causticEmitters = Distribution1D(weights.data(), int(weights.size()));
        else causticCount = 0;  // only domes: their caustics are gathered
    }
    PhotonTracer causticTracer(scene, causticEmitters, context.seed, settings.guideEmission ? &emitters.guide : nullptr);
    if (causticCount > 0) {
        PhotonTraceSettings caustic;
        caustic.maxBounces = settings.photonDepth;
        caustic.causticOnly = true;
        caustic.keepDirect = caustic.keepIndirect = false;
        uint32_t traced = causticCount;
        causticPhotons = causticTracer.tracePass(kCausticStream, causticCount, caustic, counters, context.cancel,
                                                 causticDeadline, &traced);
        scaleUp(causticPhotons, traced, causticCount, "caustic");
        if (causticPhotons.empty())
            scene.warn("photon mapping: none of " + std::to_string(causticCount) +
                       " caustic photons found a specular path to a diffuse surface; the caustic map is empty");
    }
    stats["photonTraceSeconds"] = secondsSince(traceStart);  // the pilot included
    stats["photonRays"] = double(counters.rays.load());
    stats["photonsAtDepthCap"] = double(counters.depthCapped.load());
    if (counters.depthCapped.load() > 0)
        scene.warn("photon mapping: " + std::to_string(counters.depthCapped.load()) + " photons reached the safety cap of " +
                   std::to_string(kDepthCap) + " bounces (trapped between specular surfaces?) and were stopped there");
    stats["photonsEmitted"] = globalCount;
    stats["causticPhotonsEmitted"] = causticCount;
    stats["photonBatches"] = 1;
    source->globalCount = globalCount;
    source->guided = settings.guideEmission;
    maps.source = std::move(source);

    auto buildStart = Clock::now();
    tbb::parallel_invoke([&] { maps.global.build(std::move(globalPhotons)); },
                         [&] { maps.caustic.build(std::move(causticPhotons)); });
    stats["photonMapBuildSeconds"] = secondsSince(buildStart);
    if (settings.precomputeIrradiance && !maps.global.empty()) {
        auto irradianceStart = Clock::now();
        maps.irradiance.build(irradiancePhotons(context, maps.global, settings.gatherPhotons, maps.gatherRadius));
        stats["irradianceMapPhotons"] = double(maps.irradiance.size());
        stats["irradianceMapBytes"] = double(maps.irradiance.memoryBytes());
        stats["irradianceMapSeconds"] = secondsSince(irradianceStart);
    }
    stats["globalMapPhotons"] = double(maps.global.size());
    stats["causticMapPhotons"] = double(maps.caustic.size());
    stats["globalMapBytes"] = double(maps.global.memoryBytes());
    stats["causticMapBytes"] = double(maps.caustic.memoryBytes());
    stats["photonMapBytes"] =
        double(maps.global.memoryBytes() + maps.caustic.memoryBytes() + maps.irradiance.memoryBytes());
}

uint64_t addPhotonBatch(const PreprocessContext& context, PhotonMaps& maps) {
    const PhotonSource* source = maps.source.get();
    if (!source || source->globalCount == 0 || maps.global.empty() || !maps.irradiance.empty()) return 0;
    if (double(maps.global.size()) * (1 + 1.0 / maps.batches) > kMaxPhotonsPerMap) return 0;
    auto start = Clock::now();
    const EmissionGuide* guide = source->guided ? &source->emitters.guide : nullptr;
    // Batch b's stream: the first batch's, mixed with b (photon i of a stream is its sample i).
    const uint32_t stream = kGlobalStream ^ (uint32_t(maps.batches) * 0x9E3779B9u);
    PhotonTracer::Counters counters;
    std::vector<Photon> added = PhotonTracer(context.scene, source->emitters.distribution, context.seed, guide)
                                    .tracePass(stream, source->globalCount, source->global, counters, context.cancel);
    if (context.cancelled()) return counters.rays.load();
    // Each of the b + 1 batches stands for the whole emitted power: the photons of all of them,
    // each carrying 1 / (b + 1) of its batch's power.
    const float kept = float(maps.batches) / float(maps.batches + 1), share = 1.0f / float(maps.batches + 1);
    std::vector<Photon> photons;
    photons.reserve(maps.global.size() + added.size());
    for (const Photon& photon : maps.global.tree().items()) photons.push_back(photon), photons.back().power = photon.power * kept;
    for (const Photon& photon : added) photons.push_back(photon), photons.back().power = photon.power * share;
    maps.global.build(std::move(photons));
    ++maps.batches;
    std::map<std::string, double>& stats = maps.statistics;
    stats["photonBatches"] = maps.batches;
    stats["photonBatchSeconds"] += secondsSince(start);
    stats["photonRays"] += double(counters.rays.load());
    stats["globalMapPhotons"] = double(maps.global.size());
    stats["globalMapBytes"] = double(maps.global.memoryBytes());
    stats["photonMapBytes"] = double(maps.global.memoryBytes() + maps.caustic.memoryBytes());
    return counters.rays.load();
}

}  // namespace gi
