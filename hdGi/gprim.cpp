#include "gprim.h"

#include "instancer.h"
#include "pxr/base/vt/array.h"
#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/timeSampleArray.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderParam.h"

PXR_NAMESPACE_OPEN_SCOPE

HdDirtyBits HdGiGprimInitialDirtyBits() {
    return HdChangeTracker::Clean | HdChangeTracker::InitRepr | HdChangeTracker::DirtyPoints |
           HdChangeTracker::DirtyTopology | HdChangeTracker::DirtyTransform | HdChangeTracker::DirtyVisibility |
           HdChangeTracker::DirtyCullStyle | HdChangeTracker::DirtyDoubleSided | HdChangeTracker::DirtyDisplayStyle |
           HdChangeTracker::DirtySubdivTags | HdChangeTracker::DirtyPrimvar | HdChangeTracker::DirtyNormals |
           HdChangeTracker::DirtyInstancer | HdChangeTracker::DirtyInstanceIndex | HdChangeTracker::DirtyMaterialId;
}

namespace {
bool ReadDisplayColor(VtValue const& value, GfVec3f* color) {
    if (value.IsHolding<VtVec3fArray>() && !value.UncheckedGet<VtVec3fArray>().empty()) {
        *color = value.UncheckedGet<VtVec3fArray>()[0];
        return true;
    }
    if (value.IsHolding<GfVec3f>()) {
        *color = value.UncheckedGet<GfVec3f>();
        return true;
    }
    return false;
}
}  // namespace

bool HdGiGprimState::Sync(HdRprim& prim, HdSceneDelegate* delegate, HdGiRenderParam const& param, HdDirtyBits dirtyBits) {
    SdfPath const& id = prim.GetId();
    bool changed = false;
    if (dirtyBits & HdChangeTracker::DirtyMaterialId) {
        prim.SetMaterialId(delegate->GetMaterialId(id));
        changed = true;
    }
    bool const resample = (dirtyBits & HdGiDirtyShutter) != 0;
    if (HdChangeTracker::IsTransformDirty(dirtyBits, id) || resample) {
        transform = delegate->GetTransform(id);
        // The transform over the cameras' shutters: the interval's ends and the authored samples between.
        HdTimeSampleArray<GfMatrix4d, 4> samples;
        GfVec2f interval = param.SamplingInterval();
        delegate->SampleTransform(id, interval[0], interval[1], &samples);
        transformTimes.assign(samples.times.begin(), samples.times.begin() + samples.count);
        transformSamples.assign(samples.values.begin(), samples.values.begin() + samples.count);
        changed = true;
    }
    if (HdChangeTracker::IsDoubleSidedDirty(dirtyBits, id)) {
        doubleSided = delegate->GetDoubleSided(id);
        changed = true;
    }
    if (HdChangeTracker::IsPrimvarDirty(dirtyBits, id, HdTokens->displayColor)) {
        // The first value stands for the prim (as a material would); per-vertex colors are not shaded.
        hasDisplayColor = ReadDisplayColor(delegate->Get(id, HdTokens->displayColor), &displayColor);
        changed = true;
    }
    if (HdChangeTracker::IsInstancerDirty(dirtyBits, id) || HdChangeTracker::IsInstanceIndexDirty(dirtyBits, id) ||
        HdChangeTracker::IsTransformDirty(dirtyBits, id) || resample || !prim.GetInstancerId().IsEmpty()) {
        instanced = HdGiRprimInstances(delegate, prim.GetInstancerId(), id, param.SamplingInterval(), &instances,
                                       &instanceTimes, &instanceSamples);
        changed = true;
    }
    return changed;
}

void HdGiInitRepr(std::vector<std::pair<TfToken, HdReprSharedPtr>>& reprs, TfToken const& reprToken) {
    for (auto const& entry : reprs)
        if (entry.first == reprToken) return;
    reprs.emplace_back(reprToken, HdReprSharedPtr());
}

void HdGiGprimState::Publish(HdRprim const& prim, HdGiRenderParam* param, std::shared_ptr<HdGiGeometry> geometry) const {
    HdGiSceneStore& store = param->EditScene();
    if (!prim.IsVisible()) {
        store.SetGeometry(prim.GetId(), nullptr);
        return;
    }
    HdGiGeometry& g = *geometry;
    g.name = prim.GetId().GetString();
    g.transform = transform;
    g.transformTimes = transformTimes;
    g.transformSamples = transformSamples;
    g.doubleSided = doubleSided;
    g.hasDisplayColor = hasDisplayColor;
    g.displayColor = displayColor;
    g.instanced = instanced;
    g.instanceTransforms = instances;
    g.instanceTimes = instanceTimes;
    g.instanceSamples = instanceSamples;
    if (g.material.IsEmpty()) g.material = prim.GetMaterialId();
    g.primId = prim.GetPrimId();
    store.SetGeometry(prim.GetId(), std::move(geometry));
}

PXR_NAMESPACE_CLOSE_SCOPE
