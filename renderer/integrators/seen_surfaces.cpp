#include "seen_surfaces.h"

#include <tbb/parallel_for.h>

#include "../sampling.h"
#include "photon_map.h"
#include "specular_chain.h"

namespace gi {

namespace {
// Pixel streams of this pass use a sample index the render never reaches.
constexpr uint32_t kSeenSampleIndex = 0xfffffff1u;
}  // namespace

bool SeenSurfaces::contains(const Vec3& p, const Vec3& n, uint32_t surface) const {
    std::vector<KdTree<Point>::Neighbour> near;
    points_.nearest(p, kCandidates, radius_ * radius_, [&](const Vec3& q) { return lengthSquared(q - p); },
                    [&](const Point& q) { return dot(q.n, n) >= kNormalAgreement; }, near);
    std::sort(near.begin(), near.end());
    for (const auto& candidate : near) {
        const Point& q = points_[candidate.index];
        if (q.surface == surface || clearBetween(*scene_, p, n, q.p, q.n, 0.05f * std::sqrt(candidate.distance2)))
            return true;
    }
    return false;
}

SeenSurfaces SeenSurfaces::trace(const Scene& scene, const Camera& camera, int width, int height, int rayDepth,
                                 uint32_t seed) {
    SeenSurfaces seen;
    seen.scene_ = &scene;
    float extent = maxComponent(scene.boundsMax() - scene.boundsMin());
    seen.radius_ = std::isfinite(extent) && extent > 0 ? extent * kRadiusShare : 1.0f;

    int across = std::min(width, kRaysAcross), down = std::min(height, kRaysAcross);
    std::vector<std::vector<Point>> rows(size_t(std::max(down, 0)));
    tbb::parallel_for(0, down, [&](int row) {
        Sampler sampler(seed);
        RayStats stats;
        auto add = [&](const ShadingPoint& sp) {
            rows[row].push_back({sp.si.p, recordNormal(sp), photonSurface(sp.si.shapeId, sp.si.instanceId)});
        };
        for (int column = 0; column < across; ++column) {
            // Over the whole image, also for a pilot's mosaic: photons go where the render looks.
            float x = (column + 0.5f) * camera.imageWidth() / across, y = (row + 0.5f) * camera.imageHeight() / down;
            sampler.start(int(x), int(y), kSeenSampleIndex);
            Ray ray = camera.generateImageRay(x, y, Vec2(0.5f, 0.5f));
            forEachDiffuseHit(scene, ray, sampler, stats, rayDepth, [&](const ShadingPoint& sp) {
                add(sp);
                Frame frame(recordNormal(sp));
                for (int i = 0; i < kGatherRays; ++i) {
                    Ray gather = spawnRay(sp.si, frame.toWorld(sampleCosineHemisphere(sampler.get2D())));
                    Intersection hit = intersectVisible(scene, gather, sampler, stats, false);
                    if (hit.kind == Intersection::Kind::Surface) add(makeShadingPoint(hit.si, -gather.d));
                }
            });
        }
    });
    std::vector<Point> points;
    for (const auto& row : rows)
        for (const Point& point : row)
            if (isFinite(point.p)) points.push_back(point);
    seen.points_.build(std::move(points));
    return seen;
}

}  // namespace gi
