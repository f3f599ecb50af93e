// What a host (the Hydra delegate) relies on: a camera given as a projection matrix renders the
// same rays as the UsdGeomCamera it came from, the film reports which shape and instance each
// pixel sees, and a cancelled pass leaves the film untouched.
#include <gtest/gtest.h>

#include <atomic>

#include "renderer/camera.h"
#include "renderer/render.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {
// OpenGL-style perspective projection (row vectors, as Gf) for a window [l,r]x[b,t] at `near`.
Mat4 frustum(double l, double r, double b, double t, double n, double f) {
    Mat4 p;
    p.m[0][0] = 2 * n / (r - l);
    p.m[1][1] = 2 * n / (t - b);
    p.m[2][0] = (r + l) / (r - l);
    p.m[2][1] = (t + b) / (t - b);
    p.m[2][2] = -(f + n) / (f - n);
    p.m[2][3] = -1;
    p.m[3][2] = -2 * f * n / (f - n);
    p.m[3][3] = 0;
    return p;
}
// A white floor lit by an overhead delta sun, seen from above: returns the floor's shape id.
int litFloor(Scene& scene, int material) {
    int floor = addQuad(scene, "/Floor", {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, material);
    LightDesc sun;
    sun.kind = "distant";
    sun.angle = 0;
    scene.addLight(sun);
    scene.setCamera(lookingDown({0, 5, 0}, true, 40));
    return floor;
}

RenderSettings smallImage(int size, int spp) {
    RenderSettings settings;
    settings.width = settings.height = size;
    settings.spp = spp;
    return settings;
}
}  // namespace

TEST(Host, ProjectionMatrixCameraMatchesApertureCamera) {
    CameraDesc aperture;
    aperture.focalLength = 35;
    aperture.horizontalAperture = 36, aperture.verticalAperture = 24;
    aperture.horizontalApertureOffset = 2;
    aperture.transform.m[3][0] = 1, aperture.transform.m[3][2] = 5;
    Camera reference(aperture, 300, 200);

    // The same frustum as a matrix: the window at unit distance is aperture/focal, in tenths.
    double n = 0.1, halfW = 0.5 * 36 / 35, halfH = 0.5 * 24 / 35, shift = 2.0 / 35;
    Mat4 projection = frustum(n * (shift - halfW), n * (shift + halfW), -n * halfH, n * halfH, n, 100);
    CameraDesc host = aperture;
    host.useProjection = true;
    host.projectionMatrix = projection;
    host.horizontalAperture = host.verticalAperture = 1;  // must be ignored
    Camera fromMatrix(host, 300, 200);
    for (Vec2 pixel : {Vec2(0.5f, 0.5f), Vec2(150, 100), Vec2(299.5f, 10), Vec2(20, 199)}) {
        Ray a = reference.generateRay(pixel.x, pixel.y, Vec2(0.5f, 0.5f));
        Ray b = fromMatrix.generateRay(pixel.x, pixel.y, Vec2(0.5f, 0.5f));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a.o[c], b.o[c], 1e-6f);
            EXPECT_NEAR(a.d[c], b.d[c], 1e-6f);
        }
    }
}

TEST(Host, FilmReportsShapeAndInstanceIds) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.5f)));
    int floor = litFloor(scene, white);
    int prototype = scene.addPrototype("/Proto");
    int sphere = scene.addSphere("/Proto/Ball", Vec3(0.0f), 0.5f, white, nullptr, prototype);
    Mat4 at;
    at.m[3][1] = 1;
    int instance = scene.addInstance(prototype, at, "/Proto[0]");
    scene.commit();
    Renderer renderer(scene, smallImage(16, 2));
    renderer.render();
    std::vector<int32_t> shapes = renderer.film().shapeIds(), instances = renderer.film().instanceIds();
    // Centre: the instanced sphere; corner: the floor.
    size_t centre = 8 * 16 + 8, corner = 0;
    EXPECT_EQ(shapes[centre], sphere);
    EXPECT_EQ(instances[centre], instance);
    EXPECT_EQ(shapes[corner], floor);
    EXPECT_EQ(instances[corner], -1);
}

TEST(Host, CancelledPassLeavesTheFilmAsItWas) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.5f)));
    litFloor(scene, white);
    scene.commit();
    Renderer renderer(scene, smallImage(32, 4));
    ASSERT_TRUE(renderer.renderPass(0, 1));
    std::vector<float> before = renderer.film().color();
    std::atomic<bool> cancel{true};
    EXPECT_FALSE(renderer.renderPass(1, 1, &cancel));
    EXPECT_EQ(renderer.samplesTaken(), 1);
    EXPECT_EQ(renderer.film().color(), before);
    EXPECT_TRUE(renderer.renderPass(1, 1));
    EXPECT_EQ(renderer.samplesTaken(), 2);
}
