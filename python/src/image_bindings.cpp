// gi._core's image files and their names: EXR (channels, data windows), PNG through the OCIO
// display transform, reading images back, and the render-var and frame-name rules hdGi shares.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "arrays.h"
#include "renderer/color.h"
#include "renderer/image_io.h"
#include "renderer/pixel_window.h"
#include "renderer/render_vars.h"
#include "renderer/scene.h"

namespace nb = nanobind;
using namespace nb::literals;
using namespace gi;
using namespace gi::bindings;

namespace {

// The OCIO config: the explicit one, else $OCIO, else the one installed beside this module.
std::string ocioConfig(const std::string& explicitPath) {
    if (!explicitPath.empty()) return explicitPath;
    std::string moduleFile = nb::cast<std::string>(nb::module_::import_("gi._core").attr("__file__"));
    std::string shipped = moduleFile.substr(0, moduleFile.find_last_of('/')) + "/ocio/config.ocio";
    return resolveOcioConfig(shipped);
}

}  // namespace

void bindImages(nb::module_& m) {
    // UsdRender var rules (renderer/render_vars.h), shared with hdGi.
    m.def(
        "render_var_layout",
        [](const std::string& sourceName, const std::string& dataType) {
            std::string problem;
            std::optional<RenderVarLayout> layout = renderVarLayout(sourceName, dataType, &problem);
            if (!layout) throw std::invalid_argument(problem);
            return std::make_tuple(std::string(outputName(layout->output)), layout->suffixes, layout->half);
        },
        "source_name"_a, "data_type"_a,
        "(output, channel suffixes, half) of a render var, e.g. ('color', ['R','G','B'], False); "
        "ValueError with the reason when the renderer cannot write it.");
    m.def(
        "render_var_layer",
        [](const std::string& varName, const std::string& output, bool beautyTaken) {
            std::optional<RenderOutput> o = outputNamed(output);
            if (!o) throw std::invalid_argument("no renderer output named '" + output + "'");
            return renderVarLayer(varName, *o, beautyTaken);
        },
        "var_name"_a, "output"_a, "beauty_taken"_a, "The var's layer name ('' for a product's first colour var).");
    m.def("channel_name", &channelName, "layer"_a, "suffix"_a, "layer.suffix (or either alone).");
    m.def("frame_path", &substituteFrame, "path"_a, "frame"_a,
          "`path` with $F, $F<width> and #### replaced by `frame` (zero-padded to the width).");
    m.def("has_frame_token", &hasFrameToken, "path"_a);
    m.def("indexed_name", &Scene::indexedName, "base"_a, "index"_a, "count"_a,
          "base[index], zero-padded to the width of count - 1: an instance known only by its index, named so "
          "that names sort as indices do (renderer/scene.h).");
    m.def("frame_seed", &frameSeed, "seed"_a, "frame"_a,
          "The seed frame `frame` renders with: seed + frame (mod 2^32), the frame rounded (renderer/render_vars.h).");
    m.def(
        "data_window_pixels",
        [](std::tuple<float, float, float, float> ndc, int width, int height) {
            std::string problem;
            auto [xmin, ymin, xmax, ymax] = ndc;
            PixelWindow w = dataWindowPixels(xmin, ymin, xmax, ymax, width, height, &problem);
            return std::make_tuple(std::make_tuple(w.x0, w.y0, w.x1, w.y1), problem);
        },
        "ndc"_a, "width"_a, "height"_a,
        "((x0, y0, x1, y1) pixels, row 0 at the top; problem) for a dataWindowNDC (xmin, ymin, xmax, ymax): "
        "the pixels whose centres it holds, clipped to the image (renderer/pixel_window.h); problem: '' "
        "or a sentence for a warning.");

    m.def(
        "write_channels_exr",
        [](const std::string& path, ImageArray pixels, std::vector<std::string> channels,
           std::map<std::string, std::string> metadata, std::optional<std::tuple<int, int, int, int>> dataWindow,
           std::vector<bool> half) {
            if (pixels.ndim() != 3 || pixels.shape(2) != channels.size())
                throw std::invalid_argument("expected an (H, W, " + std::to_string(channels.size()) +
                                            ") float32 array, one plane per channel name");
            if (!half.empty() && half.size() != channels.size())
                throw std::invalid_argument("half: one flag per channel");
            int h = int(pixels.shape(0)), w = int(pixels.shape(1));
            DataWindow window;
            if (dataWindow) std::tie(window.x, window.y, window.fullWidth, window.fullHeight) = *dataWindow;
            // One layer per channel, so each keeps its own storage type.
            std::vector<std::vector<float>> planes(channels.size(), std::vector<float>(size_t(w) * h));
            std::vector<ImageLayer> layers;
            for (size_t c = 0; c < channels.size(); ++c) {
                for (size_t p = 0; p < size_t(w) * h; ++p) planes[c][p] = pixels.data()[p * channels.size() + c];
                layers.push_back({"", {channels[c]}, planes[c].data(), !half.empty() && half[c]});
            }
            nb::gil_scoped_release release;
            writeExr(path, w, h, layers, metadata, window);
        },
        "path"_a, "pixels"_a, "channels"_a, "metadata"_a = std::map<std::string, std::string>(),
        "data_window"_a = nb::none(), "half"_a = std::vector<bool>(),
        "Writes an (H, W, C) float32 array as an EXR with the given channel names (e.g. 'N.X'); data_window "
        "(x, y, full width, full height) places it in a larger image; half: per channel, 16-bit storage.");

    m.def(
        "write_rgb_exr",
        [](const std::string& path, ImageArray color, std::map<std::string, std::string> metadata) {
            size_t w, h;
            std::vector<float> rgb = toVector(color, w, h);
            writeExr(path, int(w), int(h), {{"", {"R", "G", "B"}, rgb.data()}}, metadata);
        },
        "path"_a, "color"_a, "metadata"_a = std::map<std::string, std::string>());

    m.def(
        "display_transform",
        [](ImageArray color, const std::string& display, const std::string& view, float exposure,
           const std::string& config) {
            size_t w, h;
            std::vector<float> rgb = toVector(color, w, h);
            std::string path = ocioConfig(config);
            return toNumpy<3>(applyDisplayTransform(rgb, int(w), int(h), path, display, view, exposure), {h, w, 3});
        },
        "color"_a, "display"_a = "", "view"_a = "", "exposure"_a = 0.0f, "config"_a = "");

    m.def(
        "write_png",
        [](const std::string& path, ImageArray color, const std::string& display, const std::string& view,
           float exposure, const std::string& config) {
            size_t w, h;
            std::vector<float> rgb = toVector(color, w, h);
            std::string cfg = ocioConfig(config);
            writePng8(path, int(w), int(h), applyDisplayTransform(rgb, int(w), int(h), cfg, display, view, exposure));
        },
        "path"_a, "color"_a, "display"_a = "", "view"_a = "", "exposure"_a = 0.0f, "config"_a = "");

    m.def("read_image", [](const std::string& path) {
        LoadedImage img = readImage(path);
        size_t h = size_t(img.height), w = size_t(img.width), c = size_t(img.channels);
        auto* heap = new std::vector<float>(std::move(img.pixels));
        nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<float>*>(p); });
        size_t shape[3] = {h, w, c};
        nb::ndarray<nb::numpy, float> array(heap->data(), 3, shape, owner);
        nb::dict meta;
        for (const auto& [k, v] : img.metadata) meta[k.c_str()] = v;
        meta["channels"] = img.channelNames;
        meta["channel_formats"] = img.channelFormats;
        // (x, y, width, height) of the pixels read within the (full width, full height) image.
        meta["data_window"] = nb::make_tuple(img.window.x, img.window.y, img.width, img.height);
        meta["display_window"] = nb::make_tuple(img.window.fullWidth, img.window.fullHeight);
        return nb::make_tuple(array, meta);
    });
}
