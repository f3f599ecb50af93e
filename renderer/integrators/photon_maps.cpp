#include "photon_maps.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cstdio>

#include "photon_emitters.h"
#include "photon_tracer.h"

namespace gi {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr uint32_t kGlobalStream = 0x6170001u, kCausticStream = 0x6170002u;

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
std::vector<Photon> irradiancePhotons(const Scene& scene, const PhotonMap& global, int k, float maxRadius) {
    size_t stride = std::max<size_t>(kMinIrradianceStride, (global.size() + kMaxIrradiancePhotons - 1) / kMaxIrradiancePhotons);
    std::vector<Photon> result((global.size() + stride - 1) / stride);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, result.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i < r.end(); ++i) {
            Photon photon = global.tree()[uint32_t(i * stride)];
            photon.power = global.irradiance(PhotonLookup{photon.p, photon.n(), photon.surface, &scene}, k, maxRadius).value;
            result[i] = photon;
        }
    });
    return result;
}
}  // namespace

void buildPhotonMaps(const PreprocessContext& context, const PhotonMapSettings& settings, PhotonMaps& maps) {
    const Scene& scene = context.scene;
    auto traceStart = Clock::now();
    maps = PhotonMaps();
    maps.gatherRadius = settings.maxGatherRadius > 0 ? settings.maxGatherRadius : 0.1f * scene.bounds().radius;
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

    PhotonEmitters emitters;
    if (globalCount + causticCount > 0) {
        if (scene.lights().empty()) {
            scene.warn("photon mapping: the scene has no light to emit photons; the photon maps stay empty");
        } else {
            // A pilot of 1/8 of the photons, between 4096 and 65536: enough to see where each
            // significant light's photons go, a small fraction of the real passes.
            uint32_t pilot = std::clamp<uint32_t>(std::max(globalCount, causticCount) / 8, 4096, 65536);
            SeenSurfaces seen = SeenSurfaces::trace(scene, context.camera, context.width, context.height,
                                                    settings.rayDepth, context.seed);
            emitters = choosePhotonEmitters(scene, seen, pilot, settings.photonDepth, context.seed);
            stats["pilotSeconds"] = secondsSince(traceStart);
            stats["pilotPhotons"] = emitters.pilotPhotons;
            stats["photonLightsSkipped"] = double(emitters.skipped.size());
        }
    }
    if (emitters.empty()) globalCount = causticCount = 0;

    PhotonTracer::Counters counters;
    PhotonTracer tracer(scene, emitters.distribution, context.seed);
    std::vector<Photon> globalPhotons, causticPhotons;
    if (globalCount > 0) {
        PhotonTraceSettings global;
        global.maxBounces = settings.photonDepth;
        global.keepDirect = global.keepCaustic = settings.globalKeepsDirectAndCaustic;
        globalPhotons = tracer.tracePass(kGlobalStream, globalCount, global, counters, context.cancel);
        if (globalPhotons.empty())
            scene.warn("photon mapping: none of " + std::to_string(globalCount) +
                       " photons landed on a surface that reflects light diffusely; the global map is empty");
    }
    if (causticCount > 0) {
        PhotonTraceSettings caustic;
        caustic.maxBounces = settings.photonDepth;
        caustic.causticOnly = true;
        caustic.keepDirect = caustic.keepIndirect = false;
        causticPhotons = tracer.tracePass(kCausticStream, causticCount, caustic, counters, context.cancel);
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

    auto buildStart = Clock::now();
    tbb::parallel_invoke([&] { maps.global.build(std::move(globalPhotons)); },
                         [&] { maps.caustic.build(std::move(causticPhotons)); });
    stats["photonMapBuildSeconds"] = secondsSince(buildStart);
    if (settings.precomputeIrradiance && !maps.global.empty()) {
        auto irradianceStart = Clock::now();
        maps.irradiance.build(irradiancePhotons(scene, maps.global, settings.gatherPhotons, maps.gatherRadius));
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

}  // namespace gi
