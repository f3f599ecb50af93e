// Instancer: per-instance transforms from the instancer's primvars (translate, rotate, scale,
// matrix), composed through nested instancers, and their motion over the cameras' shutters
// (the primvars' and the instancer transform's samples over HdGiRenderParam's sampling
// interval). The rprims add their geometry once, as an Embree prototype, and one Embree
// instance per transform (not copies).
#pragma once
#include <map>
#include <mutex>
#include <vector>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/base/gf/vec2f.h"
#include "pxr/imaging/hd/instancer.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiInstancer final : public HdInstancer {
public:
    HdGiInstancer(HdSceneDelegate* delegate, SdfPath const& id);
    void Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits) override;
    // World-space instance transforms of `prototypeId` (to be applied after its own transform) at
    // `time`, relative to the frame, from the samples over `interval`.
    std::vector<GfMatrix4d> ComputeInstanceTransforms(SdfPath const& prototypeId, GfVec2f interval, float time);
    // The times inside `interval` at which this instancer or a parent has samples, the
    // interval's ends included; one time (0) when nothing is sampled apart from the frame.
    std::vector<float> SampleTimes(GfVec2f interval);

    // Values at increasing times (one sample: constant).
    struct Series {
        std::vector<float> times;
        std::vector<VtValue> values;
    };

private:
    void _Sample(GfVec2f interval);  // under _mutex

    std::mutex _mutex;
    std::vector<TfToken> _names;  // the instance-rate primvars
    bool _stale = true;           // the primvars or the transform changed since _Sample
    GfVec2f _sampledInterval{0.0f};
    std::map<TfToken, Series> _primvars;
    std::vector<float> _transformTimes;
    std::vector<GfMatrix4d> _transformSamples;
};

// The transforms an rprim is drawn with, at the frame: its instancer's, or none when it is not
// instanced. `times` and `samples` (per time, one transform per instance): their motion over
// `interval`, fewer than two times when they do not move.
bool HdGiRprimInstances(HdSceneDelegate* delegate, SdfPath const& instancerId, SdfPath const& rprimId,
                        GfVec2f interval, std::vector<GfMatrix4d>* transforms, std::vector<float>* times,
                        std::vector<std::vector<GfMatrix4d>>* samples);

PXR_NAMESPACE_CLOSE_SCOPE
