#include "color.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace OCIO = OCIO_NAMESPACE;

namespace gi {

std::string resolveOcioConfig(const std::string& fallback) {
    const char* env = std::getenv("OCIO");
    return env && *env ? std::string(env) : fallback;
}

std::vector<float> applyDisplayTransform(const std::vector<float>& rgb, int width, int height,
                                         const std::string& configPath, const std::string& display,
                                         const std::string& view, float exposureStops) {
    try {
        std::string path = resolveOcioConfig(configPath);
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
        std::string disp = display.empty() ? config->getDefaultDisplay() : display;
        std::string v = view.empty() ? config->getDefaultView(disp.c_str()) : view;
        auto transform = OCIO::DisplayViewTransform::Create();
        transform->setSrc(OCIO::ROLE_SCENE_LINEAR);
        transform->setDisplay(disp.c_str());
        transform->setView(v.c_str());
        OCIO::ConstProcessorRcPtr processor = config->getProcessor(transform);
        OCIO::ConstCPUProcessorRcPtr cpu = processor->getDefaultCPUProcessor();
        std::vector<float> out(rgb);
        float gain = std::exp2(exposureStops);
        for (float& x : out) x = std::isfinite(x) ? x * gain : 0.0f;
        OCIO::PackedImageDesc image(out.data(), width, height, 3);
        cpu->apply(image);
        for (float& x : out) x = std::isfinite(x) ? std::min(1.0f, std::max(0.0f, x)) : 0.0f;
        return out;
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("OpenColorIO: ") + e.what());
    }
}

}  // namespace gi
