// A polygon or subdivision mesh as USD describes it (UsdGeomMesh's attributes as plain arrays) and
// the renderer's triangles made from it. Both hosts call tessellate(): the Hydra delegate with the
// arrays Hydra hands it, the `gi` loader through gi._core.tessellate_mesh. The rules live here once:
// which faces are usable, holes, orientation, primvar interpolation (indexed or not), and OpenSubdiv
// refinement with creases and corners.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/math.h"

namespace gi {

// Tokens are UsdGeomMesh's (and Hydra's, which are the same words); an unknown one is a warning
// and its attribute's fallback.

// A primvar's values, `width` floats each; `indices` (optional) index them per element, as USD's
// indexed primvars do. `name` is for warnings ("primvars:st").
struct MeshPrimvar {
    std::string name;
    std::vector<float> values;
    int width = 3;
    std::string interpolation = "vertex";  // constant, uniform, varying, vertex or faceVarying
    std::vector<int> indices;
    bool authored() const { return !values.empty(); }
};

struct SubdivisionRules {
    std::string scheme = "catmullClark";  // catmullClark, loop, bilinear or none (a polygon mesh)
    std::string interpolateBoundary = "edgeAndCorner";            // none, edgeOnly, edgeAndCorner
    std::string faceVaryingLinearInterpolation = "cornersPlus1";  // none, cornersOnly, cornersPlus1,
                                                                  // cornersPlus2, boundaries, all
    std::string triangleSubdivisionRule = "catmullClark";         // catmullClark or smooth
    // creaseIndices are chains of points, creaseLengths long each; creaseSharpnesses holds one
    // sharpness per chain or one per edge of the chains.
    std::vector<int> creaseIndices, creaseLengths;
    std::vector<float> creaseSharpnesses;
    std::vector<int> cornerIndices;
    std::vector<float> cornerSharpnesses;
};

struct MeshDescription {
    std::vector<Vec3> points;
    std::vector<int> faceVertexCounts, faceVertexIndices, holeIndices;
    std::string orientation = "rightHanded";  // or leftHanded
    MeshPrimvar normals;  // ignored on refined surfaces: their normals come from the refined mesh
    MeshPrimvar uvs;      // width 2
    SubdivisionRules subdivision;
    // Uniform refinement levels for subdivision schemes (0: the control cage, as UsdImaging's
    // lowest complexity); polygon meshes (scheme none) are never refined.
    int refineLevel = 0;
};

// Triangles over shared vertices; normals and uvs are per vertex or empty. faces[t] is the authored
// face triangle t came from (what GeomSubset indices name), refined triangles included.
struct TriangleMesh {
    std::vector<Vec3> positions, normals;
    std::vector<Vec2> uvs;
    std::vector<uint32_t> indices;
    std::vector<int> faces;
    size_t triangleCount() const { return indices.size() / 3; }
};

struct TessellatedMesh {
    TriangleMesh mesh;
    std::vector<std::string> warnings;  // each a sentence about the mesh (the caller names it)
    bool refined = false;               // OpenSubdiv refined it (false: the polygons themselves)
};

TessellatedMesh tessellate(const MeshDescription& description);

}  // namespace gi
