#include "renderer/mesh_pieces.h"

#include <cstdint>

namespace gi {

std::vector<TriangleMesh> splitByFace(const TriangleMesh& mesh, const std::vector<int>& pieceOfFace, size_t pieces) {
    std::vector<TriangleMesh> out(pieces);
    if (pieces == 0) return out;
    size_t triangles = mesh.triangleCount();
    std::vector<size_t> pieceOfTriangle(triangles, 0);
    for (size_t t = 0; t < triangles; ++t) {
        int f = mesh.faces[t];
        int p = f >= 0 && size_t(f) < pieceOfFace.size() ? pieceOfFace[size_t(f)] : 0;
        pieceOfTriangle[t] = p >= 0 && size_t(p) < pieces ? size_t(p) : 0;
    }
    for (size_t p = 0; p < pieces; ++p) {
        TriangleMesh& piece = out[p];
        std::vector<int64_t> remap(mesh.positions.size(), -1);
        for (size_t t = 0; t < triangles; ++t)
            if (pieceOfTriangle[t] == p)
                for (int k = 0; k < 3; ++k) remap[mesh.indices[3 * t + size_t(k)]] = 0;
        for (size_t v = 0; v < remap.size(); ++v) {
            if (remap[v] < 0) continue;
            remap[v] = int64_t(piece.positions.size());
            piece.positions.push_back(mesh.positions[v]);
            if (!mesh.normals.empty()) piece.normals.push_back(mesh.normals[v]);
            if (!mesh.uvs.empty()) piece.uvs.push_back(mesh.uvs[v]);
        }
        for (size_t t = 0; t < triangles; ++t) {
            if (pieceOfTriangle[t] != p) continue;
            for (int k = 0; k < 3; ++k) piece.indices.push_back(uint32_t(remap[mesh.indices[3 * t + size_t(k)]]));
            piece.faces.push_back(mesh.faces[t]);
        }
    }
    return out;
}

}  // namespace gi
