#include "renderer/mesh_pieces.h"

#include <algorithm>
#include <cstdint>
#include <map>

namespace gi {

SubsetFaces assignSubsetFaces(size_t faceCount, const std::vector<FaceSubset>& subsets, const std::string& familyType,
                              const std::string& meshPath) {
    SubsetFaces out;
    out.pieceOfFace.assign(faceCount, 0);
    out.ownsFaces.assign(subsets.size(), 0);
    auto warn = [&](const std::string& subject, const std::string& message) { out.warnings.push_back({subject, message}); };
    for (size_t s = 0; s < subsets.size(); ++s) {
        const FaceSubset& subset = subsets[s];
        if (subset.indices.empty()) {
            warn(subset.path, "materialBind subset of " + meshPath + " has no face indices; ignored");
            continue;
        }
        std::vector<int> faces;
        size_t outOfRange = 0;
        int firstBad = 0;
        for (int f : subset.indices) {
            if (f >= 0 && size_t(f) < faceCount) faces.push_back(f);
            else if (outOfRange++ == 0) firstBad = f;
        }
        if (outOfRange)
            warn(subset.path, std::to_string(outOfRange) + " face indices out of range (e.g. " + std::to_string(firstBad) +
                                  "; " + meshPath + " has " + std::to_string(faceCount) + " faces, valid: 0.." +
                                  std::to_string(int64_t(faceCount) - 1) + "); those indices are ignored");
        std::sort(faces.begin(), faces.end());
        size_t repeated = 0;
        int firstRepeated = 0;
        for (size_t i = 0; i + 1 < faces.size(); ++i)
            if (faces[i] == faces[i + 1] && (i == 0 || faces[i - 1] != faces[i]) && repeated++ == 0) firstRepeated = faces[i];
        if (repeated)
            warn(subset.path, std::to_string(repeated) + " faces listed more than once (e.g. " +
                                  std::to_string(firstRepeated) + "); each is used once");
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
        // Faces an earlier subset owns stay its own; one warning per earlier subset.
        std::map<int, std::pair<size_t, int>> taken;  // earlier piece -> (faces, first face)
        size_t owned = 0;
        for (int f : faces) {
            int& owner = out.pieceOfFace[size_t(f)];
            if (owner != 0) {
                auto [entry, added] = taken.insert({owner, {0, f}});
                entry->second.first++;
                continue;
            }
            owner = int(s) + 1;
            ++owned;
        }
        for (const auto& [piece, count] : taken) {
            const std::string& earlier = subsets[size_t(piece - 1)].path;
            warn(subset.path, std::to_string(count.first) + " faces (e.g. " + std::to_string(count.second) +
                                  ") are also in " + earlier + ", but materialBind subsets must not overlap (family type '" +
                                  familyType + "'); they keep " + earlier + "'s material");
        }
        out.ownsFaces[s] = owned > 0;
    }
    if (familyType == "partition") {
        size_t none = size_t(std::count(out.pieceOfFace.begin(), out.pieceOfFace.end(), 0));
        if (none)
            warn(meshPath, "materialBind subsets are a 'partition' but " + std::to_string(none) +
                               " faces are in none of them; those keep the mesh's material");
    }
    return out;
}

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
