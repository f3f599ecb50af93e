// OpenColorIO display transforms: $OCIO if set, else the config shipped with hdGi.
#pragma once
#include <string>
#include <vector>

namespace gi {

// Converts linear scene RGB (W*H*3) to display RGB in [0,1] through a display/view of the
// config. Empty display/view select the config's defaults. Throws std::runtime_error with
// OCIO's message on a bad config, display or view.
std::vector<float> applyDisplayTransform(const std::vector<float>& rgb, int width, int height,
                                         const std::string& configPath, const std::string& display,
                                         const std::string& view, float exposureStops);

// The config that would be used: $OCIO, else `fallback`.
std::string resolveOcioConfig(const std::string& fallback);

}  // namespace gi
