// Image textures read through OpenImageIO, with UsdUVTexture's wrap, scale/bias and
// UsdTransform2d semantics. Pixels are converted to linear float once, at load.
#pragma once
#include <cstdint>
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
    // Bilinear lookup; (u, v) with v = 0 at the bottom row, as USD's st. `footprint` is the
    // lookup's width in (u, v) units: the level of the image's MIP chain whose texels it spans
    // one to two of is read (0: the image itself).
    void lookup(float u, float v, int wrapS, int wrapT, float out[4], float footprint = 0) const;
    int width() const { return levels_.empty() ? 0 : levels_[0].width; }
    int height() const { return levels_.empty() ? 0 : levels_[0].height; }
    int levels() const { return int(levels_.size()); }
    // Linear RGBA of one texel of a level.
    void texel(int level, int x, int y, float out[4]) const {
        const Level& l = levels_[size_t(level)];
        size_t i = (l.offset + size_t(y) * l.width + x) * 4;
        if (!pixels_.empty()) {
            for (int c = 0; c < 4; ++c) out[c] = pixels_[i + c];
        } else if (level == 0) {
            for (int c = 0; c < 3; ++c) out[c] = decode_[bytes_[i + c]];
            out[3] = bytes_[i + 3] * (1.0f / 255);
        } else {
            for (int c = 0; c < 4; ++c) out[c] = coarse_[i + c] * (1.0f / 65535);
        }
    }
    void texel(int x, int y, float out[4]) const { texel(0, x, y, out); }
    size_t memoryBytes() const {
        return pixels_.size() * sizeof(float) + bytes_.size() + coarse_.size() * sizeof(uint16_t);
    }

private:
    // The MIP chain, made at load (texture_mips.cpp): level 0 is the image, each next one half
    // its size (at least 1), every level's texels after the previous one's: in pixels_ for a
    // float image; for an 8-bit one the coarser levels in coarse_, linear in 16 bits (8-bit
    // codes rounded again at every level brightened Sibenik's stone by 0.6% at its last).
    struct Level {
        int width = 0, height = 0;
        size_t offset = 0;  // in texels, into the array that holds the level
    };
    void buildLevels(int width, int height);
    std::vector<Level> levels_;
    std::vector<float> pixels_;   // RGBA, top row first (float and 16-bit images)
    std::vector<uint8_t> bytes_;  // RGBA, top row first (8-bit images)
    std::vector<uint16_t> coarse_;  // RGBA of an 8-bit image's levels past the first
    float decode_[256] = {};
};

enum WrapMode { kWrapRepeat = 0, kWrapMirror, kWrapClamp, kWrapBlack };
// UsdUVTexture's wrapS/wrapT token (black, clamp, repeat, mirror, useMetadata) as a WrapMode;
// false, and repeat, for any other token.
bool parseWrapMode(const std::string& token, int* mode);

// A file path with a UDIM pattern (tiles 1001-1100: tile 1001 + u + 10 v covers st [u, u+1) x [v, v+1)).
inline constexpr const char* kUdimToken = "<UDIM>";
inline constexpr int kUdimFirstTile = 1001, kUdimColumns = 10, kUdimTiles = 100;
bool isUdimPath(const std::string& file);
std::string udimTilePath(const std::string& pattern, int tile);  // the pattern with its tile number

// A bound texture: the image plus the descriptor's transforms, evaluated at an st coordinate.
struct Texture {
    std::shared_ptr<Image> image;  // the image; for UDIM tiles the first one found
    // A UDIM texture's tiles (kUdimTiles, 1001 first; null where the file has none); empty otherwise.
    // Each tile is read clamped at its edges, and st outside every tile found reads the fallback.
    std::vector<std::shared_ptr<Image>> udimTiles;
    TextureDesc desc;
    int wrapS = kWrapRepeat, wrapT = kWrapRepeat;
    int channelIndex = -1;  // -1 = rgb
    float st[2][3] = {{1, 0, 0}, {0, 1, 0}};  // UsdTransform2d as a 2x3 matrix
    float stScale = 1;                        // how much the matrix scales a footprint

    void prepare();  // computes wrap modes, channel and the st matrix from `desc`
    bool valid() const { return image != nullptr; }
    // `footprint`: the lookup's width in the primvar's (u, v) units (Image::lookup).
    Color evalColor(Vec2 uv, float footprint = 0) const;
    float evalFloat(Vec2 uv, float footprint = 0) const;
    void evalRaw(Vec2 uv, float out[4], float footprint = 0) const;
};

}  // namespace gi
