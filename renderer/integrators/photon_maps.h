// The two photon maps of thesis 2.4.7, built in an integrator's preprocess step: the global
// map (photons at every non-specular landing) and the caustic map (L S+ D paths, Jensen's
// separate, denser map for the bright, sharp light focused by mirrors and glass).
//
// What a scene does not need is left out, with a warning that says why: the caustic map when
// no surface is specular, photons from lights that reach nothing the render reads
// (photon_emitters.h). A photon count beyond kMaxPhotonsPerMap is clamped, with a warning.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "../integrator.h"
#include "photon_emitters.h"
#include "photon_map.h"
#include "photon_tracer.h"

namespace gi {

// Caustic lookups weight photons with Jensen's cone filter (k = 1.1): caustics have edges, and a
// box filter spreads a halo of their light around them (+11-13% on the floor beside the Cornell
// box's glass-sphere caustic with the box filter).
constexpr float kCausticConeFilter = 1.1f;

// 2^24 emitted photons: 33 times the thesis's 500 000, and about half a gigabyte of stored
// photons in a closed, bright room.
inline constexpr double kMaxPhotonsPerMap = double(1u << 24);

struct PhotonMapSettings {
    double photons = 500000;         // emitted for the global map
    double causticPhotons = 500000;  // emitted for the caustic map
    int photonDepth = kDepthCap;     // reflections before absorption
    int gatherPhotons = 50;          // k of the density estimates
    float maxGatherRadius = 0;       // 0: a tenth of the scene's bounding radius
    int rayDepth = kDepthCap;        // specular depth of the camera paths that decide which lights matter
    // Final gathering reads every photon from the global map; the irradiance cache adds the
    // direct light by light sampling and caustics from the caustic map, so its global map
    // holds only photons that have bounced off a non-specular surface.
    bool globalKeepsDirectAndCaustic = true;
    // ... except direct photons when set (final gathering that light-samples direct light at
    // its gather points).
    bool globalLeavesOutDirect = false;
    // Christensen's (2000) precomputed irradiance for final gathering: the global map's
    // estimate at every 4th photon (Christensen's choice), so that a gather ray reads one
    // nearest photon instead of a k-nearest estimate. At most kMaxIrradiancePhotons of them:
    // a gather point one bounce away needs no finer resolution, and each costs a k-nearest
    // search (with 6 million photons, every 4th would take longer than tracing them).
    bool precomputeIrradiance = false;
    // The caustic map leaves out dome lights' photons: final gathering finds the sky through
    // window glass with its gather rays, which see the whole sky where a density estimate
    // reads a few sparse photons over a wide disc (Sibenik under its sky alone, all light
    // through the glass: 0.58 of the path tracer with them).
    bool causticMapLeavesOutDomes = false;
    // ... and the global map then keeps them, when it keeps no caustics otherwise: the photon
    // cache's photon records carry the sky through glass, as its path-traced records do.
    bool globalKeepsDomeCaustics = false;
    // Photons start where the emitter pilot saw them reach what the render reads
    // (emission_guide.h); off: uniformly over each light (for comparisons).
    bool guideEmission = true;
};

inline constexpr uint32_t kMinIrradianceStride = 4, kMaxIrradiancePhotons = 1u << 18;

// What traced the global map's first batch of photons, kept so that further batches can be added.
struct PhotonSource {
    PhotonEmitters emitters;
    PhotonTraceSettings global;
    uint32_t globalCount = 0;  // emitted per batch
    bool guided = true;
    uint64_t globalRays = 0;  // traced for the first batch's global map
};

struct PhotonMaps {
    PhotonMap global, caustic;
    std::shared_ptr<const PhotonSource> source;
    int batches = 1;  // of global photons emitted (addPhotonBatch)
    PhotonMap irradiance;  // precomputed (power holds the irradiance); empty unless asked for
    float gatherRadius = 0;  // maxGatherRadius resolved against the scene
    // Caustic-map lookups (the caches', final gathering's) reach at most 1/300 of the scene's radius,
    // not the global map's tenth: caustics are sharp, and a lookup that found few photons near it
    // searched far and tested photons on other surfaces with shadow rays. Measured with the plain
    // cache at 160x120, 5 s, shares 0.1 / 0.03 / 0.01 / 0.003: Sibenik with portals 56 / 128 / 139 /
    // 178 spp, FLIP 0.0328 / 0.0289 / 0.0281 / 0.0260; the sunlit glazed room 58 / 85 / 107 / 150 spp,
    // FLIP 0.082 / 0.072 / 0.068 / 0.063, mean 1.00 at each. At 0.003 final gathering's FLIP went
    // 0.051 -> 0.047 (room), 0.033 -> 0.029 (Sibenik with portals).
    float causticRadius = 0;
    std::map<std::string, double> statistics;
};

// Chooses the emitting lights, traces both passes and builds both kd-trees, all on every
// thread, deterministically for the context's seed.
void buildPhotonMaps(const PreprocessContext& context, const PhotonMapSettings& settings, PhotonMaps& maps);

// Traces another batch of the first batch's global photons, from a stream of its own, and
// rebuilds the global map with all batches' photons, each batch's power shared among them: the
// map stays an unbiased estimate of the same light with more photons each time (for an integrator
// whose estimates converge as its render goes on). Returns the rays traced; none (and nothing
// added) without a global map, with precomputed irradiance, or once the map would exceed
// kMaxPhotonsPerMap. The caustic map keeps its one batch.
uint64_t addPhotonBatch(const PreprocessContext& context, PhotonMaps& maps);

}  // namespace gi
