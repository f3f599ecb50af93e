#include "photon_emitters.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "../integrator.h"
#include "photon_tracer.h"

namespace gi {

namespace {
constexpr uint32_t kPilotStream = 0x7011a7u;
constexpr size_t kGuideCells = size_t(EmissionGuide::kCells) * EmissionGuide::kCells;

struct PilotCounts {
    std::vector<uint32_t> emitted, landed, seen;  // per light
    std::vector<std::vector<uint32_t>> cellEmitted, cellSeen;  // per light, per guide cell
    explicit PilotCounts(size_t lights)
        : emitted(lights, 0), landed(lights, 0), seen(lights, 0),
          cellEmitted(lights, std::vector<uint32_t>(kGuideCells, 0)), cellSeen(lights, std::vector<uint32_t>(kGuideCells, 0)) {}
};

std::string describe(const Scene& scene, const std::vector<int>& lights, const PilotCounts& counts) {
    std::string text;
    size_t shown = std::min<size_t>(lights.size(), 4);
    for (size_t i = 0; i < shown; ++i) {
        int l = lights[i];
        const std::string& name = scene.lights()[l]->name;
        text += (i ? "; " : "") + (name.empty() ? "light " + std::to_string(l) : name) + ": " +
                (counts.landed[l] == 0 ? "none of " + std::to_string(counts.emitted[l]) + " reached a surface"
                                       : std::to_string(counts.landed[l]) + " of " + std::to_string(counts.emitted[l]) +
                                             " landed only where the render never looks");
    }
    if (lights.size() > shown) text += "; and " + std::to_string(lights.size() - shown) + " more";
    return text;
}
}  // namespace

PhotonEmitters choosePhotonEmitters(const Scene& scene, const SeenSurfaces& seen, uint32_t pilotPhotons,
                                    int maxBounces, uint32_t seed, double deadline) {
    PhotonEmitters result;
    const size_t lights = scene.lights().size();
    if (lights == 0) return result;
    std::vector<float> power(lights);
    bool anyPower = false;
    for (size_t i = 0; i < lights; ++i) {
        power[i] = luminance(scene.lights()[i]->power(scene.photonBounds()));
        anyPower = anyPower || (power[i] > 0 && std::isfinite(power[i]));
    }
    if (!anyPower) {
        scene.warn("photon mapping: no light has positive, finite power; the photon maps stay empty");
        return result;
    }
    Distribution1D byPower(power.data(), int(lights));

    // The pilot: counts per light of photons emitted, photons that landed anywhere, and
    // photons that landed (at any bounce) where the render reads photons.
    tbb::enumerable_thread_specific<PilotCounts> perThread([&] { return PilotCounts(lights); });
    PhotonTracer tracer(scene, byPower, seed);
    PhotonTraceSettings settings;
    settings.maxBounces = maxBounces;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, pilotPhotons, 1024), [&](const tbb::blocked_range<uint32_t>& r) {
        if (deadline > 0 && r.begin() >= PhotonEmitters::kMinDeadlinePilotPhotons && steadySeconds() >= deadline)
            return;
        PilotCounts& counts = perThread.local();
        RayStats stats;
        for (uint32_t i = r.begin(); i < r.end(); ++i) {
            bool landed = false, wasSeen = false;
            int cell = 0;
            int light = tracer.trace(kPilotStream, i, pilotPhotons, settings, stats,
                                     [&](const Photon& photon, PhotonPath, int) {
                                         landed = true;
                                         wasSeen = wasSeen || seen.contains(photon.p, photon.n(), photon.surface);
                                     }, &cell);
            if (light < 0) continue;
            counts.emitted[light]++;
            counts.landed[light] += landed;
            counts.seen[light] += wasSeen;
            counts.cellEmitted[light][size_t(cell)]++;
            counts.cellSeen[light][size_t(cell)] += wasSeen;
        }
    });
    PilotCounts total(lights);  // sums of integers: the same whatever the threads did
    for (const PilotCounts& c : perThread)
        for (size_t i = 0; i < lights; ++i) {
            total.emitted[i] += c.emitted[i];
            total.landed[i] += c.landed[i];
            total.seen[i] += c.seen[i];
            for (size_t cell = 0; cell < kGuideCells; ++cell) {
                total.cellEmitted[i][cell] += c.cellEmitted[i][cell];
                total.cellSeen[i][cell] += c.cellSeen[i][cell];
            }
        }

    std::vector<float> weights(lights, 0.0f);
    for (size_t i = 0; i < lights; ++i) {
        if (!(power[i] > 0) || !std::isfinite(power[i])) continue;
        if (total.emitted[i] >= PhotonEmitters::kMinPilotPhotons && total.seen[i] == 0) {
            result.skipped.push_back(int(i));
            continue;
        }
        weights[i] = power[i];
        result.emitting++;
    }
    result.pilotPhotons = 0;
    for (size_t i = 0; i < lights; ++i) result.pilotPhotons += total.emitted[i];
    if (!result.skipped.empty())
        scene.warn("photon mapping: " + std::to_string(result.skipped.size()) +
                   " light(s) emit no photons, none of their pilot photons landed where the camera or a "
                   "final-gather ray looks (" + describe(scene, result.skipped, total) + ")");
    if (result.emitting == 0) {
        scene.warn("photon mapping: no light reaches a surface the render reads; the photon maps stay empty");
        return result;
    }
    result.distribution = Distribution1D(weights.data(), int(lights));
    std::vector<bool> guidable(lights);
    for (size_t i = 0; i < lights; ++i) guidable[i] = scene.lights()[i]->emitsFromFixedPositions();
    result.guide = EmissionGuide(total.cellEmitted, total.cellSeen, guidable);
    return result;
}

}  // namespace gi
