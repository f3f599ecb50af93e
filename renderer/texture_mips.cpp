// An image's MIP chain (Image::buildLevels): each level a box filter of the one before, in
// linear values, colour weighted by alpha (a cut-out's transparent texels, often black, do not
// darken the leaves around them). Each level is filtered from the one before it unrounded.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "texture.h"

namespace gi {

void Image::buildLevels(int width, int height) {
    levels_.assign(1, Level{width, height, 0});
    // A float image's levels follow its texels in pixels_; an 8-bit one's start coarse_.
    const bool floats = !pixels_.empty();
    size_t texels = floats ? size_t(width) * height : 0;
    for (int w = width, h = height; w > 1 || h > 1;) {
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
        levels_.push_back(Level{w, h, texels});
        texels += size_t(w) * h;
    }
    if (floats)
        pixels_.resize(texels * 4);
    else
        coarse_.resize(texels * 4);
    std::vector<float> previous, next;  // linear RGBA of the level before and of this one
    for (size_t l = 1; l < levels_.size(); ++l) {
        const Level& from = levels_[l - 1];
        const Level& to = levels_[l];
        next.assign(size_t(to.width) * to.height * 4, 0.0f);
        tbb::parallel_for(tbb::blocked_range<int>(0, to.height), [&](const tbb::blocked_range<int>& rows) {
            for (int y = rows.begin(); y < rows.end(); ++y) {
                // The source texels this texel covers: 2 x 2, or 3 along an odd side's last one.
                const int y0 = y * from.height / to.height, y1 = ((y + 1) * from.height + to.height - 1) / to.height;
                for (int x = 0; x < to.width; ++x) {
                    const int x0 = x * from.width / to.width, x1 = ((x + 1) * from.width + to.width - 1) / to.width;
                    float colour[3] = {0, 0, 0}, weighted[3] = {0, 0, 0}, alpha = 0;
                    for (int sy = y0; sy < y1; ++sy)
                        for (int sx = x0; sx < x1; ++sx) {
                            float t[4];
                            if (l == 1)
                                texel(0, sx, sy, t);
                            else
                                std::copy_n(&previous[(size_t(sy) * from.width + sx) * 4], 4, t);
                            for (int c = 0; c < 3; ++c) {
                                colour[c] += t[c];
                                weighted[c] += t[c] * t[3];
                            }
                            alpha += t[3];
                        }
                    const float n = float((x1 - x0) * (y1 - y0));
                    float* out = &next[(size_t(y) * to.width + x) * 4];
                    for (int c = 0; c < 3; ++c) out[c] = alpha > 0 ? weighted[c] / alpha : colour[c] / n;
                    out[3] = alpha / n;
                }
            }
        });
        const size_t begin = to.offset * 4;
        for (size_t i = 0; i < next.size(); ++i) {
            if (floats)
                pixels_[begin + i] = next[i];
            else  // 8-bit texels decode to [0, 1]
                coarse_[begin + i] = uint16_t(std::lround(std::clamp(next[i], 0.0f, 1.0f) * 65535));
        }
        std::swap(previous, next);
    }
}

}  // namespace gi
