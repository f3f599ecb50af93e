// gi._core.tessellate_mesh: the renderer's mesh rules (renderer/mesh_description.h) for the `gi`
// loader, which reads UsdGeomMesh attributes with pxr and hands them over as numpy arrays.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cstring>
#include <optional>

#include "renderer/mesh_description.h"
#include "renderer/mesh_pieces.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using gi::MeshDescription;
using gi::MeshPrimvar;
using gi::SubdivisionRules;

using Floats2d = nb::ndarray<const float, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Ints = nb::ndarray<const int32_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Points = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

std::vector<int> toInts(const std::optional<Ints>& a) {
    if (!a) return {};
    return std::vector<int>(a->data(), a->data() + a->shape(0));
}

template <typename T>
nb::object toNumpy(std::vector<T> v, size_t width) {
    if (v.empty()) return nb::none();
    auto* heap = new std::vector<T>(std::move(v));
    nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    size_t rows = heap->size() / width;
    if (width == 1) {
        size_t shape[1] = {rows};
        return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), 1, shape, owner));
    }
    size_t shape[2] = {rows, width};
    return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), 2, shape, owner));
}

MeshPrimvar makePrimvar(const std::string& name, const Floats2d& values, const std::string& interpolation,
                        const std::optional<Ints>& indices) {
    MeshPrimvar p;
    p.name = name;
    p.width = int(values.shape(1));
    p.values.assign(values.data(), values.data() + values.shape(0) * values.shape(1));
    p.interpolation = interpolation;
    p.indices = toInts(indices);
    return p;
}

nb::dict pieceArrays(gi::TriangleMesh& m) {
    std::vector<float> positions(m.positions.size() * 3), normals(m.normals.size() * 3), uvs(m.uvs.size() * 2);
    std::memcpy(positions.data(), m.positions.data(), positions.size() * sizeof(float));
    std::memcpy(normals.data(), m.normals.data(), normals.size() * sizeof(float));
    std::memcpy(uvs.data(), m.uvs.data(), uvs.size() * sizeof(float));
    std::vector<int64_t> faces(m.faces.begin(), m.faces.end());
    nb::dict out;
    out["positions"] = toNumpy(std::move(positions), 3);
    out["indices"] = toNumpy(std::move(m.indices), 3);
    out["normals"] = toNumpy(std::move(normals), 3);
    out["uvs"] = toNumpy(std::move(uvs), 2);
    out["faces"] = toNumpy(std::move(faces), 1);
    return out;
}

nb::dict tessellateMesh(const Points& points, const Ints& counts, const Ints& indices, const std::optional<Ints>& holes,
                        const std::string& orientation, const std::optional<MeshPrimvar>& normals,
                        const std::optional<MeshPrimvar>& uvs, const std::optional<SubdivisionRules>& subdivision,
                        int refineLevel, const std::optional<Ints>& pieceOfFace, size_t pieceCount) {
    MeshDescription d;
    d.points.resize(points.shape(0));
    std::memcpy(d.points.data(), points.data(), d.points.size() * sizeof(gi::Vec3));
    d.faceVertexCounts = toInts(counts);
    d.faceVertexIndices = toInts(indices);
    d.holeIndices = toInts(holes);
    d.orientation = orientation;
    if (normals) d.normals = *normals;
    if (uvs) d.uvs = *uvs;
    if (subdivision) d.subdivision = *subdivision;
    else d.subdivision.scheme = "none";
    d.refineLevel = refineLevel;
    gi::TessellatedMesh t;
    std::vector<gi::TriangleMesh> pieces;
    {
        nb::gil_scoped_release release;
        t = gi::tessellate(d);
        if (pieceOfFace) pieces = gi::splitByFace(t.mesh, toInts(pieceOfFace), std::max<size_t>(pieceCount, 1));
        else pieces.push_back(std::move(t.mesh));
    }
    nb::list arrays;
    for (gi::TriangleMesh& piece : pieces) arrays.append(pieceArrays(piece));
    nb::dict out;
    out["pieces"] = arrays;
    out["warnings"] = t.warnings;
    out["refined"] = t.refined;
    return out;
}

nb::dict assignSubsetFaces(size_t faceCount, const std::vector<std::pair<std::string, std::optional<Ints>>>& subsets,
                           const std::string& familyType, const std::string& meshPath) {
    std::vector<gi::FaceSubset> faceSubsets;
    for (const auto& [path, indices] : subsets) faceSubsets.push_back({path, toInts(indices)});
    gi::SubsetFaces faces = gi::assignSubsetFaces(faceCount, faceSubsets, familyType, meshPath);
    nb::list warnings;
    for (const gi::SubsetWarning& w : faces.warnings) warnings.append(nb::make_tuple(w.subject, w.message));
    std::vector<bool> owns(faces.ownsFaces.begin(), faces.ownsFaces.end());
    nb::dict out;
    out["piece_of_face"] = faces.pieceOfFace.empty() ? nb::none() : toNumpy(std::move(faces.pieceOfFace), 1);
    out["owns_faces"] = owns;
    out["warnings"] = warnings;
    return out;
}

}  // namespace

void bindMesh(nb::module_& m) {
    nb::class_<MeshPrimvar>(m, "MeshPrimvar")
        .def(nb::new_(&makePrimvar), "name"_a, "values"_a, "interpolation"_a, "indices"_a = nb::none())
        .def_ro("name", &MeshPrimvar::name)
        .def_ro("interpolation", &MeshPrimvar::interpolation);
    nb::class_<SubdivisionRules>(m, "SubdivisionRules")
        .def(nb::init<>())
        .def_rw("scheme", &SubdivisionRules::scheme)
        .def_rw("interpolate_boundary", &SubdivisionRules::interpolateBoundary)
        .def_rw("face_varying_linear_interpolation", &SubdivisionRules::faceVaryingLinearInterpolation)
        .def_rw("triangle_subdivision_rule", &SubdivisionRules::triangleSubdivisionRule)
        .def_rw("crease_indices", &SubdivisionRules::creaseIndices)
        .def_rw("crease_lengths", &SubdivisionRules::creaseLengths)
        .def_rw("crease_sharpnesses", &SubdivisionRules::creaseSharpnesses)
        .def_rw("corner_indices", &SubdivisionRules::cornerIndices)
        .def_rw("corner_sharpnesses", &SubdivisionRules::cornerSharpnesses);
    m.def("tessellate_mesh", &tessellateMesh, "points"_a, "face_vertex_counts"_a, "face_vertex_indices"_a,
          "hole_indices"_a = nb::none(), "orientation"_a = "rightHanded", "normals"_a = nb::none(),
          "uvs"_a = nb::none(), "subdivision"_a = nb::none(), "refine_level"_a = 0, "piece_of_face"_a = nb::none(),
          "pieces"_a = 1,
          "A UsdGeomMesh's arrays as the renderer's triangles (renderer/mesh_description.h), cut into `pieces` "
          "by piece_of_face (renderer/mesh_pieces.h; None: one piece): a dict of pieces (each a dict of "
          "positions (N, 3), indices (M, 3) or None when empty, normals and uvs per vertex or None, faces (M,): "
          "the authored face of each triangle), warnings and refined. subdivision None: a polygon mesh.");
    m.def("assign_subset_faces", &assignSubsetFaces, "face_count"_a, "subsets"_a, "family_type"_a, "mesh_path"_a,
          "Which materialBind face subset owns each face (renderer/mesh_pieces.h): subsets is [(path, int32 "
          "indices)]; returns piece_of_face (int32, 0 = the mesh's own, i + 1 = subsets[i]; None for no faces), "
          "owns_faces (per subset) and warnings [(prim path, message)].");
}
