// A tessellated mesh cut into pieces by authored face, as GeomSubsets with their own materials cut
// it: each piece holds its triangles (in mesh order) over only the vertices they use.
#pragma once
#include <vector>

#include "renderer/mesh_description.h"

namespace gi {

// Piece p gets the triangles whose authored face f has pieceOfFace[f] == p (a face beyond
// pieceOfFace, or a piece number out of range: piece 0). Vertices keep their relative order.
std::vector<TriangleMesh> splitByFace(const TriangleMesh& mesh, const std::vector<int>& pieceOfFace, size_t pieces);

}  // namespace gi
