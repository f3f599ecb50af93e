#include "renderer/mesh_description.h"

#include <algorithm>

#include "renderer/mesh_polygons.h"
#include "renderer/mesh_primvars.h"
#include "renderer/mesh_subdivision.h"

namespace gi {

namespace {

// holeIndices as a per-face mask; indices naming no face are a warning.
std::vector<char> holeMask(const MeshDescription& mesh, std::vector<std::string>& warnings) {
    std::vector<char> hole(mesh.faceVertexCounts.size(), 0);
    size_t bad = 0;
    for (int f : mesh.holeIndices) {
        if (f < 0 || size_t(f) >= hole.size()) ++bad;
        else hole[size_t(f)] = 1;
    }
    if (bad)
        warnings.push_back(std::to_string(bad) + " holeIndices name no face (valid: 0.." +
                           std::to_string(int64_t(hole.size()) - 1) + "); ignored");
    return hole;
}

}  // namespace

TessellatedMesh tessellate(const MeshDescription& mesh) {
    TessellatedMesh out;
    std::vector<std::string>& warnings = out.warnings;
    if (mesh.points.empty() || mesh.faceVertexCounts.empty()) {
        warnings.push_back("mesh has no points or no faces; ignored");
        return out;
    }
    if (std::any_of(mesh.faceVertexCounts.begin(), mesh.faceVertexCounts.end(), [](int n) { return n < 0; })) {
        warnings.push_back("faceVertexCounts has negative counts; mesh ignored");
        return out;
    }
    std::vector<char> usable = usableFaces(mesh, warnings);
    if (std::none_of(usable.begin(), usable.end(), [](char u) { return u != 0; })) {
        warnings.push_back("no valid faces remain; mesh ignored");
        return out;
    }
    std::vector<char> hole = holeMask(mesh, warnings);
    MeshCounts counts{mesh.points.size(), mesh.faceVertexCounts.size(), mesh.faceVertexIndices.size()};
    std::optional<CheckedPrimvar> uvs = checkPrimvar(mesh.uvs, 2, counts, warnings);

    SubdivisionScheme scheme = subdivisionScheme(mesh.subdivision.scheme, warnings);
    bool leftHanded = mesh.orientation == "leftHanded";
    if (!leftHanded && mesh.orientation != "rightHanded")
        warnings.push_back("orientation '" + mesh.orientation + "' is not a valid token; using rightHanded");
    bool subdivide = scheme != SubdivisionScheme::None && mesh.refineLevel > 0;
    if (subdivide) {
        if (std::all_of(usable.begin(), usable.end(), [](char u) { return u != 0; })) {
            if (std::optional<Polygons> refined = refineSubdivision(mesh, scheme, hole, uvs, warnings)) {
                refined->leftHanded = leftHanded;
                refined->normals = smoothNormals(*refined);
                out.mesh = triangulate(*refined);
                out.refined = true;
                return out;
            }
        } else {
            warnings.push_back("subdivision needs every face valid; rendering the control mesh");
        }
    }

    std::optional<CheckedPrimvar> normals = checkPrimvar(mesh.normals, 3, counts, warnings);
    Polygons polygons;
    polygons.points = mesh.points;
    polygons.counts = mesh.faceVertexCounts;
    polygons.indices = mesh.faceVertexIndices;
    polygons.leftHanded = leftHanded;
    polygons.sourceFace.resize(mesh.faceVertexCounts.size());
    polygons.rendered.resize(mesh.faceVertexCounts.size());
    for (size_t f = 0; f < polygons.sourceFace.size(); ++f) {
        polygons.sourceFace[f] = int(f);
        polygons.rendered[f] = usable[f] && !hole[f];
    }
    std::vector<int> faceOfSlot = faceOfSlots(mesh.faceVertexCounts, mesh.faceVertexIndices.size());
    if (normals) polygons.normals = expandPrimvar(*normals, faceOfSlot, mesh.points.size());
    if (uvs) polygons.uvs = expandPrimvar(*uvs, faceOfSlot, mesh.points.size());
    out.mesh = triangulate(polygons);
    return out;
}

}  // namespace gi
