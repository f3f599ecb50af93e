// Small analytic scenes built in code for the C++ tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "renderer/render.h"
#include "renderer/scene.h"

namespace gi::test {

// Row-vector camera/light frame looking from `eye` along `forward` (USD: -Z is the view axis).
inline Mat4 lookAlong(Vec3 eye, Vec3 forward, Vec3 up = Vec3(0, 1, 0)) {
    Vec3 f = normalize(forward), r = normalize(cross(f, up)), u = cross(r, f);
    Mat4 m;
    Vec3 rows[4] = {r, u, -f, eye};
    for (int i = 0; i < 4; ++i) m.m[i][0] = rows[i].x, m.m[i][1] = rows[i].y, m.m[i][2] = rows[i].z;
    return m;
}

inline MaterialDesc lambert(Color albedo, Color emission = Color(0.0f)) {
    MaterialDesc m;
    m.name = "lambert";
    m.useSpecularWorkflow = true;
    m.specularColor = Color(0.0f);
    m.roughness = 1;
    m.diffuseColor = albedo;
    m.emissiveColor = emission;
    return m;
}

// A smooth dielectric (glass, IOR 1.5) whose transmission is tinted by `tint` (UsdPreviewSurface's
// diffuseColor, 0.18 unless authored).
inline MaterialDesc smoothGlass(Color tint) {
    MaterialDesc m;
    m.name = "glass";
    m.diffuseColor = tint;
    m.opacity = 0;
    m.roughness = 0;
    m.ior = 1.5f;
    return m;
}

// A UsdLux sphere light of the given radius and intensity centred at `center`.
inline LightDesc sphereLight(const char* name, Vec3 center, float radius, float intensity) {
    LightDesc l;
    l.name = name;
    l.kind = "sphere";
    l.radius = radius;
    l.intensity = intensity;
    l.transform.m[3][0] = center.x, l.transform.m[3][1] = center.y, l.transform.m[3][2] = center.z;
    return l;
}

// A quad p0..p3 (counter-clockwise seen from the side its normal points to).
inline int addQuad(Scene& s, const char* name, Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, int material) {
    return s.addMesh(name, {p0, p1, p2, p3}, {0, 1, 2, 0, 2, 3}, {}, {}, material, nullptr, true, -1);
}

// A 2 x 2 room of the given height on y = 0, |x|, |z| <= 1: its floor and four walls, facing in; no ceiling.
inline void addRoomWalls(Scene& s, float height, int floorMaterial, int wallMaterial) {
    const float h = height;
    addQuad(s, "/Floor", {-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, floorMaterial);
    addQuad(s, "/Back", {-1, 0, -1}, {1, 0, -1}, {1, h, -1}, {-1, h, -1}, wallMaterial);
    addQuad(s, "/Front", {-1, 0, 1}, {-1, h, 1}, {1, h, 1}, {1, 0, 1}, wallMaterial);
    addQuad(s, "/Left", {-1, 0, -1}, {-1, h, -1}, {-1, h, 1}, {-1, 0, 1}, wallMaterial);
    addQuad(s, "/Right", {1, 0, -1}, {1, 0, 1}, {1, h, 1}, {1, h, -1}, wallMaterial);
}

// A closed, subdivided icosahedron of the given radius around the origin.
inline void addIcosphere(Scene& s, float radius, int subdivisions, int material) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6,
                               7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10,
                               8, 6, 7, 9, 8, 1};
    for (int level = 0; level < subdivisions; ++level) {
        std::vector<uint32_t> next;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            v.push_back((v[a] + v[b]) * 0.5f);
            return uint32_t(v.size() - 1);
        };
        for (size_t i = 0; i < f.size(); i += 3) {
            uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(next);
    }
    for (Vec3& p : v) p = normalize(p) * radius;
    s.addMesh("/Furnace", std::move(v), std::move(f), {}, {}, material, nullptr, true, -1);
}

// A white-furnace scene: a closed icosphere of uniform albedo and emission, the camera at its
// centre. Inside, radiance is Le / (1 - albedo) everywhere (per channel).
inline void buildFurnace(Scene& s, Color albedo, Color Le) {
    addIcosphere(s, 1.0f, 3, s.addMaterial(lambert(albedo, Le)));
    CameraDesc cam;
    cam.clipNear = 1e-3f;
    s.setCamera(cam);
}

// Irradiance at the origin (normal n) from a one-sided polygon of radiance L: Lambert's formula
// E = L/2 * sum_i angle(r_i, r_i+1) * dot(n, normalize(r_i x r_i+1)).
inline double polygonIrradiance(const std::vector<Vec3>& corners, Vec3 n, double L) {
    double sum = 0;
    for (size_t i = 0; i < corners.size(); ++i) {
        Vec3 a = normalize(corners[i]), b = normalize(corners[(i + 1) % corners.size()]);
        double angle = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
        sum += angle * dot(n, normalize(cross(a, b)));
    }
    return L / 2 * std::fabs(sum);
}

inline CameraDesc lookingDown(Vec3 position, bool orthographic, float apertureTenths);

// A Lambertian floor (y = 0) under a one-sided 1 x 0.6 rect light of radiance L centred at
// (0.3, 1, 0.2) and emitting down, seen through a 1 mm orthographic window at the origin.
// Returns the radiance the floor reflects there, albedo / pi * E (Lambert's polygon formula).
inline double buildFloorUnderRectLight(Scene& scene, float albedo, float L) {
    int m = scene.addMaterial(lambert(Color(albedo)));
    addQuad(scene, "/Floor", {-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, m);
    LightDesc rect;
    rect.name = "/Rect";
    rect.kind = "rect";
    rect.width = 1.0f;
    rect.height = 0.6f;
    rect.intensity = L;
    // Rotated -90 degrees about X: its local -Z (the emitting side) is world -Y.
    rect.transform.m[1][1] = 0, rect.transform.m[1][2] = -1;
    rect.transform.m[2][1] = 1, rect.transform.m[2][2] = 0;
    rect.transform.m[3][0] = 0.3f, rect.transform.m[3][1] = 1, rect.transform.m[3][2] = 0.2f;
    scene.addLight(rect);
    scene.setCamera(lookingDown({0, 0.5f, 0}, true, 0.01f));
    // Corners in world space: x in 0.3 +- 0.5, z in 0.2 +- 0.3, y = 1.
    std::vector<Vec3> corners = {{-0.2f, 1, -0.1f}, {0.8f, 1, -0.1f}, {0.8f, 1, 0.5f}, {-0.2f, 1, 0.5f}};
    return albedo / kPi * polygonIrradiance(corners, Vec3(0, 1, 0), L);
}

inline CameraDesc lookingDown(Vec3 position, bool orthographic, float apertureTenths) {
    CameraDesc c;
    c.name = "/Camera";
    c.projection = orthographic ? "orthographic" : "perspective";
    c.horizontalAperture = c.verticalAperture = apertureTenths;
    c.clipNear = 1e-4f;
    // Rotate -90 degrees about X: the camera's -Z looks down -Y.
    c.transform.m[1][1] = 0, c.transform.m[1][2] = -1;
    c.transform.m[2][1] = 1, c.transform.m[2][2] = 0;
    c.transform.m[3][0] = position.x, c.transform.m[3][1] = position.y, c.transform.m[3][2] = position.z;
    return c;
}

struct Rendered {
    std::vector<float> rgb;
    RenderStats stats;
    std::vector<std::string> warnings;
};

// Renders a square image of the committed (or now committed) scene.
inline Rendered render(Scene& scene, const std::string& integrator, int size, int spp,
                       const std::map<std::string, double>& params = {}, uint32_t seed = 1, int threads = 0) {
    scene.commit();
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.spp = spp;
    settings.integrator = integrator;
    settings.seed = seed;
    settings.threads = threads;
    for (auto& [k, v] : params) settings.params.set(k, v);
    Renderer renderer(scene, settings);
    renderer.render();
    return {renderer.film().color(), renderer.stats(), scene.warnings()};
}

inline std::vector<float> renderImage(Scene& scene, const std::string& integrator, int size, int spp,
                                      const std::map<std::string, double>& params = {}, uint32_t seed = 1) {
    return render(scene, integrator, size, spp, params, seed).rgb;
}

// Names of an integrator's reflected parameters (empty if it is not registered).
inline std::vector<std::string> paramNames(const std::string& integrator) {
    std::vector<std::string> names;
    if (const IntegratorInfo* info = findIntegrator(integrator))
        for (const ParamInfo& p : info->params) names.push_back(p.name);
    return names;
}

inline bool hasParam(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

// The parameters of `params` that `integrator` takes: for a test that sets one budget ("every
// depth 1000") across integrators; the renderer refuses a name the integrator does not take.
inline std::map<std::string, double> takenBy(const std::string& integrator, const std::map<std::string, double>& params) {
    std::vector<std::string> names = paramNames(integrator);
    std::map<std::string, double> taken;
    for (const auto& [name, value] : params)
        if (hasParam(names, name)) taken[name] = value;
    return taken;
}

inline double channelMean(const std::vector<float>& rgb, int channel) {
    double sum = 0;
    for (size_t i = channel; i < rgb.size(); i += 3) sum += rgb[i];
    return sum / (rgb.size() / 3);
}

}  // namespace gi::test
