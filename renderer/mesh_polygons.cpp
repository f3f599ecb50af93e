#include "renderer/mesh_polygons.h"

#include <algorithm>
#include <cmath>

namespace gi {

std::vector<char> usableFaces(const MeshDescription& mesh, std::vector<std::string>& warnings) {
    const std::vector<int>& counts = mesh.faceVertexCounts;
    const std::vector<int>& indices = mesh.faceVertexIndices;
    size_t faces = counts.size();
    std::vector<char> keep(faces, 1);
    size_t few = 0, pastEnd = 0, outOfRange = 0, nonFinite = 0;
    size_t start = 0;
    for (size_t f = 0; f < faces; ++f) {
        size_t n = size_t(counts[f]);
        size_t end = start + n;
        if (n < 3) few++;
        if (end > indices.size()) pastEnd++;
        if (n < 3 || end > indices.size()) {
            keep[f] = 0;
        } else {
            bool inRange = true, finite = true;
            for (size_t s = start; s < end; ++s) {
                int p = indices[s];
                if (p < 0 || size_t(p) >= mesh.points.size()) inRange = false;
                else if (!isFinite(mesh.points[size_t(p)])) finite = false;
            }
            if (!inRange) keep[f] = 0, ++outOfRange;
            else if (!finite) keep[f] = 0, ++nonFinite;
        }
        start = std::min(end, indices.size() + 1);  // past the end stays past the end
    }
    size_t total = 0;
    for (int n : counts) total += size_t(n);
    if (few) warnings.push_back(std::to_string(few) + " faces with fewer than 3 vertices dropped");
    if (total != indices.size())
        warnings.push_back("faceVertexCounts sum to " + std::to_string(total) + " but there are " +
                           std::to_string(indices.size()) + " faceVertexIndices; " +
                           (total > indices.size() ? std::to_string(pastEnd) + " faces past the end dropped"
                                    : std::string("the extra indices are ignored")));
    if (outOfRange)
        warnings.push_back(std::to_string(outOfRange) + " faces with out-of-range point indices (valid: 0.." +
                           std::to_string(int64_t(mesh.points.size()) - 1) + ") dropped");
    if (nonFinite) warnings.push_back(std::to_string(nonFinite) + " faces using NaN/Inf points dropped");
    return keep;
}

std::vector<int> faceOfSlots(const std::vector<int>& counts, size_t slots) {
    std::vector<int> face(slots, -1);
    size_t start = 0;
    for (size_t f = 0; f < counts.size() && start < slots; ++f) {
        size_t end = std::min(slots, start + size_t(std::max(0, counts[f])));
        std::fill(face.begin() + long(start), face.begin() + long(end), int(f));
        start = end;
    }
    return face;
}

PolygonAttribute expandPrimvar(const CheckedPrimvar& primvar, const std::vector<int>& faceOfSlot, size_t points) {
    PolygonAttribute out;
    out.width = primvar.width;
    auto append = [&](size_t element) {
        const float* v = primvar.element(element);
        out.values.insert(out.values.end(), v, v + primvar.width);
    };
    switch (primvar.interpolation) {
        case Interpolation::Constant:
            for (size_t p = 0; p < points; ++p) append(0);
            break;
        case Interpolation::Varying:  // per point on a polygon mesh
        case Interpolation::Vertex:
            for (size_t p = 0; p < points; ++p) append(p);
            break;
        case Interpolation::FaceVarying:
            out.perCorner = true;
            for (size_t s = 0; s < faceOfSlot.size(); ++s) append(s);
            break;
        case Interpolation::Uniform:
            out.perCorner = true;
            for (int f : faceOfSlot) append(size_t(std::max(0, f)));  // slots of no face are never used
            break;
    }
    return out;
}

void fanTriangles(const Polygons& polygons, std::vector<int>& slots, std::vector<int>& polygonOfTriangle) {
    int start = 0;
    for (size_t f = 0; f < polygons.counts.size(); ++f) {
        int n = polygons.counts[f];
        if (polygons.rendered[f])
            for (int k = 1; k + 1 < n; ++k) {
                int b = start + k, c = start + k + 1;
                if (polygons.leftHanded) std::swap(b, c);
                slots.insert(slots.end(), {start, b, c});
                polygonOfTriangle.push_back(int(f));
            }
        start += std::max(0, n);
    }
}

// Area-weighted normals of the rendered polygons' fan triangles, per point.
PolygonAttribute smoothNormals(const Polygons& polygons) {
    std::vector<int> slots, polygonOfTriangle;
    fanTriangles(polygons, slots, polygonOfTriangle);
    std::vector<Vec3> sum(polygons.points.size(), Vec3(0.0f));
    for (size_t t = 0; t + 2 < slots.size(); t += 3) {
        int a = polygons.indices[size_t(slots[t])], b = polygons.indices[size_t(slots[t + 1])],
            c = polygons.indices[size_t(slots[t + 2])];
        Vec3 face = cross(polygons.points[size_t(b)] - polygons.points[size_t(a)],
                          polygons.points[size_t(c)] - polygons.points[size_t(a)]);
        sum[size_t(a)] += face, sum[size_t(b)] += face, sum[size_t(c)] += face;
    }
    PolygonAttribute out;
    out.width = 3;
    out.values.reserve(sum.size() * 3);
    for (const Vec3& s : sum) {
        float len = length(s);
        Vec3 n = len > 0 && std::isfinite(len) ? s / len : Vec3(0, 0, 1);  // unused points only
        out.values.insert(out.values.end(), {n.x, n.y, n.z});
    }
    return out;
}

namespace {

void appendValue(const PolygonAttribute& a, size_t slot, size_t point, std::vector<Vec3>& out) {
    const float* v = a.values.data() + (a.perCorner ? slot : point) * 3;
    out.push_back(Vec3(v[0], v[1], v[2]));
}
void appendValue(const PolygonAttribute& a, size_t slot, size_t point, std::vector<Vec2>& out) {
    const float* v = a.values.data() + (a.perCorner ? slot : point) * 2;
    out.push_back(Vec2(v[0], v[1]));
}

}  // namespace

TriangleMesh triangulate(const Polygons& polygons) {
    std::vector<int> slots, polygonOfTriangle;
    fanTriangles(polygons, slots, polygonOfTriangle);
    TriangleMesh mesh;
    for (int f : polygonOfTriangle) mesh.faces.push_back(polygons.sourceFace[size_t(f)]);
    bool split = (polygons.normals.present() && polygons.normals.perCorner) ||
                 (polygons.uvs.present() && polygons.uvs.perCorner);
    // Vertex v of the output: per corner when split, else per used point in point order.
    std::vector<size_t> vertexSlot, vertexPoint;
    if (split) {
        for (size_t k = 0; k < slots.size(); ++k) {
            vertexSlot.push_back(size_t(slots[k]));
            vertexPoint.push_back(size_t(polygons.indices[size_t(slots[k])]));
            mesh.indices.push_back(uint32_t(k));
        }
    } else {
        std::vector<int64_t> remap(polygons.points.size(), -1);
        for (int s : slots) remap[size_t(polygons.indices[size_t(s)])] = 0;
        for (size_t p = 0; p < remap.size(); ++p)
            if (remap[p] == 0) {
                remap[p] = int64_t(vertexPoint.size());
                vertexPoint.push_back(p);
                vertexSlot.push_back(0);  // per-point attributes only: no slot is read
            }
        for (int s : slots) mesh.indices.push_back(uint32_t(remap[size_t(polygons.indices[size_t(s)])]));
    }
    for (size_t v = 0; v < vertexPoint.size(); ++v) {
        mesh.positions.push_back(polygons.points[vertexPoint[v]]);
        if (polygons.normals.present()) appendValue(polygons.normals, vertexSlot[v], vertexPoint[v], mesh.normals);
        if (polygons.uvs.present()) appendValue(polygons.uvs, vertexSlot[v], vertexPoint[v], mesh.uvs);
    }
    return mesh;
}

}  // namespace gi
