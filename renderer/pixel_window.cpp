#include "pixel_window.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gi {

namespace {
// The first pixel whose centre (i + 0.5) is at or past `edge` (in pixels) of a row or column of
// `size`: -1 and size + 1 stand for anything beyond the image (no overflow for huge windows).
int firstCentreFrom(double edge, int size) { return int(std::ceil(std::clamp(edge, -1.0, size + 1.0) - 0.5)); }
}  // namespace

PixelWindow dataWindowPixels(float xmin, float ymin, float xmax, float ymax, int width, int height,
                             std::string* problem) {
    problem->clear();
    std::ostringstream ndc;
    ndc << "dataWindowNDC (" << xmin << ", " << ymin << ", " << xmax << ", " << ymax << ")";
    const PixelWindow whole{0, 0, width, height};
    if (!(std::isfinite(xmin) && std::isfinite(ymin) && std::isfinite(xmax) && std::isfinite(ymax))) {
        *problem = ndc.str() + " is not finite; the whole image is rendered";
        return whole;
    }
    int const x0 = firstCentreFrom(double(xmin) * width, width), x1 = firstCentreFrom(double(xmax) * width, width);
    int const y0 = firstCentreFrom((1.0 - double(ymax)) * height, height);
    int const y1 = firstCentreFrom((1.0 - double(ymin)) * height, height);
    int const cx0 = std::max(0, x0), cy0 = std::max(0, y0), cx1 = std::min(width, x1), cy1 = std::min(height, y1);
    if (cx1 <= cx0 || cy1 <= cy0) {
        *problem = ndc.str() + " holds no pixel; the whole image is rendered";
        return whole;
    }
    if (cx0 != x0 || cy0 != y0 || cx1 != x1 || cy1 != y1)
        *problem = ndc.str() + " reaches outside the image; clipped to it";
    return PixelWindow{cx0, cy0, cx1, cy1};
}

}  // namespace gi
