// A tessellated mesh cut into pieces by authored face, as its materialBind GeomSubsets cut it:
// which subset owns each face (the rules for bad subsets included), then each piece's triangles (in
// mesh order) over only the vertices they use.
#pragma once
#include <string>
#include <vector>

#include "renderer/mesh_description.h"

namespace gi {

// A face subset: its prim path (for warnings) and its authored face indices.
struct FaceSubset {
    std::string path;
    std::vector<int> indices;
};

struct SubsetWarning {
    std::string subject;  // the prim the warning is about: a subset, or the mesh
    std::string message;
};

struct SubsetFaces {
    std::vector<int> pieceOfFace;  // 0: the mesh's own material; i + 1: subsets[i]
    std::vector<char> ownsFaces;   // per subset: it owns at least one face (else it makes no piece)
    std::vector<SubsetWarning> warnings;
};

// Which subset owns each of the mesh's faceCount faces: valid indices only, each once, a face
// claimed by several subsets going to the first (materialBind subsets must not overlap). Warns,
// naming the subset, about empty subsets, out-of-range or repeated indices and overlaps, and, for a
// "partition" family, naming the mesh, about faces in none. familyType: UsdGeom's token, for the
// warning ("" when the host does not know it).
SubsetFaces assignSubsetFaces(size_t faceCount, const std::vector<FaceSubset>& subsets, const std::string& familyType,
                              const std::string& meshPath);

// Piece p gets the triangles whose authored face f has pieceOfFace[f] == p (a face beyond
// pieceOfFace, or a piece number out of range: piece 0). Vertices keep their relative order.
std::vector<TriangleMesh> splitByFace(const TriangleMesh& mesh, const std::vector<int>& pieceOfFace, size_t pieces);

}  // namespace gi
