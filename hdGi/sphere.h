// An exact sphere (Embree sphere primitive), as the USD loader makes it: the delegate declares
// the sphere rprim type (as hdPrman does) so the implicit-surface scene index leaves it alone.
#pragma once
#include <algorithm>

#include "gprim.h"
#include "pxr/imaging/hd/rprim.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiSphere final : public HdRprim {
public:
    HdGiSphere(SdfPath const& id, SdfPath const& instancerId = SdfPath());
    HdDirtyBits GetInitialDirtyBitsMask() const override;
    TfTokenVector const& GetBuiltinPrimvarNames() const override;
    void Sync(HdSceneDelegate* sceneDelegate, HdRenderParam* renderParam, HdDirtyBits* dirtyBits,
              TfToken const& reprToken) override;
    void Finalize(HdRenderParam* renderParam) override;

protected:
    HdDirtyBits _PropagateDirtyBits(HdDirtyBits bits) const override { return bits; }
    void _InitRepr(TfToken const& reprToken, HdDirtyBits* dirtyBits) override;

private:
    HdGiGprimState _state;
    float _radius = 1;
};

PXR_NAMESPACE_CLOSE_SCOPE
