// Marks the stage's active UsdRenderSettings prim as active and keeps its "gi:" settings, so
// HdGiRenderSettings can apply them (HdRenderSettings::IsActive needs this scene index).
#include "pxr/imaging/hd/retainedDataSource.h"
#include "pxr/imaging/hd/sceneIndexPlugin.h"
#include "pxr/imaging/hd/sceneIndexPluginRegistry.h"
#include "pxr/imaging/hdsi/renderSettingsFilteringSceneIndex.h"
#include "pxr/pxr.h"

PXR_NAMESPACE_OPEN_SCOPE

class HdGi_RenderSettingsFilteringSceneIndexPlugin final : public HdSceneIndexPlugin {
protected:
    HdSceneIndexBaseRefPtr _AppendSceneIndex(HdSceneIndexBaseRefPtr const& inputScene,
                                             HdContainerDataSourceHandle const& inputArgs) override {
        return HdsiRenderSettingsFilteringSceneIndex::New(inputScene, inputArgs);
    }
};

TF_REGISTRY_FUNCTION(TfType) { HdSceneIndexPluginRegistry::Define<HdGi_RenderSettingsFilteringSceneIndexPlugin>(); }

TF_REGISTRY_FUNCTION(HdSceneIndexPlugin) {
    HdContainerDataSourceHandle const args = HdRetainedContainerDataSource::New(
        HdsiRenderSettingsFilteringSceneIndexTokens->namespacePrefixes,
        HdRetainedTypedSampledDataSource<VtArray<TfToken>>::New({TfToken("gi")}));
    HdSceneIndexPluginRegistry::GetInstance().RegisterSceneIndexForRenderer(
        "Gi", TfToken("HdGi_RenderSettingsFilteringSceneIndexPlugin"), args, 1,
        HdSceneIndexPluginRegistry::InsertionOrderAtStart);
}

PXR_NAMESPACE_CLOSE_SCOPE
