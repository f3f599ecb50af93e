#include "instancer.h"

#include "pxr/base/gf/quatd.h"
#include "pxr/base/gf/quatf.h"
#include "pxr/base/gf/quath.h"
#include "pxr/base/gf/rotation.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/base/gf/vec4f.h"
#include "pxr/base/vt/array.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/imaging/hd/tokens.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiInstancer::HdGiInstancer(HdSceneDelegate* delegate, SdfPath const& id) : HdInstancer(delegate, id) {}

void HdGiInstancer::Sync(HdSceneDelegate* delegate, HdRenderParam*, HdDirtyBits* dirtyBits) {
    _UpdateInstancer(delegate, dirtyBits);
    SdfPath const& id = GetId();
    if (!HdChangeTracker::IsAnyPrimvarDirty(*dirtyBits, id)) return;
    std::lock_guard<std::mutex> lock(_mutex);
    for (HdPrimvarDescriptor const& pv : delegate->GetPrimvarDescriptors(id, HdInterpolationInstance))
        if (HdChangeTracker::IsPrimvarDirty(*dirtyBits, id, pv.name)) _primvars[pv.name] = delegate->Get(id, pv.name);
}

namespace {

bool Rotation(VtValue const& value, size_t i, GfMatrix4d* m) {
    auto set = [&](GfQuatd q) {
        m->SetRotate(q);
        return true;
    };
    if (value.IsHolding<VtQuathArray>()) {
        auto const& a = value.UncheckedGet<VtQuathArray>();
        if (i < a.size()) return set(GfQuatd(a[i]));
    } else if (value.IsHolding<VtQuatfArray>()) {
        auto const& a = value.UncheckedGet<VtQuatfArray>();
        if (i < a.size()) return set(GfQuatd(a[i]));
    } else if (value.IsHolding<VtQuatdArray>()) {
        auto const& a = value.UncheckedGet<VtQuatdArray>();
        if (i < a.size()) return set(a[i]);
    } else if (value.IsHolding<VtVec4fArray>()) {  // (real, i, j, k), hdEmbree's convention
        auto const& a = value.UncheckedGet<VtVec4fArray>();
        if (i < a.size()) return set(GfQuatd(a[i][0], a[i][1], a[i][2], a[i][3]));
    }
    return false;
}

bool Vector(VtValue const& value, size_t i, GfVec3d* v) {
    if (value.IsHolding<VtVec3fArray>()) {
        auto const& a = value.UncheckedGet<VtVec3fArray>();
        if (i < a.size()) return *v = GfVec3d(a[i]), true;
    } else if (value.IsHolding<VtVec3dArray>()) {
        auto const& a = value.UncheckedGet<VtVec3dArray>();
        if (i < a.size()) return *v = a[i], true;
    } else if (value.IsHolding<VtVec3hArray>()) {
        auto const& a = value.UncheckedGet<VtVec3hArray>();
        if (i < a.size()) return *v = GfVec3d(a[i]), true;
    }
    return false;
}

}  // namespace

std::vector<GfMatrix4d> HdGiInstancer::ComputeInstanceTransforms(SdfPath const& prototypeId) {
    HdSceneDelegate* delegate = GetDelegate();
    GfMatrix4d instancerTransform = delegate->GetInstancerTransform(GetId());
    VtIntArray indices = delegate->GetInstanceIndices(GetId(), prototypeId);
    std::vector<GfMatrix4d> transforms(indices.size(), instancerTransform);
    {
        std::lock_guard<std::mutex> lock(_mutex);
        auto find = [&](TfToken const& name) -> VtValue const* {
            auto it = _primvars.find(name);
            return it == _primvars.end() ? nullptr : &it->second;
        };
        VtValue const* translate = find(HdInstancerTokens->instanceTranslations);
        VtValue const* rotate = find(HdInstancerTokens->instanceRotations);
        VtValue const* scale = find(HdInstancerTokens->instanceScales);
        VtValue const* matrix = find(HdInstancerTokens->instanceTransforms);
        for (size_t k = 0; k < indices.size(); ++k) {
            size_t i = size_t(indices[k]);
            // Row-vector convention: scale, then rotate, then translate, then the instancer.
            GfMatrix4d local(1.0), m(1.0);
            GfVec3d v;
            if (scale && Vector(*scale, i, &v)) local = local * m.SetScale(v);
            if (rotate && Rotation(*rotate, i, &m)) local = local * m;
            if (translate && Vector(*translate, i, &v)) local = local * GfMatrix4d(1.0).SetTranslate(v);
            if (matrix && matrix->IsHolding<VtMatrix4dArray>() && i < matrix->UncheckedGet<VtMatrix4dArray>().size())
                local = matrix->UncheckedGet<VtMatrix4dArray>()[i] * local;
            transforms[k] = local * instancerTransform;
        }
    }
    if (GetParentId().IsEmpty()) return transforms;
    auto* parent = dynamic_cast<HdGiInstancer*>(delegate->GetRenderIndex().GetInstancer(GetParentId()));
    if (!parent) return transforms;
    std::vector<GfMatrix4d> parents = parent->ComputeInstanceTransforms(GetId());
    std::vector<GfMatrix4d> nested;
    nested.reserve(parents.size() * transforms.size());
    for (GfMatrix4d const& p : parents)
        for (GfMatrix4d const& t : transforms) nested.push_back(t * p);
    return nested;
}

bool HdGiRprimInstances(HdSceneDelegate* delegate, SdfPath const& instancerId, SdfPath const& rprimId,
                        std::vector<GfMatrix4d>* transforms) {
    transforms->clear();
    if (instancerId.IsEmpty()) return false;
    HdRenderIndex& index = delegate->GetRenderIndex();
    HdInstancer::_SyncInstancerAndParents(index, instancerId);
    auto* instancer = dynamic_cast<HdGiInstancer*>(index.GetInstancer(instancerId));
    if (instancer) *transforms = instancer->ComputeInstanceTransforms(rprimId);
    return true;
}

PXR_NAMESPACE_CLOSE_SCOPE
