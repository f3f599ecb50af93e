#include "camera.h"

#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "renderParam.h"

PXR_NAMESPACE_OPEN_SCOPE

void HdGiCamera::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) {
    HdCamera::Sync(delegate, renderParam, dirtyBits);
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    // Cameras sync before rprims: a changed interval resamples every rprim's motion in this sync.
    if (param->NoteShutter(GetId(), float(GetShutterOpen()), float(GetShutterClose())))
        delegate->GetRenderIndex().GetChangeTracker().MarkAllRprimsDirty(HdChangeTracker::DirtyTransform |
                                                                         HdChangeTracker::DirtyPoints);
}

void HdGiCamera::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->ForgetShutter(GetId());
    HdCamera::Finalize(renderParam);
}

PXR_NAMESPACE_CLOSE_SCOPE
