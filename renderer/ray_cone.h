// Ray cones (Ray::coneWidth, coneSpread): how wide a ray's footprint is where it hits, which
// sizes the texture footprint its hit reads (SurfaceInteraction::uvFootprint, Image::lookup's
// MIP level). A camera ray's cone is its pixel's; a path's next ray keeps the arriving spread
// after a delta bounce (a mirror shows a texture as sharp as it arrives) and after any other
// takes the cone of the solid angle 1 / pdf its sampled direction stands for, of full angle
// 2 / sqrt(pi pdf). Both are narrowed to kConeSpreadScale: a pixel's many samples filter the
// texture as well, as pbrt-v4 narrows its footprints with the samples per pixel (to 1/8 at
// most). The coarser levels an indirect ray reads stay in the caches (Sibenik's 512 x 512
// textures read at full size cost 15-20% of a path's time) and blur only what a diffuse
// bounce blurs anyway. Cones follow camera rays, continued paths (the path tracer's, and the
// irradiance records' past their first hit) and final gathering's rays; an irradiance record's
// own rays and photons carry none (the finest level): on Sibenik under its sky, three 10 s
// irradiance-cache renders were 0.5% brighter with cones on the records' rays, 0.2% without
// (their seeds spread by 0.3%).
#pragma once
#include <immintrin.h>

#include <cmath>

#include "bsdf.h"
#include "scene.h"

namespace gi {

inline constexpr float kConeSpreadScale = 1.0f / 8;

// The spread of a ray sampled with solid-angle density `pdf` (at most a radian), to the 12 bits
// of the reciprocal square root's estimate: plenty for a texture level, and quick at every vertex.
inline float sampledConeSpread(float pdf) {
    const float spread = kConeSpreadScale * 2 / std::sqrt(kPi) * _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(pdf)));
    return spread < 1 ? spread : 1.0f;  // also for a NaN pdf
}

inline float continuedConeSpread(float arriving, const BsdfSample& bs) {
    return bs.delta ? arriving : sampledConeSpread(bs.pdf);
}

// The cone of the ray a BSDF sample sends on from `si`, where the arriving cone left it.
inline void continueCone(Ray& ray, const SurfaceInteraction& si, const BsdfSample& bs) {
    ray.coneWidth = si.coneWidth;
    ray.coneSpread = continuedConeSpread(si.coneSpread, bs);
}

}  // namespace gi
