#include "renderSettings.h"

#include <cstdlib>

#include "pxr/base/tf/diagnostic.h"
#include "pxr/imaging/hd/tokens.h"
#include "renderParam.h"

PXR_NAMESPACE_OPEN_SCOPE

namespace {
constexpr int kDefaultSamples = 64;

// Hosts send numbers as whatever type their UI produced (usdview's dialog: text).
bool ToDouble(VtValue const& v, double* out) {
    if (v.IsHolding<int>()) return *out = v.UncheckedGet<int>(), true;
    if (v.IsHolding<unsigned>()) return *out = v.UncheckedGet<unsigned>(), true;
    if (v.IsHolding<int64_t>()) return *out = double(v.UncheckedGet<int64_t>()), true;
    if (v.IsHolding<float>()) return *out = v.UncheckedGet<float>(), true;
    if (v.IsHolding<double>()) return *out = v.UncheckedGet<double>(), true;
    if (v.IsHolding<bool>()) return *out = v.UncheckedGet<bool>() ? 1 : 0, true;
    if (v.IsHolding<std::string>() || v.IsHolding<TfToken>()) {
        std::string s = v.IsHolding<std::string>() ? v.UncheckedGet<std::string>() : v.UncheckedGet<TfToken>().GetString();
        char* end = nullptr;
        double d = std::strtod(s.c_str(), &end);
        if (end != s.c_str()) return *out = d, true;
    }
    return false;
}

std::string ToString(VtValue const& v) {
    if (v.IsHolding<std::string>()) return v.UncheckedGet<std::string>();
    if (v.IsHolding<TfToken>()) return v.UncheckedGet<TfToken>().GetString();
    return "";
}

VtValue Typed(gi::ParamInfo const& p, double value) {
    if (p.type == "int") return VtValue(int(value));
    if (p.type == "bool") return VtValue(value != 0);
    return VtValue(float(value));
}
}  // namespace

TfToken const& HdGiSettingsTokens::Integrator() {
    static TfToken t("gi:integrator");
    return t;
}
TfToken const& HdGiSettingsTokens::Seed() {
    static TfToken t("gi:seed");
    return t;
}
TfToken const& HdGiSettingsTokens::TimeLimit() {
    static TfToken t("gi:timeLimit");
    return t;
}
TfToken const& HdGiSettingsTokens::Preset() {
    static TfToken t("gi:preset");
    return t;
}
TfToken const& HdGiSettingsTokens::Denoise() {
    static TfToken t("gi:denoise");
    return t;
}
TfToken HdGiSettingsTokens::Param(std::string const& integrator, std::string const& param) {
    return TfToken("gi:" + integrator + ":" + param);
}

HdRenderSettingDescriptorList HdGiSettingDescriptors() {
    HdRenderSettingDescriptorList list;
    std::string names;
    for (gi::IntegratorInfo const& info : gi::integratorRegistry()) names += (names.empty() ? "" : ", ") + info.name;
    list.push_back({"Integrator (" + names + ")", HdGiSettingsTokens::Integrator(), VtValue(std::string("path"))});
    list.push_back({"Samples per pixel", HdRenderSettingsTokens->convergedSamplesPerPixel, VtValue(kDefaultSamples)});
    list.push_back({"Seed", HdGiSettingsTokens::Seed(), VtValue(0)});
    list.push_back({"Time limit (seconds, 0 = none)", HdGiSettingsTokens::TimeLimit(), VtValue(0.0f)});
    std::string presets;
    for (gi::Preset const& p : gi::presets()) presets += (presets.empty() ? "" : ", ") + p.name;
    list.push_back({"Preset (" + presets + "; empty = the defaults)", HdGiSettingsTokens::Preset(), VtValue(std::string())});
    list.push_back({"Denoise the colour (Open Image Denoise 2.x: pip install pyoidn)", HdGiSettingsTokens::Denoise(),
                    VtValue(false)});
    for (gi::IntegratorInfo const& info : gi::integratorRegistry())
        for (gi::ParamInfo const& p : info.params)
            list.push_back({info.name + ": " + p.name + " (" + p.description + ")",
                            HdGiSettingsTokens::Param(info.name, p.name), Typed(p, p.defaultValue)});
    return list;
}

gi::RenderSettings HdGiReadSettings(HdRenderDelegate const& delegate) {
    gi::RenderSettings s;
    std::string name = ToString(delegate.GetRenderSetting(HdGiSettingsTokens::Integrator()));
    if (name.empty()) name = "path";
    gi::IntegratorInfo const* info = gi::findIntegrator(name);
    if (!info) {
        TF_WARN("hdGi: render setting gi:integrator: unknown integrator '%s'; using path", name.c_str());
        info = gi::findIntegrator("path");
    }
    s.integrator = info->name;
    double v = 0;
    s.spp = ToDouble(delegate.GetRenderSetting(HdRenderSettingsTokens->convergedSamplesPerPixel), &v) && v >= 1
                ? int(v)
                : kDefaultSamples;
    s.seed = ToDouble(delegate.GetRenderSetting(HdGiSettingsTokens::Seed()), &v) && v >= 0 ? uint32_t(v) : 0;
    s.timeLimit = ToDouble(delegate.GetRenderSetting(HdGiSettingsTokens::TimeLimit()), &v) && v > 0 ? v : 0;
    std::string preset = ToString(delegate.GetRenderSetting(HdGiSettingsTokens::Preset()));
    if (!preset.empty() && !gi::findPreset(preset)) TF_WARN("hdGi: render setting gi:preset: unknown preset '%s'; ignored", preset.c_str());
    else s.preset = preset;
    for (gi::ParamInfo const& p : info->params) {
        VtValue value = delegate.GetRenderSetting(HdGiSettingsTokens::Param(info->name, p.name));
        if (value.IsEmpty()) continue;
        if (!ToDouble(value, &v)) {
            TF_WARN("hdGi: render setting %s: not a number; using %g", HdGiSettingsTokens::Param(info->name, p.name).GetText(), p.defaultValue);
            continue;
        }
        // Every setting holds its default from the start (HdRenderDelegate fills them in), so
        // one at its default leaves the preset's value; compared at the setting's own precision.
        if (s.preset.empty() || Typed(p, v) != Typed(p, p.defaultValue)) s.params.set(p.name, v);
    }
    return s;
}

bool HdGiReadDenoise(HdRenderDelegate const& delegate) {
    double v = 0;
    return ToDouble(delegate.GetRenderSetting(HdGiSettingsTokens::Denoise()), &v) && v != 0;
}

bool HdGiIsKnownSetting(std::string const& key) {
    for (TfToken const& t : {HdGiSettingsTokens::Integrator(), HdGiSettingsTokens::Seed(), HdGiSettingsTokens::TimeLimit(),
                             HdGiSettingsTokens::Preset(), HdGiSettingsTokens::Denoise()})
        if (key == t.GetString()) return true;
    if (key == "gi:samples") return true;
    // gi:<integrator>:<param>, both names the registry's.
    size_t colon = key.find(':', 3);
    if (key.rfind("gi:", 0) != 0 || colon == std::string::npos) return false;
    gi::IntegratorInfo const* info = gi::findIntegrator(key.substr(3, colon - 3));
    if (!info) return false;
    for (gi::ParamInfo const& p : info->params)
        if (p.name == key.substr(colon + 1)) return true;
    return false;
}

void HdGiRenderSettings::_Sync(HdSceneDelegate*, HdRenderParam* renderParam, HdDirtyBits const*) {
    if (!IsActive()) return;
    static_cast<HdGiRenderParam*>(renderParam)->SetProducts(GetRenderProducts());
    static TfToken const samples("gi:samples");
    for (auto const& [key, value] : GetNamespacedSettings()) {
        // A typo ("gi:path:pathDepht") would otherwise leave that parameter at its default unseen.
        if (key.rfind("gi:", 0) == 0 && !HdGiIsKnownSetting(key))
            TF_WARN("hdGi: render settings %s: unknown setting %s (gi:integrator, gi:samples, gi:seed, gi:timeLimit, "
                    "gi:preset, gi:denoise or gi:<integrator>:<parameter>); ignored",
                    GetId().GetText(), key.c_str());
        TfToken token(key);
        if (token == samples) token = HdRenderSettingsTokens->convergedSamplesPerPixel;
        if (_delegate->GetRenderSetting(token) != value) _delegate->SetRenderSetting(token, value);
    }
}

PXR_NAMESPACE_CLOSE_SCOPE
