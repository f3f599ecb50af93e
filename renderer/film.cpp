#include "film.h"

namespace gi {

Filter Filter::byName(const std::string& name) {
    Filter f;
    if (name == "gaussian") {
        f.name = name;
        f.radius = 1.5f;
        f.sigma = 0.5f;
    }
    return f;
}

float Filter::weight(float dx, float dy) const {
    if (name == "box") return (std::fabs(dx) <= radius && std::fabs(dy) <= radius) ? 1.0f : 0.0f;
    auto g = [&](float d) {
        float edge = std::exp(-radius * radius / (2 * sigma * sigma));
        return std::max(0.0f, std::exp(-d * d / (2 * sigma * sigma)) - edge);
    };
    return g(dx) * g(dy);
}

FilmTile::FilmTile(int x0_, int y0_, int x1_, int y1_, const Filter& filter)
    : x0(x0_), y0(y0_), x1(x1_), y1(y1_), filter_(filter) {
    int pad = filter.name == "box" ? 0 : int(std::ceil(filter.radius - 0.5f));
    px0 = x0 - pad, py0 = y0 - pad, px1 = x1 + pad, py1 = y1 + pad;
    pixels.resize(size_t(px1 - px0) * (py1 - py0));
}

void FilmTile::addSample(float filmX, float filmY, const Color& L, const SampleAovs& aovs) {
    // x + u rounds up to x + 1 in float for large x and u close to 1: keep the sample in the
    // pixel it was drawn for.
    int cx = std::clamp(int(std::floor(filmX)), x0, x1 - 1), cy = std::clamp(int(std::floor(filmY)), y0, y1 - 1);
    auto accumulateAovs = [&](Pixel& p) {
        p.aovWeight += 1;
        float dx = filmX - (cx + 0.5f), dy = filmY - (cy + 0.5f);
        if (aovs.hit && dx * dx + dy * dy < p.idDistance2) {
            p.idDistance2 = dx * dx + dy * dy;
            p.shapeId = aovs.shapeId;
            p.instanceId = aovs.instanceId;
        }
        for (int c = 0; c < 3; ++c) {
            p.normal[c] += aovs.normal[c];
            p.albedo[c] += aovs.albedo[c];
        }
        if (aovs.hit && std::isfinite(aovs.depth)) {
            p.depth += aovs.depth;
            p.depthCount += 1;
        }
    };
    if (filter_.name == "box") {  // the common case: one pixel, weight 1
        Pixel& p = pixels[size_t(cy - py0) * (px1 - px0) + (cx - px0)];
        for (int c = 0; c < 3; ++c) p.color[c] += L[c];
        p.weight += 1;
        accumulateAovs(p);
        return;
    }
    int r = int(std::ceil(filter_.radius - 0.5f));
    for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x) {
            if (x < px0 || x >= px1 || y < py0 || y >= py1) continue;
            float w = filter_.weight(x + 0.5f - filmX, y + 0.5f - filmY);
            if (w <= 0) continue;
            Pixel& p = pixels[size_t(y - py0) * (px1 - px0) + (x - px0)];
            for (int c = 0; c < 3; ++c) p.color[c] += w * L[c];
            p.weight += w;
        }
    accumulateAovs(pixels[size_t(cy - py0) * (px1 - px0) + (cx - px0)]);
}

Film::Film(int width, int height, const Filter& filter)
    : width_(width), height_(height), filter_(filter), pixels_(size_t(width) * height) {}

void Film::clear() { std::fill(pixels_.begin(), pixels_.end(), FilmTile::Pixel()); }

void Film::merge(const FilmTile& tile) {
    int tw = tile.px1 - tile.px0;
    for (int y = std::max(0, tile.py0); y < std::min(height_, tile.py1); ++y)
        for (int x = std::max(0, tile.px0); x < std::min(width_, tile.px1); ++x) {
            const FilmTile::Pixel& s = tile.pixels[size_t(y - tile.py0) * tw + (x - tile.px0)];
            FilmTile::Pixel& d = pixels_[size_t(y) * width_ + x];
            for (int c = 0; c < 3; ++c) {
                d.color[c] += s.color[c];
                d.normal[c] += s.normal[c];
                d.albedo[c] += s.albedo[c];
            }
            d.weight += s.weight;
            d.depth += s.depth;
            d.aovWeight += s.aovWeight;
            d.depthCount += s.depthCount;
            if (s.idDistance2 < d.idDistance2) {
                d.idDistance2 = s.idDistance2;
                d.shapeId = s.shapeId;
                d.instanceId = s.instanceId;
            }
        }
}

std::vector<float> Film::color() const {
    std::vector<float> out(pixels_.size() * 3);
    for (size_t i = 0; i < pixels_.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double v = pixels_[i].weight > 0 ? pixels_[i].color[c] / pixels_[i].weight : 0.0;
            out[i * 3 + c] = std::isfinite(v) ? float(v) : 0.0f;
        }
    return out;
}

std::vector<float> Film::depth() const {
    std::vector<float> out(pixels_.size());
    for (size_t i = 0; i < pixels_.size(); ++i)
        out[i] = pixels_[i].depthCount > 0 ? float(pixels_[i].depth / pixels_[i].depthCount) : kInf;
    return out;
}

std::vector<float> Film::normal() const {
    std::vector<float> out(pixels_.size() * 3);
    for (size_t i = 0; i < pixels_.size(); ++i) {
        Vec3 n(float(pixels_[i].normal[0]), float(pixels_[i].normal[1]), float(pixels_[i].normal[2]));
        n = lengthSquared(n) > 0 ? normalize(n) : Vec3(0.0f);
        out[i * 3] = n.x, out[i * 3 + 1] = n.y, out[i * 3 + 2] = n.z;
    }
    return out;
}

std::vector<float> Film::albedo() const {
    std::vector<float> out(pixels_.size() * 3);
    for (size_t i = 0; i < pixels_.size(); ++i)
        for (int c = 0; c < 3; ++c)
            out[i * 3 + c] = pixels_[i].aovWeight > 0 ? float(pixels_[i].albedo[c] / pixels_[i].aovWeight) : 0.0f;
    return out;
}

std::vector<int32_t> Film::shapeIds() const {
    std::vector<int32_t> out(pixels_.size());
    for (size_t i = 0; i < pixels_.size(); ++i) out[i] = pixels_[i].shapeId;
    return out;
}

std::vector<int32_t> Film::instanceIds() const {
    std::vector<int32_t> out(pixels_.size());
    for (size_t i = 0; i < pixels_.size(); ++i) out[i] = pixels_[i].instanceId;
    return out;
}

}  // namespace gi
