// UsdRender products through Hydra: the active render settings' RenderProducts, written by the
// render thread when a render converges, each as one EXR with its RenderVars as named channels
// (renderer/render_vars.h: the rules `gi render` follows for the same products). usdrecord with
// render settings checks that these files exist instead of writing its own image.
#pragma once
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pxr/imaging/hd/renderSettings.h"
#include "pxr/pxr.h"
#include "renderer/pixel_window.h"
#include "renderer/render_vars.h"

PXR_NAMESPACE_OPEN_SCOPE

// One output of the render at its resolution: outputComponents(output) floats per pixel, row 0
// at the top.
using HdGiOutputPixels = std::function<std::vector<float>(gi::RenderOutput output)>;

// Writes every product at the render's width x height, its pixels inside `window` (the product's
// dataWindowNDC as pixels, renderer/pixel_window.h; the whole image when empty) as the file's
// data window. `frame`: the time code rendered (HdUtils::GetCurrentFrame), which names the
// file when its productName has frame tokens (renderer/render_vars.h's substitution, as `gi
// render` names its frames); none: the name is kept as it is, with a warning. Warns (once per
// message, through `warn`) about what it cannot honour: a var the renderer cannot write
// (skipped), a resolution other than the render's.
void HdGiWriteProducts(HdRenderSettings::RenderProducts const& products, int width, int height,
                       gi::PixelWindow const& window, std::optional<double> frame, HdGiOutputPixels const& pixels,
                       std::map<std::string, std::string> const& metadata,
                       std::function<void(std::string const&)> const& warn);

// The pixels of a width x height render the product's dataWindowNDC holds (renderer/pixel_window.h,
// `gi render`'s rule); *problem (when given) set to a sentence for a warning when it reaches
// outside the image (clipped) or holds no pixel (the whole image).
gi::PixelWindow HdGiProductWindow(HdRenderSettings::RenderProduct const& product, int width, int height,
                                  std::string* problem);

// The file name a productName writes at `frame` (its frame tokens replaced), or *problem set
// (a sentence naming the token, for a warning) and the name as it is.
std::string HdGiProductFileName(std::string const& productName, std::optional<double> frame, std::string* problem);

PXR_NAMESPACE_CLOSE_SCOPE
