// gi._core: the renderer for Python (see python/gi/_core.pyi for the documented API).
#include <cmath>
#include <limits>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <chrono>
#include <thread>

#include "arrays.h"
#include "renderer/color.h"
#include "renderer/image_io.h"
#include "renderer/ray_benchmark.h"
#include "renderer/render.h"
#include "renderer/render_vars.h"
#include "renderer/scene.h"
#include "renderer/usd_shading.h"

namespace nb = nanobind;
using namespace nb::literals;
using namespace gi;
using namespace gi::bindings;

namespace {

using Float3 = std::tuple<float, float, float>;
using Float4 = std::tuple<float, float, float, float>;
using Float2 = std::tuple<float, float>;
using Matrix = nb::ndarray<const double, nb::shape<4, 4>, nb::device::cpu>;

Color toColor(const Float3& t) { return {std::get<0>(t), std::get<1>(t), std::get<2>(t)}; }
Float3 fromColor(const Color& c) { return {c.x, c.y, c.z}; }

Mat4 toMat4(const Matrix& m) {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = m(i, j);
    return r;
}
nb::ndarray<nb::numpy, double, nb::shape<4, 4>> fromMat4(const Mat4& m) {
    double* data = new double[16];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) data[i * 4 + j] = m.m[i][j];
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    return nb::ndarray<nb::numpy, double, nb::shape<4, 4>>(data, {4, 4}, owner);
}

nb::ndarray<nb::numpy, int32_t> toNumpyInt(std::vector<int32_t> v, size_t h, size_t w) {
    auto* heap = new std::vector<int32_t>(std::move(v));
    nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<int32_t>*>(p); });
    size_t shape[2] = {h, w};
    return nb::ndarray<nb::numpy, int32_t>(heap->data(), 2, shape, owner);
}

#define RW_COLOR(cls, pyname, field) \
    def_prop_rw(pyname, [](const cls& o) { return fromColor(o.field); }, [](cls& o, Float3 v) { o.field = toColor(v); })

using StepPoints = nb::ndarray<const float, nb::shape<-1, -1, 3>, nb::c_contig, nb::device::cpu>;
using StepMatrices = nb::ndarray<const double, nb::shape<-1, 4, 4>, nb::c_contig, nb::device::cpu>;

// (steps, N, 3) points and (steps, 4, 4) transforms over the shutter (motion.h).
MotionSteps toMotion(const std::optional<StepPoints>& points, const std::optional<StepMatrices>& transforms) {
    MotionSteps motion;
    if (points)
        for (size_t step = 0; step < points->shape(0); ++step) {
            const Vec3* first = reinterpret_cast<const Vec3*>(points->data()) + step * points->shape(1);
            motion.points.emplace_back(first, first + points->shape(1));
        }
    if (transforms)
        for (size_t step = 0; step < transforms->shape(0); ++step)
            motion.transforms.push_back(Mat4::fromRowMajor(transforms->data() + step * 16));
    return motion;
}

// (steps, 4, 4) transforms as numpy, or None when there are none (a descriptor's motion_transforms).
nb::object stepMatrices(const std::vector<Mat4>& steps) {
    if (steps.empty()) return nb::none();
    auto* data = new std::vector<double>;
    for (const Mat4& m : steps) data->insert(data->end(), &m.m[0][0], &m.m[0][0] + 16);
    nb::capsule owner(data, [](void* p) noexcept { delete static_cast<std::vector<double>*>(p); });
    size_t shape[3] = {steps.size(), 4, 4};
    return nb::cast(nb::ndarray<nb::numpy, double>(data->data(), 3, shape, owner), nb::rv_policy::move);
}

void bindDescriptors(nb::module_& m) {
    nb::class_<TextureDesc>(m, "TextureDesc")
        .def(nb::init<>())
        .def_rw("file", &TextureDesc::file)
        .def_rw("wrap_s", &TextureDesc::wrapS)
        .def_rw("wrap_t", &TextureDesc::wrapT)
        .def_rw("channel", &TextureDesc::channel)
        .def_rw("source_color_space", &TextureDesc::sourceColorSpace)
        .def_rw("st_rotation", &TextureDesc::stRotation)
        .def_prop_rw("scale", [](const TextureDesc& t) { return Float4{t.scale[0], t.scale[1], t.scale[2], t.scale[3]}; },
                     [](TextureDesc& t, Float4 v) { std::tie(t.scale[0], t.scale[1], t.scale[2], t.scale[3]) = v; })
        .def_prop_rw("bias", [](const TextureDesc& t) { return Float4{t.bias[0], t.bias[1], t.bias[2], t.bias[3]}; },
                     [](TextureDesc& t, Float4 v) { std::tie(t.bias[0], t.bias[1], t.bias[2], t.bias[3]) = v; })
        .def_prop_rw("fallback",
                     [](const TextureDesc& t) { return Float4{t.fallback[0], t.fallback[1], t.fallback[2], t.fallback[3]}; },
                     [](TextureDesc& t, Float4 v) { std::tie(t.fallback[0], t.fallback[1], t.fallback[2], t.fallback[3]) = v; })
        .def_prop_rw("st_scale", [](const TextureDesc& t) { return Float2{t.stScale.x, t.stScale.y}; },
                     [](TextureDesc& t, Float2 v) { std::tie(t.stScale.x, t.stScale.y) = v; })
        .def_prop_rw("st_translation", [](const TextureDesc& t) { return Float2{t.stTranslation.x, t.stTranslation.y}; },
                     [](TextureDesc& t, Float2 v) { std::tie(t.stTranslation.x, t.stTranslation.y) = v; });

    nb::class_<MaterialDesc>(m, "MaterialDesc")
        .def(nb::init<>())
        .def_rw("name", &MaterialDesc::name)
        .RW_COLOR(MaterialDesc, "diffuse_color", diffuseColor)
        .RW_COLOR(MaterialDesc, "emissive_color", emissiveColor)
        .RW_COLOR(MaterialDesc, "specular_color", specularColor)
        .def_rw("use_specular_workflow", &MaterialDesc::useSpecularWorkflow)
        .def_rw("metallic", &MaterialDesc::metallic)
        .def_rw("roughness", &MaterialDesc::roughness)
        .def_rw("clearcoat", &MaterialDesc::clearcoat)
        .def_rw("clearcoat_roughness", &MaterialDesc::clearcoatRoughness)
        .def_rw("opacity", &MaterialDesc::opacity)
        .def_rw("opacity_mode", &MaterialDesc::opacityMode)
        .def_rw("opacity_threshold", &MaterialDesc::opacityThreshold)
        .def_rw("ior", &MaterialDesc::ior)
        .def_rw("diffuse_color_texture", &MaterialDesc::diffuseColorTexture)
        .def_rw("emissive_color_texture", &MaterialDesc::emissiveColorTexture)
        .def_rw("specular_color_texture", &MaterialDesc::specularColorTexture)
        .def_rw("metallic_texture", &MaterialDesc::metallicTexture)
        .def_rw("roughness_texture", &MaterialDesc::roughnessTexture)
        .def_rw("opacity_texture", &MaterialDesc::opacityTexture)
        .def_rw("normal_texture", &MaterialDesc::normalTexture);

    // The shading rules shared with hdGi (renderer/usd_shading.h; networks: shading_bindings.cpp).
    m.def(
        "display_color_material",
        [](const std::string& prim, std::optional<Float3> color) {
            Color c = color ? toColor(*color) : Color(0.0f);
            return displayColorMaterial(prim, color ? &c : nullptr);
        },
        "prim"_a, "display_color"_a = nb::none(),
        "The material of a gprim with no usable material: UsdPreviewSurface defaults, diffuse = its displayColor.");
    m.def("uv_primvar_of", &uvPrimvarOf, "reader_varnames"_a, "mesh_primvars"_a,
          "The first reader varname the mesh has as a primvar, else '' (no texture coordinates).");

    nb::class_<LightDesc>(m, "LightDesc")
        .def(nb::init<>())
        .def_rw("name", &LightDesc::name)
        .def_rw("kind", &LightDesc::kind)
        .RW_COLOR(LightDesc, "color", color)
        .def_rw("intensity", &LightDesc::intensity)
        .def_rw("exposure", &LightDesc::exposure)
        .def_rw("normalize", &LightDesc::normalize)
        .def_rw("width", &LightDesc::width)
        .def_rw("height", &LightDesc::height)
        .def_rw("radius", &LightDesc::radius)
        .def_rw("length", &LightDesc::length)
        .def_rw("angle", &LightDesc::angle)
        .def_rw("texture_file", &LightDesc::textureFile)
        .def_rw("visible_to_camera", &LightDesc::visibleToCamera)
        .def_prop_rw("transform", [](const LightDesc& l) { return nb::cast(fromMat4(l.transform), nb::rv_policy::move); },
                     [](LightDesc& l, Matrix v) { l.transform = toMat4(v); })
        .def_prop_rw(
            "motion_transforms", [](const LightDesc& l) { return stepMatrices(l.motionTransforms); },
            [](LightDesc& l, std::optional<StepMatrices> steps) { l.motionTransforms = toMotion(std::nullopt, steps).transforms; },
            nb::arg("value").none());

    nb::class_<CameraDesc>(m, "CameraDesc")
        .def(nb::init<>())
        .def_rw("name", &CameraDesc::name)
        .def_rw("projection", &CameraDesc::projection)
        .def_rw("focal_length", &CameraDesc::focalLength)
        .def_rw("horizontal_aperture", &CameraDesc::horizontalAperture)
        .def_rw("vertical_aperture", &CameraDesc::verticalAperture)
        .def_rw("horizontal_aperture_offset", &CameraDesc::horizontalApertureOffset)
        .def_rw("vertical_aperture_offset", &CameraDesc::verticalApertureOffset)
        .def_rw("f_stop", &CameraDesc::fStop)
        .def_rw("focus_distance", &CameraDesc::focusDistance)
        .def_rw("shutter_open", &CameraDesc::shutterOpen)
        .def_rw("shutter_close", &CameraDesc::shutterClose)
        .def_prop_rw(
            "motion_transforms", [](const CameraDesc& c) { return stepMatrices(c.motionTransforms); },
            [](CameraDesc& c, std::optional<StepMatrices> steps) { c.motionTransforms = toMotion(std::nullopt, steps).transforms; },
            nb::arg("value").none())
        .def_prop_rw("clipping_range", [](const CameraDesc& c) { return Float2{c.clipNear, c.clipFar}; },
                     [](CameraDesc& c, Float2 v) { std::tie(c.clipNear, c.clipFar) = v; })
        .def_prop_rw("transform", [](const CameraDesc& c) { return nb::cast(fromMat4(c.transform), nb::rv_policy::move); },
                     [](CameraDesc& c, Matrix v) { c.transform = toMat4(v); });
    m.def(
        "framing_camera",
        [](std::tuple<double, double, double> center, std::tuple<double, double, double> size, bool zUp) {
            auto d = [](const std::tuple<double, double, double>& t) {
                return std::array<double, 3>{std::get<0>(t), std::get<1>(t), std::get<2>(t)};
            };
            return framingCamera(d(center), d(size), zUp);
        },
        "center"_a, "size"_a, "z_up"_a,
        "The camera that frames a bounding box (its centre and size) when the stage has none: usdrecord's "
        "(renderer/camera_framing.h).");
}

using Points = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Uvs = nb::ndarray<const float, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using Indices = nb::ndarray<const uint32_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

std::vector<Vec3> toVec3s(const std::optional<Points>& a) {
    std::vector<Vec3> out;
    if (!a) return out;
    out.resize(a->shape(0));
    std::memcpy(out.data(), a->data(), out.size() * sizeof(Vec3));
    return out;
}

void requireBuilding(const Scene& s) {
    if (s.committed()) throw std::runtime_error("the scene was already rendered; build a new Scene to change it");
}

void bindScene(nb::module_& m) {
    nb::class_<Scene>(m, "Scene")
        .def(nb::init<>())
        .def("add_material", [](Scene& s, const MaterialDesc& d) { requireBuilding(s); return s.addMaterial(d); })
        .def("add_prototype", [](Scene& s, const std::string& name) { requireBuilding(s); return s.addPrototype(name); })
        .def(
            "add_mesh",
            [](Scene& s, const std::string& name, Points positions, Indices indices, std::optional<Points> normals,
               std::optional<Uvs> uvs, int material, std::optional<Matrix> transform, bool doubleSided, int prototype,
               std::optional<StepPoints> motionPoints, std::optional<StepMatrices> motionTransforms) {
                requireBuilding(s);
                std::vector<Vec3> p = toVec3s(positions);
                std::vector<uint32_t> idx(indices.data(), indices.data() + indices.shape(0) * 3);
                std::vector<Vec2> st;
                if (uvs) {
                    st.resize(uvs->shape(0));
                    std::memcpy(st.data(), uvs->data(), st.size() * sizeof(Vec2));
                }
                Mat4 xf = transform ? toMat4(*transform) : Mat4();
                MotionSteps motion = toMotion(motionPoints, motionTransforms);
                nb::gil_scoped_release release;
                return s.addMesh(name, std::move(p), std::move(idx), toVec3s(normals), std::move(st), material,
                                 transform ? &xf : nullptr, doubleSided, prototype, motion);
            },
            "name"_a, "positions"_a, "indices"_a, "normals"_a = nb::none(), "uvs"_a = nb::none(), "material"_a = -1,
            "transform"_a = nb::none(), "double_sided"_a = true, "prototype"_a = -1, "motion_points"_a = nb::none(),
            "motion_transforms"_a = nb::none())
        .def(
            "add_sphere",
            [](Scene& s, const std::string& name, Float3 center, float radius, int material,
               std::optional<Matrix> transform, int prototype, std::optional<StepMatrices> motionTransforms) {
                requireBuilding(s);
                Mat4 xf = transform ? toMat4(*transform) : Mat4();
                return s.addSphere(name, toColor(center), radius, material, transform ? &xf : nullptr, prototype,
                                   toMotion(std::nullopt, motionTransforms));
            },
            "name"_a, "center"_a, "radius"_a, "material"_a = -1, "transform"_a = nb::none(), "prototype"_a = -1,
            "motion_transforms"_a = nb::none())
        .def(
            "add_instance",
            [](Scene& s, int prototype, Matrix transform, const std::string& name,
               std::optional<StepMatrices> motionTransforms) {
                requireBuilding(s);
                return s.addInstance(prototype, toMat4(transform), name, toMotion(std::nullopt, motionTransforms));
            },
            "prototype"_a, "transform"_a, "name"_a = "", "motion_transforms"_a = nb::none())
        .def("add_light", [](Scene& s, const LightDesc& d) { requireBuilding(s); return s.addLight(d); })
        .def("set_camera", [](Scene& s, const CameraDesc& d) { requireBuilding(s); s.setCamera(d); })
        .def(
            "reuse_bvh_of",
            [](Scene& s, const Scene& previous, bool edits) {
                requireBuilding(s);
                s.reuseBvhOf(previous, edits ? Scene::BvhReuse::Edits : Scene::BvhReuse::Frames);
            },
            "previous"_a, "edits"_a = false,
            "Build only the BVHs of what changed since `previous` (the last frame's committed scene; "
            "Scene::reuseBvhOf). edits: keep a static BVH whose shapes changed, masking them (an "
            "interactive host's edits), instead of rebuilding it. Call before commit.")
        .def("commit", [](Scene& s) { nb::gil_scoped_release release; s.commit(); })
        .def("warnings", &Scene::warnings)
        .def("stats", [](const Scene& s) {
            const Scene::Stats& st = s.stats();
            std::map<std::string, double> d{{"triangles", double(st.triangles)},
                                            {"spheres", double(st.spheres)},
                                            {"instances", double(st.instances)},
                                            {"prototypes", double(st.prototypes)},
                                            {"lights", double(st.lights)},
                                            {"emissive_triangles", double(st.emissiveTriangles)},
                                            {"textures", double(st.textures)},
                                            {"texture_bytes", double(st.textureBytes)},
                                            {"textures_read", double(st.texturesRead)}, {"portals", double(st.portals)},
                                            {"build_seconds", st.buildSeconds},
                                            {"primitives_built", double(st.primitivesBuilt)},
                                            {"primitives_reused", double(st.primitivesReused)},
                                            {"primitives_masked", double(st.primitivesMasked)},
                                            {"moving_shapes", double(st.movingShapes)},
                                            {"moving_instances", double(st.movingInstances)},
                                            {"moving_lights", double(st.movingLights)},
                                            {"committed", s.committed() ? 1.0 : 0.0},
                                            {"specular_surfaces", s.hasSpecularSurfaces() ? 1.0 : 0.0}};
            return d;
        });
}

struct PyRenderSettings {
    int width = 512, height = 512, spp = 16;
    std::string integrator = "path";
    nb::dict params;
    std::string preset;
    std::string keptAutoChoice;
    uint32_t seed = 0;
    int threads = 0;
    double timeLimit = 0;
    std::string filter = "box";
    std::tuple<int, int, int, int> dataWindow{0, 0, 0, 0};  // (x0, y0, x1, y1); empty: the whole image
    ImageFraming framing;  // the conform policy and pixel aspect ratio (no display window: Hydra's)
};

struct RenderResult {
    nb::object color, depth, normal, albedo;
    nb::object primId, instanceId;  // int32, -1 where nothing (no instance) was hit
    int width = 0, height = 0;
    PixelWindow window;  // the pixels rendered (the whole image unless a data window was set)
    int spp = 0;
    std::map<std::string, double> stats;
    std::string integrator;  // the one that rendered: the settings', or the one "auto" chose
    std::string autoSummary;  // "auto": its choice and every technique's predicted error
};

RenderSettings toRenderSettings(const PyRenderSettings& py) {
    RenderSettings settings;
    settings.width = py.width;
    settings.height = py.height;
    settings.spp = py.spp;
    settings.integrator = py.integrator;
    settings.keptAutoChoice = py.keptAutoChoice;
    settings.seed = py.seed;
    settings.threads = py.threads;
    settings.timeLimit = py.timeLimit;
    settings.filter = py.filter;
    settings.preset = py.preset;
    std::tie(settings.window.x0, settings.window.y0, settings.window.x1, settings.window.y1) = py.dataWindow;
    settings.framing = py.framing;
    for (auto [key, value] : py.params) settings.params.set(nb::cast<std::string>(key), nb::cast<double>(value));
    return settings;
}

RenderResult render(Scene& scene, const PyRenderSettings& py, std::optional<nb::callable> progress,
                    std::optional<CameraDesc> camera) {
    RenderSettings settings = toRenderSettings(py);
    double started = steadySeconds();  // the time limit counts committing the scene too
    {
        nb::gil_scoped_release release;
        scene.commit();
    }
    Renderer renderer(scene, settings, camera ? &*camera : nullptr);
    std::atomic<bool> cancel{false}, finished{false};
    std::exception_ptr error;
    {
        nb::gil_scoped_release release;
        std::thread worker([&] {
            try {
                renderer.render(&cancel, started);
            } catch (...) {
                error = std::current_exception();
            }
            finished = true;
        });
        // The calling thread reports progress and watches for Ctrl-C every 50 ms while workers
        // render; it looks for the end every 2 ms, so that a time-limited call returns on time.
        for (int tick = 1; !finished; ++tick) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            if (tick % 25 != 0) continue;
            nb::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) {
                cancel = true;
                break;
            }
            if (progress) (*progress)(renderer.progress());
        }
        worker.join();
    }
    if (cancel) throw nb::python_error();
    if (error) std::rethrow_exception(error);
    if (progress) (*progress)(1.0);
    const Film& film = renderer.film();
    size_t w = size_t(film.width()), h = size_t(film.height());
    RenderResult r;
    r.color = nb::cast(toNumpy<3>(film.color(), {h, w, 3}));
    r.depth = nb::cast(toNumpy<2>(film.depth(), {h, w}));
    r.normal = nb::cast(toNumpy<3>(film.normal(), {h, w, 3}));
    r.albedo = nb::cast(toNumpy<3>(film.albedo(), {h, w, 3}));
    r.primId = nb::cast(toNumpyInt(film.shapeIds(), h, w));
    r.instanceId = nb::cast(toNumpyInt(film.instanceIds(), h, w));
    r.width = int(w), r.height = int(h);
    r.window = settings.window.empty() ? PixelWindow{0, 0, int(w), int(h)} : settings.window;
    r.spp = renderer.samplesTaken();
    const RenderStats& s = renderer.stats();
    r.stats = {{"seconds", s.seconds},
               {"preprocess_seconds", s.preprocessSeconds},
               {"render_seconds", s.renderSeconds},
               {"rays", double(s.rays)},
               {"rays_per_second", s.renderSeconds > 0 ? s.rays / s.renderSeconds : 0},
               {"camera_samples", double(s.cameraSamples)},
               {"samples_per_second", s.renderSeconds > 0 ? s.cameraSamples / s.renderSeconds : 0},
               {"non_finite_samples", double(s.nonFiniteSamples)},
               {"clamped_samples", double(s.clampedSamples)},
               {"depth_capped_paths", double(s.depthCappedPaths)},
               {"peak_memory_bytes", double(s.peakMemoryBytes)},
               {"spp", double(s.spp)},
               {"partial_pass_pixels", double(s.partialPassPixels)},
               {"partial_pass_samples", double(s.partialPassSamples)},
               {"preprocess_scaled_down", double(s.preprocessScaledDown)},
               {"sample_thread_seconds", s.sampleThreadSeconds},
               {"pass_setup_seconds", s.passSetupSeconds}};
    for (const auto& [k, v] : s.integrator) r.stats[k] = v;
    r.integrator = renderer.integratorName();
    if (!renderer.autoChoice().integrator.empty()) {
        r.autoSummary = renderer.autoChoice().summary();
        r.stats["auto_pilot_seconds"] = renderer.autoChoice().pilotSeconds;
    }
    return r;
}

void bindRendering(nb::module_& m) {
    nb::class_<PyRenderSettings>(m, "RenderSettings")
        .def(nb::init<>())
        .def_rw("width", &PyRenderSettings::width)
        .def_rw("height", &PyRenderSettings::height)
        .def_rw("spp", &PyRenderSettings::spp)
        .def_rw("integrator", &PyRenderSettings::integrator)
        .def_rw("params", &PyRenderSettings::params)
        .def_rw("preset", &PyRenderSettings::preset)
        .def_rw("kept_auto_choice", &PyRenderSettings::keptAutoChoice,
                "integrator 'auto': the technique an earlier render chose, taken without pilots")
        .def_rw("seed", &PyRenderSettings::seed)
        .def_rw("threads", &PyRenderSettings::threads)
        .def_rw("time_limit", &PyRenderSettings::timeLimit)
        .def_rw("filter", &PyRenderSettings::filter)
        .def_prop_rw(
            "aspect_ratio_conform_policy",
            [](const PyRenderSettings& s) { return std::string(apertureConformToken(s.framing.conform)); },
            [](PyRenderSettings& s, const std::string& token) {
                if (!parseApertureConform(token, &s.framing.conform))
                    throw nb::value_error(("aspectRatioConformPolicy '" + token + "' is none of expandAperture, "
                                           "cropAperture, adjustApertureWidth, adjustApertureHeight, "
                                           "adjustPixelAspectRatio").c_str());
            },
            "UsdRenderSettings' aspectRatioConformPolicy: how the camera's aperture fits the image")
        .def_prop_rw(
            "pixel_aspect_ratio", [](const PyRenderSettings& s) { return s.framing.pixelAspectRatio; },
            [](PyRenderSettings& s, float aspect) { s.framing.pixelAspectRatio = aspect; },
            "a pixel's width over its height (UsdRenderSettings' pixelAspectRatio)")
        .def_rw("data_window", &PyRenderSettings::dataWindow,
                "(x0, y0, x1, y1): render only pixels [x0, x1) x [y0, y1); (0, 0, 0, 0): the whole image");

    nb::class_<RenderResult>(m, "RenderResult")
        .def_ro("color", &RenderResult::color)
        .def_ro("depth", &RenderResult::depth)
        .def_ro("normal", &RenderResult::normal)
        .def_ro("albedo", &RenderResult::albedo)
        .def_ro("prim_id", &RenderResult::primId)
        .def_ro("instance_id", &RenderResult::instanceId)
        .def_prop_ro("data_window", [](const RenderResult& r) {
            return std::make_tuple(r.window.x0, r.window.y0, r.window.x1, r.window.y1);
        })
        .def_ro("spp", &RenderResult::spp)
        .def_ro("stats", &RenderResult::stats)
        .def_ro("integrator", &RenderResult::integrator)
        .def_ro("auto_summary", &RenderResult::autoSummary);

    m.def("render", &render, "scene"_a, "settings"_a, "progress"_a = nb::none(), "camera"_a = nb::none(),
          "camera: a CameraDesc used instead of the scene's (a committed scene renders again from another view)");

    m.def("presets", [] {
        nb::list out;
        for (const Preset& preset : presets()) {
            nb::dict d;
            d["name"] = preset.name;
            d["description"] = preset.description;
            nb::dict params;
            for (const auto& [integrator, values] : preset.params) params[integrator.c_str()] = values;
            d["params"] = params;
            out.append(d);
        }
        return out;
    });

    m.def("auto_candidates", [] { return autoCandidates(); },
          "the techniques integrator 'auto' chooses among, in the order its pilots render them");

    m.def("integrators", [] {
        nb::list out;
        for (const IntegratorInfo& info : integratorRegistry()) {
            nb::list params;
            for (const ParamInfo& p : info.params) {
                nb::dict d;
                d["name"] = p.name;
                d["type"] = p.type;
                d["description"] = p.description;
                if (p.type == "int") {
                    d["default"] = int64_t(p.defaultValue), d["min"] = int64_t(p.minValue), d["max"] = int64_t(p.maxValue);
                } else if (p.type == "bool") {
                    d["default"] = p.defaultValue != 0, d["min"] = false, d["max"] = true;
                } else {
                    d["default"] = p.defaultValue, d["min"] = p.minValue, d["max"] = p.maxValue;
                }
                params.append(d);
            }
            nb::dict d;
            d["name"] = info.name;
            d["description"] = info.description;
            d["params"] = params;
            out.append(d);
        }
        return out;
    });

    m.def(
        "write_exr",
        [](const std::string& path, const RenderResult& r, std::map<std::string, std::string> metadata,
           std::optional<ImageArray> colorOverride, std::map<std::string, ImageArray> extraLayers) {
            auto color = nb::cast<ImageArray>(r.color);
            auto depth = nb::cast<ImageArray>(r.depth);
            auto normal = nb::cast<ImageArray>(r.normal);
            auto albedo = nb::cast<ImageArray>(r.albedo);
            // Only the rendered pixels (the result's data window) go into the file, placed in the
            // whole image as the EXR's data window.
            const PixelWindow& win = r.window;
            int w = win.x1 - win.x0, h = win.y1 - win.y0;
            auto crop = [&](const float* pixels, int channels) {
                std::vector<float> out(size_t(w) * h * channels);
                for (int y = 0; y < h; ++y)
                    std::copy_n(pixels + (size_t(y + win.y0) * r.width + win.x0) * channels, size_t(w) * channels,
                                out.begin() + size_t(y) * w * channels);
                return out;
            };
            std::vector<float> rgb = crop(color.data(), 3), z = crop(depth.data(), 1), n = crop(normal.data(), 3),
                               a = crop(albedo.data(), 3);
            // The file holds no Inf: pixels that hit nothing get the largest finite depth.
            for (float& v : z)
                if (!std::isfinite(v)) v = std::numeric_limits<float>::max();
            std::vector<ImageLayer> layers{{"", {"R", "G", "B"}, rgb.data()},
                                           {"", {"Z"}, z.data()},
                                           {"N", {"X", "Y", "Z"}, n.data()},
                                           {"albedo", {"R", "G", "B"}, a.data()}};
            DataWindow window;
            if (w != r.width || h != r.height) window = DataWindow{win.x0, win.y0, r.width, r.height};
            std::vector<std::vector<float>> extraPixels;  // owns the extra layers' RGB while writing
            extraPixels.reserve(extraLayers.size() + 1);
            auto rgbOf = [&](const ImageArray& image, const std::string& what) {
                size_t iw, ih;
                std::vector<float> whole = toVector(image, iw, ih);
                if (int(iw) != r.width || int(ih) != r.height)
                    throw std::invalid_argument(what + " is " + std::to_string(iw) + "x" + std::to_string(ih) +
                                                ", the render " + std::to_string(r.width) + "x" +
                                                std::to_string(r.height));
                extraPixels.push_back(crop(whole.data(), 3));
                return extraPixels.back().data();
            };
            if (colorOverride) layers[0].pixels = rgbOf(*colorOverride, "color");
            for (const auto& [name, image] : extraLayers) layers.push_back({name, {"R", "G", "B"}, rgbOf(image, name)});
            nb::gil_scoped_release release;
            writeExr(path, w, h, layers, metadata, window);
        },
        "path"_a, "result"_a, "metadata"_a = std::map<std::string, std::string>(), "color"_a = nb::none(),
        "layers"_a = std::map<std::string, ImageArray>(),
        "The render's colour (or `color` instead), depth, normal and albedo, plus each of `layers` "
        "(name -> (H, W, 3) array) as name.R/G/B.");

    m.def("peak_memory_bytes", &peakResidentMemoryBytes);

    m.def(
        "embree_ray_benchmark",
        [](Scene& scene, uint64_t rays, uint32_t seed, int threads) {
            nb::gil_scoped_release release;
            scene.commit();
            RayBenchmarkResult r = castIncoherentRays(scene, rays, seed, threads);
            return std::map<std::string, double>{{"rays", double(r.rays)},
                                                 {"hits", double(r.hits)},
                                                 {"seconds", r.seconds},
                                                 {"cpu_seconds", r.cpuSeconds},
                                                 {"rays_per_second", r.raysPerSecond()}};
        },
        "scene"_a, "rays"_a, "seed"_a = 0, "threads"_a = 0);
    m.def(
        "embree_replay_render_rays",
        [](Scene& scene, const PyRenderSettings& py, const std::string& order) {
            RenderSettings settings = toRenderSettings(py);  // reads Python objects: before the GIL is released
            RayReplay replay = order == "render" ? RayReplay::RenderOrder
                               : order == "wavefront" ? RayReplay::Wavefront
                               : order == "wavefront-packets8"
                                   ? RayReplay::WavefrontPackets8
                                   : throw std::invalid_argument("replay order '" + order +
                                                                 "': expected render, wavefront or wavefront-packets8");
            nb::gil_scoped_release release;
            scene.commit();
            RenderReplayResult r = replayRenderRays(scene, settings, replay);
            return std::map<std::string, double>{{"render_rays", double(r.render.rays)},
                                                 {"render_seconds", r.render.seconds},
                                                 {"render_cpu_seconds", r.render.cpuSeconds},
                                                 {"replay_rays", double(r.replay.rays)},
                                                 {"replay_seconds", r.replay.seconds},
                                                 {"replay_cpu_seconds", r.replay.cpuSeconds}};
        },
        "scene"_a, "settings"_a, "order"_a = "render",
        "Renders once timed, once recording its rays, then casts those rays through Embree alone: "
        "replay_seconds / render_seconds is Embree's share of the render. order: 'render' (one ray "
        "at a time, as rendered), 'wavefront' (waves of paths, each step's rays together) or "
        "'wavefront-packets8' (the same as Embree's 8-wide packets).");
}

}  // namespace

void bindImages(nb::module_& m);    // image_bindings.cpp: EXR and PNG files, display transforms, render vars
void bindImport(nb::module_& m);    // import_bindings.cpp: read_obj, read_gltf
void bindDenoiser(nb::module_& m);  // denoise_bindings.cpp: Denoiser, DenoiserUnavailable
void bindMesh(nb::module_& m);      // mesh_bindings.cpp: tessellate_mesh, MeshPrimvar, SubdivisionRules
void bindShading(nb::module_& m);   // shading_bindings.cpp: ShaderNetwork, resolve_preview_surface

NB_MODULE(_core, m) {
    m.doc() = "hdGi's CPU global-illumination renderer";
    bindDescriptors(m);
    bindScene(m);
    bindRendering(m);
    bindImages(m);
    bindImport(m);
    bindDenoiser(m);
    bindMesh(m);
    bindShading(m);
}
