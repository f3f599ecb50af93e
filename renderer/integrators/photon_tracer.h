// Photon emission and tracing (thesis 2.4.7, figures 2.24-2.26).
//
// Photons leave the lights in proportion to their power (a light is picked by the emitter
// distribution, then Light::emit picks a point and a direction: cosine-weighted on area
// lights, from a disc over the scene's bounds for distant and dome lights). At every surface
// Russian roulette decides between diffuse reflection, specular reflection or refraction
// and absorption (2.40-2.42): the BSDF picks the lobe with its own lobe probabilities, and
// the photon survives with probability p = max(beta f cos / pdf) / max(beta), its power
// divided by p. For a Lambertian surface of albedo rho that is p_d = max(rho) and absorption
// 1 - max(rho), as in the thesis, and a photon keeps (nearly) its power whatever it meets,
// which is what makes density estimates from it low in noise.
//
// Photon i of a pass uses sample i of the pass's sampler stream, so the photons, and the maps
// built from them, depend only on the seed, never on the thread that traced them.
#pragma once
#include <atomic>
#include <functional>
#include <vector>

#include "emission_guide.h"
#include "lighting.h"
#include "path.h"
#include "photon.h"

namespace gi {

// What a photon's path did before it landed: nothing (direct light), only specular (delta)
// bounces (a caustic, L S+ D), or at least one non-specular bounce (indirect light).
enum class PhotonPath : uint8_t { Direct, Caustic, Indirect };

struct PhotonTraceSettings {
    int maxBounces = kDepthCap;  // the thesis's "photon depth": reflections before absorption
    bool causticOnly = false;  // end a path at its first non-specular bounce (the caustic pass)
    // Which landings tracePass keeps.
    bool keepDirect = true, keepCaustic = true, keepIndirect = true;
    // Caustic landings of dome lights' photons kept even without keepCaustic.
    bool keepDomeCaustic = false;
    bool keeps(PhotonPath path, bool fromDome) const {
        if (path == PhotonPath::Caustic) return keepCaustic || (keepDomeCaustic && fromDome);
        return path == PhotonPath::Direct ? keepDirect : keepIndirect;
    }
};

// Called at every landing with the photon, its path so far and the light that emitted it.
using PhotonLanding = std::function<void(const Photon&, PhotonPath, int light)>;

class PhotonTracer {
public:
    // `emitters`: a distribution over scene.lights() (zero for lights that emit none).
    // `guide` (may be null: uniform): where on each light photons start (emission_guide.h).
    PhotonTracer(const Scene& scene, const Distribution1D& emitters, uint32_t seed, const EmissionGuide* guide = nullptr)
        : scene_(scene), emitters_(emitters), seed_(seed), guide_(guide), outsideLightCarrier_(outsideLightCarrierOf(scene)) {}

    // Traces photon `index` of `stream`, one of `emitted` photons of its pass. Calls
    // land(photon, path, light) at every non-specular surface with a non-black BSDF it
    // reaches. Returns the light that emitted it, or -1 if none could. `cell` (if given): the
    // guide's cell of the photon's starting point (EmissionGuide::cellOf), for the pilot.
    int trace(uint32_t stream, uint32_t index, double emitted, const PhotonTraceSettings& settings, RayStats& stats,
               const PhotonLanding& land, int* cell = nullptr) const;

    // Traces photons [0, count) of `stream` on all threads and returns the landings that
    // settings.keeps(), in photon order. Stops early (between chunks) when cancelled, or once
    // steadySeconds() passes `deadline` (0 = none; the first chunk is always traced): then
    // `*traced` (if given) says how many of the `count` photons were, and the caller must
    // scale the photons' power by count / *traced.
    struct Counters {
        std::atomic<uint64_t> rays{0};
        std::atomic<uint64_t> depthCapped{0};  // photons stopped by the safety depth cap
    };
    std::vector<Photon> tracePass(uint32_t stream, uint32_t count, const PhotonTraceSettings& settings,
                                  Counters& counters, const std::atomic<bool>* cancel, double deadline = 0,
                                  uint32_t* traced = nullptr) const;

private:
    // The light whose portal photons carry what outside surfaces send through the portals
    // (portal.h): the first dome, or -1.
    static int outsideLightCarrierOf(const Scene& scene);

    const Scene& scene_;
    const Distribution1D& emitters_;
    uint32_t seed_;
    const EmissionGuide* guide_;
    int outsideLightCarrier_;
};

}  // namespace gi
