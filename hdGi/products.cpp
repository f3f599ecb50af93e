#include "products.h"

#include <cmath>
#include <limits>
#include <list>

#include "renderer/image_io.h"

PXR_NAMESPACE_OPEN_SCOPE

void HdGiWriteProducts(HdRenderSettings::RenderProducts const& products, int width, int height,
                       HdGiOutputPixels const& pixels, std::map<std::string, std::string> const& metadata,
                       std::function<void(std::string const&)> const& warn) {
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
        std::string const path = product.name.GetString();
        std::string const where = "render product " + product.productPath.GetString();
        if (path.empty()) {
            warn(where + ": no productName; not written");
            continue;
        }
        if (gi::hasFrameToken(path))
            warn(where + ": productName '" + path + "' has frame tokens, but Hydra gives the delegate no frame "
                 "number; written under that name as it is");
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
                std::vector<float>& plane = planes.emplace_back(size_t(width) * size_t(height));
                for (size_t i = 0; i < plane.size(); ++i) plane[i] = values[i * components + c];
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
            gi::writeExr(path, width, height, layers, fileMetadata);
        } catch (std::exception const& e) {
            warn(where + ": " + e.what());
        }
    }
}

PXR_NAMESPACE_CLOSE_SCOPE
