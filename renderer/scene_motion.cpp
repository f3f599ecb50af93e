// The Scene's validation of motion steps (motion.h) handed to addMesh, addSphere and addInstance:
// unusable motion is warned about, naming the prim, and the prim is rendered without it; steps
// that are all equal are no motion at all, so nothing static becomes motion geometry.
#include <algorithm>
#include <cstring>

#include "scene.h"

namespace gi {

std::vector<Mat4> Scene::transformMotion(const std::string& what, const MotionSteps& motion) {
    if (motion.transforms.size() < 2) return {};
    if (motion.transforms.size() > kMaxMotionSteps) {
        warn(what + ": " + std::to_string(motion.transforms.size()) + " motion steps (at most " +
             std::to_string(kMaxMotionSteps) + "); rendered without motion blur");
        return {};
    }
    Mat4 inverse;
    for (size_t i = 0; i < motion.transforms.size(); ++i)
        if (!motion.transforms[i].isFinite() || !motion.transforms[i].inverse(inverse)) {
            warn(what + ": NaN, Inf or singular transform at motion step " + std::to_string(i) +
                 "; rendered without motion blur");
            return {};
        }
    auto same = [&](const Mat4& m) { return std::equal(&m.m[0][0], &m.m[0][0] + 16, &motion.transforms[0].m[0][0]); };
    if (std::all_of(motion.transforms.begin(), motion.transforms.end(), same)) return {};
    return motion.transforms;
}

std::vector<std::vector<Vec3>> Scene::meshMotion(const std::string& name, const std::vector<Vec3>& positions,
                                                 const Mat4* transform, int prototype, const MotionSteps& motion,
                                                 std::vector<Mat4>& transforms) {
    transforms.clear();
    const size_t steps = motion.count();
    if (steps < 2) return {};
    auto without = [&](const std::string& why) {
        warn("mesh " + name + ": " + why + "; rendered without motion blur");
        return std::vector<std::vector<Vec3>>();
    };
    if (steps > kMaxMotionSteps)
        return without(std::to_string(steps) + " motion steps (at most " + std::to_string(kMaxMotionSteps) + ")");
    if (!motion.points.empty() && !motion.transforms.empty() && motion.points.size() != motion.transforms.size())
        return without(std::to_string(motion.points.size()) + " point steps but " +
                       std::to_string(motion.transforms.size()) + " transform steps");
    for (size_t i = 0; i < motion.points.size(); ++i)
        if (motion.points[i].size() != positions.size())
            return without("motion step " + std::to_string(i) + " has " + std::to_string(motion.points[i].size()) +
                           " points for " + std::to_string(positions.size()));
    if (!motion.transforms.empty() && prototype >= 0)
        warn("mesh " + name + ": transform motion inside a prototype is ignored (its instances' motion applies)");
    else if (!motion.transforms.empty()) {
        transforms = transformMotion("mesh " + name, motion);
        if (transforms.empty() && motion.points.empty()) return {};  // unusable (warned) or not moving
    }
    std::vector<std::vector<Vec3>> out(steps);
    for (size_t i = 0; i < steps; ++i) {
        out[i] = motion.points.empty() ? positions : motion.points[i];
        const Mat4* m = !transforms.empty() ? &transforms[i] : prototype < 0 ? transform : nullptr;
        if (m)
            for (Vec3& p : out[i]) p = m->point(p);
    }
    auto sameAsFirst = [&](const std::vector<Vec3>& step) {
        return std::memcmp(step.data(), out[0].data(), step.size() * sizeof(Vec3)) == 0;
    };
    if (std::all_of(out.begin(), out.end(), sameAsFirst)) {  // nothing moves: static geometry
        transforms.clear();
        return {};
    }
    return out;
}

}  // namespace gi
