// Hydra mesh data to renderer triangles: triangulation (holes included), the primvars the
// renderer reads (normals, st), GeomSubset material pieces, and OpenSubdiv refinement for
// subdivision meshes at the host's refine level (no OpenSubdiv work for anything else).
#pragma once
#include <string>
#include <vector>

#include "pxr/base/vt/value.h"
#include "pxr/imaging/hd/enums.h"
#include "pxr/imaging/hd/meshTopology.h"
#include "pxr/pxr.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

struct HdGiPrimvar {
    VtValue value;
    HdInterpolation interpolation = HdInterpolationVertex;
    bool IsEmpty() const { return value.IsEmpty(); }
};

struct HdGiMeshInput {
    HdMeshTopology topology;
    VtValue points;
    HdGiPrimvar normals, st;
    int refineLevel = 0;
};

struct HdGiMeshPieces {
    std::vector<HdGiTriangleMesh> pieces;
    std::vector<SdfPath> materials;  // per piece; empty = the mesh's own binding
    std::vector<std::string> warnings;
    bool refined = false;
};

HdGiMeshPieces HdGiTriangulate(SdfPath const& id, HdGiMeshInput const& input);

PXR_NAMESPACE_CLOSE_SCOPE
