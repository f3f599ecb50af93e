#include "emission_guide.h"

#include <algorithm>

namespace gi {

EmissionGuide::EmissionGuide(const std::vector<std::vector<uint32_t>>& emitted,
                             const std::vector<std::vector<uint32_t>>& seen, const std::vector<bool>& guidable) {
    constexpr int n = kCells * kCells;
    cells_.resize(emitted.size());
    for (size_t light = 0; light < emitted.size(); ++light) {
        if (!guidable[light]) continue;
        uint32_t total = 0, useful = 0;
        for (int c = 0; c < n; ++c) total += emitted[light][size_t(c)], useful += seen[light][size_t(c)];
        // Too few pilot photons to tell the cells apart, none useful (the emitter choice leaves
        // such a light out, or keeps it for lack of evidence), or most useful already: uniform.
        if (total < kMinPilotPhotons || useful == 0 || float(useful) >= kGuideBelowUsefulShare * float(total)) continue;
        // Density of useful photons per cell, as a share of all: a cell's share of the
        // photons follows the share of the useful ones it sent, plus the uniform floor.
        std::vector<float> weights(n);
        for (int c = 0; c < n; ++c)
            weights[size_t(c)] = (1 - kUniformShare) * float(seen[light][size_t(c)]) / float(useful) + kUniformShare / n;
        cells_[light] = Distribution1D(weights.data(), n);
    }
}

int EmissionGuide::cellOf(Vec2 uPos) {
    int x = std::clamp(int(uPos.x * kCells), 0, kCells - 1), y = std::clamp(int(uPos.y * kCells), 0, kCells - 1);
    return y * kCells + x;
}

Vec2 EmissionGuide::sample(int light, Vec2 u, float* density) const {
    if (!guides(light)) {
        *density = 1;
        return u;
    }
    float pmf = 0, remapped = 0;
    int cell = cells_[size_t(light)].sample(u.x, &pmf, &remapped);
    *density = pmf * float(kCells * kCells);
    // The bin's remapped number places the point across the cell, the second number along it.
    Vec2 p((float(cell % kCells) + remapped) / kCells, (float(cell / kCells) + u.y) / kCells);
    return {std::min(p.x, 0.99999994f), std::min(p.y, 0.99999994f)};
}

int EmissionGuide::guidedLights() const {
    int count = 0;
    for (const Distribution1D& d : cells_) count += d.size() > 0;
    return count;
}

}  // namespace gi
