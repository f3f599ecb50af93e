#include "texture.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace gi {

namespace {

float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Maps an integer texel coordinate into range; returns false for 'black' outside the image.
[[gnu::always_inline]] inline bool wrapCoordinate(int& i, int n, int mode) {
    if (i >= 0 && i < n) return true;
    switch (mode) {
        case kWrapClamp: i = std::clamp(i, 0, n - 1); return true;
        case kWrapBlack: return false;
        case kWrapMirror: {
            int period = 2 * n;
            int m = i % period;  // one integer division: each is about 25 cycles
            if (m < 0) m += period;
            i = m < n ? m : period - 1 - m;
            return true;
        }
        default:
            i %= n;
            if (i < 0) i += n;
            return true;
    }
}

}  // namespace

bool parseWrapMode(const std::string& token, int* mode) {
    *mode = token == "mirror" ? kWrapMirror : token == "clamp" ? kWrapClamp : token == "black" ? kWrapBlack : kWrapRepeat;
    // useMetadata reads the image's own wrap metadata, which no format we read carries: UsdUVTexture
    // falls back to repeat.
    return *mode != kWrapRepeat || token == "repeat" || token == "useMetadata";
}

namespace {
// Widens 1-4 channels to RGBA: grey to RGB, grey+alpha, extra channels dropped.
template <typename T>
void widenToRgba(const T* s, int nc, T opaque, T* d) {
    d[0] = s[0];
    d[1] = nc >= 3 ? s[1] : s[0];
    d[2] = nc >= 3 ? s[2] : s[0];
    d[3] = nc == 2 ? s[1] : (nc >= 4 ? s[3] : opaque);
}
}  // namespace

std::shared_ptr<Image> Image::load(const std::string& path, const std::string& colorSpace, std::string& error) {
    // Colour stays as stored (PNG's straight alpha): OIIO would premultiply it by default,
    // darkening every partly transparent texel's colour.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageBuf buf(path, 0, 0, nullptr, &config);
    if (!buf.init_spec(path, 0, 0)) {
        error = buf.geterror();
        if (error.empty()) error = "cannot read image";
        return nullptr;
    }
    bool eightBit = buf.spec().format.basetype == OIIO::TypeDesc::UINT8;
    if (!buf.read(0, 0, true, eightBit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT)) {
        error = buf.geterror();
        if (error.empty()) error = "cannot read image";
        return nullptr;
    }
    const OIIO::ImageSpec& spec = buf.spec();
    int w = spec.width, h = spec.height, nc = spec.nchannels;
    // 'auto' treats 8-bit images as sRGB-encoded and float images as linear (UsdUVTexture's rule).
    bool isFloat = spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF;
    bool decodeSrgb = colorSpace == "sRGB" || (colorSpace != "raw" && !isFloat);
    if (eightBit) {
        std::vector<uint8_t> src(size_t(w) * h * nc), rgba(size_t(w) * h * 4);
        buf.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, nc), OIIO::TypeDesc::UINT8, src.data());
        for (size_t p = 0; p < size_t(w) * h; ++p) widenToRgba(&src[p * nc], nc, uint8_t(255), &rgba[p * 4]);
        return fromBytes(w, h, std::move(rgba), decodeSrgb);
    }
    std::vector<float> src(size_t(w) * h * nc);
    buf.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, nc), OIIO::TypeDesc::FLOAT, src.data());
    std::vector<float> rgba(size_t(w) * h * 4);
    for (size_t p = 0; p < size_t(w) * h; ++p) {
        float* d = &rgba[p * 4];
        widenToRgba(&src[p * nc], nc, 1.0f, d);
        for (int c = 0; c < 4; ++c) {
            if (decodeSrgb && c < 3) d[c] = srgbToLinear(d[c]);
            if (!std::isfinite(d[c])) d[c] = c < 3 ? 0.0f : 1.0f;
        }
    }
    return fromPixels(w, h, std::move(rgba));
}

std::shared_ptr<Image> Image::fromBytes(int width, int height, std::vector<uint8_t> rgba, bool srgb) {
    auto image = std::make_shared<Image>();
    image->bytes_ = std::move(rgba);
    for (int v = 0; v < 256; ++v) image->decode_[v] = srgb ? srgbToLinear(v / 255.0f) : v / 255.0f;
    image->buildLevels(width, height);
    return image;
}

std::shared_ptr<Image> Image::fromPixels(int width, int height, std::vector<float> rgba) {
    auto image = std::make_shared<Image>();
    image->pixels_ = std::move(rgba);
    image->buildLevels(width, height);
    return image;
}

void Image::lookup(float u, float v, int wrapS, int wrapT, float out[4], float footprint) const {
    // The level where the footprint spans one to two texels along the image's longer side.
    int level = 0;
    const float texels = footprint * float(std::max(levels_[0].width, levels_[0].height));
    if (texels >= 2 && std::isfinite(texels)) level = std::min(int(levels_.size()) - 1, std::ilogb(texels));
    const int width = levels_[size_t(level)].width, height = levels_[size_t(level)].height;
    // Texel centres at half-integers; v flipped because row 0 is the top of the file.
    float x = u * width - 0.5f, y = (1 - v) * height - 0.5f;
    if (!std::isfinite(x) || !std::isfinite(y)) x = y = 0;
    x = std::clamp(x, -1e7f, 1e7f);
    y = std::clamp(y, -1e7f, 1e7f);
    int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    float fx = x - x0, fy = y - y0;
    for (int c = 0; c < 4; ++c) out[c] = 0;
    // Rows and columns wrapped once, not per texel: the four texels' coordinates, or -1 for black.
    int xs[2] = {x0, x0 + 1}, ys[2] = {y0, y0 + 1};
    for (int i = 0; i < 2; ++i) {
        if (!wrapCoordinate(xs[i], width, wrapS)) xs[i] = -1;
        if (!wrapCoordinate(ys[i], height, wrapT)) ys[i] = -1;
    }
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            int xi = xs[dx], yi = ys[dy];
            float w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
            if (xi < 0 || yi < 0) continue;
            float t[4];
            texel(level, xi, yi, t);
            for (int c = 0; c < 4; ++c) out[c] += w * t[c];
        }
}

void Texture::prepare() {
    parseWrapMode(desc.wrapS, &wrapS);
    parseWrapMode(desc.wrapT, &wrapT);
    const std::string& c = desc.channel;
    channelIndex = c == "r" ? 0 : c == "g" ? 1 : c == "b" ? 2 : c == "a" ? 3 : -1;
    // UsdTransform2d: st' = R(rotation) * (st * scale) + translation.
    float rad = desc.stRotation * kPi / 180.0f;
    float cs = std::cos(rad), sn = std::sin(rad);
    st[0][0] = cs * desc.stScale.x;
    st[0][1] = -sn * desc.stScale.y;
    st[0][2] = desc.stTranslation.x;
    st[1][0] = sn * desc.stScale.x;
    st[1][1] = cs * desc.stScale.y;
    st[1][2] = desc.stTranslation.y;
    stScale = std::sqrt(std::fabs(st[0][0] * st[1][1] - st[0][1] * st[1][0]));
}

bool isUdimPath(const std::string& file) { return file.find(kUdimToken) != std::string::npos; }

std::string udimTilePath(const std::string& pattern, int tile) {
    std::string path = pattern;
    for (size_t at = path.find(kUdimToken); at != std::string::npos; at = path.find(kUdimToken, at))
        path.replace(at, std::string(kUdimToken).size(), std::to_string(tile));
    return path;
}

void Texture::evalRaw(Vec2 uv, float out[4], float footprint) const {
    float u = st[0][0] * uv.x + st[0][1] * uv.y + st[0][2];
    float v = st[1][0] * uv.x + st[1][1] * uv.y + st[1][2];
    const Image* source = image.get();
    int sWrap = wrapS, tWrap = wrapT;
    if (!udimTiles.empty()) {  // the tile under (u, v), read in its own [0, 1)^2, clamped at its edges
        float column = std::floor(u), row = std::floor(v);
        source = column >= 0 && column < kUdimColumns && row >= 0 && row < kUdimTiles / kUdimColumns
                     ? udimTiles[size_t(row) * kUdimColumns + size_t(column)].get()
                     : nullptr;
        if (!source) {  // no tile there: UsdUVTexture's fallback, as for a file that cannot be read
            for (int c = 0; c < 4; ++c) out[c] = desc.fallback[c];
            return;
        }
        u -= column, v -= row;
        sWrap = tWrap = kWrapClamp;
    }
    source->lookup(u, v, sWrap, tWrap, out, footprint * stScale);
    for (int c = 0; c < 4; ++c) out[c] = out[c] * desc.scale[c] + desc.bias[c];
}

Color Texture::evalColor(Vec2 uv, float footprint) const {
    float t[4];
    evalRaw(uv, t, footprint);
    if (channelIndex >= 0) return Color(t[channelIndex]);
    return {t[0], t[1], t[2]};
}

float Texture::evalFloat(Vec2 uv, float footprint) const {
    float t[4];
    evalRaw(uv, t, footprint);
    return t[channelIndex >= 0 ? channelIndex : 0];
}

}  // namespace gi
