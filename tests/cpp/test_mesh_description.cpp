// The mesh rules both hosts share (renderer/mesh_description.h): holes, orientation, primvar
// interpolations (indexed or not), OpenSubdiv refinement with creases and corners, and a cage with
// a warning when a subdivision mesh cannot be refined.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "renderer/mesh_description.h"
#include "renderer/mesh_pieces.h"

using namespace gi;

namespace {

// A cube of side 2 centred at the origin, outward-facing counter-clockwise quads. Point i is at
// (x, y, z) = (bit 0, bit 1, bit 2 of i) mapped {0, 1} -> {-1, +1}.
MeshDescription cube(int refineLevel) {
    MeshDescription m;
    for (int i = 0; i < 8; ++i) m.points.push_back(Vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
    m.faceVertexCounts = {4, 4, 4, 4, 4, 4};
    m.faceVertexIndices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
    m.refineLevel = refineLevel;
    return m;
}

// A width x height grid of unit quads in the z = 0 plane, counter-clockwise seen from +z.
MeshDescription grid(int width, int height) {
    MeshDescription m;
    for (int y = 0; y <= height; ++y)
        for (int x = 0; x <= width; ++x) m.points.push_back(Vec3(float(x), float(y), 0));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            int a = y * (width + 1) + x;
            m.faceVertexCounts.push_back(4);
            m.faceVertexIndices.insert(m.faceVertexIndices.end(), {a, a + 1, a + width + 2, a + width + 1});
        }
    m.subdivision.scheme = "none";
    return m;
}

Vec3 triangleNormal(const TriangleMesh& m, size_t t) {
    Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
    return cross(b - a, c - a);
}

double area(const TriangleMesh& m) {
    double sum = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) sum += 0.5 * double(length(triangleNormal(m, t)));
    return sum;
}

// Enclosed volume by the divergence theorem (positive for outward-facing triangles).
double volume(const TriangleMesh& m) {
    double sum = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
        sum += double(dot(a, cross(b, c))) / 6.0;
    }
    return sum;
}

bool warned(const TessellatedMesh& t, const std::string& text) {
    for (const std::string& w : t.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

// The refined vertex at the centre of the cube's +z face, and the one on the +x+y+z diagonal.
float faceCentreZ(const TriangleMesh& m) {
    float z = -1;
    for (const Vec3& p : m.positions)
        if (std::fabs(p.x) < 1e-6f && std::fabs(p.y) < 1e-6f && p.z > 0) z = p.z;
    return z;
}
float cornerX(const TriangleMesh& m) {
    float x = -1;
    for (const Vec3& p : m.positions)
        if (p.x > 0 && std::fabs(p.x - p.y) < 1e-6f && std::fabs(p.x - p.z) < 1e-6f) x = p.x;
    return x;
}

}  // namespace

TEST(MeshDescription, HolesAreNotTriangulated) {
    MeshDescription m = grid(3, 1);
    m.holeIndices = {1};
    TessellatedMesh t = tessellate(m);
    ASSERT_EQ(t.mesh.triangleCount(), 4u);
    for (int f : t.mesh.faces) EXPECT_NE(f, 1);
    for (const Vec3& p : t.mesh.positions) EXPECT_FALSE(p.x > 1.0f && p.x < 2.0f);
    m.holeIndices = {7};
    EXPECT_TRUE(warned(tessellate(m), "holeIndices name no face"));
}

TEST(MeshDescription, HolesStayHolesWhenRefined) {
    // A 3x3 Catmull-Clark grid with its centre face a hole: every level-2 child of it is left out.
    MeshDescription m = grid(3, 3);
    m.subdivision.scheme = "catmullClark";
    m.refineLevel = 2;
    m.holeIndices = {4};
    TessellatedMesh t = tessellate(m);
    ASSERT_TRUE(t.refined);
    EXPECT_EQ(t.mesh.triangleCount(), 8u * 16u * 2u);  // 8 faces, 16 quads each, 2 triangles a quad
    for (int f : t.mesh.faces) EXPECT_NE(f, 4);
}

TEST(MeshDescription, LeftHandedReversesTheWinding) {
    for (bool left : {false, true}) {
        MeshDescription m = grid(1, 1);
        m.orientation = left ? "leftHanded" : "rightHanded";
        TriangleMesh tri = tessellate(m).mesh;
        ASSERT_EQ(tri.triangleCount(), 2u);
        for (size_t t = 0; t < 2; ++t) EXPECT_FLOAT_EQ(normalize(triangleNormal(tri, t)).z, left ? -1.0f : 1.0f);
    }
    // A refined cube authored clockwise (leftHanded) still faces out: positive volume, outward normals.
    MeshDescription m = cube(2);
    for (size_t f = 0; f < 6; ++f) std::swap(m.faceVertexIndices[4 * f + 1], m.faceVertexIndices[4 * f + 3]);
    m.orientation = "leftHanded";
    TriangleMesh tri = tessellate(m).mesh;
    EXPECT_GT(volume(tri), 2.0);
    for (size_t v = 0; v < tri.positions.size(); ++v) EXPECT_GT(dot(tri.normals[v], tri.positions[v]), 0.0f);
}

TEST(MeshDescription, IndexedFaceVaryingNormalsAreDeIndexedPerCorner) {
    MeshDescription m = grid(1, 1);
    m.normals = {"primvars:normals", {0, 0, 1, 0, 1, 0}, 3, "faceVarying", {0, 1, 0, 1}};
    TriangleMesh tri = tessellate(m).mesh;
    ASSERT_EQ(tri.positions.size(), 6u);  // one vertex per triangle corner
    ASSERT_EQ(tri.normals.size(), 6u);
    const int cornerOfVertex[6] = {0, 1, 2, 0, 2, 3};  // fans (0, 1, 2), (0, 2, 3)
    for (size_t v = 0; v < 6; ++v) {
        Vec3 expected = cornerOfVertex[v] % 2 == 0 ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
        EXPECT_EQ(tri.normals[v].y, expected.y) << v;
        EXPECT_EQ(tri.normals[v].z, expected.z) << v;
        EXPECT_EQ(tri.indices[v], uint32_t(v));
    }
    // A value no index names may be anything: the primvar is still used.
    m.normals.values.insert(m.normals.values.end(), {INFINITY, 0, 0});
    EXPECT_EQ(tessellate(m).mesh.normals.size(), 6u);
    m.normals.indices = {0, 1, 0, 2};  // now 2, the infinite value, is used
    EXPECT_TRUE(warned(tessellate(m), "NaN/Inf"));
    m.normals.indices = {0, 1, 0, 3};  // 3 names no value
    TessellatedMesh bad = tessellate(m);
    EXPECT_TRUE(warned(bad, "invalid indices"));
    EXPECT_TRUE(bad.mesh.normals.empty());
}

TEST(MeshDescription, EveryPrimvarInterpolation) {
    MeshDescription m = grid(2, 1);  // faces 0, 1; points 0..5
    m.uvs = {"primvars:st", {0.25f, 0.5f, 0.75f, 0.5f}, 2, "uniform", {}};
    TriangleMesh uniform = tessellate(m).mesh;
    ASSERT_EQ(uniform.uvs.size(), 12u);
    for (size_t v = 0; v < 12; ++v) EXPECT_EQ(uniform.uvs[v].x, uniform.faces[v / 3] == 0 ? 0.25f : 0.75f);

    m.uvs = {"primvars:st", {0.5f, 0.125f}, 2, "constant", {}};
    TriangleMesh constant = tessellate(m).mesh;
    ASSERT_EQ(constant.uvs.size(), 6u);  // shared points: constant values do not split corners
    for (const Vec2& uv : constant.uvs) EXPECT_EQ(uv.y, 0.125f);

    std::vector<float> perPoint;
    for (const Vec3& p : m.points) perPoint.insert(perPoint.end(), {p.x, p.y});
    for (const char* i : {"vertex", "varying"}) {
        m.uvs = {"primvars:st", perPoint, 2, i, {}};
        TriangleMesh tri = tessellate(m).mesh;
        ASSERT_EQ(tri.uvs.size(), tri.positions.size());
        for (size_t v = 0; v < tri.positions.size(); ++v) EXPECT_EQ(tri.uvs[v].x, tri.positions[v].x);
    }
    m.uvs = {"primvars:st", {0, 0, 1, 1}, 2, "vertex", {}};  // 2 values for 6 points
    TessellatedMesh tooFew = tessellate(m);
    EXPECT_TRUE(warned(tooFew, "'vertex' interpolation needs 6"));
    EXPECT_TRUE(tooFew.mesh.uvs.empty());
}

// Catmull-Clark on a cube converges to its limit surface. Analytic anchors: the centre of a face
// is a regular (valence-4) vertex from level 1 on, with limit z = 68/81 (the regular limit mask
// (16 v + 4 sum(edge neighbours) + sum(diagonal neighbours)) / 36 applied to the level-1 points),
// and by 4-fold symmetry its distance to it shrinks by the subdominant-but-one eigenvalue 1/4 per
// level; a cube corner's limit point is (1/2, 1/2, 1/2) (the valence-3 mask (9 v + 4 sum e + sum f)
// / 24). The limit solid is convex and contains the convex hull of its limit points: the unit cube
// of the corners with a pyramid of height 68/81 - 1/2 on each face, volume 1 + 2 (68/81 - 1/2) and
// area 24 * (1/2) * sqrt(1/4 + (68/81 - 1/2)^2); it lies inside every refined mesh (convex hull
// property), so each level's volume and area are upper bounds and fall towards it.
TEST(MeshDescription, SubdividedCubeConvergesToItsLimitSurface) {
    const double zLimit = 68.0 / 81.0, h = zLimit - 0.5;
    const double innerVolume = 1 + 2 * h, innerArea = 12 * std::sqrt(0.25 + h * h);
    double previousVolume = 8, previousArea = 24, previousStep = 0, previousZError = 0;
    for (int level = 1; level <= 5; ++level) {
        TessellatedMesh t = tessellate(cube(level));
        ASSERT_TRUE(t.refined);
        EXPECT_TRUE(t.warnings.empty());
        ASSERT_EQ(t.mesh.triangleCount(), size_t(6 * 2) << (2 * level));
        double v = volume(t.mesh), a = area(t.mesh);
        EXPECT_LT(v, previousVolume);
        EXPECT_LT(a, previousArea);
        EXPECT_GT(v, innerVolume);
        EXPECT_GT(a, innerArea);
        // A C2 surface's control mesh converges quadratically: each step a quarter of the last.
        double step = previousVolume - v;
        if (level >= 3) EXPECT_NEAR(step / previousStep, 0.25, 0.05) << level;
        double zError = faceCentreZ(t.mesh) - zLimit;
        EXPECT_GT(zError, 0);
        if (level >= 2) EXPECT_NEAR(zError / previousZError, 0.25, 0.01) << level;
        float corner = cornerX(t.mesh);
        EXPECT_GT(corner, 0.5f);
        EXPECT_LT(corner, level == 1 ? 5.0f / 9.0f + 1e-6f : 0.51f);  // 5/9: the level-1 vertex point
        previousVolume = v, previousArea = a, previousStep = step, previousZError = zError;
    }
    EXPECT_NEAR(cornerX(tessellate(cube(5)).mesh), 0.5f, 1e-4f);
    // Normals of the refined surface point away from the centre (they are computed, not authored).
    TriangleMesh m = tessellate(cube(3)).mesh;
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (size_t v = 0; v < m.positions.size(); ++v) EXPECT_GT(dot(m.normals[v], normalize(m.positions[v])), 0.5f);
}

TEST(MeshDescription, CreasesAndCornersStaySharp) {
    // The four edges round the +z face (points 4, 5, 7, 6) infinitely sharp: the face keeps its
    // points at z = 1 (its limit is a plane patch) and meets the sides along a crease.
    MeshDescription creased = cube(3);
    creased.subdivision.creaseIndices = {4, 5, 7, 6, 4};
    creased.subdivision.creaseLengths = {5};
    creased.subdivision.creaseSharpnesses = {10};
    TriangleMesh c = tessellate(creased).mesh;
    float top = -1;
    size_t onTop = 0;
    for (const Vec3& p : c.positions) top = std::max(top, p.z), onTop += p.z > 1 - 1e-6f;
    EXPECT_FLOAT_EQ(top, 1.0f);
    EXPECT_GT(onTop, 50u);  // the top face's 9x9 level-3 points, less its rounded rim
    EXPECT_LT(faceCentreZ(tessellate(cube(3)).mesh), 0.86f);  // smooth: the centre sinks to ~0.849
    // Across the crease the surface folds: the triangles touching the rim of the flat top are
    // either flat (normal +z) or steep (more than 45 degrees from +z), none in between.
    size_t steep = 0, between = 0;
    for (size_t t = 0; t < c.triangleCount(); ++t) {
        bool touchesTop = false;
        for (int k = 0; k < 3; ++k) touchesTop |= c.positions[c.indices[3 * t + k]].z > 1 - 1e-6f;
        if (!touchesTop) continue;
        float nz = normalize(triangleNormal(c, t)).z;
        if (nz < 0.999f && nz > 0.7071f) ++between;
        if (nz <= 0.7071f) ++steep;
    }
    EXPECT_GT(steep, 20u);
    EXPECT_EQ(between, 0u);
    // Per-edge sharpness (one value per crease edge) reads the same.
    creased.subdivision.creaseSharpnesses = {10, 10, 10, 10};
    EXPECT_FLOAT_EQ(faceCentreZ(tessellate(creased).mesh), 1.0f);
    creased.subdivision.creaseSharpnesses = {10, 10};
    EXPECT_TRUE(warned(tessellate(creased), "creases ignored"));

    // An infinitely sharp corner at point 7 = (1, 1, 1): the surface passes through it.
    MeshDescription cornered = cube(3);
    cornered.subdivision.cornerIndices = {7};
    cornered.subdivision.cornerSharpnesses = {10};
    EXPECT_FLOAT_EQ(cornerX(tessellate(cornered).mesh), 1.0f);
    EXPECT_LT(cornerX(tessellate(cube(3)).mesh), 0.51f);
}

TEST(MeshDescription, BadTopologyWarnsAndRendersTheCage) {
    MeshDescription m = cube(2);
    m.faceVertexIndices[3] = 42;  // face 0 names a point that does not exist
    TessellatedMesh t = tessellate(m);
    EXPECT_FALSE(t.refined);
    EXPECT_TRUE(warned(t, "out-of-range point indices"));
    EXPECT_TRUE(warned(t, "rendering the control mesh"));
    EXPECT_EQ(t.mesh.triangleCount(), 10u);  // the five valid quads of the cage

    MeshDescription loop = cube(2);
    loop.subdivision.scheme = "loop";  // loop needs triangles
    TessellatedMesh l = tessellate(loop);
    EXPECT_FALSE(l.refined);
    EXPECT_TRUE(warned(l, "loop subdivision needs triangles"));
    EXPECT_EQ(l.mesh.triangleCount(), 12u);

    MeshDescription unknown = cube(2);
    unknown.subdivision.scheme = "catmullclark";  // misspelt: a polygon mesh, with a warning
    unknown.orientation = "left";
    TessellatedMesh u = tessellate(unknown);
    EXPECT_FALSE(u.refined);
    EXPECT_TRUE(warned(u, "subdivisionScheme 'catmullclark' is not a valid token"));
    EXPECT_TRUE(warned(u, "orientation 'left'"));
    EXPECT_DOUBLE_EQ(volume(u.mesh), 8.0);

    MeshDescription nothing;
    EXPECT_TRUE(warned(tessellate(nothing), "no points or no faces"));
}

TEST(MeshDescription, LevelZeroAndPolygonMeshesAreTheCage) {
    for (std::string s : {"catmullClark", "none"}) {
        MeshDescription m = cube(s == "none" ? 3 : 0);
        m.subdivision.scheme = s;
        TessellatedMesh t = tessellate(m);
        EXPECT_FALSE(t.refined);
        EXPECT_EQ(t.mesh.triangleCount(), 12u);
        EXPECT_DOUBLE_EQ(volume(t.mesh), 8.0);
    }
}

TEST(MeshDescription, PiecesByFaceKeepTheirTrianglesAndOnlyTheirVertices) {
    MeshDescription m = grid(3, 1);  // faces 0, 1, 2 left to right, shared points
    TriangleMesh whole = tessellate(m).mesh;
    std::vector<TriangleMesh> pieces = splitByFace(whole, {0, 1, 1}, 3);  // face 3 and piece 2: none
    ASSERT_EQ(pieces.size(), 3u);
    EXPECT_EQ(pieces[0].triangleCount(), 2u);
    EXPECT_EQ(pieces[0].positions.size(), 4u);  // face 0's four points only
    EXPECT_EQ(pieces[1].triangleCount(), 4u);
    EXPECT_EQ(pieces[1].positions.size(), 6u);
    EXPECT_EQ(pieces[2].triangleCount(), 0u);
    for (size_t t = 0; t < pieces[1].triangleCount(); ++t) {
        EXPECT_GE(pieces[1].faces[t], 1);
        for (int k = 0; k < 3; ++k) EXPECT_GE(pieces[1].positions[pieces[1].indices[3 * t + k]].x, 1.0f);
    }
    // Winding and positions survive the cut.
    for (size_t t = 0; t < pieces[0].triangleCount(); ++t) EXPECT_GT(triangleNormal(pieces[0], t).z, 0.0f);
}

TEST(MeshDescription, UvsAreRefinedWithTheSurface) {
    // A 2x2 Catmull-Clark grid with indexed face-varying uvs: each point's grid (x, y) / 2, the
    // centre's moved to (0.7, 0.5) so that the uvs are not linear. With linear face-varying
    // interpolation everywhere ("all") each refined corner's uv is bilinear in its coarse face's
    // corners: at level 2 every uv is one of those faces' bilinear values at quarter parameters.
    MeshDescription m = grid(2, 2);
    m.subdivision.scheme = "catmullClark";
    m.subdivision.faceVaryingLinearInterpolation = "all";
    m.refineLevel = 2;
    std::vector<float> values;
    for (const Vec3& p : m.points) values.insert(values.end(), {p.x / 2, p.y / 2});
    values[2 * 4] = 0.7f;  // point 4 is the centre (1, 1)
    m.uvs = {"primvars:st", values, 2, "faceVarying", m.faceVertexIndices};
    std::vector<Vec2> bilinear;
    for (size_t f = 0; f < 4; ++f) {
        Vec2 c[4];
        for (int k = 0; k < 4; ++k) {
            int p = m.faceVertexIndices[4 * f + size_t(k)];
            c[k] = Vec2(values[2 * size_t(p)], values[2 * size_t(p) + 1]);
        }
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; j <= 4; ++j) {
                float u = i / 4.0f, v = j / 4.0f;  // corners 0..3 at (0,0), (1,0), (1,1), (0,1)
                auto mix = [&](float a, float b, float cc, float d) {
                    return (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * cc + (1 - u) * v * d;
                };
                bilinear.push_back(Vec2(mix(c[0].x, c[1].x, c[2].x, c[3].x), mix(c[0].y, c[1].y, c[2].y, c[3].y)));
            }
    }
    auto allBilinear = [&](const TriangleMesh& t) {
        for (const Vec2& uv : t.uvs) {
            float nearest = 1;
            for (const Vec2& b : bilinear) nearest = std::min(nearest, std::max(std::fabs(uv.x - b.x), std::fabs(uv.y - b.y)));
            if (nearest > 1e-5f) return false;
        }
        return true;
    };
    TriangleMesh linear = tessellate(m).mesh;
    ASSERT_EQ(linear.uvs.size(), linear.positions.size());
    ASSERT_EQ(linear.triangleCount(), 4u * 16u * 2u);
    EXPECT_TRUE(allBilinear(linear));
    m.subdivision.faceVaryingLinearInterpolation = "cornersPlus1";  // smooth inside: not bilinear
    EXPECT_FALSE(allBilinear(tessellate(m).mesh));

    // Per-point uvs are refined like the points (the vertex rule, not the varying one's bilinear):
    // with uv = (x, y) / 2 of each control point, each refined uv is (x, y) / 2 of its refined
    // position. The centre point is moved so that the two rules differ.
    m.points[4] = Vec3(1.3f, 1.2f, 0);
    values.clear();
    for (const Vec3& p : m.points) values.insert(values.end(), {p.x / 2, p.y / 2});
    m.uvs = {"primvars:st", values, 2, "vertex", {}};
    TriangleMesh v = tessellate(m).mesh;
    ASSERT_EQ(v.uvs.size(), v.positions.size());
    for (size_t i = 0; i < v.uvs.size(); ++i) {
        EXPECT_NEAR(v.uvs[i].x, v.positions[i].x / 2, 1e-5f);
        EXPECT_NEAR(v.uvs[i].y, v.positions[i].y / 2, 1e-5f);
    }
}

TEST(MeshDescription, PerCreaseSharpnessesApplyToTheirOwnChains) {
    // Two closed chains: round the +z face (4-5-7-6-4) infinitely sharp, round the -z face
    // (0-1-3-2-0) smooth (sharpness 0). Each is read with its own sharpness: the +z face stays flat
    // at z = 1 (as in CreasesAndCornersStaySharp), the -z face sinks like the smooth cube's.
    MeshDescription m = cube(3);
    m.subdivision.creaseIndices = {4, 5, 7, 6, 4, 0, 1, 3, 2, 0};
    m.subdivision.creaseLengths = {5, 5};
    m.subdivision.creaseSharpnesses = {10, 0};
    TriangleMesh t = tessellate(m).mesh;
    float top = -1, bottom = 1;
    for (const Vec3& p : t.positions) top = std::max(top, p.z), bottom = std::min(bottom, p.z);
    EXPECT_FLOAT_EQ(faceCentreZ(t), 1.0f);
    EXPECT_FLOAT_EQ(top, 1.0f);
    EXPECT_GT(bottom, -0.86f);  // the smooth cube's face centre: -0.849 at level 3
}

TEST(MeshDescription, SubsetsOwnTheirFacesFirstComeFirstServed) {
    // 4 faces; /A takes 0 and 1 (1 twice, 7 out of range), /B wants 1 and 2 (1 is /A's), /C only
    // faces /A owns, /D nothing. A partition leaves face 3 in none.
    std::vector<FaceSubset> subsets = {{"/A", {0, 1, 1, 7}}, {"/B", {2, 1}}, {"/C", {0}}, {"/D", {}}};
    SubsetFaces s = assignSubsetFaces(4, subsets, "partition", "/Mesh");
    EXPECT_EQ(s.pieceOfFace, (std::vector<int>{1, 1, 2, 0}));
    EXPECT_EQ(s.ownsFaces, (std::vector<char>{1, 1, 0, 0}));
    auto said = [&](const std::string& subject, const std::string& text) {
        for (const SubsetWarning& w : s.warnings)
            if (w.subject == subject && w.message.find(text) != std::string::npos) return true;
        return false;
    };
    EXPECT_TRUE(said("/A", "1 face indices out of range (e.g. 7; /Mesh has 4 faces"));
    EXPECT_TRUE(said("/A", "1 faces listed more than once (e.g. 1)"));
    EXPECT_TRUE(said("/B", "1 faces (e.g. 1) are also in /A"));
    EXPECT_TRUE(said("/C", "are also in /A"));
    EXPECT_TRUE(said("/D", "has no face indices"));
    EXPECT_TRUE(said("/Mesh", "'partition' but 1 faces are in none"));
    EXPECT_EQ(s.warnings.size(), 6u);
}
