// Float accumulation of radiance and the auxiliary outputs (depth, normal, albedo) with a
// reconstruction filter. Tiles accumulate into their own padded buffers which are merged in a
// fixed order, so the image is bit-identical whatever the thread timing.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "math.h"

namespace gi {

// Box (each sample only in its own pixel: the spec's filter) or a truncated Gaussian.
struct Filter {
    std::string name = "box";
    float radius = 0.5f;
    float sigma = 0.5f;
    static Filter byName(const std::string& name);  // "box" | "gaussian"
    float weight(float dx, float dy) const;
};

struct SampleAovs {
    float depth = kInf;
    Vec3 normal{0.0f};
    Color albedo{0.0f};
    bool hit = false;
    // What the first visible surface is: the scene's shape and instance (-1 for none), so a
    // host can map a pixel back to a prim (picking).
    int32_t shapeId = -1, instanceId = -1;
};

class FilmTile {
public:
    FilmTile(int x0, int y0, int x1, int y1, const Filter& filter);
    void addSample(float filmX, float filmY, const Color& L, const SampleAovs& aovs);

    int x0, y0, x1, y1;  // the pixels this tile samples
    int px0, py0, px1, py1;  // the pixels it may write (padded by the filter radius)
    struct Pixel {
        double color[3] = {0, 0, 0};
        double weight = 0;
        double normal[3] = {0, 0, 0}, albedo[3] = {0, 0, 0};
        double depth = 0, aovWeight = 0, depthCount = 0;
        // Ids of the sample nearest the pixel centre so far (stable as samples accumulate).
        int32_t shapeId = -1, instanceId = -1;
        float idDistance2 = kInf;
    };
    std::vector<Pixel> pixels;

private:
    Filter filter_;
};

class Film {
public:
    Film(int width, int height, const Filter& filter = Filter());
    int width() const { return width_; }
    int height() const { return height_; }
    const Filter& filter() const { return filter_; }
    void merge(const FilmTile& tile);
    void clear();

    // Resolved images, row 0 at the top.
    std::vector<float> color() const;   // W*H*3
    std::vector<float> depth() const;   // W*H (inf where nothing was hit)
    std::vector<float> normal() const;  // W*H*3
    std::vector<float> albedo() const;  // W*H*3
    std::vector<int32_t> shapeIds() const;     // W*H, -1 where nothing was hit
    std::vector<int32_t> instanceIds() const;  // W*H, -1 where no instance was hit

private:
    int width_, height_;
    Filter filter_;
    std::vector<FilmTile::Pixel> pixels_;
};

}  // namespace gi
