// A mesh primvar checked against the mesh's topology: the right width, finite values, indices in
// range and enough elements for its interpolation; anything else is a warning and no primvar.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "renderer/mesh_description.h"

namespace gi {

enum class Interpolation { Constant, Uniform, Varying, Vertex, FaceVarying };

// Element counts each interpolation needs.
struct MeshCounts {
    size_t points = 0, faces = 0, corners = 0;  // corners: faceVertexIndices' length
};

// A usable primvar: element e's value is values[index[e] * width ...], for e below elements().
// index is the authored indices when the primvar was indexed (OpenSubdiv then sees which
// face-varying corners share a value), else 0, 1, 2, ...
struct CheckedPrimvar {
    std::vector<float> values;
    std::vector<int> index;
    int width = 0;
    Interpolation interpolation = Interpolation::Vertex;
    size_t elements() const { return index.size(); }
    const float* element(size_t e) const { return values.data() + size_t(index[e]) * size_t(width); }
};

std::optional<CheckedPrimvar> checkPrimvar(const MeshPrimvar& primvar, int width, const MeshCounts& counts,
                                           std::vector<std::string>& warnings);

}  // namespace gi
