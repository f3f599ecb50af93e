// Where on each light photons start: a guide learnt from the emitter pilot (photon_emitters.h).
//
// A light emits a photon from two uniform numbers for its position (Light::emit's uPos: the
// point on a rect or disc light, or on the disc a distant or dome light shines through around
// the scene). For a sun over a courtyard, or a sky over a church with small windows, most of
// that disc leads nowhere the render reads: on Sponza under sun and sky 94% of the photons
// stored nothing the camera sees. The guide splits uPos into kCells x kCells cells and draws
// them in proportion to the pilot photons of each cell that landed on a surface the render
// reads, mixed with a uniform share (kUniformShare) so that no cell is ever left out: photons
// from a cell drawn with probability density p carry 1/p of the power, and every photon map
// stays an unbiased estimate, only with fewer wasted photons.
#pragma once
#include <cstdint>
#include <vector>

#include "../math.h"
#include "../sampling.h"

namespace gi {

class EmissionGuide {
public:
    static constexpr int kCells = 16;
    static constexpr float kUniformShare = 0.1f;
    // Pilot photons a light needs for a guide (8 per cell on average); fewer: uniform.
    static constexpr uint32_t kMinPilotPhotons = 8 * kCells * kCells;
    // A light whose pilot photons were useful this often keeps uniform emission: guided photons
    // carry unequal powers (1/p), which costs more variance than the few wasted photons it saves
    // (a closed room, a Cornell box).
    static constexpr float kGuideBelowUsefulShare = 0.5f;

    EmissionGuide() = default;
    // emitted[light][cell], seen[light][cell]: the pilot's photons per cell of uPos, and those
    // of them that landed (at any bounce) on a surface the render reads.
    // Lights with guidable[light] false keep uniform emission.
    EmissionGuide(const std::vector<std::vector<uint32_t>>& emitted, const std::vector<std::vector<uint32_t>>& seen,
                  const std::vector<bool>& guidable);

    static int cellOf(Vec2 uPos);
    // uPos for a light's photon from uniform u, and its density relative to uniform (1 where
    // the light has no guide).
    Vec2 sample(int light, Vec2 u, float* density) const;
    bool guides(int light) const { return light >= 0 && size_t(light) < cells_.size() && cells_[size_t(light)].size() > 0; }
    int guidedLights() const;

private:
    std::vector<Distribution1D> cells_;  // per light; empty: no guide
};

}  // namespace gi
