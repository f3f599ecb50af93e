// A data window: the pixels of an image a render produces (a farm tile, a RenderProduct's
// dataWindowNDC), and the rule that turns UsdRender's dataWindowNDC into one, which both hosts
// follow (`gi render`'s products.py, hdGi's product mode).
#pragma once
#include <string>

namespace gi {

// Pixels [x0, x1) x [y0, y1) of the image, row 0 at the top. Empty (the default): the whole image.
struct PixelWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    long long area() const { return empty() ? 0 : (long long)(x1 - x0) * (y1 - y0); }
    bool operator==(const PixelWindow& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};

// dataWindowNDC (xmin, ymin, xmax, ymax; (0, 0) the bottom-left corner of the aperture, (1, 1) the
// top-right) as the pixels of a width x height image whose centres it contains (UsdRender's rule:
// a pixel is included if its centre is; the window's low edges included, its high edges not).
// NDC y runs up, so ymax gives the top row. A window reaching outside the image is clipped to it
// (overscan is not rendered) and one holding no pixel becomes the whole image; either way
// *problem says so in a sentence for a warning naming the product, else it is left empty.
PixelWindow dataWindowPixels(float xmin, float ymin, float xmax, float ymax, int width, int height,
                             std::string* problem);

}  // namespace gi
