// Image textures read through OpenImageIO, with UsdUVTexture's wrap, scale/bias and
// UsdTransform2d semantics. Pixels are converted to linear float once, at load.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "math.h"

namespace gi {

struct TextureDesc {
    std::string file;  // empty = no texture
    std::string wrapS = "useMetadata", wrapT = "useMetadata";
    float scale[4] = {1, 1, 1, 1};
    float bias[4] = {0, 0, 0, 0};
    float fallback[4] = {0, 0, 0, 1};
    std::string channel = "rgb";  // rgb | r | g | b | a
    std::string sourceColorSpace = "auto";
    float stRotation = 0;  // degrees
    Vec2 stScale{1, 1};
    Vec2 stTranslation{0, 0};
};

class Image {
public:
    // Returns nullptr and sets `error` when the file cannot be read.
    static std::shared_ptr<Image> load(const std::string& path, const std::string& colorSpace, std::string& error);
    static std::shared_ptr<Image> fromPixels(int width, int height, std::vector<float> rgba);
    // 8-bit RGBA kept as bytes (a quarter of the memory, and of the cache misses); colour
    // channels decode through a table (sRGB or linear), alpha is linear.
    static std::shared_ptr<Image> fromBytes(int width, int height, std::vector<uint8_t> rgba, bool srgb);
    // Bilinear lookup; (u, v) with v = 0 at the bottom row, as USD's st.
    void lookup(float u, float v, int wrapS, int wrapT, float out[4]) const;
    int width() const { return width_; }
    int height() const { return height_; }
    // Linear RGBA of one texel.
    void texel(int x, int y, float out[4]) const {
        size_t i = (size_t(y) * width_ + x) * 4;
        if (bytes_.empty()) {
            for (int c = 0; c < 4; ++c) out[c] = pixels_[i + c];
            return;
        }
        for (int c = 0; c < 3; ++c) out[c] = decode_[bytes_[i + c]];
        out[3] = bytes_[i + 3] * (1.0f / 255);
    }
    size_t memoryBytes() const { return pixels_.size() * sizeof(float) + bytes_.size(); }

private:
    int width_ = 0, height_ = 0;
    std::vector<float> pixels_;   // RGBA, top row first (float and 16-bit images)
    std::vector<uint8_t> bytes_;  // RGBA, top row first (8-bit images)
    float decode_[256] = {};
};

enum WrapMode { kWrapRepeat = 0, kWrapMirror, kWrapClamp, kWrapBlack };
// UsdUVTexture's wrapS/wrapT token (black, clamp, repeat, mirror, useMetadata) as a WrapMode;
// false, and repeat, for any other token.
bool parseWrapMode(const std::string& token, int* mode);

// A bound texture: the image plus the descriptor's transforms, evaluated at an st coordinate.
struct Texture {
    std::shared_ptr<Image> image;
    TextureDesc desc;
    int wrapS = kWrapRepeat, wrapT = kWrapRepeat;
    int channelIndex = -1;  // -1 = rgb
    float st[2][3] = {{1, 0, 0}, {0, 1, 0}};  // UsdTransform2d as a 2x3 matrix

    void prepare();  // computes wrap modes, channel and the st matrix from `desc`
    bool valid() const { return image != nullptr; }
    Color evalColor(Vec2 uv) const;
    float evalFloat(Vec2 uv) const;
    void evalRaw(Vec2 uv, float out[4]) const;
};

}  // namespace gi
