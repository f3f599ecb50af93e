#include "meshGeometry.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <cmath>

#include "pxr/base/gf/vec2d.h"
#include "pxr/base/gf/vec2f.h"
#include "pxr/base/gf/vec3d.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/vt/array.h"
#include "pxr/imaging/hd/meshUtil.h"
#include "pxr/imaging/hd/tokens.h"
#include "pxr/imaging/hd/types.h"
#include "pxr/imaging/pxOsd/tokens.h"

PXR_NAMESPACE_OPEN_SCOPE

namespace {

namespace Osd = OpenSubdiv::OPENSUBDIV_VERSION;

// Primvar values as float arrays, whatever precision the scene authored.
template <int N>
std::vector<std::array<float, N>> ReadFloats(VtValue const& value) {
    std::vector<std::array<float, N>> out;
    auto copy = [&](auto const& array) {
        out.resize(array.size());
        for (size_t i = 0; i < array.size(); ++i)
            for (int c = 0; c < N; ++c) out[i][c] = float(array[i][c]);
    };
    if constexpr (N == 3) {
        if (value.IsHolding<VtVec3fArray>()) copy(value.UncheckedGet<VtVec3fArray>());
        else if (value.IsHolding<VtVec3dArray>()) copy(value.UncheckedGet<VtVec3dArray>());
    } else {
        if (value.IsHolding<VtVec2fArray>()) copy(value.UncheckedGet<VtVec2fArray>());
        else if (value.IsHolding<VtVec2dArray>()) copy(value.UncheckedGet<VtVec2dArray>());
    }
    return out;
}

gi::Vec3 ToVec3(std::array<float, 3> const& a) { return gi::Vec3(a[0], a[1], a[2]); }
gi::Vec2 ToVec2(std::array<float, 2> const& a) { return gi::Vec2(a[0], a[1]); }

// Which piece each coarse face belongs to: 0 = the mesh's own material, i+1 = subset i.
std::vector<int> FacePieces(HdMeshTopology const& topology, HdGiMeshPieces& out) {
    size_t faces = topology.GetFaceVertexCounts().size();
    std::vector<int> piece(faces, 0);
    out.materials.assign(1, SdfPath());
    for (HdGeomSubset const& subset : topology.GetGeomSubsets()) {
        if (subset.type != HdGeomSubset::TypeFaceSet) continue;
        int index = int(out.materials.size());
        out.materials.push_back(subset.materialId);
        // A face claimed by several subsets (invalid for a materialBind family) goes to the
        // first, as in the gi loader, so both front ends render such a file alike.
        for (int f : subset.indices)
            if (f >= 0 && size_t(f) < faces && piece[size_t(f)] == 0) piece[size_t(f)] = index;
    }
    return piece;
}

// Per-corner attribute source: faceVarying/uniform data need corners unshared.
struct Corners {
    std::vector<gi::Vec3> points, normals;
    std::vector<gi::Vec2> uvs;
    std::vector<int> face;  // coarse face of each triangle
};

// Splits per-corner data into pieces, sharing vertices within a piece when `shared` says the
// corner data are per point (vertex index = the point index).
void Distribute(std::vector<int> const& trianglePiece, size_t pieceCount, std::vector<int> const& cornerVertex,
                bool shared, Corners const& c, HdGiMeshPieces& out) {
    out.pieces.assign(pieceCount, HdGiTriangleMesh());
    std::vector<std::vector<int>> remap(pieceCount);
    size_t triangles = trianglePiece.size();
    for (size_t t = 0; t < triangles; ++t) {
        HdGiTriangleMesh& m = out.pieces[size_t(trianglePiece[t])];
        for (int k = 0; k < 3; ++k) {
            size_t corner = 3 * t + k;
            size_t source = shared ? size_t(cornerVertex[corner]) : corner;
            if (shared) {
                std::vector<int>& r = remap[size_t(trianglePiece[t])];
                if (r.empty()) r.assign(c.points.size(), -1);
                if (r[source] >= 0) {
                    m.indices.push_back(uint32_t(r[source]));
                    continue;
                }
                r[source] = int(m.points.size());
            }
            m.indices.push_back(uint32_t(m.points.size()));
            m.points.push_back(c.points[source]);
            if (!c.normals.empty()) m.normals.push_back(c.normals[source]);
            if (!c.uvs.empty()) m.uvs.push_back(c.uvs[source]);
        }
    }
}

// Area-weighted vertex normals of a triangle list (refined subdivision surfaces are smooth).
std::vector<gi::Vec3> SmoothNormals(std::vector<gi::Vec3> const& points, std::vector<int> const& corners) {
    std::vector<gi::Vec3> n(points.size(), gi::Vec3(0.0f));
    for (size_t t = 0; t + 2 < corners.size(); t += 3) {
        gi::Vec3 a = points[corners[t]], b = points[corners[t + 1]], c = points[corners[t + 2]];
        gi::Vec3 face = gi::cross(b - a, c - a);
        for (int k = 0; k < 3; ++k) n[corners[t + k]] += face;
    }
    for (gi::Vec3& v : n) {
        float len = gi::length(v);
        v = len > 0 && std::isfinite(len) ? v / len : gi::Vec3(0, 0, 1);
    }
    return n;
}

struct OsdPoint {
    float v[3] = {0, 0, 0};
    void Clear() { v[0] = v[1] = v[2] = 0; }
    void AddWithWeight(OsdPoint const& s, float w) {
        for (int c = 0; c < 3; ++c) v[c] += w * s.v[c];
    }
};
struct OsdUv {
    float v[2] = {0, 0};
    void Clear() { v[0] = v[1] = 0; }
    void AddWithWeight(OsdUv const& s, float w) {
        v[0] += w * s.v[0];
        v[1] += w * s.v[1];
    }
};

bool Refine(SdfPath const& id, HdGiMeshInput const& in, std::vector<std::array<float, 3>> const& points,
            HdGiMeshPieces& out) {
    HdMeshTopology const& topology = in.topology;
    TfToken scheme = topology.GetScheme();
    Osd::Sdc::SchemeType type = scheme == PxOsdOpenSubdivTokens->loop       ? Osd::Sdc::SCHEME_LOOP
                                : scheme == PxOsdOpenSubdivTokens->bilinear ? Osd::Sdc::SCHEME_BILINEAR
                                                                           : Osd::Sdc::SCHEME_CATMARK;
    VtIntArray const& counts = topology.GetFaceVertexCounts();
    VtIntArray const& indices = topology.GetFaceVertexIndices();
    if (type == Osd::Sdc::SCHEME_LOOP)
        for (int n : counts)
            if (n != 3) {
                out.warnings.push_back("loop subdivision needs triangles; rendering the control mesh");
                return false;
            }
    PxOsdSubdivTags const& tags = topology.GetSubdivTags();
    Osd::Sdc::Options options;
    TfToken boundary = tags.GetVertexInterpolationRule();
    options.SetVtxBoundaryInterpolation(boundary == PxOsdOpenSubdivTokens->none ? Osd::Sdc::Options::VTX_BOUNDARY_NONE
                                        : boundary == PxOsdOpenSubdivTokens->edgeOnly
                                            ? Osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                            : Osd::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    TfToken fvar = tags.GetFaceVaryingInterpolationRule();
    options.SetFVarLinearInterpolation(
        fvar == PxOsdOpenSubdivTokens->none           ? Osd::Sdc::Options::FVAR_LINEAR_NONE
        : fvar == PxOsdOpenSubdivTokens->cornersOnly  ? Osd::Sdc::Options::FVAR_LINEAR_CORNERS_ONLY
        : fvar == PxOsdOpenSubdivTokens->cornersPlus2 ? Osd::Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2
        : fvar == PxOsdOpenSubdivTokens->boundaries   ? Osd::Sdc::Options::FVAR_LINEAR_BOUNDARIES
        : fvar == PxOsdOpenSubdivTokens->all          ? Osd::Sdc::Options::FVAR_LINEAR_ALL
                                                      : Osd::Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1);

    Osd::Far::TopologyDescriptor desc;
    desc.numVertices = int(points.size());
    desc.numFaces = int(counts.size());
    desc.numVertsPerFace = counts.cdata();
    desc.vertIndicesPerFace = indices.cdata();
    // USD creases are chains of vertices; Far wants edges.
    std::vector<int> creasePairs;
    std::vector<float> creaseWeights;
    VtIntArray const& creaseIndices = tags.GetCreaseIndices();
    VtIntArray const& creaseLengths = tags.GetCreaseLengths();
    VtFloatArray const& weights = tags.GetCreaseWeights();
    bool perEdge = false;
    size_t edges = 0;
    for (int len : creaseLengths) edges += size_t(std::max(0, len - 1));
    perEdge = weights.size() == edges;
    size_t cursor = 0, edge = 0;
    for (size_t c = 0; c < creaseLengths.size(); ++c) {
        int len = creaseLengths[c];
        for (int k = 0; k + 1 < len && cursor + k + 1 < creaseIndices.size(); ++k, ++edge) {
            creasePairs.push_back(creaseIndices[cursor + k]);
            creasePairs.push_back(creaseIndices[cursor + k + 1]);
            size_t w = perEdge ? edge : c;
            creaseWeights.push_back(w < weights.size() ? weights[w] : 10.0f);
        }
        cursor += size_t(std::max(0, len));
    }
    desc.numCreases = int(creaseWeights.size());
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseWeights.data();
    VtIntArray const& corners = tags.GetCornerIndices();
    VtFloatArray const& cornerWeights = tags.GetCornerWeights();
    if (corners.size() == cornerWeights.size()) {
        desc.numCorners = int(corners.size());
        desc.cornerVertexIndices = corners.cdata();
        desc.cornerWeights = cornerWeights.cdata();
    }
    VtIntArray const& holes = topology.GetHoleIndices();
    desc.numHoles = int(holes.size());
    desc.holeIndices = holes.cdata();

    std::vector<std::array<float, 2>> st = ReadFloats<2>(in.st.value);
    bool faceVaryingSt = !st.empty() && in.st.interpolation == HdInterpolationFaceVarying && st.size() == indices.size();
    bool vertexSt = !st.empty() && (in.st.interpolation == HdInterpolationVertex ||
                                    in.st.interpolation == HdInterpolationVarying) && st.size() == points.size();
    std::vector<int> stIndices;
    Osd::Far::TopologyDescriptor::FVarChannel channel;
    if (faceVaryingSt) {
        stIndices.resize(st.size());
        for (size_t i = 0; i < st.size(); ++i) stIndices[i] = int(i);
        channel.numValues = int(st.size());
        channel.valueIndices = stIndices.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    using Factory = Osd::Far::TopologyRefinerFactory<Osd::Far::TopologyDescriptor>;
    std::unique_ptr<Osd::Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(type, options)));
    if (!refiner) {
        out.warnings.push_back("OpenSubdiv rejected the topology; rendering the control mesh");
        return false;
    }
    int level = std::clamp(in.refineLevel, 1, 8);
    refiner->RefineUniform(Osd::Far::TopologyRefiner::UniformOptions(level));

    Osd::Far::PrimvarRefiner primvarRefiner(*refiner);
    std::vector<OsdPoint> vertexData(size_t(refiner->GetNumVerticesTotal()));
    for (size_t i = 0; i < points.size(); ++i)
        for (int c = 0; c < 3; ++c) vertexData[i].v[c] = points[i][c];
    std::vector<OsdUv> uvData;
    if (vertexSt || faceVaryingSt) {
        uvData.resize(size_t(vertexSt ? refiner->GetNumVerticesTotal() : refiner->GetNumFVarValuesTotal(0)));
        for (size_t i = 0; i < st.size(); ++i) uvData[i].v[0] = st[i][0], uvData[i].v[1] = st[i][1];
    }
    OsdPoint* src = vertexData.data();
    OsdUv* uvSrc = uvData.data();
    for (int l = 1; l <= level; ++l) {
        OsdPoint* dst = src + refiner->GetLevel(l - 1).GetNumVertices();
        primvarRefiner.Interpolate(l, src, dst);
        src = dst;
        if (vertexSt) {
            OsdUv* uvDst = uvSrc + refiner->GetLevel(l - 1).GetNumVertices();
            primvarRefiner.Interpolate(l, uvSrc, uvDst);
            uvSrc = uvDst;
        } else if (faceVaryingSt) {
            OsdUv* uvDst = uvSrc + refiner->GetLevel(l - 1).GetNumFVarValues(0);
            primvarRefiner.InterpolateFaceVarying(l, uvSrc, uvDst, 0);
            uvSrc = uvDst;
        }
    }

    Osd::Far::TopologyLevel const& last = refiner->GetLevel(level);
    Corners c;
    c.points.resize(size_t(last.GetNumVertices()));
    for (size_t i = 0; i < c.points.size(); ++i) c.points[i] = gi::Vec3(src[i].v[0], src[i].v[1], src[i].v[2]);
    // Children of a coarse face are contiguous in Far's uniform refinement, in parent order.
    std::vector<int> coarseFacePieces = FacePieces(topology, out);
    std::vector<int> childrenPerFace(counts.size());
    int perQuad = 1 << (2 * (level - 1));
    for (size_t f = 0; f < counts.size(); ++f)
        childrenPerFace[f] = type == Osd::Sdc::SCHEME_LOOP ? perQuad * 4 : counts[f] * perQuad;
    std::vector<int> cornerVertex, cornerUv, trianglePiece;
    bool flip = topology.GetOrientation() == HdTokens->leftHanded;
    size_t coarse = 0;
    int seen = 0;
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        while (coarse < childrenPerFace.size() && seen >= childrenPerFace[coarse]) ++coarse, seen = 0;
        ++seen;
        if (last.IsFaceHole(f)) continue;
        auto verts = last.GetFaceVertices(f);
        int n = verts.size();
        for (int k = 1; k + 1 < n; ++k) {
            int tri[3] = {0, k, k + 1};
            if (flip) std::swap(tri[1], tri[2]);
            for (int j : tri) {
                cornerVertex.push_back(verts[j]);
                if (faceVaryingSt) cornerUv.push_back(last.GetFaceFVarValues(f, 0)[j]);
            }
            trianglePiece.push_back(coarse < coarseFacePieces.size() ? coarseFacePieces[coarse] : 0);
        }
    }
    std::vector<gi::Vec3> normals = SmoothNormals(c.points, cornerVertex);
    if (faceVaryingSt) {
        // Unshare corners: uv per corner.
        Corners unshared;
        for (size_t k = 0; k < cornerVertex.size(); ++k) {
            unshared.points.push_back(c.points[size_t(cornerVertex[k])]);
            unshared.normals.push_back(normals[size_t(cornerVertex[k])]);
            OsdUv const& uv = uvSrc[cornerUv[k]];
            unshared.uvs.push_back(gi::Vec2(uv.v[0], uv.v[1]));
        }
        Distribute(trianglePiece, out.materials.size(), cornerVertex, false, unshared, out);
    } else {
        c.normals = normals;
        if (vertexSt)
            for (size_t i = 0; i < c.points.size(); ++i) c.uvs.push_back(gi::Vec2(uvSrc[i].v[0], uvSrc[i].v[1]));
        Distribute(trianglePiece, out.materials.size(), cornerVertex, true, c, out);
    }
    out.refined = true;
    return true;
}

}  // namespace

HdGiMeshPieces HdGiTriangulate(SdfPath const& id, HdGiMeshInput const& in) {
    HdGiMeshPieces out;
    std::vector<std::array<float, 3>> points = ReadFloats<3>(in.points);
    if (points.empty()) {
        if (!in.topology.GetFaceVertexCounts().empty()) out.warnings.push_back("no points; not rendered");
        return out;
    }
    TfToken scheme = in.topology.GetScheme();
    if (in.refineLevel > 0 && scheme != PxOsdOpenSubdivTokens->none && Refine(id, in, points, out)) return out;

    HdMeshUtil util(&in.topology, id);
    VtVec3iArray triangles;
    VtIntArray params;
    util.ComputeTriangleIndices(&triangles, &params);
    std::vector<int> facePieces = FacePieces(in.topology, out);

    // Corner sources of each primvar.
    auto perCorner = [&](HdGiPrimvar const& pv, int components, HdType type, VtValue* result) -> bool {
        if (pv.IsEmpty() || pv.interpolation != HdInterpolationFaceVarying) return false;
        size_t n = pv.value.GetArraySize();
        void const* data = nullptr;
        if (components == 3 && pv.value.IsHolding<VtVec3fArray>()) data = pv.value.UncheckedGet<VtVec3fArray>().cdata();
        if (components == 2 && pv.value.IsHolding<VtVec2fArray>()) data = pv.value.UncheckedGet<VtVec2fArray>().cdata();
        if (!data) return false;
        return util.ComputeTriangulatedFaceVaryingPrimvar(data, int(n), type, result);
    };
    VtValue fvNormals, fvUvs;
    bool normalsFv = perCorner(in.normals, 3, HdTypeFloatVec3, &fvNormals);
    bool uvsFv = perCorner(in.st, 2, HdTypeFloatVec2, &fvUvs);
    std::vector<std::array<float, 3>> normals = ReadFloats<3>(in.normals.value);
    std::vector<std::array<float, 2>> uvs = ReadFloats<2>(in.st.value);
    auto isPerPoint = [&](HdGiPrimvar const& pv, size_t size) {
        return (pv.interpolation == HdInterpolationVertex || pv.interpolation == HdInterpolationVarying) &&
               size == points.size();
    };
    bool normalsUniform = in.normals.interpolation == HdInterpolationUniform &&
                          normals.size() == in.topology.GetFaceVertexCounts().size();
    bool uvsUniform = in.st.interpolation == HdInterpolationUniform && uvs.size() == in.topology.GetFaceVertexCounts().size();
    bool normalsPoint = isPerPoint(in.normals, normals.size());
    bool uvsPoint = isPerPoint(in.st, uvs.size());
    if (!in.normals.IsEmpty() && !normalsFv && !normalsUniform && !normalsPoint &&
        in.normals.interpolation != HdInterpolationConstant)
        out.warnings.push_back("normals have " + std::to_string(normals.size()) +
                               " values, which fits no interpolation; ignored");
    if (!in.st.IsEmpty() && !uvsFv && !uvsUniform && !uvsPoint && in.st.interpolation != HdInterpolationConstant)
        out.warnings.push_back("primvars:st has " + std::to_string(uvs.size()) +
                               " values, which fits no interpolation; ignored");
    bool shared = !normalsFv && !uvsFv && !normalsUniform && !uvsUniform;

    Corners c;
    std::vector<int> cornerVertex, trianglePiece;
    size_t dropped = 0;
    VtVec3fArray const* fvN = normalsFv ? &fvNormals.UncheckedGet<VtVec3fArray>() : nullptr;
    VtVec2fArray const* fvUv = uvsFv ? &fvUvs.UncheckedGet<VtVec2fArray>() : nullptr;
    if (shared) {
        for (auto const& p : points) c.points.push_back(ToVec3(p));
        if (normalsPoint)
            for (auto const& n : normals) c.normals.push_back(ToVec3(n));
        if (uvsPoint)
            for (auto const& uv : uvs) c.uvs.push_back(ToVec2(uv));
    }
    for (size_t t = 0; t < triangles.size(); ++t) {
        GfVec3i const& tri = triangles[t];
        bool valid = true;
        for (int k = 0; k < 3; ++k) valid = valid && tri[k] >= 0 && size_t(tri[k]) < points.size();
        if (!valid) {
            ++dropped;
            continue;
        }
        int face = HdMeshUtil::DecodeFaceIndexFromCoarseFaceParam(params[t]);
        trianglePiece.push_back(face >= 0 && size_t(face) < facePieces.size() ? facePieces[size_t(face)] : 0);
        for (int k = 0; k < 3; ++k) {
            cornerVertex.push_back(tri[k]);
            if (shared) continue;
            c.points.push_back(ToVec3(points[size_t(tri[k])]));
            if (fvN) c.normals.push_back(gi::Vec3((*fvN)[3 * t + k][0], (*fvN)[3 * t + k][1], (*fvN)[3 * t + k][2]));
            else if (normalsUniform) c.normals.push_back(ToVec3(normals[size_t(face)]));
            else if (normalsPoint) c.normals.push_back(ToVec3(normals[size_t(tri[k])]));
            if (fvUv) c.uvs.push_back(gi::Vec2((*fvUv)[3 * t + k][0], (*fvUv)[3 * t + k][1]));
            else if (uvsUniform) c.uvs.push_back(ToVec2(uvs[size_t(face)]));
            else if (uvsPoint) c.uvs.push_back(ToVec2(uvs[size_t(tri[k])]));
        }
    }
    if (dropped) out.warnings.push_back(std::to_string(dropped) + " triangles index points that do not exist; dropped");
    Distribute(trianglePiece, out.materials.size(), cornerVertex, shared, c, out);
    return out;
}

PXR_NAMESPACE_CLOSE_SCOPE
