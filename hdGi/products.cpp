#include "products.h"

#include <cmath>
#include <limits>
#include <list>

#include "renderer/image_io.h"

PXR_NAMESPACE_OPEN_SCOPE

std::string HdGiProductFileName(std::string const& productName, std::optional<double> frame, std::string* problem) {
    problem->clear();
    if (!gi::hasFrameToken(productName)) return productName;
    if (!frame) {
        *problem = "productName '" + productName + "' has frame tokens, but the host sets no current frame "
                   "(sceneGlobals' currentFrame); written under that name as it is";
        return productName;
    }
    double const number = std::round(*frame);
    if (number != *frame)
        *problem = "productName '" + productName + "' names frames by whole numbers; frame " + std::to_string(*frame) +
                   " is written as frame " + std::to_string(int(number));
    return gi::substituteFrame(productName, int(number));
}

gi::PixelWindow HdGiProductWindow(HdRenderSettings::RenderProduct const& product, int width, int height,
                                  std::string* problem) {
    GfRange2f const& ndc = product.dataWindowNDC;
    std::string ignored;
    gi::PixelWindow const window = gi::dataWindowPixels(ndc.GetMin()[0], ndc.GetMin()[1], ndc.GetMax()[0],
                                                        ndc.GetMax()[1], width, height, problem ? problem : &ignored);
    return window;
}

void HdGiWriteProducts(HdRenderSettings::RenderProducts const& products, int width, int height,
                       gi::PixelWindow const& window, std::optional<double> frame, HdGiOutputPixels const& pixels,
                       std::map<std::string, std::string> const& metadata,
                       std::function<void(std::string const&)> const& warn) {
    gi::PixelWindow const area = window.empty() ? gi::PixelWindow{0, 0, width, height} : window;
    int const areaWidth = area.x1 - area.x0, areaHeight = area.y1 - area.y0;
    std::map<gi::RenderOutput, std::vector<float>> outputs;  // each computed once for all products
    auto output = [&](gi::RenderOutput o) -> std::vector<float> const& {
        auto it = outputs.find(o);
        if (it != outputs.end()) return it->second;
        std::vector<float> values = pixels(o);
        if (o == gi::RenderOutput::Depth)  // no Inf in the file, as `gi render` writes it
            for (float& v : values)
                if (!std::isfinite(v)) v = std::numeric_limits<float>::max();
        return outputs.emplace(o, std::move(values)).first->second;
    };
    for (HdRenderSettings::RenderProduct const& product : products) {
        std::string const where = "render product " + product.productPath.GetString();
        if (product.name.IsEmpty()) {
            warn(where + ": no productName; not written");
            continue;
        }
        std::string nameProblem;
        std::string const path = HdGiProductFileName(product.name.GetString(), frame, &nameProblem);
        if (!nameProblem.empty()) warn(where + ": " + nameProblem);
        if (HdGiProductWindow(product, width, height, nullptr) != area)
            warn(where + ": dataWindowNDC differs from the first product's, whose pixels the render makes; written "
                 "with the first product's data window");
        if (product.resolution != GfVec2i(0) && product.resolution != GfVec2i(width, height))
            warn(where + ": resolution " + std::to_string(product.resolution[0]) + "x" +
                 std::to_string(product.resolution[1]) + " is not the render's; written at " + std::to_string(width) +
                 "x" + std::to_string(height));
        std::list<std::vector<float>> planes;  // one per channel, alive until written
        std::vector<gi::ImageLayer> layers;
        bool beautyTaken = false;
        for (HdRenderSettings::RenderProduct::RenderVar const& var : product.renderVars) {
            std::string problem;
            std::optional<gi::RenderVarLayout> layout = gi::renderVarLayout(var.sourceName, var.dataType.GetString(), &problem);
            if (!layout) {
                warn("render var " + var.varPath.GetString() + ": " + problem + "; var skipped");
                continue;
            }
            std::string layer = gi::renderVarLayer(var.varPath.GetName(), layout->output, beautyTaken);
            beautyTaken = beautyTaken || layout->output == gi::RenderOutput::Color;
            std::vector<float> const& values = output(layout->output);
            size_t const components = layout->suffixes.size();
            for (size_t c = 0; c < components; ++c) {
                std::vector<float>& plane = planes.emplace_back(size_t(areaWidth) * size_t(areaHeight));
                for (int y = 0; y < areaHeight; ++y)
                    for (int x = 0; x < areaWidth; ++x) {
                        size_t const pixel = size_t(area.y0 + y) * size_t(width) + size_t(area.x0 + x);
                        plane[size_t(y) * size_t(areaWidth) + size_t(x)] = values[pixel * components + c];
                    }
                layers.push_back({"", {gi::channelName(layer, layout->suffixes[c])}, plane.data(), layout->half});
            }
        }
        if (layers.empty()) {
            warn(where + ": no render var this renderer can write; not written");
            continue;
        }
        std::map<std::string, std::string> fileMetadata = metadata;
        fileMetadata["gi:product"] = product.productPath.GetString();
        try {
            // The data window in the whole image's display window, as `gi render` writes it.
            gi::DataWindow placed;
            if (areaWidth != width || areaHeight != height) placed = gi::DataWindow{area.x0, area.y0, width, height};
            gi::writeExr(path, areaWidth, areaHeight, layers, fileMetadata, placed);
        } catch (std::exception const& e) {
            warn(where + ": " + e.what());
        }
    }
}

PXR_NAMESPACE_CLOSE_SCOPE
