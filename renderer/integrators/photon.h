// One stored photon (thesis 2.4.7): where it landed, the flux it carries, the direction it
// came from, the surface normal on the side it arrived at and which surface (shape or
// instance) it landed on. Directions are packed octahedrally into 2 x 16 bits (Cigolle et al.
// 2014; under 0.01 degrees of error), so a photon takes 36 bytes.
#pragma once
#include <cstdint>

#include "../math.h"

namespace gi {

namespace octahedral {

inline uint32_t encode(const Vec3& v) {
    float l1 = std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z);
    if (!(l1 > 0)) return encode(Vec3(0, 0, 1));
    float x = v.x / l1, y = v.y / l1;
    if (v.z < 0) {  // fold the lower half onto the corners of the square
        float fx = (1 - std::fabs(y)) * (x >= 0 ? 1.0f : -1.0f);
        float fy = (1 - std::fabs(x)) * (y >= 0 ? 1.0f : -1.0f);
        x = fx, y = fy;
    }
    auto quantize = [](float f) { return uint32_t(std::lround((std::clamp(f, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
    return quantize(x) | (quantize(y) << 16);
}

// The direction, not yet normalised.
inline Vec3 decodeUnnormalized(uint32_t packed) {
    float x = float(packed & 0xffffu) / 65535.0f * 2 - 1, y = float(packed >> 16) / 65535.0f * 2 - 1;
    Vec3 v(x, y, 1 - std::fabs(x) - std::fabs(y));
    if (v.z < 0) {
        float fx = (1 - std::fabs(y)) * (x >= 0 ? 1.0f : -1.0f);
        float fy = (1 - std::fabs(x)) * (y >= 0 ? 1.0f : -1.0f);
        v.x = fx, v.y = fy;
    }
    return v;
}

inline Vec3 decode(uint32_t packed) { return normalize(decodeUnnormalized(packed)); }

// Whether the packed direction makes an angle with unit n whose cosine is at least cosMin > 0,
// without the square root and division of normalising it (queries test many photons).
inline bool agrees(uint32_t packed, const Vec3& n, float cosMin) {
    Vec3 v = decodeUnnormalized(packed);
    float d = dot(v, n);
    return d > 0 && d * d >= cosMin * cosMin * lengthSquared(v);
}

}  // namespace octahedral

struct Photon {
    Vec3 p;
    Color power;         // flux, already divided by the number of photons emitted
    uint32_t normal;     // octahedral: the surface normal on the side the photon arrived at
    uint32_t direction;  // octahedral: unit direction towards where the photon came from
    uint32_t surface;    // photonSurface() of where it landed
    // Whether it came from its light through specular surfaces alone (L S+): light that a ray
    // traced from a glossy lobe finds only by chance, so such an integrator reads these photons
    // through the glossy lobes as well (PhotonMap::radianceBesideGlossyRays).
    bool caustic = false;

    Vec3 n() const { return octahedral::decode(normal); }
    Vec3 wi() const { return octahedral::decode(direction); }
};
static_assert(sizeof(Photon) == 40);

// Tells surfaces apart for the photon map's visibility guard: the shape, or for instanced
// geometry the instance.
inline uint32_t photonSurface(uint32_t shapeId, uint32_t instanceId) {
    return instanceId != 0xffffffffu ? (instanceId | 0x80000000u) : shapeId;
}

}  // namespace gi
