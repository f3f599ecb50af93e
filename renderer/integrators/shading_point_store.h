// The shading points of adaptive refinement's first pass (thesis 3.3.2): one camera ray per
// pixel, through its centre, and every non-specular hit along its specular branches - the
// points whose indirect light the ray tracer would ask the cache for.
//
// Kept compact because there is one per pixel or more (the thesis's implementation ran out
// of memory here): 44 bytes a point, normals octahedron-encoded, and only the luminance
// terms the discernibility test needs instead of colours and BSDFs.
#pragma once
#include <vector>

#include "../integrator.h"
#include "irradiance_record_sampler.h"
#include "pixel_footprint.h"

namespace gi {

// A unit vector in 32 bits (two 16-bit octahedral coordinates; error below 1e-4 radians).
uint32_t encodeUnitVector(const Vec3& v);
Vec3 decodeUnitVector(uint32_t bits);

struct StoredShadingPoint {
    Vec3 p;
    uint32_t n, ng, wo;  // encoded: hemisphere normal, geometric normal, towards the viewer
    // Y(rho / pi * E) = dot(luminanceWeights, E): the diffuse reflectance folded into the
    // luminance weights, so the test compares what the image would show (2.37, 2.38).
    float luminanceWeights[3];
    float directLuminance;  // Y(L_d), the direct light the ray tracer adds there
    uint32_t pixel;         // y * width + x
};

class ShadingPointStore {
public:
    // The first pass: all pixels in parallel, stored in pixel order (branch order within a pixel).
    void collect(const PreprocessContext& context, int rayDepth, int lightSamples);

    size_t size() const { return points_.size(); }
    const StoredShadingPoint& operator[](size_t i) const { return points_[i]; }
    Vec3 normal(size_t i) const { return decodeUnitVector(points_[i].n); }
    RecordSite site(size_t i, const PixelFootprint& footprint) const;
    size_t memoryBytes() const { return points_.capacity() * sizeof(StoredShadingPoint); }

private:
    std::vector<StoredShadingPoint> points_;
};

}  // namespace gi
