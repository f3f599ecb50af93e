// OpenSubdiv uniform refinement of a subdivision mesh (Catmull-Clark, Loop or bilinear) with its
// creases, corners, holes and boundary / face-varying rules, into polygons whose normals are the
// refined surface's (area-weighted over its faces, as Hydra computes them for refined meshes).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "renderer/mesh_description.h"
#include "renderer/mesh_polygons.h"
#include "renderer/mesh_primvars.h"

namespace gi {

// The highest refine level honoured (UsdImaging's complexity reaches 8 too); each level has about
// four times the faces of the one before.
constexpr int kMaxRefineLevel = 8;

// `mesh` refined mesh.refineLevel times; every face must be usable (see usableFaces). hole[f] marks
// the authored holes. nullopt, with a warning saying why, when OpenSubdiv cannot refine it.
std::optional<Polygons> refineSubdivision(const MeshDescription& mesh, const std::vector<char>& hole,
                                          const std::optional<CheckedPrimvar>& uvs,
                                          std::vector<std::string>& warnings);

}  // namespace gi
