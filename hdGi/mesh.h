// A mesh rprim: triangulated (or refined with OpenSubdiv at the host's refine level) when its
// topology, points, primvars or display style change; transform, material and instancing edits
// reuse the triangles.
#pragma once
#include <memory>
#include <vector>

#include "gprim.h"
#include "pxr/imaging/hd/mesh.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiMesh final : public HdMesh {
public:
    explicit HdGiMesh(SdfPath const& id);
    HdDirtyBits GetInitialDirtyBitsMask() const override;
    void Sync(HdSceneDelegate* sceneDelegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits,
              TfToken const& reprToken) override;
    void Finalize(HdRenderParam* renderParam) override;

protected:
    HdDirtyBits _PropagateDirtyBits(HdDirtyBits bits) const override { return bits; }
    void _InitRepr(TfToken const& reprToken, HdDirtyBits* dirtyBits) override;

private:
    HdGiGprimState _state;
    std::vector<std::shared_ptr<const HdGiTriangleMesh>> _pieces;
    std::vector<SdfPath> _pieceMaterials;
    std::vector<std::string> _pieceNames;
};

PXR_NAMESPACE_CLOSE_SCOPE
