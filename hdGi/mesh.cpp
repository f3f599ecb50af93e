#include "mesh.h"

#include <algorithm>

#include "meshGeometry.h"
#include "pxr/imaging/hd/meshUtil.h"
#include "pxr/imaging/hd/timeSampleArray.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderParam.h"
#include "renderer/usd_shading.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiMesh::HdGiMesh(SdfPath const& id) : HdMesh(id) {}

HdDirtyBits HdGiMesh::GetInitialDirtyBitsMask() const { return HdGiGprimInitialDirtyBits(); }

void HdGiMesh::_InitRepr(TfToken const& reprToken, HdDirtyBits*) { HdGiInitRepr(_reprs, reprToken); }

namespace {

HdGiPrimvar FindPrimvar(HdRprim const& prim, HdSceneDelegate* delegate, TfToken const& name) {
    for (size_t i = 0; i < HdInterpolationCount; ++i) {
        auto interpolation = HdInterpolation(i);
        for (HdPrimvarDescriptor const& pv : prim.GetPrimvarDescriptors(delegate, interpolation))
            if (pv.name == name) {
                HdGiPrimvar out;
                out.interpolation = interpolation;
                // An indexed primvar keeps its indices: OpenSubdiv then sees which face-varying
                // corners share a value, as the gi loader hands them over.
                if (pv.indexed) out.value = delegate->GetIndexedPrimvar(prim.GetId(), name, &out.indices);
                else out.value = prim.GetPrimvar(delegate, name);
                return out;
            }
    }
    return HdGiPrimvar();
}

// The primvar holding the mesh's texture coordinates: the first its materials' (its own, then its
// GeomSubsets') UsdPrimvarReader_float2 nodes name that it has (renderer/usd_shading.h).
TfToken UvPrimvar(HdRprim const& prim, HdSceneDelegate* delegate, HdMeshTopology const& topology,
                  HdGiSceneStore const& store) {
    std::vector<std::string> wanted = store.ReaderVarnames(prim.GetMaterialId());
    for (HdGeomSubset const& subset : topology.GetGeomSubsets())
        for (std::string const& name : store.ReaderVarnames(subset.materialId))
            if (std::find(wanted.begin(), wanted.end(), name) == wanted.end()) wanted.push_back(name);
    if (wanted.empty()) return TfToken();
    std::vector<std::string> names;
    for (size_t i = 0; i < HdInterpolationCount; ++i)
        for (HdPrimvarDescriptor const& pv : prim.GetPrimvarDescriptors(delegate, HdInterpolation(i)))
            names.push_back(pv.name.GetString());
    return TfToken(gi::uvPrimvarOf(wanted, names));
}

// The mesh's points over the cameras' shutters (SamplePrimvar: the interval's ends and the
// authored samples between), each sample triangulated as the mesh is, so that its vertices match
// the pieces'. A sample whose triangulation differs (the point count changed) drops the motion.
void AddDeformation(HdSceneDelegate* delegate, SdfPath const& id, HdGiMeshInput const& input, HdGiRenderParam* param,
                    HdGiMeshPieces* pieces) {
    HdTimeSampleArray<VtValue, 4> samples;
    GfVec2f interval = param->SamplingInterval();
    delegate->SamplePrimvar(id, HdTokens->points, interval[0], interval[1], &samples);
    if (samples.count < 2) return;
    std::vector<HdGiMeshPieces> steps;
    for (size_t i = 0; i < samples.count; ++i) {
        HdGiMeshInput step = input;
        step.points = samples.values[i];
        steps.push_back(HdGiTriangulate(id, step));
        bool matches = steps.back().pieces.size() == pieces->pieces.size();
        for (size_t p = 0; matches && p < pieces->pieces.size(); ++p)
            matches = steps.back().pieces[p].points.size() == pieces->pieces[p].points.size();
        if (!matches) {
            param->Warn(id, "its points change in number during the shutter; rendered without deformation blur");
            return;
        }
    }
    for (size_t p = 0; p < pieces->pieces.size(); ++p) {
        HdGiTriangleMesh& piece = pieces->pieces[p];
        piece.pointTimes.assign(samples.times.begin(), samples.times.begin() + samples.count);
        for (HdGiMeshPieces& step : steps) piece.pointSamples.push_back(std::move(step.pieces[p].points));
    }
}

}  // namespace

void HdGiMesh::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits,
                    TfToken const&) {
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    SdfPath const& id = GetId();
    HdDirtyBits bits = *dirtyBits;
    bool wasVisible = IsVisible();
    if (HdChangeTracker::IsVisibilityDirty(bits, id)) _UpdateVisibility(delegate, dirtyBits);
    _UpdateInstancer(delegate, dirtyBits);
    bool changed = _state.Sync(*this, delegate, *param, bits) || wasVisible != IsVisible();

    bool geometryDirty = HdChangeTracker::IsTopologyDirty(bits, id) || HdChangeTracker::IsPrimvarDirty(bits, id, HdTokens->points) ||
                         HdChangeTracker::IsPrimvarDirty(bits, id, HdTokens->normals) ||
                         HdChangeTracker::IsSubdivTagsDirty(bits, id) || HdChangeTracker::IsDisplayStyleDirty(bits, id) ||
                         HdChangeTracker::IsAnyPrimvarDirty(bits, id) ||
                         (bits & (HdChangeTracker::DirtyMaterialId | HdGiDirtyUvPrimvar | HdGiDirtyShutter));
    if (geometryDirty) {
        HdGiMeshInput input;
        input.topology = GetMeshTopology(delegate);
        // The topology comes without its creases, corners and boundary rules: as in HdStMesh,
        // they are asked for apart.
        if (input.topology.GetScheme() != PxOsdOpenSubdivTokens->none)
            input.topology.SetSubdivTags(delegate->GetSubdivTags(id));
        input.points = delegate->Get(id, HdTokens->points);
        input.normals = FindPrimvar(*this, delegate, HdTokens->normals);
        input.uvName = UvPrimvar(*this, delegate, input.topology, param->EditScene());
        if (!input.uvName.IsEmpty()) input.st = FindPrimvar(*this, delegate, input.uvName);
        // Only subdivision meshes are refined; the host's complexity sets the level.
        input.refineLevel = input.topology.GetScheme() == PxOsdOpenSubdivTokens->none
                                ? 0
                                : delegate->GetDisplayStyle(id).refineLevel;
        HdGiMeshPieces pieces = HdGiTriangulate(id, input);
        for (std::string const& w : pieces.warnings) param->Warn(id, w);
        AddDeformation(delegate, id, input, param, &pieces);
        _pieces.clear();
        for (HdGiTriangleMesh& m : pieces.pieces) _pieces.push_back(std::make_shared<const HdGiTriangleMesh>(std::move(m)));
        _pieceMaterials = pieces.materials;
        _pieceNames = pieces.names;
        changed = true;
    }

    if (changed) {
        auto g = std::make_shared<HdGiGeometry>();
        g->pieces = _pieces;
        g->pieceMaterials = _pieceMaterials;
        g->pieceNames = _pieceNames;
        _state.Publish(*this, param, std::move(g));
    }
    *dirtyBits &= ~(HdChangeTracker::AllSceneDirtyBits | HdGiDirtyUvPrimvar | HdGiDirtyShutter);
}

void HdGiMesh::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->EditScene().Remove(GetId());
}

PXR_NAMESPACE_CLOSE_SCOPE
