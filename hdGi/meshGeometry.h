// Hydra mesh data to renderer triangles: the topology, subdivision tags and the primvars the
// renderer reads (normals, texture coordinates) become plain arrays for gi::tessellate (renderer/mesh_description.h),
// which holds the rules (holes, orientation, interpolations, OpenSubdiv refinement) for both hosts;
// GeomSubset material pieces are cut by gi::splitByFace.
#pragma once
#include <string>
#include <vector>

#include "pxr/base/tf/token.h"
#include "pxr/base/vt/types.h"
#include "pxr/base/vt/value.h"
#include "pxr/imaging/hd/enums.h"
#include "pxr/imaging/hd/meshTopology.h"
#include "pxr/pxr.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

struct HdGiPrimvar {
    VtValue value;
    HdInterpolation interpolation = HdInterpolationVertex;
    VtIntArray indices;  // an indexed primvar's indices (empty: value is per element)
    bool IsEmpty() const { return value.IsEmpty(); }
};

struct HdGiMeshInput {
    HdMeshTopology topology;
    VtValue points;
    HdGiPrimvar normals, st;  // st: the texture coordinates, whatever the primvar's name
    TfToken uvName;            // that name (HdGiMesh picks it by the materials' primvar readers)
    int refineLevel = 0;
};

struct HdGiMeshPieces {
    std::vector<HdGiTriangleMesh> pieces;
    std::vector<SdfPath> materials;  // per piece; empty = the mesh's own binding
    std::vector<std::string> names;  // per piece: the mesh's path, then each subset's (as `gi render` names them)
    std::vector<std::string> warnings;
    bool refined = false;
};

HdGiMeshPieces HdGiTriangulate(SdfPath const& id, HdGiMeshInput const& input);

PXR_NAMESPACE_CLOSE_SCOPE
