// The camera sprim: Hydra's HdCamera, which also tells the render param its shutter, so that the
// gprims sample their motion over it (a scene index hands out only the samples inside the
// interval a delegate asks for; UsdImaging's legacy delegate ignores the interval and uses the
// camera it samples for).
#pragma once
#include "pxr/imaging/hd/camera.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiCamera final : public HdCamera {
public:
    explicit HdGiCamera(SdfPath const& id) : HdCamera(id) {}
    void Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    void Finalize(HdRenderParam* renderParam) override;
};

PXR_NAMESPACE_CLOSE_SCOPE
