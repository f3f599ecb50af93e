// Image files through OpenImageIO: linear EXR (color plus AOV layers and metadata), 8-bit
// display-referred PNG, and reading any format OIIO knows.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace gi {

struct ImageLayer {
    std::string name;                  // "" for the main RGB, else a prefix like "N" or "albedo"
    std::vector<std::string> channels;  // e.g. {"R","G","B"} or {"Z"}
    const float* pixels;               // width*height*channels.size(), row 0 at the top
    bool half = false;                 // stored as 16-bit half floats (else 32-bit floats)
};

// Where a width x height image lies in a larger one (EXR's data window in its display window):
// its top-left pixel at (x, y) of a fullWidth x fullHeight image. fullWidth 0: the whole image.
struct DataWindow {
    int x = 0, y = 0, fullWidth = 0, fullHeight = 0;
};

// Throws std::runtime_error naming the file on failure.
void writeExr(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
              const std::map<std::string, std::string>& metadata, const DataWindow& window = {});
void writePng8(const std::string& path, int width, int height, const std::vector<float>& displayRgb);

struct LoadedImage {
    int width = 0, height = 0, channels = 0;  // the data window's size
    DataWindow window;                        // where it lies in the display window
    std::vector<float> pixels;
    std::vector<std::string> channelNames;
    std::vector<std::string> channelFormats;  // per channel as stored: "half", "float", "uint", ...
    std::map<std::string, std::string> metadata;
};
LoadedImage readImage(const std::string& path);

}  // namespace gi
