#include "renderPass.h"

#include <algorithm>

#include "camera.h"
#include "pxr/imaging/hd/camera.h"
#include "pxr/imaging/hd/renderIndex.h"
#include "pxr/imaging/hd/renderPassState.h"
#include "pxr/imaging/hd/tokens.h"
#include "pxr/imaging/hd/utils.h"
#include "products.h"
#include "renderBuffer.h"
#include "renderSettings.h"
#include "renderer/render_vars.h"

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

// The camera sprim's UsdGeomCamera attributes as Hydra holds them, for the renderer's camera
// rule (renderer/camera_framing.h), which `gi render` fills from the same attributes on the
// stage. Lengths stay in Hydra's scene units (UsdImaging's conversion of USD's tenths; the rule
// converts USD's tenths the same way), so both hosts start from the same floats.
gi::CameraDesc CameraOf(HdCamera const& camera) {
    gi::CameraDesc desc;
    desc.name = camera.GetId().GetString();
    desc.transform = HdGiToMat4(camera.GetTransform());
    desc.projection = camera.GetProjection() == HdCamera::Orthographic ? "orthographic" : "perspective";
    desc.lengthUnit = gi::CameraLengthUnit::SceneUnit;
    desc.focalLength = camera.GetFocalLength();
    desc.horizontalAperture = camera.GetHorizontalAperture();
    desc.verticalAperture = camera.GetVerticalAperture();
    desc.horizontalApertureOffset = camera.GetHorizontalApertureOffset();
    desc.verticalApertureOffset = camera.GetVerticalApertureOffset();
    desc.fStop = camera.GetFStop();
    desc.focusDistance = camera.GetFocusDistance();
    desc.clipNear = camera.GetClippingRange().GetMin();
    desc.clipFar = camera.GetClippingRange().GetMax();
    // Relative to the frame, as SampleTransform's and SamplePrimvar's times (motion blur).
    desc.shutterOpen = float(camera.GetShutterOpen());
    desc.shutterClose = float(camera.GetShutterClose());
    if (auto const* gi = dynamic_cast<HdGiCamera const*>(&camera))
        for (GfMatrix4d const& m : gi->MotionSteps()) desc.motionTransforms.push_back(HdGiToMat4(m));
    return desc;
}

// Hydra's conform window policies are UsdRenderSettings' aspectRatioConformPolicy tokens under
// other names (CameraUtilConformWindowPolicy's documentation).
gi::ApertureConform ConformOf(CameraUtilConformWindowPolicy policy) {
    switch (policy) {
        case CameraUtilMatchVertically: return gi::ApertureConform::AdjustApertureWidth;
        case CameraUtilMatchHorizontally: return gi::ApertureConform::AdjustApertureHeight;
        case CameraUtilCrop: return gi::ApertureConform::CropAperture;
        case CameraUtilDontConform: return gi::ApertureConform::AdjustPixelAspectRatio;
        case CameraUtilFit: break;
    }
    return gi::ApertureConform::ExpandAperture;
}

// An interactive host's framing: its window policy, and its display window (where the camera's
// frame lies in the pixels rendered, the data window; usdview may show more than the frame).
gi::ImageFraming ViewportFraming(HdRenderPassStateSharedPtr const& state, GfRect2i const& dataWindow) {
    gi::ImageFraming framing;
    framing.conform = ConformOf(state->GetWindowPolicy());
    CameraUtilFraming const& hydra = state->GetFraming();
    if (!hydra.IsValid() || dataWindow.IsEmpty()) return framing;
    GfVec2f const origin(float(dataWindow.GetMinX()), float(dataWindow.GetMinY()));
    GfVec2f const size(float(dataWindow.GetWidth()), float(dataWindow.GetHeight()));
    GfVec2f const from = hydra.displayWindow.GetMin() - origin, to = hydra.displayWindow.GetMax() - origin;
    framing.displayLeft = from[0] / size[0];
    framing.displayTop = from[1] / size[1];
    framing.displayRight = to[0] / size[0];
    framing.displayBottom = to[1] / size[1];
    framing.pixelAspectRatio = hydra.pixelAspectRatio;
    return framing;
}

// A batch host's render products (usdrecord sets enableInteractive false) are rendered as the
// stage declares them: each product's camera, resolution, aspect ratio conform policy, pixel
// aspect ratio and data window (pixels of the resolution), instead of the host's viewport.
// Products that agree on all of these share one render; the others render after it, in the order
// of their first product (`gi render` renders each product on its own, to the same bits). A
// product without a resolution, or whose camera is not in the scene (warned), is written from
// `host`, the host's camera and image size.
std::vector<HdGiProductImage> ProductImages(HdRenderIndex* index, HdRenderSettings::RenderProducts const& products,
                                            HdGiProductImage const& host, std::vector<std::string>* problems) {
    std::vector<HdGiProductImage> images;
    auto sameImage = [](HdRenderSettings::RenderProduct const& a, HdRenderSettings::RenderProduct const& b) {
        return a.cameraPath == b.cameraPath && a.resolution == b.resolution &&
               a.aspectRatioConformPolicy == b.aspectRatioConformPolicy && a.pixelAspectRatio == b.pixelAspectRatio &&
               a.dataWindowNDC == b.dataWindowNDC;
    };
    for (HdRenderSettings::RenderProduct const& product : products) {
        std::string const where = "render product " + product.productPath.GetString();
        auto const* sprim =
            product.resolution[0] > 0 && product.resolution[1] > 0
                ? dynamic_cast<HdCamera const*>(index->GetSprim(HdPrimTypeTokens->camera, product.cameraPath))
                : nullptr;
        if (product.resolution[0] > 0 && product.resolution[1] > 0 && !sprim)
            problems->push_back(where + ": camera <" + product.cameraPath.GetString() +
                                "> is not in the scene; the host's camera and image size are used");
        auto same = std::find_if(images.begin(), images.end(), [&](HdGiProductImage const& image) {
            return sprim ? image.productFramed && sameImage(image.products.front(), product) : !image.productFramed;
        });
        if (same != images.end()) {
            same->products.push_back(product);
            continue;
        }
        if (!sprim) {
            images.push_back(host);
            images.back().products = {product};
            continue;
        }
        HdGiProductImage& image = images.emplace_back();
        image.productFramed = true;
        image.products = {product};
        image.camera = CameraOf(*sprim);
        // The flattened product holds the settings' policy when the product authors none.
        std::string const policy = product.aspectRatioConformPolicy.GetString();
        if (!policy.empty() && !gi::parseApertureConform(policy, &image.framing.conform))
            problems->push_back(where + ": aspectRatioConformPolicy '" + policy + "' is unknown; " +
                                gi::apertureConformToken(image.framing.conform) + " is used");
        image.framing.pixelAspectRatio = product.pixelAspectRatio;
        image.dataWindow = GfRect2i(GfVec2i(0), product.resolution[0], product.resolution[1]);
        std::string problem;
        image.window = HdGiProductWindow(product, product.resolution[0], product.resolution[1], &problem);
        if (!problem.empty()) problems->push_back(where + ": " + problem);
    }
    return images;
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
    // Every Hydra host gives the pass a camera sprim: a scene camera, or usdview's and usdrecord's
    // free camera (HdxFreeCameraSceneDelegate, whose UsdGeomCamera attributes GfCamera derives
    // from the viewport's view and projection matrices), so its attributes are always there for
    // the shared rule. Without one (Hydra's matrices are then the identity) the renderer frames
    // the whole scene, as `gi render` does for a stage without a camera.
    std::optional<gi::CameraDesc> camera;
    if (HdCamera const* sprim = state->GetCamera()) camera = CameraOf(*sprim);
    else if (!_warnedNoCamera) {
        _warnedNoCamera = true;
        _param->Warn("the render pass has no camera; using one that frames the whole scene");
    }
    gi::ImageFraming framing = ViewportFraming(state, dataWindow);
    HdRenderSettings::RenderProducts products;
    std::vector<HdGiProductImage> moreImages;
    bool productMode = false;
    gi::PixelWindow window;  // the pixels rendered: empty, all of dataWindow
    if (!delegate->GetRenderSetting<bool>(HdRenderSettingsTokens->enableInteractive, true) &&
        !(products = _param->Products()).empty()) {
        std::vector<std::string> problems;
        HdGiProductImage host{camera, framing, dataWindow, window, {}, false};
        std::vector<HdGiProductImage> images = ProductImages(GetRenderIndex(), products, host, &problems);
        for (std::string const& problem : problems) _param->Warn(problem);
        HdGiProductImage const& first = images.front();
        productMode = first.productFramed;
        camera = first.camera;
        framing = first.framing;
        dataWindow = first.dataWindow;
        window = first.window;
        products = first.products;
        moreImages.assign(images.begin() + 1, images.end());
    }
    // The frame the host renders (usdrecord's time code, through the scene globals' currentFrame):
    // it seeds the render as `gi render --frames` does and names the products' files, so a new
    // frame renders (and writes them) again even where nothing moved.
    std::optional<double> frame;
    double currentFrame = 0;
    if (HdUtils::GetCurrentFrame(GetRenderIndex()->GetTerminalSceneIndex(), &currentFrame)) frame = currentFrame;
    if (dataWindow != _dataWindow || !(window == _window) || frame != _frame) restart = true;
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
    _window = window;
    _frame = frame;
    _aovs = aovs;

    HdGiRenderJob job;
    job.settings = HdGiReadSettings(*delegate);
    if (frame) job.settings.seed = gi::frameSeed(job.settings.seed, *frame);
    job.settings.framing = framing;
    job.settings.window = window;
    job.frame = frame;
    job.denoise = HdGiReadDenoise(*delegate);
    job.products = products;
    job.moreImages = moreImages;
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
