// OpenSubdiv uniform refinement of a subdivision mesh (Catmull-Clark, Loop or bilinear) with its
// creases, corners, holes and boundary / face-varying rules, into polygons (with uvs refined
// alike; the caller sets the orientation and computes normals).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "renderer/mesh_description.h"
#include "renderer/mesh_polygons.h"
#include "renderer/mesh_primvars.h"

namespace gi {

enum class SubdivisionScheme { None, CatmullClark, Loop, Bilinear };

// UsdGeomMesh's subdivisionScheme token; an unknown one is a warning and a polygon mesh.
SubdivisionScheme subdivisionScheme(const std::string& token, std::vector<std::string>& warnings);

// The highest refine level honoured (UsdImaging's complexity reaches 8 too); each level has about
// four times the faces of the one before.
constexpr int kMaxRefineLevel = 8;

// `mesh` refined mesh.refineLevel times; every face must be usable (see usableFaces). hole[f] marks
// the authored holes. nullopt, with a warning saying why, when OpenSubdiv cannot refine it.
std::optional<Polygons> refineSubdivision(const MeshDescription& mesh, SubdivisionScheme scheme,
                                          const std::vector<char>& hole, const std::optional<CheckedPrimvar>& uvs,
                                          std::vector<std::string>& warnings);

}  // namespace gi
