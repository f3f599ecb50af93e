// Cubes, cones, cylinders, capsules and planes reach Gi as meshes (the implicit-surface scene
// index tessellates them); spheres stay spheres, rendered exactly.
#include "pxr/imaging/hd/retainedDataSource.h"
#include "pxr/imaging/hd/sceneIndexPlugin.h"
#include "pxr/imaging/hd/sceneIndexPluginRegistry.h"
#include "pxr/imaging/hd/tokens.h"
#include "pxr/imaging/hdsi/implicitSurfaceSceneIndex.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGi_ImplicitSurfaceSceneIndexPlugin final : public HdSceneIndexPlugin {
protected:
    HdSceneIndexBaseRefPtr _AppendSceneIndex(HdSceneIndexBaseRefPtr const& inputScene,
                                             HdContainerDataSourceHandle const& inputArgs) override {
        return HdsiImplicitSurfaceSceneIndex::New(inputScene, inputArgs);
    }
};

TF_REGISTRY_FUNCTION(TfType) { HdSceneIndexPluginRegistry::Define<HdGi_ImplicitSurfaceSceneIndexPlugin>(); }

TF_REGISTRY_FUNCTION(HdSceneIndexPlugin) {
    HdDataSourceBaseHandle const toMesh =
        HdRetainedTypedSampledDataSource<TfToken>::New(HdsiImplicitSurfaceSceneIndexTokens->toMesh);
    HdContainerDataSourceHandle const args = HdRetainedContainerDataSource::New(
        HdPrimTypeTokens->cube, toMesh, HdPrimTypeTokens->cone, toMesh, HdPrimTypeTokens->cylinder, toMesh,
        HdPrimTypeTokens->capsule, toMesh, HdPrimTypeTokens->plane, toMesh);
    HdSceneIndexPluginRegistry::GetInstance().RegisterSceneIndexForRenderer(
        "Gi", TfToken("HdGi_ImplicitSurfaceSceneIndexPlugin"), args, 0,
        HdSceneIndexPluginRegistry::InsertionOrderAtStart);
}

PXR_NAMESPACE_CLOSE_SCOPE
