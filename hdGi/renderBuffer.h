// A Hydra render buffer the render thread fills with resolved film data after every pass.
// Hydra's buffers are bottom-up; the film is top-down.
#pragma once
#include <atomic>
#include <mutex>
#include <vector>

#include "pxr/base/gf/rect2i.h"
#include "pxr/imaging/hd/renderBuffer.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderBuffer final : public HdRenderBuffer {
public:
    explicit HdGiRenderBuffer(SdfPath const& id);
    ~HdGiRenderBuffer() override;

    bool Allocate(GfVec3i const& dimensions, HdFormat format, bool multiSampled) override;
    unsigned int GetWidth() const override { return _width; }
    unsigned int GetHeight() const override { return _height; }
    unsigned int GetDepth() const override { return 1; }
    HdFormat GetFormat() const override { return _format; }
    bool IsMultiSampled() const override { return _multiSampled; }
    void* Map() override;
    void Unmap() override;
    bool IsMapped() const override { return _mappers.load() != 0; }
    void Resolve() override {}
    bool IsConverged() const override { return _converged.load(); }
    void SetConverged(bool converged) { _converged.store(converged); }

    // Writes a top-down image of `components` values per pixel into `window` (top-down
    // coordinates), converting to the buffer's format; extra buffer components get `fill`.
    void WriteFloats(float const* image, int components, GfRect2i const& window, float fill = 1.0f);
    void WriteInts(int32_t const* image, GfRect2i const& window);
    void Clear(float value);

private:
    void _Deallocate() override;

    unsigned int _width = 0, _height = 0;
    HdFormat _format = HdFormatInvalid;
    bool _multiSampled = false;
    std::vector<uint8_t> _buffer;
    std::atomic<int> _mappers{0};
    std::atomic<bool> _converged{false};
    std::mutex _mutex;
};

PXR_NAMESPACE_CLOSE_SCOPE
