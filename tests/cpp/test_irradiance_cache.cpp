// Irradiance caching and its adaptive refinement (thesis 2.4.5, 3.3.1, 3.3.2): degenerate
// records, the gradients, the accuracy parameter, determinism across thread counts, and
// plausibility against the path tracer. (The white furnace is in test_integrators.cpp.)
#include <gtest/gtest.h>

#include <cstdio>

#include "renderer/integrators/irradiance_cache_integrator.h"
#include "renderer/integrators/progressive_fill.h"
#include "renderer/integrators/record_outliers.h"
#include "indirect_error.h"
#include "scenes.h"

using namespace gi;
using namespace gi::test;

namespace {

void addDistantLight(Scene& scene, Vec3 direction, float intensity) {
    LightDesc sun;
    sun.name = "/Sun";
    sun.kind = "distant";
    sun.angle = 0;
    sun.intensity = intensity;
    Vec3 up = std::fabs(normalize(direction).y) > 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    sun.transform = lookAlong(Vec3(0.0f), direction, up);
    scene.addLight(sun);
}

// Two perpendicular quads meeting at the line x = y = 0 (a floor and a wall), lit by a sun.
void buildCorner(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.8f)));
    int red = scene.addMaterial(lambert(Color(0.8f, 0.2f, 0.2f)));
    addQuad(scene, "/Floor", {0, 0, -1}, {0, 0, 1}, {2, 0, 1}, {2, 0, -1}, white);
    addQuad(scene, "/Wall", {0, 0, -1}, {0, 2, -1}, {0, 2, 1}, {0, 0, 1}, red);
    addDistantLight(scene, Vec3(-1, -1.5f, -0.4f), 3);
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 25;
    camera.transform = lookAlong(Vec3(2.6f, 1.6f, 2.2f), Vec3(-2.4f, -1.4f, -2.2f));
    scene.setCamera(camera);
}

// A unit Cornell box open towards +z, lit by a small sphere light under the ceiling that the
// camera does not see (its edges would dominate any error measure).
void buildCornellBox(Scene& scene) {
    int white = scene.addMaterial(lambert(Color(0.75f)));
    int red = scene.addMaterial(lambert(Color(0.75f, 0.15f, 0.15f)));
    int green = scene.addMaterial(lambert(Color(0.15f, 0.75f, 0.15f)));
    addQuad(scene, "/Floor", {0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, white);
    addQuad(scene, "/Ceiling", {0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}, white);
    addQuad(scene, "/Back", {0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}, white);
    addQuad(scene, "/Left", {0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}, red);
    addQuad(scene, "/Right", {1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}, green);
    addQuad(scene, "/Block", {0.25f, 0, 0.35f}, {0.25f, 0.45f, 0.35f}, {0.45f, 0.45f, 0.5f}, {0.45f, 0, 0.5f}, white);
    LightDesc bulb = sphereLight("/Light", {0.5f, 0.85f, 0.5f}, 0.05f, 35);
    bulb.visibleToCamera = false;
    scene.addLight(bulb);
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 35;
    camera.transform = lookAlong(Vec3(0.5f, 0.5f, 2.3f), Vec3(0, 0, -1));
    scene.setCamera(camera);
}


void printStatistics(const char* label, const RenderStats& stats) {
    std::printf("[ stats    ] %s: %.0f records (%.0f at render time), %.3f s computing records, %.3f s interpolating,"
                " preprocess %.3f s, render %.3f s, peak RSS %.1f MB\n",
                label, stats.integrator.at("records"), stats.integrator.at("renderTimeRecords"),
                stats.integrator.at("recordSeconds"), stats.integrator.at("interpolationSeconds"),
                stats.preprocessSeconds, stats.renderSeconds, stats.peakMemoryBytes / 1048576.0);
}

const char* const kCaches[] = {"irradianceCache", "adaptiveIrradianceCache"};

TEST(IrradianceCacheRegistry, BothIntegratorsReflectTheirParameters) {
    for (const char* name : kCaches) {
        ASSERT_NE(findIntegrator(name), nullptr) << name;
        std::vector<std::string> names = paramNames(name);
        for (const char* expected : {"paths", "pathDepth", "rayDepth", "accuracy", "minSpacing", "maxSpacing"})
            EXPECT_TRUE(hasParam(names, expected)) << name << " " << expected;
        bool adaptive = std::string(name) == "adaptiveIrradianceCache";
        EXPECT_EQ(hasParam(names, "threshold"), adaptive) << name;
    }
    ParamSet p;
    p.set("accuracy", -3);  // out of range: clamped
    EXPECT_GT(paramValue(*findIntegrator("irradianceCache"), p, "accuracy"), 0.0);
}

// --- records in degenerate places ---------------------------------------------------------

IrradianceRecord recordAt(const Scene& scene, Vec3 p, Vec3 n, int paths = 256, float footprint = 0.01f,
                          Vec3 towardsViewer = Vec3(0.0f)) {
    RecordSettings settings;
    settings.paths = paths;
    IrradianceRecordSampler sampler(settings);
    RecordSite site{p, n, n, lengthSquared(towardsViewer) > 0 ? towardsViewer : n, footprint};
    RayStats stats;
    return sampler.sample(scene, site, 1, IrradianceRecordSampler::streamKey(site), stats);
}

void expectFiniteRecord(const IrradianceRecord& r, const char* where) {
    EXPECT_TRUE(isFinite(r.E)) << where;
    EXPECT_GE(std::min(r.E.x, std::min(r.E.y, r.E.z)), 0.0f) << where;
    for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(isFinite(r.rotationGradient[c])) << where;
        EXPECT_TRUE(isFinite(r.translationGradient[c])) << where;
    }
    EXPECT_TRUE(std::isfinite(r.radius) && r.radius > 0) << where;
    EXPECT_TRUE(std::isfinite(r.sigma)) << where;
}

TEST(IrradianceRecord, DegenerateSitesStayFinite) {
    Scene scene;
    buildCorner(scene);
    scene.commit();
    // In the crease: the hemisphere rays towards the wall hit it at ~0 distance.
    IrradianceRecord nearCrease = recordAt(scene, Vec3(1e-4f, 0, 0), Vec3(0, 1, 0));
    expectFiniteRecord(nearCrease, "near the crease");
    EXPECT_NEAR(nearCrease.radius, 1.5f * 0.01f, 1e-6f) << "a crease record takes the smallest radius, R-";
    // Exactly on the crease line, on the floor's plane and the wall's: no ray may slip under
    // the wall, so the record sees what its neighbours see, and takes the smallest radius.
    IrradianceRecord onCrease = recordAt(scene, Vec3(0, 0, 0), Vec3(0, 1, 0), 256, 0.01f, normalize(Vec3(1, 1, 0)));
    expectFiniteRecord(onCrease, "on the crease");
    EXPECT_NEAR(onCrease.radius, 1.5f * 0.01f, 1e-6f);
    EXPECT_NEAR(luminance(onCrease.E), luminance(nearCrease.E), 0.1f * luminance(nearCrease.E));
    IrradianceRecord onWallEdge = recordAt(scene, Vec3(0, 0, 0.5f), Vec3(1, 0, 0), 256, 0.01f, normalize(Vec3(1, 1, 0)));
    IrradianceRecord nearWallEdge = recordAt(scene, Vec3(0, 1e-4f, 0.5f), Vec3(1, 0, 0));
    expectFiniteRecord(onWallEdge, "the wall's edge on the floor");
    EXPECT_NEAR(luminance(onWallEdge.E), luminance(nearWallEdge.E), 0.1f * luminance(nearWallEdge.E));
    // On the floor's outer edge, and beyond it (the hemisphere half over nothing).
    expectFiniteRecord(recordAt(scene, Vec3(2, 0, 0), Vec3(0, 1, 0)), "mesh edge");
    expectFiniteRecord(recordAt(scene, Vec3(2, 0, 1), Vec3(0, 1, 0)), "mesh corner");
    // A flipped normal: the hemisphere under the floor sees nothing.
    IrradianceRecord below = recordAt(scene, Vec3(1, 0, 0), Vec3(0, -1, 0));
    expectFiniteRecord(below, "flipped normal");
    EXPECT_EQ(luminance(below.E), 0.0f);
    // Light arriving only from near the horizon: tan(theta) must not blow up the rotation gradient.
    IrradianceRecord grazing = recordAt(scene, Vec3(1.9f, 0, 0), Vec3(0, 1, 0), 1024);
    expectFiniteRecord(grazing, "grazing");
    for (int c = 0; c < 3; ++c)
        EXPECT_LT(length(grazing.rotationGradient[c]), 50 * std::max(grazing.E[c], 1e-3f)) << "channel " << c;
}

TEST(IrradianceRecord, FlippedNormalFindsNoRecord) {
    IrradianceRecord r;
    r.p = Vec3(0.0f);
    r.n = Vec3(0, 1, 0);
    r.radius = 1;
    EXPECT_GT(r.weight(Vec3(0.1f, 0, 0), Vec3(0, 1, 0), 1), 0.0f);
    EXPECT_LE(r.weight(Vec3(0.1f, 0, 0), Vec3(0, -1, 0), 1), 0.0f);
    EXPECT_LE(r.weight(Vec3(0.1f, 0, 0), Vec3(0, -1, 0), 0.01f, true), 0.0f) << "not even at the lowest accuracy";
    EXPECT_LE(r.weight(Vec3(0.1f, 0, 0), normalize(Vec3(1, 0.2f, 0)), 1), 0.0f) << "past alpha+";
}

// --- gradients ----------------------------------------------------------------------------

// A floor next to a sunlit white wall: the floor gets no direct light (the sun grazes it), and
// its indirect irradiance falls off steeply away from the wall and rises as its normal tilts
// towards it.
TEST(IrradianceRecord, GradientsPredictNearbyRecords) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.8f)));
    addQuad(scene, "/Floor", {0, 0, -20}, {0, 0, 20}, {20, 0, 20}, {20, 0, -20}, white);
    addQuad(scene, "/Wall", {0, 0, -20}, {0, 1, -20}, {0, 1, 20}, {0, 0, 20}, white);
    addDistantLight(scene, Vec3(-1, 0, 0), 5);
    scene.commit();
    const int paths = 16384;
    const Vec3 p0(0.6f, 0, 0), up(0, 1, 0);
    IrradianceRecord base = recordAt(scene, p0, up, paths);
    ASSERT_GT(base.E.x, 0.01f);
    for (Vec3 offset : {Vec3(0.08f, 0, 0), Vec3(-0.08f, 0, 0), Vec3(0.05f, 0, 0.05f)}) {
        IrradianceRecord fresh = recordAt(scene, p0 + offset, up, paths);
        float with = std::fabs(base.extrapolate(p0 + offset, up).x - fresh.E.x);
        float without = std::fabs(base.E.x - fresh.E.x);
        std::printf("[ gradient ] translation by (%g, %g, %g): E %.4f -> %.4f, extrapolated %.4f\n", offset.x,
                    offset.y, offset.z, base.E.x, fresh.E.x, base.extrapolate(p0 + offset, up).x);
        EXPECT_LT(with, 0.5f * without) << "translation by (" << offset.x << ", " << offset.z << ")";
    }
    for (float degrees : {8.0f, -8.0f}) {
        float a = degrees * kPi / 180;
        Vec3 tilted(-std::sin(a), std::cos(a), 0);  // positive: towards the wall
        IrradianceRecord fresh = recordAt(scene, p0, tilted, paths);
        float with = std::fabs(base.extrapolate(p0, tilted).x - fresh.E.x);
        float without = std::fabs(base.E.x - fresh.E.x);
        std::printf("[ gradient ] rotation by %g degrees: E %.4f -> %.4f, extrapolated %.4f\n", degrees, base.E.x,
                    fresh.E.x, base.extrapolate(p0, tilted).x);
        EXPECT_LT(with, 0.5f * without) << "rotation by " << degrees << " degrees";
    }
}

// --- whole renders --------------------------------------------------------------------------

// The caches at 128 paths and 4 spp in the sunlit corner: finite, non-negative, no pixel brighter
// than the path-traced reference's brightest by more than its measured spread, and each channel's
// mean the reference's within its measured spread.
//
// Measured over seeds 1-10, each against its own reference (seed 100 + s), the ratios (mean, sd):
//   the brightest value over the reference's brightest: irradianceCache 1.0006 (0.027; worst
//     1.068), adaptiveIrradianceCache 0.995 (0.014): bound the larger mean + 4 sd, 1.11 (was 1.25);
//   each channel's mean over the reference's: irradianceCache red 0.9963 (0.0034), green and blue
//     0.9987 (0.0019); adaptive 0.9959 (0.0018), 0.9987 (0.0014) -- a 0.4% bias in red (the wall's
//     colour bleeding onto the floor, which the records interpolate) beside the reference's noise:
//     bounds the larger |1 - mean| + 4 sd, 1.7% in red, 0.9% in green and blue (was 5%).
TEST(IrradianceCacheRender, CornerIsFiniteAndPlausible) {
    const double maxOverReferenceMax = 1.11, channelBound[3] = {0.017, 0.009, 0.009};
    Scene scene;
    buildCorner(scene);
    Rendered reference = render(scene, "path", 32, 256, {{"pathDepth", 5}});
    float referenceMax = *std::max_element(reference.rgb.begin(), reference.rgb.end());
    for (const char* integrator : kCaches) {
        Rendered image = render(scene, integrator, 32, 4, {{"paths", 128}, {"pathDepth", 5}});
        printStatistics(integrator, image.stats);
        EXPECT_EQ(image.stats.nonFiniteSamples, 0u) << integrator;
        for (size_t i = 0; i < image.rgb.size(); ++i) {
            ASSERT_TRUE(std::isfinite(image.rgb[i])) << integrator << " value " << i;
            ASSERT_GE(image.rgb[i], 0.0f) << integrator << " value " << i;
            ASSERT_LE(image.rgb[i], maxOverReferenceMax * referenceMax) << integrator << " value " << i;
        }
        for (int c = 0; c < 3; ++c) {
            double ratio = channelMean(image.rgb, c) / channelMean(reference.rgb, c);
            std::printf("[ corner   ] %s channel %d: mean %.4f of the reference's\n", integrator, c, ratio);
            EXPECT_NEAR(ratio, 1.0, channelBound[c]) << integrator << " channel " << c;
        }
    }
}

// The records the accuracy controls: the plain cache's, and the adaptive cache's first fill.
// (The adaptive cache's refinement then adds records where the cache is discernibly wrong,
// more the looser the start, so its total is not monotone in the accuracy.)
TEST(IrradianceCacheRender, RecordsGrowAsAccuracyTightens) {
    for (const char* integrator : kCaches) {
        const char* counted = std::string(integrator) == "adaptiveIrradianceCache" ? "firstFillRecords" : "records";
        double previous = 0;
        for (double accuracy : {0.5, 1.0, 2.0, 4.0}) {
            Scene scene;
            buildCorner(scene);
            Rendered image = render(scene, integrator, 48, 1, {{"paths", 32}, {"accuracy", accuracy}});
            double records = image.stats.integrator.at(counted);
            std::printf("[ records  ] %s accuracy %g: %.0f %s\n", integrator, accuracy, records, counted);
            EXPECT_GT(records, previous) << integrator << " accuracy " << accuracy;
            previous = records;
        }
    }
}

TEST(IrradianceCacheRender, SameImageWhateverTheThreadCount) {
    for (const char* integrator : kCaches) {
        auto once = [&](int threads, uint32_t seed) {
            Scene scene;
            buildCorner(scene);
            return render(scene, integrator, 32, 2, {{"paths", 32}}, seed, threads).rgb;
        };
        std::vector<float> a = once(0, 5), b = once(0, 5), single = once(1, 5);
        EXPECT_EQ(a, b) << integrator;
        EXPECT_EQ(a, single) << integrator << ": one thread vs all";
        EXPECT_NE(a, once(0, 6)) << integrator << ": the seed must matter";
    }
}

// --- the Cornell box against a path-traced reference (issue 4) -----------------------------

class CornellBox : public ::testing::Test {
public:
    static constexpr int kSize = 48;
    // The reference at the caches' depth (unbounded: Russian roulette ends paths). Two independent
    // halves each of the path tracer and of `direct` give its indirect light and its own noise.
    static void SetUpTestSuite() {
        scene_ = new Scene;
        buildCornellBox(*scene_);
        makeReference(0);
    }
    static void makeReference(uint32_t seedBase) {
        Rendered halves[2] = {render(*scene_, "path", kSize, 512, {}, seedBase + 101), render(*scene_, "path", kSize, 512, {}, seedBase + 102)};
        std::vector<double> path[2] = {blockLuminance(halves[0].rgb, kSize), blockLuminance(halves[1].rgb, kSize)};
        std::vector<double> direct[2] = {directBlocks(seedBase + 103, 256), directBlocks(seedBase + 104, 256)};
        delete reference_;
        delete referenceImage_;
        reference_ = new IndirectReference(indirectReference(path, direct));
        referenceImage_ = new std::vector<float>(halves[0].rgb.size());
        for (size_t i = 0; i < referenceImage_->size(); ++i) (*referenceImage_)[i] = (halves[0].rgb[i] + halves[1].rgb[i]) / 2;
    }
    static void TearDownTestSuite() {
        delete referenceImage_;
        delete reference_;
        delete scene_;
    }
    // Enough light samples that the direct light's noise does not hide the cache's error in the
    // seams test; the convergence test subtracts it (the cache draws no samples).
    static Rendered renderCache(const char* integrator, double accuracy, int paths = 512, uint32_t seed = 1) {
        return render(*scene_, integrator, kSize, 16, {{"paths", paths}, {"accuracy", accuracy}, {"lightSamples", 4}}, seed);
    }
    static std::vector<double> directBlocks(uint32_t seed, int spp = 16) {
        return blockLuminance(render(*scene_, "direct", kSize, spp, {{"lightSamples", 4}}, seed).rgb, kSize);
    }
    static double luminanceAt(const std::vector<float>& rgb, int x, int y) {
        const float* p = &rgb[3 * (size_t(y) * kSize + x)];
        return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
    // Energy of the discrete Laplacian of the luminance error: seams and blotches, not bias.
    static double highFrequencyError(const std::vector<float>& rgb) {
        double sum = 0;
        auto error = [&](int x, int y) { return luminanceAt(rgb, x, y) - luminanceAt(*referenceImage_, x, y); };
        for (int y = 1; y + 1 < kSize; ++y)
            for (int x = 1; x + 1 < kSize; ++x) {
                double l = 4 * error(x, y) - error(x - 1, y) - error(x + 1, y) - error(x, y - 1) - error(x, y + 1);
                sum += l * l;
            }
        return sum / ((kSize - 2) * (kSize - 2));
    }
    static Scene* scene_;
    static IndirectReference* reference_;
    static std::vector<float>* referenceImage_;
};
Scene* CornellBox::scene_ = nullptr;
IndirectReference* CornellBox::reference_ = nullptr;
std::vector<float>* CornellBox::referenceImage_ = nullptr;

// The caches' indirect error (indirect_error.h) over `seeds` seeds from seedBase + 1: the plain and
// the adaptive cache at accuracies 0.25, 1 and 4 with 512 paths per record, and the plain cache at
// accuracy 4 with 128.
struct CacheFigures {
    double plain[3], adaptive[3], plain128, meanPlain, meanAdaptive;  // e^2 means; indirect means at accuracy 4
};
CacheFigures cacheFigures(uint32_t seedBase, int seeds) {
    CacheFigures f{};
    const double accuracies[3] = {0.25, 1.0, 4.0};
    for (int s = 1; s <= seeds; ++s) {
        uint32_t seed = seedBase + uint32_t(s);
        std::vector<double> direct = CornellBox::directBlocks(seed);
        auto error = [&](const char* integrator, double accuracy, int paths) {
            Rendered r = CornellBox::renderCache(integrator, accuracy, paths, seed);
            EXPECT_EQ(r.stats.nonFiniteSamples, 0u) << integrator;
            return indirectError(blockLuminance(r.rgb, CornellBox::kSize), direct, *CornellBox::reference_);
        };
        for (int a = 0; a < 3; ++a) {
            IndirectError plain = error("irradianceCache", accuracies[a], 512), adaptive = error("adaptiveIrradianceCache", accuracies[a], 512);
            f.plain[a] += plain.e2 / seeds;
            f.adaptive[a] += adaptive.e2 / seeds;
            if (a == 2) f.meanPlain += plain.mean / seeds, f.meanAdaptive += adaptive.mean / seeds;
        }
        f.plain128 += error("irradianceCache", 4, 128).e2 / seeds;
    }
    std::printf("[ cornell  ] indirect e^2 at accuracy 0.25, 1, 4: irradianceCache %.5f %.5f %.5f (128 paths: %.5f),"
                " adaptiveIrradianceCache %.5f %.5f %.5f; indirect means %.4f, %.4f of the reference's (its noise %.6f)\n",
                f.plain[0], f.plain[1], f.plain[2], f.plain128, f.adaptive[0], f.adaptive[1], f.adaptive[2], f.meanPlain,
                f.meanAdaptive, CornellBox::reference_->variance / (CornellBox::reference_->mean * CornellBox::reference_->mean));
    return f;
}

// The caches converge to the path tracer: their indirect error e^2 (indirect_error.h; over two
// seeds, against a reference at the caches' depth) falls as the accuracy tightens, at the tightest
// accuracy it falls as 1 / paths (the records' Monte Carlo noise) down to no floor, and the
// indirect light carries the reference's energy. The adaptive variant's error need not fall - its
// refinement already removes what a loose cache gets discernibly wrong - but at every accuracy it
// is no further from the reference than the plain cache's.
//
// Measured over ten independent runs of makeReference(1000 k) and cacheFigures(1000 k, 2), k = 1..10
// (mean, sd):
//   plain e^2 at accuracy 0.25, 1, 4: 0.00264 (0.00044), 0.00079 (0.00013), 0.00030 (0.000026);
//     each step's fall, 0.00185 (0.00041) and 0.00048 (0.00013), is 4.5 and 3.6 sd above zero;
//   e^2(4, 512 paths) - e^2(4, 128 paths) / 4: -0.000078 (0.000042) -- at most 0 if what is left
//     is record noise, which falls as 1 / paths; bound 4 sd, 0.00017. A constant bias b adds
//     3 b^2 / 4 to it: beyond 1.8% of the indirect light it fails;
//   indirect mean at accuracy 4 over the reference's: plain 1.0009 (0.0013), adaptive 1.0009
//     (0.0013), most of it the reference's noise: bound 4 sd, 0.0054;
//   adaptive e^2 - plain e^2 at accuracy 0.25, 1, 4: -0.0015 (0.00048), -0.00021 (0.00016),
//     +0.000004 (0.000036): bounds 4 sd, 0.0019, 0.00066, 0.00014.
// (The reference used to be path traced to depth 5 while the caches' records go on: the caches
// read 8.5% brighter than it, a constant bias the old RMSE-only test let pass.)
TEST_F(CornellBox, ErrorFallsAsAccuracyTightens) {
    CacheFigures f = cacheFigures(0, 2);
    EXPECT_GT(f.plain[0], f.plain[1]);
    EXPECT_GT(f.plain[1], f.plain[2]);
    EXPECT_LT(f.plain[2] - f.plain128 / 4, 0.00017) << "the records' noise must fall as 1 / paths";
    EXPECT_NEAR(f.meanPlain, 1.0, 0.0054);
    EXPECT_NEAR(f.meanAdaptive, 1.0, 0.0054);
    const double adaptiveBound[3] = {0.0019, 0.00066, 0.00014};
    for (int a = 0; a < 3; ++a) EXPECT_LT(f.adaptive[a] - f.plain[a], adaptiveBound[a]) << "accuracy index " << a;
}

// At (at least) equal record count the adaptive variant has no more seams than the plain cache
// beyond what one seed resolves: the high-frequency energy of its error exceeds the plain cache's
// by less than 4 sd of that difference.
//
// Measured over eight independent runs of makeReference(1000 k) and seed 1000 k + 1, k = 1..8: the
// adaptive cache at accuracy 1 (495-538 records) against the plain cache at 1.5 (598-603 records),
// energies 0.00060-0.00076; adaptive - plain -0.000013 (sd 0.000054), from -0.000074 to +0.00010
// (in three runs of eight the adaptive cache is not ahead): one seed does not tell them apart, so
// the bound is 4 sd, 0.00021 (it was "adaptive <= plain" on one seed, which passed by the seed's
// luck). What this resolves is a gross excess, a third of the energy: the refinement switched off
// (the adaptive cache its first fill, 416 records) reads 0.000621 and the refinement shrinking the
// wrong records 0.000632, against 0.000604 and the plain cache's 0.000666 -- within the noise (at the
// 1-sigma discernibility rule; 437 records and 0.000621 at the 2-sigma rule, adaptive_refinement.cpp). The
// adaptive cache's error against the plain cache's is bounded by ErrorFallsAsAccuracyTightens.
TEST_F(CornellBox, AdaptiveHasNoMoreDiscontinuities) {
    const double excessBound = 0.00021;
    Rendered adaptive = renderCache("adaptiveIrradianceCache", 1);
    double records = adaptive.stats.integrator.at("records");
    for (double accuracy : {1.0, 1.5, 2.0, 3.0, 4.0, 8.0}) {
        Rendered plain = renderCache("irradianceCache", accuracy);
        if (plain.stats.integrator.at("records") < records) continue;
        double adaptiveHf = highFrequencyError(adaptive.rgb), plainHf = highFrequencyError(plain.rgb);
        std::printf("[ seams    ] adaptive %.0f records: %.3g; plain (accuracy %g) %.0f records: %.3g\n", records,
                    adaptiveHf, accuracy, plain.stats.integrator.at("records"), plainHf);
        EXPECT_LT(adaptiveHf - plainHf, excessBound);
        return;
    }
    FAIL() << "no plain cache reached " << records << " records";
}

}  // namespace

// --- records robust to outliers (issue 15) --------------------------------------------------

bool same(const std::vector<Color>& a, const std::vector<Color>& b) {
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
    return a.size() == b.size();
}

TEST(RecordOutliers, ASunPathIsClampedAWindowIsNot) {
    // 108 samples of indirect light ~0.05, five of which see a window at 0.9: untouched.
    std::vector<Color> window(108, Color(0.05f));
    for (int i = 0; i < 5; ++i) window[size_t(i * 20)] = Color(0.9f);
    std::vector<Color> before = window;
    EXPECT_EQ(clampRecordOutliers(window), 0);
    EXPECT_TRUE(same(window, before));
    // One path through the glass to the sun, 10^5 times brighter: clamped so that it adds no
    // more than kOutlierContribution times the mean of the samples without the brightest 2%
    // (here the sun and one window sample) to the 108 samples' estimate - 4096 times that mean -,
    // hue kept; the rest untouched.
    std::vector<Color> sun = before;
    sun[7] = Color(2e4f, 1.8e4f, 1.6e4f);
    EXPECT_EQ(clampRecordOutliers(sun), 1);
    double kept = -luminance(Color(0.9f));
    for (size_t i = 0; i < sun.size(); ++i)
        if (i != 7) kept += luminance(before[i]);
    EXPECT_NEAR(luminance(sun[7]), 4096 * kept / 106, 1e-3 * luminance(sun[7]));
    EXPECT_NEAR(sun[7].x / sun[7].z, 2e4f / 1.6e4f, 1e-4);
    sun[7] = before[7];
    EXPECT_TRUE(same(sun, before));
    // A dark record (every sample 0) has nothing to compare with.
    std::vector<Color> dark(108, Color(0.0f));
    dark[3] = Color(1.0f);
    EXPECT_EQ(clampRecordOutliers(dark), 0);
    // A path 2 10^4 times the others' is clamped in a record of 108 samples, but not when the
    // same 108 are added to a record that already has 108 x 63: the bound is 64 times higher.
    std::vector<Color> bright = before;
    bright[7] = Color(1000.0f);
    EXPECT_EQ(clampRecordOutliers(bright), 1);
    bright[7] = Color(1000.0f);
    EXPECT_EQ(clampRecordOutliers(bright, 108 * 64), 0);
    EXPECT_EQ(bright[7].x, 1000.0f);
}

// Records refined between passes (record_refinement.h): with few paths per record (32) the
// cache's error is the records' noise, which a cache fixed after its fill keeps however many
// samples the render takes; refined, the records get about as many rays as the passes, so the
// error falls as the render goes on, the image stays unbiased, and it is still the same image on
// any number of threads.
TEST_F(CornellBox, RefinedRecordsConvergeAsTheRenderGoesOn) {
    auto renderWith = [&](int spp, bool refine, int threads = 0) {
        return render(*scene_, "irradianceCache", kSize, spp,
                      {{"paths", 32}, {"accuracy", 4}, {"lightSamples", 4}, {"refineRecords", refine ? 1.0 : 0.0}}, 1, threads);
    };
    auto error = [&](const Rendered& r, int spp) {
        return indirectError(blockLuminance(r.rgb, kSize), directBlocks(1, spp), *reference_);
    };
    Rendered fixed = renderWith(256, false), short_ = renderWith(16, true), long_ = renderWith(256, true);
    IndirectError eFixed = error(fixed, 256), eShort = error(short_, 16), eLong = error(long_, 256);
    std::printf("[ refined  ] indirect e^2: fixed %.5f (mean %.4f); refined 16 spp %.5f (%.0f paths per record), 256 spp "
                "%.5f (%.0f paths, mean %.4f)\n",
                eFixed.e2, eFixed.mean, eShort.e2, short_.stats.integrator.at("recordPathsMean"), eLong.e2,
                long_.stats.integrator.at("recordPathsMean"), eLong.mean);
    EXPECT_EQ(fixed.stats.integrator.at("recordPathsMean"), 32);
    EXPECT_GT(long_.stats.integrator.at("recordPathsMean"), short_.stats.integrator.at("recordPathsMean"));
    EXPECT_LT(eLong.e2, eShort.e2);
    EXPECT_LT(eLong.e2, eFixed.e2);
    EXPECT_NEAR(eLong.mean, 1.0, 0.0054);
    EXPECT_EQ(renderWith(64, true, 1).rgb, renderWith(64, true).rgb) << "one thread vs all";
}

// Looks at the scene from `eye` along `forward` (35 mm) and holds the green mean of each of the three
// caches (cacheSpp samples) within `tolerance` of the path tracer's (pathSpp samples).
static void expectCachesMatchThePathTracer(Scene& scene, Vec3 eye, Vec3 forward, int pathSpp, int cacheSpp, double tolerance,
                                           const char* label) {
    CameraDesc camera;
    camera.name = "/Camera";
    camera.focalLength = 35;
    camera.transform = lookAlong(eye, forward);
    scene.setCamera(camera);
    Rendered path = render(scene, "path", 48, pathSpp, {}, 1);
    for (const char* cache : {"irradianceCache", "adaptiveIrradianceCache", "photonMapIrradianceCache"}) {
        Rendered r = render(scene, cache, 48, cacheSpp, {}, 2);
        double ratio = channelMean(r.rgb, 1) / channelMean(path.rgb, 1);
        std::printf("[ %-8s ] %s %.4f of the path tracer's mean\n", label, cache, ratio);
        EXPECT_NEAR(ratio, 1.0, tolerance) << cache;
    }
}

// A dark floor with a glossy lobe (UsdPreviewSurface's default specular, roughness 0.2) seen at
// grazing angles, where it reflects a sunlit white wall: that reflection is indirect light of the
// glossy lobe, which no irradiance record holds. The caches trace it (DirectIntegrator::
// glossyIndirect); without that the plain, adaptive and photon caches read 0.71, 0.70 and 0.71 of
// the path tracer here, with it 1.001, 0.987 and 1.003 (Sponza's sunlit floor read 0.75).
TEST(IrradianceCacheRender, GlossyFloorAtGrazingAngles) {
    Scene scene;
    MaterialDesc floor = lambert(Color(0.05f));
    floor.useSpecularWorkflow = false;
    floor.roughness = 0.2f;
    int glossy = scene.addMaterial(floor), white = scene.addMaterial(lambert(Color(0.8f)));
    addQuad(scene, "/Floor", {-4, 0, -3}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -3}, glossy);
    addQuad(scene, "/Wall", {-4, 0, -3}, {4, 0, -3}, {4, 3, -3}, {-4, 3, -3}, white);
    addDistantLight(scene, Vec3(0.3f, -0.5f, -1), 3);
    expectCachesMatchThePathTracer(scene, Vec3(0, 0.4f, 3.5f), Vec3(0, -0.12f, -1), 512, 64, 0.02, "glossy");
}

// A sunlit floor whose shading normals lean 35 degrees off its plane (a smooth-shaded mesh, as
// Sponza's arcades are): a share of each record's hemisphere lies below the floor. The path
// tracer's rays in those directions cross the floor and find nothing under it; a record's rays
// left from a point lifted towards the viewer, hit the floor itself from the front and brought its
// sunlit radiance back as indirect light (irradiance_record_sampler.h's recordRayOrigin): the
// plain, adaptive and photon caches read 1.185, 1.182 and 1.103 of the path tracer here, 1.000 now
// (both see no indirect light). On Sponza the plain cache read 1.018 of the reference, 1.002 now.
TEST(IrradianceCacheRender, ShadingNormalsLeaningPastTheSurface) {
    Scene scene;
    int white = scene.addMaterial(lambert(Color(0.8f)));
    const float lean = 35 * kPi / 180;
    const Vec3 n(std::sin(lean), std::cos(lean), 0);
    scene.addMesh("/Floor", {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}}, {0, 1, 2, 0, 2, 3}, {n, n, n, n}, {}, white,
                  nullptr, true, -1);
    addDistantLight(scene, Vec3(0.2f, -1, -0.3f), 3);
    expectCachesMatchThePathTracer(scene, Vec3(0, 2.5f, 3), Vec3(0, -0.7f, -1), 256, 16, 0.01, "leaning");
}

// The photon cache's photon records are estimates from the global map: fixed, they keep its
// photon noise however long the render runs. Between passes further batches of photons join the
// map and the photon records are estimated again from it with more photons (photon_maps.h's
// addPhotonBatch), so their error falls as the render goes on.
TEST_F(CornellBox, PhotonRecordsConvergeAsPhotonsAreAdded) {
    auto renderWith = [&](int spp, bool refine, int threads = 0) {
        return render(*scene_, "photonMapIrradianceCache", kSize, spp,
                      {{"photons", 20000}, {"paths", 32}, {"lightSamples", 4}, {"refineRecords", refine ? 1.0 : 0.0}}, 1,
                      threads);
    };
    auto error = [&](const Rendered& r, int spp) {
        return indirectError(blockLuminance(r.rgb, kSize), directBlocks(1, spp), *reference_);
    };
    Rendered fixed = renderWith(256, false), long_ = renderWith(256, true);
    IndirectError eFixed = error(fixed, 256), eLong = error(long_, 256);
    std::printf("[ photons  ] indirect e^2: fixed %.5f (mean %.4f, %.0f photon records); with photon batches %.5f (mean %.4f, "
                "%.0f batches, %.0f photons per estimate)\n",
                eFixed.e2, eFixed.mean, fixed.stats.integrator.at("photonRecords"), eLong.e2, eLong.mean,
                long_.stats.integrator.at("photonBatches"), long_.stats.integrator.at("recordPhotons"));
    EXPECT_GT(fixed.stats.integrator.at("photonRecords"), 0);
    EXPECT_EQ(fixed.stats.integrator.at("photonBatches"), 1);
    EXPECT_GT(long_.stats.integrator.at("photonBatches"), 2);
    // Measured: e^2 0.0075 fixed, 0.00042 with 87 batches (1963 photons per estimate); means 0.993, 0.997.
    EXPECT_LT(eLong.e2, 0.25 * eFixed.e2);
    EXPECT_NEAR(eLong.mean, 1.0, 0.01);
    EXPECT_EQ(renderWith(64, true, 1).rgb, renderWith(64, true).rgb) << "one thread vs all";
}

// A lookup that finds no record computes one for its sample alone (render_time_records.h); the
// records of one pass join the cache before the next, so later passes find them: per sample, the
// fifth pass computes a small share of what the first two did. (Before, every pass computed them
// again: on Sibenik at 32 spp four times as many as the cache held.) Slats a tenth of a pixel
// wide stand on the corner's floor: the fill's pixel centres see few of them, jittered samples
// many others.
TEST(IrradianceCacheRender, RenderTimeRecordsJoinTheCacheForTheNextPass) {
    auto misses = [&](int spp) {
        Scene scene;
        buildCorner(scene);
        int white = scene.addMaterial(lambert(Color(0.8f)));
        for (int i = 0; i < 48; ++i) {
            float z = -0.9f + 0.0375f * float(i), x = 0.3f + 0.05f * float(i % 7);
            std::string name = "/Slat" + std::to_string(i);
            addQuad(scene, name.c_str(), {x, 0, z}, {x, 1.2f, z}, {x + 0.008f, 1.2f, z + 0.008f}, {x + 0.008f, 0, z + 0.008f},
                    white);
        }
        Rendered r = render(scene, "irradianceCache", 64, spp, {{"paths", 32}});
        return std::make_pair(r.stats.integrator.at("renderTimeRecords"), r.stats.integrator.at("adoptedRenderTimeRecords"));
    };
    // Passes of 1, 2, 4, 8 and 16 samples.
    auto [one, adoptedAfterOne] = misses(1);
    double three = misses(3).first, fifteen = misses(15).first;
    auto [thirtyOne, adopted] = misses(31);
    double first = one, second = (three - one) / 2, fifth = (thirtyOne - fifteen) / 16;
    std::printf("[ adopted  ] render-time records per sample: passes 1, 2 and 5 %.1f, %.1f, %.2f; %.0f joined the cache\n",
                first, second, fifth, adopted);
    EXPECT_EQ(adoptedAfterOne, 0);  // nothing after the last pass
    EXPECT_GT(first, 10);
    EXPECT_GT(adopted, first);
    EXPECT_LT(fifth, 0.1 * std::max(first, second));
}

// A closed room lit only by a sunlit spot on its floor, under a small hole in its ceiling: a record
// sees the spot in few of its 128 directions, so records' estimates are skewed (most a little dark,
// a few that caught the spot bright). The adaptive refinement must not shrink the bright ones for
// being discernible when it is their noise that is (adaptive_refinement.cpp, kDiscernibleSigmas).
// Over seeds 1-64 the mean read 0.9786 of the path tracer's (sd 0.114 a seed, 0.014 of the mean),
// so 0.06 is 4 sd; with the former 1-sigma rule it read 0.8956 (sd of the mean 0.006).
TEST(IrradianceCacheRender, AdaptiveRefinementKeepsBrightRecords) {
    auto build = [](Scene& scene) {
        int white = scene.addMaterial(lambert(Color(0.7f)));
        addRoomWalls(scene, 2, white, white);
        const float h = 0.15f;  // the hole: |x|, |z| < h
        addQuad(scene, "/CeilingA", {-1, 2, -1}, {-1, 2, 1}, {-h, 2, 1}, {-h, 2, -1}, white);
        addQuad(scene, "/CeilingB", {h, 2, -1}, {h, 2, 1}, {1, 2, 1}, {1, 2, -1}, white);
        addQuad(scene, "/CeilingC", {-h, 2, -1}, {-h, 2, -h}, {h, 2, -h}, {h, 2, -1}, white);
        addQuad(scene, "/CeilingD", {-h, 2, h}, {-h, 2, 1}, {h, 2, 1}, {h, 2, h}, white);
        addDistantLight(scene, Vec3(0.05f, -1, 0.03f), 200);
        CameraDesc camera;
        camera.name = "/Camera";
        camera.focalLength = 20;
        camera.transform = lookAlong(Vec3(0, 1.4f, 0.95f), Vec3(0, -0.1f, -1));
        scene.setCamera(camera);
    };
    Scene reference;
    build(reference);
    Rendered path = render(reference, "path", 32, 2048, {}, 1);
    double sum = 0;
    for (uint32_t seed = 1; seed <= 64; ++seed) {
        Scene scene;
        build(scene);
        Rendered adaptive = render(scene, "adaptiveIrradianceCache", 32, 16, {{"paths", 128}}, seed);
        sum += channelMean(adaptive.rgb, 1) / channelMean(path.rgb, 1);
    }
    std::printf("[ skewed   ] adaptive cache %.4f of the path tracer's mean over 64 seeds\n", sum / 64);
    EXPECT_NEAR(sum / 64, 1.0, 0.06);
}
