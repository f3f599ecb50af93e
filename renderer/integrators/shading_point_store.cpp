#include "shading_point_store.h"

#include <tbb/parallel_for.h>

#include "specular_chain.h"

namespace gi {

namespace {
float signNotZero(float v) { return v >= 0 ? 1.0f : -1.0f; }
uint32_t quantize(float v) { return uint32_t(std::lround((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); }
float dequantize(uint32_t q) { return float(q) / 65535.0f * 2 - 1; }
// Pixel streams of the first pass use a sample index the render never reaches.
constexpr uint32_t kFirstPassSampleIndex = 0xfffffff1u;
}  // namespace

uint32_t encodeUnitVector(const Vec3& v) {
    float l1 = std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z);
    float x = v.x / l1, y = v.y / l1;
    if (v.z < 0) {  // fold the lower hemisphere over the diagonals
        float fx = (1 - std::fabs(y)) * signNotZero(x), fy = (1 - std::fabs(x)) * signNotZero(y);
        x = fx, y = fy;
    }
    return quantize(x) | (quantize(y) << 16);
}

Vec3 decodeUnitVector(uint32_t bits) {
    float x = dequantize(bits & 0xffffu), y = dequantize(bits >> 16);
    Vec3 v(x, y, 1 - std::fabs(x) - std::fabs(y));
    if (v.z < 0) {
        float fx = (1 - std::fabs(y)) * signNotZero(x), fy = (1 - std::fabs(x)) * signNotZero(y);
        v.x = fx, v.y = fy;
    }
    return normalize(v);
}

void ShadingPointStore::collect(const PreprocessContext& context, int rayDepth, int lightSamples) {
    constexpr uint32_t kChunk = 256;  // pixels per task; chunks are concatenated in order
    uint32_t pixels = uint32_t(context.width) * uint32_t(context.height);
    std::vector<std::vector<StoredShadingPoint>> chunks((pixels + kChunk - 1) / kChunk);
    tbb::parallel_for(size_t(0), chunks.size(), [&](size_t chunk) {
        Sampler sampler(context.seed);
        RayStats stats;
        for (uint32_t pixel = uint32_t(chunk) * kChunk; pixel < std::min(pixels, uint32_t(chunk + 1) * kChunk); ++pixel) {
            int x = int(pixel % uint32_t(context.width)), y = int(pixel / uint32_t(context.width));
            sampler.start(x, y, kFirstPassSampleIndex);
            Ray ray = context.camera.generateRay(x + 0.5f, y + 0.5f, Vec2(0.5f, 0.5f));
            forEachDiffuseHit(context.scene, ray, sampler, stats, rayDepth, [&](const ShadingPoint& sp) {
                Color rho = sp.bsdf.diffuseReflectance();
                if (isBlack(rho)) return;  // the cache adds nothing here
                Color direct(0.0f);
                for (int i = 0; i < lightSamples; ++i) direct += sampleDirectLight(context.scene, sp, sampler, stats, false);
                StoredShadingPoint point;
                point.p = sp.si.p;
                point.n = encodeUnitVector(recordNormal(sp));
                point.ng = encodeUnitVector(sp.si.ng);
                point.wo = encodeUnitVector(sp.wo);
                point.luminanceWeights[0] = 0.2126f * rho.x * kInvPi;
                point.luminanceWeights[1] = 0.7152f * rho.y * kInvPi;
                point.luminanceWeights[2] = 0.0722f * rho.z * kInvPi;
                point.directLuminance = std::max(0.0f, luminance(direct / float(lightSamples)));
                point.pixel = pixel;
                chunks[chunk].push_back(point);
            });
        }
    });
    size_t total = 0;
    for (const auto& c : chunks) total += c.size();
    points_.clear();
    points_.reserve(total);
    for (auto& c : chunks) {
        points_.insert(points_.end(), c.begin(), c.end());
        std::vector<StoredShadingPoint>().swap(c);  // release as we go: peak stays near one copy
    }
}

RecordSite ShadingPointStore::site(size_t i, const PixelFootprint& footprint) const {
    const StoredShadingPoint& s = points_[i];
    return RecordSite{s.p, decodeUnitVector(s.ng), decodeUnitVector(s.n), decodeUnitVector(s.wo), footprint.at(s.p)};
}

}  // namespace gi
