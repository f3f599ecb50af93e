// Polygons to the renderer's triangles: the checks that decide which authored faces are usable, fan
// triangulation in the mesh's orientation, and vertices shared by point unless an attribute
// varies per face corner. Used for the control mesh and for OpenSubdiv's refined faces alike.
#pragma once
#include <string>
#include <vector>

#include "renderer/mesh_description.h"
#include "renderer/mesh_primvars.h"

namespace gi {

// Values per point, or per slot of `indices` (a face corner) when perCorner; `width` floats each.
struct PolygonAttribute {
    std::vector<float> values;
    int width = 0;
    bool perCorner = false;
    bool present() const { return width > 0; }
};

struct Polygons {
    std::vector<Vec3> points;
    std::vector<int> counts, indices;
    std::vector<int> sourceFace;  // per polygon: the authored face it is (or was refined from)
    std::vector<char> rendered;   // per polygon: usable and not a hole
    bool leftHanded = false;
    PolygonAttribute normals, uvs;
};

// Which authored faces can be triangulated (at least 3 corners, within faceVertexIndices, point
// indices in range, finite points); warns once per kind of problem. counts must be non-negative.
std::vector<char> usableFaces(const MeshDescription& mesh, std::vector<std::string>& warnings);

// The face each slot of faceVertexIndices belongs to (-1 past the last face).
std::vector<int> faceOfSlots(const std::vector<int>& counts, size_t slots);

// A checked primvar of the authored mesh as per-point or per-corner values.
PolygonAttribute expandPrimvar(const CheckedPrimvar& primvar, const std::vector<int>& faceOfSlot, size_t points);

// Fan triangles (v0, vk, vk+1) of each rendered polygon, reversed for leftHanded meshes (the renderer
// takes counter-clockwise triangles): as slots of `indices`, and the polygon of each triangle.
void fanTriangles(const Polygons& polygons, std::vector<int>& slots, std::vector<int>& polygonOfTriangle);

// Per-point normals of a refined surface: the area-weighted normals of the rendered polygons' fan
// triangles (as Hydra computes them for refined meshes).
PolygonAttribute smoothNormals(const Polygons& polygons);

TriangleMesh triangulate(const Polygons& polygons);

}  // namespace gi
