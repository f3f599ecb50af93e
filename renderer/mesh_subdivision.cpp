#include "renderer/mesh_subdivision.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <memory>
#include <unordered_set>

namespace gi {

namespace {

namespace Osd = OpenSubdiv::OPENSUBDIV_VERSION;

// N floats that OpenSubdiv's PrimvarRefiner can blend.
template <int N>
struct Blend {
    float v[N];
    void Clear() { std::fill(v, v + N, 0.0f); }
    void AddWithWeight(const Blend& s, float w) {
        for (int c = 0; c < N; ++c) v[c] += w * s.v[c];
    }
};

Osd::Sdc::SchemeType schemeType(SubdivisionScheme s) {
    switch (s) {
        case SubdivisionScheme::Loop: return Osd::Sdc::SCHEME_LOOP;
        case SubdivisionScheme::Bilinear: return Osd::Sdc::SCHEME_BILINEAR;
        default: return Osd::Sdc::SCHEME_CATMARK;
    }
}

// The enumerator `token` names among `names` (tokens) / `values`; else a warning and `fallback`.
template <typename T, size_t N>
T fromToken(const std::string& attribute, const std::string& token, const char* const (&names)[N], const T (&values)[N],
            T fallback, std::vector<std::string>& warnings) {
    for (size_t i = 0; i < N; ++i)
        if (token == names[i]) return values[i];
    warnings.push_back(attribute + " '" + token + "' is not a valid token; using its fallback");
    return fallback;
}

Osd::Sdc::Options schemeOptions(const SubdivisionRules& rules, std::vector<std::string>& warnings) {
    using O = Osd::Sdc::Options;
    O options;
    options.SetVtxBoundaryInterpolation(
        fromToken("interpolateBoundary", rules.interpolateBoundary, {"none", "edgeOnly", "edgeAndCorner"},
                  {O::VTX_BOUNDARY_NONE, O::VTX_BOUNDARY_EDGE_ONLY, O::VTX_BOUNDARY_EDGE_AND_CORNER},
                  O::VTX_BOUNDARY_EDGE_AND_CORNER, warnings));
    options.SetFVarLinearInterpolation(fromToken(
        "faceVaryingLinearInterpolation", rules.faceVaryingLinearInterpolation,
        {"none", "cornersOnly", "cornersPlus1", "cornersPlus2", "boundaries", "all"},
        {O::FVAR_LINEAR_NONE, O::FVAR_LINEAR_CORNERS_ONLY, O::FVAR_LINEAR_CORNERS_PLUS1, O::FVAR_LINEAR_CORNERS_PLUS2,
         O::FVAR_LINEAR_BOUNDARIES, O::FVAR_LINEAR_ALL},
        O::FVAR_LINEAR_CORNERS_PLUS1, warnings));
    options.SetTriangleSubdivision(fromToken("triangleSubdivisionRule", rules.triangleSubdivisionRule,
                                             {"catmullClark", "smooth"}, {O::TRI_SUB_CATMARK, O::TRI_SUB_SMOOTH},
                                             O::TRI_SUB_CATMARK, warnings));
    return options;
}

uint64_t edgeKey(int a, int b) {
    return (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b));
}

// USD creases are chains of points with a sharpness per chain or per edge; Far wants sharp edges.
// Edges that are not edges of the mesh are left out with a warning (Far would only print one).
void sharpEdges(const MeshDescription& mesh, std::vector<int>& pairs, std::vector<float>& sharpness,
                std::vector<std::string>& warnings) {
    const SubdivisionRules& rules = mesh.subdivision;
    if (rules.creaseLengths.empty()) return;
    size_t chained = 0, edges = 0;
    for (int n : rules.creaseLengths) {
        chained += size_t(std::max(0, n));
        edges += size_t(std::max(0, n - 1));
    }
    bool perCrease = rules.creaseSharpnesses.size() == rules.creaseLengths.size();
    bool perEdge = rules.creaseSharpnesses.size() == edges;
    if (chained != rules.creaseIndices.size() || (!perCrease && !perEdge)) {
        warnings.push_back("creases ignored: creaseLengths cover " + std::to_string(chained) + " of " +
                           std::to_string(rules.creaseIndices.size()) + " creaseIndices, and creaseSharpnesses has " +
                           std::to_string(rules.creaseSharpnesses.size()) + " values for " +
                           std::to_string(rules.creaseLengths.size()) + " creases of " + std::to_string(edges) +
                           " edges");
        return;
    }
    std::unordered_set<uint64_t> meshEdges;
    size_t start = 0;
    for (int n : mesh.faceVertexCounts) {
        for (int k = 0; k < n; ++k)
            meshEdges.insert(edgeKey(mesh.faceVertexIndices[start + size_t(k)],
                                     mesh.faceVertexIndices[start + size_t((k + 1) % n)]));
        start += size_t(n);
    }
    size_t cursor = 0, edge = 0, notEdges = 0;
    for (size_t c = 0; c < rules.creaseLengths.size(); ++c) {
        int n = rules.creaseLengths[c];
        for (int k = 0; k + 1 < n; ++k, ++edge) {
            int a = rules.creaseIndices[cursor + size_t(k)], b = rules.creaseIndices[cursor + size_t(k) + 1];
            if (!meshEdges.count(edgeKey(a, b))) {
                ++notEdges;
                continue;
            }
            pairs.insert(pairs.end(), {a, b});
            sharpness.push_back(rules.creaseSharpnesses[perEdge ? edge : c]);
        }
        cursor += size_t(std::max(0, n));
    }
    if (notEdges) warnings.push_back(std::to_string(notEdges) + " crease edges are not edges of the mesh; ignored");
}

void sharpCorners(const MeshDescription& mesh, std::vector<int>& corners, std::vector<float>& sharpness,
                  std::vector<std::string>& warnings) {
    const SubdivisionRules& rules = mesh.subdivision;
    if (rules.cornerIndices.size() != rules.cornerSharpnesses.size()) {
        warnings.push_back("corners ignored: " + std::to_string(rules.cornerIndices.size()) + " cornerIndices but " +
                           std::to_string(rules.cornerSharpnesses.size()) + " cornerSharpnesses");
        return;
    }
    size_t bad = 0;
    for (size_t i = 0; i < rules.cornerIndices.size(); ++i) {
        int p = rules.cornerIndices[i];
        if (p < 0 || size_t(p) >= mesh.points.size()) {
            ++bad;
            continue;
        }
        corners.push_back(p);
        sharpness.push_back(rules.cornerSharpnesses[i]);
    }
    if (bad) warnings.push_back(std::to_string(bad) + " cornerIndices out of range; ignored");
}

}  // namespace

SubdivisionScheme subdivisionScheme(const std::string& token, std::vector<std::string>& warnings) {
    return fromToken("subdivisionScheme", token, {"none", "catmullClark", "loop", "bilinear"},
                     {SubdivisionScheme::None, SubdivisionScheme::CatmullClark, SubdivisionScheme::Loop,
                      SubdivisionScheme::Bilinear},
                     SubdivisionScheme::None, warnings);
}

std::optional<Polygons> refineSubdivision(const MeshDescription& mesh, SubdivisionScheme scheme,
                                          const std::vector<char>& hole, const std::optional<CheckedPrimvar>& uvs,
                                          std::vector<std::string>& warnings) {
    if (scheme == SubdivisionScheme::Loop)
        for (int n : mesh.faceVertexCounts)
            if (n != 3) {
                warnings.push_back("loop subdivision needs triangles only; rendering the control mesh");
                return std::nullopt;
            }
    Osd::Far::TopologyDescriptor desc;
    desc.numVertices = int(mesh.points.size());
    desc.numFaces = int(mesh.faceVertexCounts.size());
    desc.numVertsPerFace = mesh.faceVertexCounts.data();
    desc.vertIndicesPerFace = mesh.faceVertexIndices.data();
    std::vector<int> creasePairs, corners;
    std::vector<float> creaseSharpness, cornerSharpness;
    sharpEdges(mesh, creasePairs, creaseSharpness, warnings);
    sharpCorners(mesh, corners, cornerSharpness, warnings);
    desc.numCreases = int(creaseSharpness.size());
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseSharpness.data();
    desc.numCorners = int(corners.size());
    desc.cornerVertexIndices = corners.data();
    desc.cornerWeights = cornerSharpness.data();
    std::vector<int> holes;
    for (size_t f = 0; f < hole.size(); ++f)
        if (hole[f]) holes.push_back(int(f));
    desc.numHoles = int(holes.size());
    desc.holeIndices = holes.data();
    bool faceVaryingUvs = uvs && uvs->interpolation == Interpolation::FaceVarying;
    Osd::Far::TopologyDescriptor::FVarChannel channel;
    if (faceVaryingUvs) {
        channel.numValues = int(uvs->values.size() / 2);
        channel.valueIndices = uvs->index.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    using Factory = Osd::Far::TopologyRefinerFactory<Osd::Far::TopologyDescriptor>;
    std::unique_ptr<Osd::Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(schemeType(scheme), schemeOptions(mesh.subdivision, warnings))));
    if (!refiner) {
        warnings.push_back("OpenSubdiv rejected the topology; rendering the control mesh");
        return std::nullopt;
    }
    int level = std::min(mesh.refineLevel, kMaxRefineLevel);
    if (level < mesh.refineLevel)
        warnings.push_back("refine level " + std::to_string(mesh.refineLevel) + " lowered to " +
                           std::to_string(kMaxRefineLevel));
    refiner->RefineUniform(Osd::Far::TopologyRefiner::UniformOptions(level));

    // Every level's values one after the other, as Far numbers them.
    Osd::Far::PrimvarRefiner primvars(*refiner);
    std::vector<Blend<3>> points(size_t(refiner->GetNumVerticesTotal()));
    for (size_t i = 0; i < mesh.points.size(); ++i) points[i] = {{mesh.points[i].x, mesh.points[i].y, mesh.points[i].z}};
    std::vector<int> sourceFace(size_t(refiner->GetNumFacesTotal()));
    for (size_t f = 0; f < mesh.faceVertexCounts.size(); ++f) sourceFace[f] = int(f);
    bool pointUvs = uvs && (uvs->interpolation == Interpolation::Vertex || uvs->interpolation == Interpolation::Varying);
    std::vector<Blend<2>> uvValues;
    if (pointUvs || faceVaryingUvs) {
        size_t coarse = pointUvs ? mesh.points.size() : uvs->values.size() / 2;
        uvValues.resize(size_t(pointUvs ? refiner->GetNumVerticesTotal() : refiner->GetNumFVarValuesTotal(0)));
        for (size_t i = 0; i < coarse; ++i) {
            const float* v = pointUvs ? uvs->element(i) : uvs->values.data() + 2 * i;
            uvValues[i] = {{v[0], v[1]}};
        }
    }
    Blend<3>* pointSrc = points.data();
    int* faceSrc = sourceFace.data();
    Blend<2>* uvSrc = uvValues.data();
    for (int l = 1; l <= level; ++l) {
        const Osd::Far::TopologyLevel& parent = refiner->GetLevel(l - 1);
        Blend<3>* pointDst = pointSrc + parent.GetNumVertices();
        primvars.Interpolate(l, pointSrc, pointDst);
        pointSrc = pointDst;
        int* faceDst = faceSrc + parent.GetNumFaces();
        primvars.InterpolateFaceUniform(l, faceSrc, faceDst);
        faceSrc = faceDst;
        if (pointUvs) {
            Blend<2>* uvDst = uvSrc + parent.GetNumVertices();
            if (uvs->interpolation == Interpolation::Varying) primvars.InterpolateVarying(l, uvSrc, uvDst);
            else primvars.Interpolate(l, uvSrc, uvDst);
            uvSrc = uvDst;
        } else if (faceVaryingUvs) {
            Blend<2>* uvDst = uvSrc + parent.GetNumFVarValues(0);
            primvars.InterpolateFaceVarying(l, uvSrc, uvDst, 0);
            uvSrc = uvDst;
        }
    }

    const Osd::Far::TopologyLevel& last = refiner->GetLevel(level);
    Polygons out;
    for (int v = 0; v < last.GetNumVertices(); ++v) out.points.push_back(Vec3(pointSrc[v].v[0], pointSrc[v].v[1], pointSrc[v].v[2]));
    if (uvs) out.uvs.width = 2;
    out.uvs.perCorner = uvs && !pointUvs && uvs->interpolation != Interpolation::Constant;
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        Osd::Far::ConstIndexArray verts = last.GetFaceVertices(f);
        out.counts.push_back(verts.size());
        out.indices.insert(out.indices.end(), verts.begin(), verts.end());
        out.sourceFace.push_back(faceSrc[f]);
        out.rendered.push_back(!last.IsFaceHole(f));
        if (faceVaryingUvs) {
            for (int value : last.GetFaceFVarValues(f, 0)) out.uvs.values.insert(out.uvs.values.end(), uvSrc[value].v, uvSrc[value].v + 2);
        } else if (uvs && uvs->interpolation == Interpolation::Uniform) {
            const float* v = uvs->element(size_t(faceSrc[f]));
            for (int k = 0; k < verts.size(); ++k) out.uvs.values.insert(out.uvs.values.end(), v, v + 2);
        }
    }
    if (pointUvs)
        for (size_t v = 0; v < out.points.size(); ++v) out.uvs.values.insert(out.uvs.values.end(), uvSrc[v].v, uvSrc[v].v + 2);
    else if (uvs && uvs->interpolation == Interpolation::Constant)
        for (size_t v = 0; v < out.points.size(); ++v) out.uvs.values.insert(out.uvs.values.end(), uvs->element(0), uvs->element(0) + 2);
    return out;
}

}  // namespace gi
