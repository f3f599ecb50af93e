#include "renderPass.h"

#include "camera.h"
#include "pxr/imaging/hd/camera.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/renderPassState.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderBuffer.h"
#include "renderSettings.h"

PXR_NAMESPACE_OPEN_SCOPE

HdGiRenderPass::HdGiRenderPass(HdRenderIndex* index, HdRprimCollection const& collection, HdRenderThread* thread,
                               HdGiRenderSession* session, HdGiRenderParam* param, std::atomic<bool>* cancel)
    : HdRenderPass(index, collection), _thread(thread), _session(session), _param(param), _cancel(cancel) {}

HdGiRenderPass::~HdGiRenderPass() { _param->StopRender(); }

bool HdGiRenderPass::IsConverged() const { return _started && _session->IsConverged(); }

namespace {

GfRect2i DataWindow(HdRenderPassStateSharedPtr const& state) {
    CameraUtilFraming const& framing = state->GetFraming();
    if (framing.IsValid()) return framing.dataWindow;
    GfVec4f const vp = state->GetViewport();
    return GfRect2i(GfVec2i(0), int(vp[2]), int(vp[3]));
}

gi::CameraDesc CameraOf(HdCamera const* camera, GfMatrix4d const& view, GfMatrix4d const& projection) {
    gi::CameraDesc desc;
    desc.name = camera ? camera->GetId().GetString() : "<viewport camera>";
    desc.transform = HdGiToMat4(view.GetInverse());
    desc.useProjection = true;
    desc.projectionMatrix = HdGiToMat4(projection);
    desc.projection = std::round(projection[3][3]) == 1 ? "orthographic" : "perspective";
    if (camera) {
        // HdCamera's lengths are in scene units; the renderer's (as UsdGeomCamera's) in tenths.
        desc.focalLength = camera->GetFocalLength() * 10.0f;
        desc.fStop = camera->GetFStop();
        desc.focusDistance = camera->GetFocusDistance();
        desc.clipNear = camera->GetClippingRange().GetMin();
        desc.clipFar = camera->GetClippingRange().GetMax();
        // Relative to the frame, as SampleTransform's and SamplePrimvar's times (motion blur).
        desc.shutterOpen = float(camera->GetShutterOpen());
        desc.shutterClose = float(camera->GetShutterClose());
        // A camera moving during the shutter, when it is the one the view comes from (usdview's
        // free camera is not).
        if (auto const* gi = dynamic_cast<HdGiCamera const*>(camera); gi && GfIsClose(camera->GetTransform(), view.GetInverse(), 1e-9))
            for (GfMatrix4d const& m : gi->MotionSteps()) desc.motionTransforms.push_back(HdGiToMat4(m));
    }
    return desc;
}

// A batch host's render products (usdrecord sets enableInteractive false) are rendered as the
// stage declares them: the first product's camera and resolution, instead of the host's viewport.
bool ProductFraming(HdRenderIndex* index, HdRenderSettings::RenderProducts const& products, gi::CameraDesc* camera,
                    GfRect2i* dataWindow, std::string* problem) {
    HdRenderSettings::RenderProduct const& product = products.front();
    if (product.resolution[0] <= 0 || product.resolution[1] <= 0) return false;
    auto const* sprim = dynamic_cast<HdCamera const*>(index->GetSprim(HdPrimTypeTokens->camera, product.cameraPath));
    if (!sprim) {
        *problem = "render product " + product.productPath.GetString() + ": camera <" + product.cameraPath.GetString() +
                   "> is not in the scene; the host's camera and image size are used";
        return false;
    }
    *camera = CameraOf(sprim, sprim->GetTransform().GetInverse(), GfMatrix4d(1.0));
    camera->useProjection = false;
    camera->projection = sprim->GetProjection() == HdCamera::Orthographic ? "orthographic" : "perspective";
    // UsdGeomCamera's tenths of a unit, as `gi render` reads them; the renderer conforms them to
    // the resolution (renderer/camera.cpp). UsdImaging's scene index leaves the product's own
    // conformed apertureSize at 0.
    camera->horizontalAperture = float(sprim->GetHorizontalAperture() * 10.0);
    camera->verticalAperture = float(sprim->GetVerticalAperture() * 10.0);
    camera->horizontalApertureOffset = float(sprim->GetHorizontalApertureOffset() * 10.0);
    camera->verticalApertureOffset = float(sprim->GetVerticalApertureOffset() * 10.0);
    *dataWindow = GfRect2i(GfVec2i(0), product.resolution[0], product.resolution[1]);
    if (product.dataWindowNDC != GfRange2f(GfVec2f(0.0f), GfVec2f(1.0f)))
        *problem = "render product " + product.productPath.GetString() + ": dataWindowNDC is not supported through "
                   "Hydra; the whole image is rendered";
    return true;
}

}  // namespace

void HdGiRenderPass::_Execute(HdRenderPassStateSharedPtr const& state, TfTokenVector const&) {
    HdRenderDelegate* delegate = GetRenderIndex()->GetRenderDelegate();
    bool restart = !_started;
    int sceneVersion = _param->SceneVersion();
    if (sceneVersion != _sceneVersion) restart = true;
    if (delegate->GetRenderSettingsVersion() != _settingsVersion) restart = true;
    GfMatrix4d view = state->GetWorldToViewMatrix(), projection = state->GetProjectionMatrix();
    if (view != _view || projection != _projection) restart = true;
    GfRect2i dataWindow = DataWindow(state);
    gi::CameraDesc camera = CameraOf(state->GetCamera(), view, projection);
    HdRenderSettings::RenderProducts products;
    bool productMode = false;
    if (!delegate->GetRenderSetting<bool>(HdRenderSettingsTokens->enableInteractive, true) &&
        !(products = _param->Products()).empty()) {
        std::string problem;
        productMode = ProductFraming(GetRenderIndex(), products, &camera, &dataWindow, &problem);
        if (!problem.empty()) _param->Warn(problem);
    }
    if (dataWindow != _dataWindow) restart = true;
    HdRenderPassAovBindingVector aovs = state->GetAovBindings();
    for (HdRenderPassAovBinding& aov : aovs)
        if (!aov.renderBuffer && !aov.renderBufferId.IsEmpty())
            aov.renderBuffer = static_cast<HdRenderBuffer*>(
                GetRenderIndex()->GetBprim(HdPrimTypeTokens->renderBuffer, aov.renderBufferId));
    bool aovsChanged = aovs != _aovs;
    if (!restart && !aovsChanged) return;

    _param->StopRender();
    if (aovsChanged) {
        for (HdRenderPassAovBinding const& aov : aovs) {
            auto* buffer = dynamic_cast<HdGiRenderBuffer*>(aov.renderBuffer);
            if (!buffer) continue;
            double clear = 0;
            if (aov.clearValue.IsHolding<float>()) clear = aov.clearValue.UncheckedGet<float>();
            else if (aov.clearValue.IsHolding<int>()) clear = aov.clearValue.UncheckedGet<int>();
            else if (aov.clearValue.IsHolding<GfVec4f>()) clear = aov.clearValue.UncheckedGet<GfVec4f>()[0];
            buffer->Clear(float(clear));
            if (!HdGiIsSupportedAov(aov.aovName))
                TF_WARN("hdGi: AOV '%s' is not supported; it keeps its clear value", aov.aovName.GetText());
        }
    }
    _sceneVersion = sceneVersion;
    _settingsVersion = delegate->GetRenderSettingsVersion();
    _view = view;
    _projection = projection;
    _dataWindow = dataWindow;
    _aovs = aovs;

    HdGiRenderJob job;
    job.settings = HdGiReadSettings(*delegate);
    job.denoise = HdGiReadDenoise(*delegate);
    job.products = products;
    job.productMode = productMode;
    job.camera = camera;
    job.projection = projection;
    job.dataWindow = dataWindow;
    job.aovs = aovs;
    job.domeLightCameraVisibility =
        delegate->GetRenderSetting<bool>(HdRenderSettingsTokens->domeLightCameraVisibility, true);
    for (HdRenderPassAovBinding const& aov : aovs)
        if (auto* buffer = dynamic_cast<HdGiRenderBuffer*>(aov.renderBuffer)) buffer->SetConverged(false);
    _session->SetJob(job);
    _cancel->store(false);
    _thread->StartRender();
    _started = true;
}

PXR_NAMESPACE_CLOSE_SCOPE
