// Which lights emit photons (issue 5: "no photons from lights that reach nothing visible").
//
// A pilot pass traces photons from every light in proportion to power and watches where they
// land. A light that got at least kMinPilotPhotons pilot photons and none of them landed on
// a surface the render reads (SeenSurfaces) is left out: sealed in a box, facing away from
// the scene, or lighting only rooms the camera cannot see into. The others keep their
// power-proportional share, so every photon map is still an unbiased estimate of the light
// that can reach the image. Lights with fewer pilot photons are kept: too little is known.
// The same pilot, counted per cell of each light's emission positions, makes the guide that
// starts photons where they reach what the render reads (emission_guide.h).
#pragma once
#include <string>
#include <vector>

#include "../scene.h"
#include "emission_guide.h"
#include "seen_surfaces.h"

namespace gi {

struct PhotonEmitters {
    Distribution1D distribution;  // over scene.lights(); empty when no light emits photons
    EmissionGuide guide;          // where on each light its photons start
    std::vector<int> skipped;     // lights left out
    int emitting = 0;             // lights with a share of the photons
    uint32_t pilotPhotons = 0;  // traced (fewer than asked when a deadline stopped the pilot)
    static constexpr uint32_t kMinDeadlinePilotPhotons = 4096;
    bool empty() const { return emitting == 0; }

    static constexpr uint32_t kMinPilotPhotons = 64;
};

// Runs the pilot (pilotPhotons photons of up to maxBounces bounces, on all threads) and
// warns on the scene about every light it leaves out, and why. With a `deadline`
// (steadySeconds(); 0 = none) it stops starting photons once it passes, after the first
// kMinDeadlinePilotPhotons: a time-limited render's pilot must not outlast its preprocessing.
PhotonEmitters choosePhotonEmitters(const Scene& scene, const SeenSurfaces& seen, uint32_t pilotPhotons,
                                    int maxBounces, uint32_t seed, double deadline = 0);

}  // namespace gi
