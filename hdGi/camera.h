// The camera sprim: Hydra's HdCamera, which also tells the render param its shutter, so that the
// gprims sample their motion over it (a scene index hands out only the samples inside the
// interval a delegate asks for; UsdImaging's legacy delegate ignores the interval and uses the
// camera it samples for), and samples its own transform over the shutter (a moving camera).
#pragma once
#include <vector>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/imaging/hd/camera.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiCamera final : public HdCamera {
public:
    explicit HdGiCamera(SdfPath const& id) : HdCamera(id) {}
    void Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    void Finalize(HdRenderParam* renderParam) override;

    // Camera-to-world at the renderer's even steps over the shutter (renderer/motion.h), step 0
    // at shutter open; empty when the camera does not move during it.
    std::vector<GfMatrix4d> MotionSteps() const;

private:
    std::vector<float> _motionTimes;  // SampleTransform over the shutter
    std::vector<GfMatrix4d> _motionSamples;
};

PXR_NAMESPACE_CLOSE_SCOPE
