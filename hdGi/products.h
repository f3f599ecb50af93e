// UsdRender products through Hydra: the active render settings' RenderProducts, written by the
// render thread when a render converges, each as one EXR with its RenderVars as named channels
// (renderer/render_vars.h: the rules `gi render` follows for the same products). usdrecord with
// render settings checks that these files exist instead of writing its own image.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "pxr/imaging/hd/renderSettings.h"
#include "pxr/pxr.h"
#include "renderer/render_vars.h"

PXR_NAMESPACE_OPEN_SCOPE

// One output of the render at its resolution: outputComponents(output) floats per pixel, row 0
// at the top.
using HdGiOutputPixels = std::function<std::vector<float>(gi::RenderOutput output)>;

// Writes every product at the render's width x height; warns (once per message, through `warn`)
// about what it cannot honour: a var the renderer cannot write (skipped), a resolution other than
// the render's, frame tokens in a productName (Hydra gives the delegate no frame number).
void HdGiWriteProducts(HdRenderSettings::RenderProducts const& products, int width, int height,
                       HdGiOutputPixels const& pixels, std::map<std::string, std::string> const& metadata,
                       std::function<void(std::string const&)> const& warn);

PXR_NAMESPACE_CLOSE_SCOPE
