#include "meshGeometry.h"

#include "pxr/base/gf/vec2d.h"
#include "pxr/base/gf/vec2f.h"
#include "pxr/base/gf/vec3d.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/vt/types.h"
#include "pxr/imaging/hd/types.h"
#include "pxr/imaging/pxOsd/subdivTags.h"
#include "renderer/mesh_description.h"
#include "renderer/mesh_pieces.h"

PXR_NAMESPACE_OPEN_SCOPE

namespace {

// Values of a Vec3 or Vec2 (float or double) array as floats, N per element; false for other types.
template <int N>
bool ReadFloats(VtValue const& value, std::vector<float>& out) {
    auto copy = [&](auto const& array) {
        out.resize(array.size() * N);
        for (size_t i = 0; i < array.size(); ++i)
            for (int c = 0; c < N; ++c) out[i * N + c] = float(array[i][c]);
        return true;
    };
    if constexpr (N == 3) {
        if (value.IsHolding<VtVec3fArray>()) return copy(value.UncheckedGet<VtVec3fArray>());
        if (value.IsHolding<VtVec3dArray>()) return copy(value.UncheckedGet<VtVec3dArray>());
    } else {
        if (value.IsHolding<VtVec2fArray>()) return copy(value.UncheckedGet<VtVec2fArray>());
        if (value.IsHolding<VtVec2dArray>()) return copy(value.UncheckedGet<VtVec2dArray>());
    }
    return false;
}

std::vector<int> ToInts(VtIntArray const& a) { return std::vector<int>(a.cbegin(), a.cend()); }
std::vector<float> ToFloats(VtFloatArray const& a) { return std::vector<float>(a.cbegin(), a.cend()); }

// Hydra's interpolation as UsdGeom's token (the same words); "instance" is not a mesh primvar's.
std::string InterpolationToken(HdInterpolation i) {
    switch (i) {
        case HdInterpolationConstant: return "constant";
        case HdInterpolationUniform: return "uniform";
        case HdInterpolationVarying: return "varying";
        case HdInterpolationVertex: return "vertex";
        case HdInterpolationFaceVarying: return "faceVarying";
        default: return "instance";
    }
}

template <int N>
gi::MeshPrimvar ToMeshPrimvar(std::string const& name, HdGiPrimvar const& primvar, std::vector<std::string>& warnings) {
    gi::MeshPrimvar out;
    out.name = name;
    out.width = N;
    if (primvar.IsEmpty()) return out;
    if (!ReadFloats<N>(primvar.value, out.values)) {
        warnings.push_back(name + " has type " + primvar.value.GetTypeName() + ", not a " + std::to_string(N) +
                           "-vector array; ignored");
        return out;
    }
    out.interpolation = InterpolationToken(primvar.interpolation);
    out.indices = ToInts(primvar.indices);
    return out;
}

// An authored token, else the description's fallback (Hydra leaves unrefined meshes' tags empty).
void SetToken(std::string& field, TfToken const& token) {
    if (!token.IsEmpty()) field = token.GetString();
}

}  // namespace

HdGiMeshPieces HdGiTriangulate(SdfPath const& id, HdGiMeshInput const& in) {
    HdGiMeshPieces out;
    HdMeshTopology const& topology = in.topology;
    gi::MeshDescription d;
    std::vector<float> points;
    if (!ReadFloats<3>(in.points, points) && !in.points.IsEmpty())
        out.warnings.push_back("points have type " + in.points.GetTypeName() + "; not rendered");
    d.points.resize(points.size() / 3);
    for (size_t i = 0; i < d.points.size(); ++i) d.points[i] = gi::Vec3(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
    d.faceVertexCounts = ToInts(topology.GetFaceVertexCounts());
    d.faceVertexIndices = ToInts(topology.GetFaceVertexIndices());
    d.holeIndices = ToInts(topology.GetHoleIndices());
    SetToken(d.orientation, topology.GetOrientation());
    SetToken(d.subdivision.scheme, topology.GetScheme());
    PxOsdSubdivTags const& tags = topology.GetSubdivTags();
    SetToken(d.subdivision.interpolateBoundary, tags.GetVertexInterpolationRule());
    SetToken(d.subdivision.faceVaryingLinearInterpolation, tags.GetFaceVaryingInterpolationRule());
    SetToken(d.subdivision.triangleSubdivisionRule, tags.GetTriangleSubdivision());
    d.subdivision.creaseIndices = ToInts(tags.GetCreaseIndices());
    d.subdivision.creaseLengths = ToInts(tags.GetCreaseLengths());
    d.subdivision.creaseSharpnesses = ToFloats(tags.GetCreaseWeights());
    d.subdivision.cornerIndices = ToInts(tags.GetCornerIndices());
    d.subdivision.cornerSharpnesses = ToFloats(tags.GetCornerWeights());
    d.normals = ToMeshPrimvar<3>("normals", in.normals, out.warnings);
    d.uvs = ToMeshPrimvar<2>("primvars:" + in.uvName.GetString(), in.st, out.warnings);
    d.refineLevel = in.refineLevel;

    gi::TessellatedMesh t = gi::tessellate(d);
    out.warnings.insert(out.warnings.end(), t.warnings.begin(), t.warnings.end());
    out.refined = t.refined;
    // GeomSubset pieces: piece 0 keeps the mesh's own binding, piece i + 1 is face set i's.
    std::vector<gi::FaceSubset> subsets;
    out.materials.assign(1, SdfPath());
    out.names.assign(1, id.GetString());
    for (HdGeomSubset const& subset : topology.GetGeomSubsets()) {
        if (subset.type != HdGeomSubset::TypeFaceSet) continue;
        subsets.push_back({subset.id.GetString(), ToInts(subset.indices)});
        out.materials.push_back(subset.materialId);
        out.names.push_back(subset.id.GetString());
    }
    // Hydra does not carry the subsets' family type: no "partition" check here.
    gi::SubsetFaces faces = gi::assignSubsetFaces(d.faceVertexCounts.size(), subsets, "", id.GetString());
    for (gi::SubsetWarning const& w : faces.warnings) out.warnings.push_back(w.subject + ": " + w.message);
    for (gi::TriangleMesh& piece : gi::splitByFace(t.mesh, faces.pieceOfFace, out.materials.size())) {
        HdGiTriangleMesh m;
        m.points = std::move(piece.positions);
        m.normals = std::move(piece.normals);
        m.uvs = std::move(piece.uvs);
        m.indices = std::move(piece.indices);
        out.pieces.push_back(std::move(m));
    }
    return out;
}

PXR_NAMESPACE_CLOSE_SCOPE
