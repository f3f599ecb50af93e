#include "camera.h"

#include "gprim.h"
#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/imaging/hd/timeSampleArray.h"
#include "renderParam.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

void HdGiCamera::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) {
    HdDirtyBits const bits = *dirtyBits;  // HdCamera::Sync clears them
    HdCamera::Sync(delegate, renderParam, dirtyBits);
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    if (bits & (DirtyTransform | DirtyParams)) {
        HdTimeSampleArray<GfMatrix4d, 4> samples;
        float open = float(GetShutterOpen()), close = float(GetShutterClose());
        _motionTimes.clear();
        _motionSamples.clear();
        if (close > open) {
            delegate->SampleTransform(GetId(), open, close, &samples);
            _motionTimes.assign(samples.times.begin(), samples.times.begin() + samples.count);
            _motionSamples.assign(samples.values.begin(), samples.values.begin() + samples.count);
        }
    }
    // Cameras sync before rprims: a changed interval resamples every rprim's motion in this sync.
    // A custom bit (gprim.h): the scene index emulation drops scene-data bits marked this way.
    if (param->NoteShutter(GetId(), float(GetShutterOpen()), float(GetShutterClose())))
        delegate->GetRenderIndex().GetChangeTracker().MarkAllRprimsDirty(HdGiDirtyShutter);
}

std::vector<GfMatrix4d> HdGiCamera::MotionSteps() const {
    std::vector<GfMatrix4d> steps =
        HdGiTransformSteps(_motionTimes, _motionSamples, float(GetShutterOpen()), float(GetShutterClose()));
    bool moves = false;
    for (GfMatrix4d const& step : steps) moves = moves || step != steps.front();
    if (!moves) steps.clear();
    return steps;
}

void HdGiCamera::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->ForgetShutter(GetId());
    HdCamera::Finalize(renderParam);
}

PXR_NAMESPACE_CLOSE_SCOPE
