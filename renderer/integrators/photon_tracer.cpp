#include "photon_tracer.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "path.h"
#include "specular_chain.h"

namespace gi {

namespace {
// The paths that find what an outside surface sends through a portal cost several rays each, for
// a small share of the light: a quarter of them are traced (weighted by 4), with Russian roulette
// from their first vertex. On Sibenik with portals, all of them with roulette from the third vertex
// cost the progressive photon map 40% of its samples; these settings 20%, and its noise at 60 s was
// 0.43 codes squared against 0.49.
constexpr int kOutsidePathRouletteDepth = 1;
constexpr float kOutsidePathSurvival = 0.25f;
}  // namespace

int PhotonTracer::outsideLightCarrierOf(const Scene& scene) {
    for (size_t i = 0; i < scene.lights().size(); ++i)
        if (scene.lights()[i]->isDome()) return int(i);
    return -1;
}

int PhotonTracer::trace(uint32_t stream, uint32_t index, double emitted, const PhotonTraceSettings& settings,
                        RayStats& stats, const PhotonLanding& land, int* cell) const {
    if (scene_.lights().empty() || emitters_.size() != int(scene_.lights().size())) return -1;
    Sampler sampler(seed_);
    sampler.startStream(stream, index);
    Vec2 uLight = sampler.get2D(), uPosition = sampler.get2D(), uDirection = sampler.get2D();
    float pmf = 0;
    int light = emitters_.sample(uLight.x, &pmf);
    if (!(pmf > 0)) return -1;
    float density = 1;
    if (guide_) uPosition = guide_->sample(light, uPosition, &density);
    if (cell) *cell = EmissionGuide::cellOf(uPosition);
    // Photons leave throughout the shutter, as camera rays arrive (a moving light from where it is).
    float const time = sampler.shutterTime();
    PhotonEmission emission = scene_.lights()[light]->emit(uPosition, uDirection, scene_.photonBounds(), time);
    Color beta = emission.power / float(double(pmf) * density * emitted);
    if (!isFinite(emission.ray.o) || !isFinite(emission.ray.d)) return light;
    Ray ray = emission.ray;
    ray.time = time;
    PhotonPath path = PhotonPath::Direct;
    // A portal's photon carries the light's own radiance only if the sky or sun is seen from its
    // origin: outside the opening, walls, roofs and window reveals shade it as they shade the
    // opening. Where they do, the first dome's photon carries what the surface there sends
    // through the portal (portal.h): a path traced from it, reflected light (indirect).
    if (emission.fromPortal) {
        if (light != outsideLightCarrier_) {
            if (scene_.occluded(emission.ray.o, -emission.ray.d, kInf, stats, time)) return light;
        } else {
            Ray back = emission.ray;
            back.d = -emission.ray.d;
            back.time = time;
            Intersection outside = intersectVisible(scene_, back, sampler, stats, false);
            if (outside.kind == Intersection::Kind::Light) return light;  // that light's own photons
            if (outside.kind == Intersection::Kind::Surface) {
                if (sampler.get1D() >= kOutsidePathSurvival) return light;
                const ShadingPoint there = makeShadingPoint(outside.si, emission.ray.d);
                const Color reflected =
                    PathIntegrator(1, kDepthCap, kDepthCap, kOutsidePathRouletteDepth).continuePath(scene_, there, sampler, stats);
                beta = reflected * (emission.powerPerRadiance /
                                    float(double(pmf) * density * emitted * kOutsidePathSurvival));
                path = PhotonPath::Indirect;
            }
        }
    }
    if (!isFinite(beta) || isBlack(beta)) return light;
    for (int bounces = 0;; ++bounces) {
        // Lights are not in the BVH: a photon that meets one's surface ends there, as a path does.
        Intersection hit = intersectVisible(scene_, ray, sampler, stats, false);
        if (hit.kind != Intersection::Kind::Surface) return light;
        ShadingPoint sp = makeShadingPoint(hit.si, -ray.d);
        // Stored where a density estimate will read it: surfaces with a non-specular lobe
        // that reflects anything at all.
        if (sp.bsdf.hasNonDelta() && !isBlack(sp.bsdf.albedo()) && isFinite(sp.si.p)) {
            Photon photon;
            photon.p = sp.si.p;
            photon.power = beta;
            photon.normal = octahedral::encode(recordNormal(sp));
            photon.direction = octahedral::encode(-ray.d);
            photon.surface = photonSurface(sp.si.shapeId, sp.si.instanceId);
            photon.caustic = path == PhotonPath::Caustic;
            land(photon, path, light);
        }
        if (depthLimitReached(bounces, settings.maxBounces, stats)) return light;
        float uLobe = sampler.get1D();
        Vec2 u = sampler.get2D();
        float uSurvival = sampler.get1D();
        BsdfSample bs = sp.bsdf.sample(sp.woLocal, uLobe, u, TransportMode::Importance);
        if (!bs.valid) return light;
        if (settings.causticOnly && !bs.delta) return light;  // no caustic path continues past a diffuse bounce
        // Russian roulette (2.40-2.42): reflect (diffusely or specularly, as the BSDF chose)
        // with probability `survival`, absorb otherwise.
        Color next = beta * bs.weight;
        float survival = std::min(1.0f, maxComponent(next) / maxComponent(beta));
        if (!(survival > 0) || uSurvival >= survival) return light;
        beta = next / survival;
        if (!isFinite(beta)) return light;
        if (!bs.delta)
            path = PhotonPath::Indirect;
        else if (path == PhotonPath::Direct)
            path = PhotonPath::Caustic;
        ray = spawnRay(sp.si, sp.frame.toWorld(bs.wi));
    }
}

std::vector<Photon> PhotonTracer::tracePass(uint32_t stream, uint32_t count, const PhotonTraceSettings& settings,
                                            Counters& counters, const std::atomic<bool>* cancel,
                                            double deadline, uint32_t* traced) const {
    // Chunks of 4,096 photons, or smaller in small passes so that threads share them evenly: at
    // 11,344 photons (auto's pilots, photons scaled with their pixels) three chunks of 4,096 on
    // two threads traced a photon in 0.93 us of wall time, against 0.56 in the render's passes.
    const uint32_t chunkSize = std::clamp<uint32_t>(count / 64, 256, 4096);
    size_t chunks = (size_t(count) + chunkSize - 1) / chunkSize;
    std::vector<std::vector<Photon>> stored(chunks);
    std::atomic<uint32_t> tracedCount{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks, 1), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t chunk = range.begin(); chunk < range.end(); ++chunk) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            if (chunk > 0 && deadline > 0 && steadySeconds() >= deadline) return;
            std::vector<Photon>& out = stored[chunk];
            PhotonLanding keep = [&](const Photon& photon, PhotonPath path, int light) {
                if (settings.keeps(path, scene_.lights()[size_t(light)]->isDome())) out.push_back(photon);
            };
            RayStats stats;
            uint32_t end = uint32_t(std::min<size_t>(count, (chunk + 1) * chunkSize));
            for (uint32_t i = uint32_t(chunk * chunkSize); i < end; ++i) trace(stream, i, count, settings, stats, keep);
            counters.rays.fetch_add(stats.rays, std::memory_order_relaxed);
            counters.depthCapped.fetch_add(stats.depthCapped, std::memory_order_relaxed);
            tracedCount.fetch_add(end - uint32_t(chunk * chunkSize), std::memory_order_relaxed);
        }
    });
    if (traced) *traced = tracedCount.load();
    // Concatenated in chunk order: photon order, whichever thread traced what.
    size_t total = 0;
    for (const auto& chunk : stored) total += chunk.size();
    std::vector<Photon> photons;
    photons.reserve(total);
    for (auto& chunk : stored) {
        photons.insert(photons.end(), chunk.begin(), chunk.end());
        std::vector<Photon>().swap(chunk);
    }
    return photons;
}

}  // namespace gi
