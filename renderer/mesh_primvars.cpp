#include "renderer/mesh_primvars.h"

#include <cmath>

namespace gi {

namespace {

std::optional<Interpolation> interpolationFromToken(const std::string& token) {
    if (token == "constant") return Interpolation::Constant;
    if (token == "uniform") return Interpolation::Uniform;
    if (token == "varying") return Interpolation::Varying;
    if (token == "vertex") return Interpolation::Vertex;
    if (token == "faceVarying") return Interpolation::FaceVarying;
    return std::nullopt;
}

size_t elementsNeeded(Interpolation i, const MeshCounts& counts) {
    switch (i) {
        case Interpolation::Constant: return 1;
        case Interpolation::Uniform: return counts.faces;
        case Interpolation::Varying:
        case Interpolation::Vertex: return counts.points;
        case Interpolation::FaceVarying: return counts.corners;
    }
    return 0;
}

}  // namespace

std::optional<CheckedPrimvar> checkPrimvar(const MeshPrimvar& primvar, int width, const MeshCounts& counts,
                                           std::vector<std::string>& warnings) {
    if (!primvar.authored()) return std::nullopt;
    const std::string& name = primvar.name;
    if (primvar.width != width || primvar.values.size() % size_t(width) != 0) {
        warnings.push_back(name + " is not " + std::to_string(width) + "-dimensional; ignored");
        return std::nullopt;
    }
    size_t valueCount = primvar.values.size() / size_t(width);
    bool indexed = !primvar.indices.empty();
    for (int i : primvar.indices)
        if (i < 0 || size_t(i) >= valueCount) {
            warnings.push_back(name + " has invalid indices (e.g. " + std::to_string(i) + "; " +
                               std::to_string(valueCount) + " values); ignored");
            return std::nullopt;
        }
    // Only values some element uses count: an indexed primvar may hold others.
    std::vector<char> used(valueCount, char(!indexed));
    for (int i : primvar.indices) used[size_t(i)] = 1;
    for (size_t v = 0; v < valueCount; ++v)
        for (int c = 0; c < width && used[v]; ++c)
            if (!std::isfinite(primvar.values[v * size_t(width) + size_t(c)])) {
                warnings.push_back(name + " has NaN/Inf values; ignored");
                return std::nullopt;
            }
    std::optional<Interpolation> interpolation = interpolationFromToken(primvar.interpolation);
    if (!interpolation) {
        warnings.push_back(name + " has unsupported interpolation '" + primvar.interpolation + "'; ignored");
        return std::nullopt;
    }
    size_t available = indexed ? primvar.indices.size() : valueCount;
    size_t needed = elementsNeeded(*interpolation, counts);
    if (available < needed) {
        warnings.push_back(name + " has " + std::to_string(available) + (indexed ? " indices" : " values") +
                           " but its '" + primvar.interpolation + "' interpolation needs " +
                           std::to_string(needed) + "; ignored");
        return std::nullopt;
    }
    CheckedPrimvar out;
    out.values = primvar.values;
    out.width = width;
    out.interpolation = *interpolation;
    out.index.resize(needed);  // extra elements (more than the interpolation uses) are left out
    for (size_t e = 0; e < needed; ++e) out.index[e] = indexed ? primvar.indices[e] : int(e);
    return out;
}

}  // namespace gi
