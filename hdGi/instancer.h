// Instancer: per-instance transforms from the instancer's primvars (translate, rotate, scale,
// matrix), composed through nested instancers. The rprims add their geometry once, as an
// Embree prototype, and one Embree instance per transform (not copies).
#pragma once
#include <map>
#include <mutex>
#include <vector>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/imaging/hd/instancer.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiInstancer final : public HdInstancer {
public:
    HdGiInstancer(HdSceneDelegate* delegate, SdfPath const& id);
    void Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    // World-space instance transforms of `prototypeId` (to be applied after its own transform).
    std::vector<GfMatrix4d> ComputeInstanceTransforms(SdfPath const& prototypeId);

private:
    std::mutex _mutex;
    std::map<TfToken, VtValue> _primvars;
};

// The transforms an rprim is drawn with: its instancer's, or none when it is not instanced.
bool HdGiRprimInstances(HdSceneDelegate* delegate, SdfPath const& instancerId, SdfPath const& rprimId,
                        std::vector<GfMatrix4d>* transforms);

PXR_NAMESPACE_CLOSE_SCOPE
