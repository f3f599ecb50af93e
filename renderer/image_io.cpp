#include "image_io.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <stdexcept>

namespace gi {

void writeExr(const std::string& path, int width, int height, const std::vector<ImageLayer>& layers,
              const std::map<std::string, std::string>& metadata, const DataWindow& window) {
    std::vector<std::string> names;
    std::vector<OIIO::TypeDesc> formats;
    bool anyHalf = false;
    for (const ImageLayer& l : layers)
        for (const std::string& c : l.channels) {
            names.push_back(l.name.empty() ? c : l.name + "." + c);
            formats.push_back(l.half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
            anyHalf = anyHalf || l.half;
        }
    int nc = int(names.size());
    OIIO::ImageSpec spec(width, height, nc, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    if (anyHalf) spec.channelformats = formats;  // EXR keeps a type per channel
    if (window.fullWidth > 0) {
        spec.x = window.x, spec.y = window.y;
        spec.full_x = spec.full_y = 0;
        spec.full_width = window.fullWidth, spec.full_height = window.fullHeight;
    }
    spec.attribute("compression", "zip");
    for (const auto& [key, value] : metadata) spec.attribute(key, value);
    std::vector<float> interleaved(size_t(width) * height * nc);
    int offset = 0;
    for (const ImageLayer& l : layers) {
        int lc = int(l.channels.size());
        for (size_t p = 0; p < size_t(width) * height; ++p)
            for (int c = 0; c < lc; ++c) interleaved[p * nc + offset + c] = l.pixels[p * lc + c];
        offset += lc;
    }
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": cannot create an image writer: " + OIIO::geterror());
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, interleaved.data()) || !out->close())
        throw std::runtime_error(path + ": " + out->geterror());
}

void writePng8(const std::string& path, int width, int height, const std::vector<float>& displayRgb) {
    std::vector<unsigned char> bytes(displayRgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) {
        float v = std::isfinite(displayRgb[i]) ? std::min(1.0f, std::max(0.0f, displayRgb[i])) : 0.0f;
        bytes[i] = (unsigned char)std::lround(v * 255.0f);
    }
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": cannot create an image writer: " + OIIO::geterror());
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) || !out->close())
        throw std::runtime_error(path + ": " + out->geterror());
}

LoadedImage readImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error(path + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    LoadedImage img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.channelNames = spec.channelnames;
    for (int c = 0; c < spec.nchannels; ++c) img.channelFormats.push_back(spec.channelformat(c).c_str());
    img.window = DataWindow{spec.x - spec.full_x, spec.y - spec.full_y, spec.full_width, spec.full_height};
    img.pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw std::runtime_error(path + ": " + in->geterror());
    for (const OIIO::ParamValue& p : spec.extra_attribs) img.metadata[p.name().string()] = p.get_string();
    in->close();
    return img;
}

}  // namespace gi
