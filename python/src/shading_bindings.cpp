// gi._core's shading networks: the `gi` loader describes each UsdShade material's network
// (renderer/shader_network.h) and resolves it by the rules hdGi uses (renderer/preview_surface.h).
#include <nanobind/nanobind.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "renderer/preview_surface.h"

namespace nb = nanobind;
using namespace nb::literals;

namespace {

using gi::ShaderAsset;
using gi::ShaderNetwork;
using gi::ShaderNode;
using gi::ShaderValue;

template <size_t N>
std::array<float, N> floatsOf(nb::sequence values) {
    std::array<float, N> out;
    for (size_t i = 0; i < N; ++i) out[i] = float(nb::cast<double>(nb::float_(values[i])));
    return out;
}

// A Python constant as the description holds it: a number (bool and int too) as float, a tuple or
// list of 2 to 4 numbers as floats, a str, a ShaderAsset.
ShaderValue shaderValueOf(nb::handle value) {
    if (nb::isinstance<ShaderAsset>(value)) return nb::cast<ShaderAsset>(value);
    if (nb::isinstance<nb::str>(value)) return nb::cast<std::string>(value);
    if (nb::isinstance<nb::bool_>(value) || nb::isinstance<nb::int_>(value) || nb::isinstance<nb::float_>(value))
        return float(nb::cast<double>(nb::float_(value)));
    if (nb::isinstance<nb::tuple>(value) || nb::isinstance<nb::list>(value)) {
        nb::sequence values = nb::borrow<nb::sequence>(value);
        switch (nb::len(values)) {
            case 2: return floatsOf<2>(values);
            case 3: return floatsOf<3>(values);
            case 4: return floatsOf<4>(values);
        }
    }
    throw nb::type_error(("a shader input holds a number, 2 to 4 numbers, a str or a ShaderAsset, not " +
                          std::string(nb::type_name(value.type()).c_str()))
                             .c_str());
}

nb::object resolve(const std::string& materialPath, const ShaderNetwork& network, const std::string& surface,
                   const gi::ShadingWarning& warn) {
    std::optional<gi::PreviewSurface> s = gi::resolvePreviewSurface(materialPath, network, surface, warn);
    if (!s) return nb::none();
    std::vector<std::pair<std::string, std::string>> files;
    for (const ShaderAsset& f : s->textureFiles) files.emplace_back(f.authored, f.resolved);
    return nb::make_tuple(s->material, s->readerVarnames, files);
}

}  // namespace

void bindShading(nb::module_& m) {
    nb::class_<ShaderAsset>(m, "ShaderAsset")
        .def(nb::init<>())
        .def("__init__", [](ShaderAsset* a, std::string authored, std::string resolved) {
            new (a) ShaderAsset{std::move(authored), std::move(resolved)};
        }, "authored"_a, "resolved"_a)
        .def_rw("authored", &ShaderAsset::authored)
        .def_rw("resolved", &ShaderAsset::resolved);
    nb::class_<ShaderNode>(m, "ShaderNode")
        .def(nb::init<>())
        .def("__init__", [](ShaderNode* n, std::string id) { new (n) ShaderNode{std::move(id), {}, {}}; }, "id"_a)
        .def_rw("id", &ShaderNode::id)
        .def("set", [](ShaderNode& n, const std::string& input, nb::handle value) { n.parameters[input] = shaderValueOf(value); },
             "input"_a, "value"_a, "An authored constant on input `input` (without 'inputs:').")
        .def("connect", [](ShaderNode& n, const std::string& input, std::string node, std::string output) {
            n.connections[input] = {std::move(node), std::move(output)};
        }, "input"_a, "node"_a, "output"_a, "Input `input` driven by output `output` of the node at path `node`.");
    nb::class_<ShaderNetwork>(m, "ShaderNetwork")
        .def(nb::init<>())
        .def("add", [](ShaderNetwork& n, const std::string& path, const ShaderNode& node) { n.nodes[path] = node; },
             "path"_a, "node"_a)
        .def("__contains__", [](const ShaderNetwork& n, const std::string& path) { return n.nodes.count(path) > 0; });
    m.def("resolve_preview_surface", &resolve, "material_path"_a, "network"_a, "surface"_a, "warn"_a,
          "The material whose surface output node `surface` ('' for none) drives (renderer/preview_surface.h, "
          "the rules hdGi shares): (MaterialDesc, reader varnames, [(authored, resolved) texture files]), or None "
          "after warn(material_path, message) when it is not a UsdPreviewSurface.");
}
