#include "renderBuffer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "pxr/base/gf/half.h"
#include "pxr/base/gf/vec3i.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiRenderBuffer::HdGiRenderBuffer(SdfPath const& id) : HdRenderBuffer(id) {}

HdGiRenderBuffer::~HdGiRenderBuffer() = default;

bool HdGiRenderBuffer::Allocate(GfVec3i const& dimensions, HdFormat format, bool multiSampled) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (dimensions[2] != 1) {
        TF_WARN("hdGi: render buffer %s: 3D buffers are not supported", GetId().GetText());
        return false;
    }
    HdFormat component = HdGetComponentFormat(format);
    if (component != HdFormatFloat32 && component != HdFormatFloat16 && component != HdFormatUNorm8 &&
        component != HdFormatInt32) {
        TF_WARN("hdGi: render buffer %s: format %d is not supported", GetId().GetText(), int(format));
        return false;
    }
    _width = unsigned(std::max(0, dimensions[0]));
    _height = unsigned(std::max(0, dimensions[1]));
    _format = format;
    _multiSampled = multiSampled;
    _buffer.assign(size_t(_width) * _height * HdDataSizeOfFormat(format), 0);
    _converged = false;
    return true;
}

void HdGiRenderBuffer::_Deallocate() {
    std::lock_guard<std::mutex> lock(_mutex);
    _width = _height = 0;
    _format = HdFormatInvalid;
    _buffer.clear();
    _converged = false;
}

void* HdGiRenderBuffer::Map() {
    _mappers++;
    return _buffer.data();
}

void HdGiRenderBuffer::Unmap() { _mappers--; }

namespace {
void StoreFloat(uint8_t* dst, HdFormat component, float v) {
    switch (component) {
    case HdFormatFloat32: std::memcpy(dst, &v, 4); break;
    case HdFormatFloat16: {
        GfHalf h(v);
        std::memcpy(dst, &h, 2);
        break;
    }
    case HdFormatUNorm8: *dst = uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); break;
    case HdFormatInt32: {
        int32_t i = int32_t(v);
        std::memcpy(dst, &i, 4);
        break;
    }
    default: break;
    }
}
}  // namespace

void HdGiRenderBuffer::WriteFloats(float const* image, int components, GfRect2i const& window, float fill) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (_buffer.empty()) return;
    HdFormat component = HdGetComponentFormat(_format);
    size_t count = HdGetComponentCount(_format), pixelSize = HdDataSizeOfFormat(_format);
    size_t componentSize = pixelSize / count;
    int w = window.GetWidth(), h = window.GetHeight();
    for (int y = 0; y < h; ++y) {
        int row = int(_height) - 1 - (window.GetMinY() + y);  // Hydra's buffers are bottom-up
        if (row < 0 || row >= int(_height)) continue;
        for (int x = 0; x < w; ++x) {
            int column = window.GetMinX() + x;
            if (column < 0 || column >= int(_width)) continue;
            uint8_t* dst = _buffer.data() + (size_t(row) * _width + size_t(column)) * pixelSize;
            float const* src = image + (size_t(y) * w + x) * components;
            for (size_t c = 0; c < count; ++c)
                StoreFloat(dst + c * componentSize, component, int(c) < components ? src[c] : fill);
        }
    }
}

void HdGiRenderBuffer::WriteInts(int32_t const* image, GfRect2i const& window) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (_buffer.empty() || HdGetComponentFormat(_format) != HdFormatInt32) return;
    size_t pixelSize = HdDataSizeOfFormat(_format);
    int w = window.GetWidth(), h = window.GetHeight();
    for (int y = 0; y < h; ++y) {
        int row = int(_height) - 1 - (window.GetMinY() + y);
        if (row < 0 || row >= int(_height)) continue;
        for (int x = 0; x < w; ++x) {
            int column = window.GetMinX() + x;
            if (column < 0 || column >= int(_width)) continue;
            std::memcpy(_buffer.data() + (size_t(row) * _width + size_t(column)) * pixelSize, &image[size_t(y) * w + x], 4);
        }
    }
}

void HdGiRenderBuffer::Clear(float value) {
    std::lock_guard<std::mutex> lock(_mutex);
    if (_buffer.empty()) return;
    HdFormat component = HdGetComponentFormat(_format);
    size_t count = HdGetComponentCount(_format), pixelSize = HdDataSizeOfFormat(_format);
    std::vector<uint8_t> pixel(pixelSize);
    for (size_t c = 0; c < count; ++c) StoreFloat(pixel.data() + c * (pixelSize / count), component, value);
    for (size_t i = 0; i < _buffer.size(); i += pixelSize) std::memcpy(_buffer.data() + i, pixel.data(), pixelSize);
}

PXR_NAMESPACE_CLOSE_SCOPE
