// What meshes and spheres share: material binding, displayColor, transform, visibility,
// sidedness and instancing, pulled from the scene delegate only when their bits are dirty.
#pragma once
#include <vector>

#include "pxr/base/gf/matrix4d.h"
#include "pxr/base/gf/vec3f.h"
#include "pxr/imaging/hd/changeTracker.h"
#include "pxr/imaging/hd/rprim.h"
#include "pxr/imaging/hd/sceneDelegate.h"
#include "pxr/pxr.h"
#include "sceneStore.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGiRenderParam;

struct HdGiGprimState {
    GfMatrix4d transform{1.0};
    std::vector<float> transformTimes;  // motion samples over the shutter (HdGiGeometry's)
    std::vector<GfMatrix4d> transformSamples;
    bool doubleSided = true;
    bool hasDisplayColor = false;
    GfVec3f displayColor{0.0f};  // read only when hasDisplayColor (else the spec's default diffuse)
    bool instanced = false;
    std::vector<GfMatrix4d> instances;
    std::vector<float> instanceTimes;  // the instances' motion samples (HdGiGeometry's)
    std::vector<std::vector<GfMatrix4d>> instanceSamples;

    // Updates what `dirtyBits` marks; returns true if anything the renderer sees changed.
    bool Sync(HdRprim& prim, HdSceneDelegate* delegate, HdGiRenderParam const& param, HdDirtyBits dirtyBits);
    // Fills the fields of `g` this state owns and stores it for the prim (nothing when hidden),
    // stopping the render first.
    void Publish(HdRprim const& prim, HdGiRenderParam* param, std::shared_ptr<HdGiGeometry> g) const;
};

// Reprs are unused (the renderer draws everything one way) but Hydra expects an entry per token.
void HdGiInitRepr(std::vector<std::pair<TfToken, HdReprSharedPtr>>& reprs, TfToken const& reprToken);

// Dirty bits every gprim wants on first sync.
HdDirtyBits HdGiGprimInitialDirtyBits();

// A material's primvar readers changed (HdGiMaterial::Sync): meshes pick their texture
// coordinates again. A custom bit, because with UsdImaging's scene index (scene index emulation)
// MarkAllRprimsDirty drops scene-data bits such as DirtyPrimvar for prims the emulation does not
// hold, which is every prim; custom bits reach the rprims directly (HdChangeTracker::MarkRprimDirty).
constexpr HdDirtyBits HdGiDirtyUvPrimvar = HdChangeTracker::CustomBitsBegin;
// The cameras' shutters changed (HdGiCamera::Sync): motion is sampled again over the new interval
// (transforms, instances, points). Custom for the same reason.
constexpr HdDirtyBits HdGiDirtyShutter = HdChangeTracker::CustomBitsBegin << 1;

PXR_NAMESPACE_CLOSE_SCOPE
