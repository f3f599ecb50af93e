// A UsdPreviewSurface network (UsdPreviewSurface, UsdUVTexture, UsdTransform2d,
// UsdPrimvarReader_float2) resolved into the renderer's MaterialDesc: the one place both USD hosts
// take their shading rules from (hdGi from Hydra's material networks, the gi loader from UsdShade
// through gi._core). Each rule is UsdImaging's as Storm draws it (OpenUSD 24.11) unless its comment
// in preview_surface.cpp says otherwise.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "material.h"
#include "shader_network.h"

namespace gi {

struct PreviewSurface {
    MaterialDesc material;
    // The primvars its textures' UsdPrimvarReader_float2 nodes read (varname), each once, in the
    // order of the UsdPreviewSurface inputs they feed (usd_shading.h's uvPrimvarOf picks among them).
    std::vector<std::string> readerVarnames;
    // The UsdUVTexture files it names, each once (for reports: `gi inspect` lists missing ones).
    std::vector<ShaderAsset> textureFiles;
};

// A problem with the network: `path` is the material's, `message` names the node and input.
// Each message is reported once per call (one missing file feeding several inputs is one problem).
using ShadingWarning = std::function<void(const std::string& path, const std::string& message)>;

// The material `materialPath` whose surface output is driven by node `surface` of `network` ("":
// by nothing). Unauthored inputs keep MaterialDesc's and TextureDesc's defaults (the spec's,
// material.h and texture.h). nullopt, after a warning, when `surface` is not a UsdPreviewSurface:
// the gprim then shades with its displayColor (usd_shading.h's displayColorMaterial).
std::optional<PreviewSurface> resolvePreviewSurface(const std::string& materialPath, const ShaderNetwork& network,
                                                    const std::string& surface, const ShadingWarning& warn);

}  // namespace gi
