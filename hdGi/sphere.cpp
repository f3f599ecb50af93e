#include "sphere.h"

#include "pxr/imaging/hd/sphereSchema.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderParam.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiSphere::HdGiSphere(SdfPath const& id, SdfPath const&) : HdRprim(id) {}

HdDirtyBits HdGiSphere::GetInitialDirtyBitsMask() const { return HdGiGprimInitialDirtyBits(); }

TfTokenVector const& HdGiSphere::GetBuiltinPrimvarNames() const {
    static TfTokenVector names{HdSphereSchemaTokens->radius};
    return names;
}

void HdGiSphere::_InitRepr(TfToken const& reprToken, HdDirtyBits*) { HdGiInitRepr(_reprs, reprToken); }

void HdGiSphere::Sync(HdSceneDelegate* delegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits,
                      TfToken const&) {
    auto* param = static_cast<HdGiRenderParam*>(renderParam);
    SdfPath const& id = GetId();
    HdDirtyBits bits = *dirtyBits;
    bool wasVisible = IsVisible();
    if (HdChangeTracker::IsVisibilityDirty(bits, id)) _UpdateVisibility(delegate, dirtyBits);
    _UpdateInstancer(delegate, dirtyBits);
    bool changed = _state.Sync(*this, delegate, *param, bits) || wasVisible != IsVisible();
    if (HdChangeTracker::IsAnyPrimvarDirty(bits, id)) {
        VtValue radius = delegate->Get(id, HdSphereSchemaTokens->radius);
        _radius = radius.IsHolding<double>() ? float(radius.UncheckedGet<double>())
                  : radius.IsHolding<float>() ? radius.UncheckedGet<float>()
                                               : 1.0f;
        changed = true;
    }
    if (changed) {
        auto g = std::make_shared<HdGiGeometry>();
        g->isSphere = true;
        g->radius = _radius;
        _state.Publish(*this, param, std::move(g));
    }
    *dirtyBits &= ~(HdChangeTracker::AllSceneDirtyBits | HdGiDirtyUvPrimvar | HdGiDirtyShutter);  // a sphere has no uvs to pick
}

void HdGiSphere::Finalize(HdRenderParam* renderParam) {
    static_cast<HdGiRenderParam*>(renderParam)->EditScene().Remove(GetId());
}

PXR_NAMESPACE_CLOSE_SCOPE
