// A material's shading network as both USD hosts hand it over, with no pxr types: hdGi converts
// Hydra's HdMaterialNetwork2 into it, the gi loader UsdShade's shaders (through gi._core). It only
// records what the stage says; what that means (which nodes and inputs are read, their defaults,
// the warnings) is decided once, by resolvePreviewSurface (preview_surface.h).
#pragma once
#include <array>
#include <map>
#include <string>
#include <variant>

namespace gi {

// An asset-valued input: the path as authored, and the file the host's asset resolver found for
// it ("" when it found none).
struct ShaderAsset {
    std::string authored, resolved;
};

// An authored constant input. Hosts hand numbers (bool, int, double) over as float, vectors of 2 to
// 4 components (float or double) as float arrays and tokens as strings; they leave out a value of
// any other type (the input then reads as unauthored).
using ShaderValue = std::variant<float, std::array<float, 2>, std::array<float, 3>, std::array<float, 4>, std::string,
                                 ShaderAsset>;

// The output of another node that drives an input.
struct ShaderConnection {
    std::string node;    // its path in the network
    std::string output;  // e.g. "rgb", "r", "result"
};

struct ShaderNode {
    std::string id;  // the shader's identifier, e.g. "UsdPreviewSurface"; "" when it names none
    // Inputs by name without the "inputs:" prefix. Connections are already followed through node
    // graphs and material interface inputs by the host (UsdImaging flattens them for Hydra; the
    // loader asks UsdShade for each input's value-producing attribute).
    std::map<std::string, ShaderValue> parameters;
    std::map<std::string, ShaderConnection> connections;
};

struct ShaderNetwork {
    std::map<std::string, ShaderNode> nodes;  // by prim path
};

}  // namespace gi
