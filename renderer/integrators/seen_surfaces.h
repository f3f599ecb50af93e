// Where a render reads photons: the surfaces the camera sees (directly or through specular
// chains, as the ray tracer visits them) and the surfaces one diffuse bounce away from those
// (where final-gather rays and irradiance-record paths land), as a set of sampled points.
//
// It decides which lights are worth photons (photon_emitters.h): a light whose photons all
// land elsewhere (sealed in a box, facing away from the scene) cannot change the image. A
// landing counts as seen when a sampled point lies within a radius of it (kRadiusShare of the
// scene's extent) with a normal that agrees, on the same surface or with nothing in between:
// the inside of a box on a floor is a centimetre from the floor around it, but its walls
// stand between them.
#pragma once
#include <vector>

#include "../camera.h"
#include "../scene.h"
#include "kd_tree.h"

namespace gi {

class SeenSurfaces {
public:
    // Traces camera rays through a grid of at most kRaysAcross x kRaysAcross (and at most width x
    // height, the film's pixels) spread over the camera's image, following specular chains up to
    // rayDepth, and kGatherRays cosine-distributed rays from each non-specular point they reach.
    static SeenSurfaces trace(const Scene& scene, const Camera& camera, int width, int height, int rayDepth,
                              uint32_t seed);

    // Whether light landing at p (normal n, on surface `surface`) reaches a sampled point.
    bool contains(const Vec3& p, const Vec3& n, uint32_t surface) const;
    size_t points() const { return points_.size(); }

    static constexpr int kRaysAcross = 128, kGatherRays = 4, kCandidates = 8;
    static constexpr float kRadiusShare = 1.0f / 32, kNormalAgreement = 0.5f;

private:
    struct Point {
        Vec3 p;
        Vec3 n;
        uint32_t surface;
    };
    const Scene* scene_ = nullptr;
    float radius_ = 0;
    KdTree<Point> points_;
};

}  // namespace gi
