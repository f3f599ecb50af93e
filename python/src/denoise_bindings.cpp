// gi._core.Denoiser: renderer/denoiser.h for Python (gi render --denoise, gi study's denoised rows).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "arrays.h"
#include "renderer/denoiser.h"

namespace nb = nanobind;
using namespace nb::literals;
using namespace gi;
using namespace gi::bindings;

void bindDenoiser(nb::module_& m) {
    nb::exception<DenoiserUnavailable>(m, "DenoiserUnavailable", PyExc_RuntimeError);

    nb::class_<Denoiser>(m, "Denoiser")
        .def(nb::init<const std::vector<std::string>&, int>(), "library_folders"_a = std::vector<std::string>(),
             "threads"_a = 0,
             "Loads Open Image Denoise 2.x ($GI_OIDN_LIBRARY, else `library_folders`, the copy found at build "
             "time, the system's); raises DenoiserUnavailable saying what to install.")
        .def_prop_ro("version", &Denoiser::version)
        .def_prop_ro("library_path", &Denoiser::libraryPath)
        .def(
            "denoise",
            [](Denoiser& denoiser, ImageArray color, ImageArray albedo, ImageArray normal, bool prefilterAux) {
                size_t w, h, aw, ah, nw, nh;
                std::vector<float> c = toVector(color, w, h), a = toVector(albedo, aw, ah), n = toVector(normal, nw, nh);
                if (aw != w || ah != h || nw != w || nh != h)
                    throw std::invalid_argument("denoise: colour, albedo and normal must be the same size");
                std::vector<float> out;
                {
                    nb::gil_scoped_release release;
                    out = denoiser.denoise(c, a, n, int(w), int(h), prefilterAux);
                }
                return toNumpy<3>(std::move(out), {h, w, 3});
            },
            "color"_a, "albedo"_a, "normal"_a, "prefilter_aux"_a = true,
            "The denoised (H, W, 3) colour; prefilter_aux denoises the albedo and normal first (final frames).");
}
