#include "denoiser.h"

#include <algorithm>
#include <cmath>

namespace gi {

namespace {

float finiteOr0(float v) { return std::isfinite(v) ? v : 0.0f; }

}  // namespace

Denoiser::Denoiser(const std::vector<std::string>& hostFolders, int threads)
    : library_(OidnLibrary::load(OidnLibrary::candidates(hostFolders))) {
    // The CPU device: the renderer's images are in host memory, which OIDN's CPU device reads
    // in place (a GPU device would need them copied into its own buffers).
    device_ = library_->newDevice(oidn::kDeviceCpu);
    if (device_ && threads > 0) library_->setDeviceInt(device_, "numThreads", threads);
    if (device_) library_->commitDevice(device_);
    const char* message = nullptr;
    if (!device_ || library_->getDeviceError(device_, &message) != oidn::kErrorNone) {
        std::string why = message ? message : "no device";
        if (device_) library_->releaseDevice(device_);
        throw DenoiserUnavailable("Open Image Denoise (" + library_->path() + ") cannot create its CPU device: " + why);
    }
    int major = library_->getDeviceInt(device_, "versionMajor");
    if (major != 2) {
        library_->releaseDevice(device_);
        throw DenoiserUnavailable(std::string(kOidnInstallHint) + "; " + library_->path() + " is version " +
                                  std::to_string(major) + ".x");
    }
}

Denoiser::~Denoiser() {
    releaseFilters();
    library_->releaseDevice(device_);
}

std::string Denoiser::version() const {
    return std::to_string(library_->getDeviceInt(device_, "versionMajor")) + "." +
           std::to_string(library_->getDeviceInt(device_, "versionMinor")) + "." +
           std::to_string(library_->getDeviceInt(device_, "versionPatch"));
}

void Denoiser::check(const char* step) const {
    const char* message = nullptr;
    if (library_->getDeviceError(device_, &message) != oidn::kErrorNone)
        throw std::runtime_error(std::string("Open Image Denoise failed to ") + step + ": " +
                                 (message ? message : "unknown error"));
}

void Denoiser::releaseFilters() {
    for (oidn::Filter* filter : {&beauty_, &albedoFilter_, &normalFilter_}) {
        if (*filter) library_->releaseFilter(*filter);
        *filter = nullptr;
    }
}

void Denoiser::prepare(int width, int height, bool prefilterAux) {
    if (beauty_ && width == width_ && height == height_ && prefilterAux == prefilterAux_) return;
    releaseFilters();
    size_t values = size_t(width) * height * 3;
    for (std::vector<float>* buffer : {&color_, &albedo_, &normal_, &output_}) buffer->assign(values, 0.0f);
    cleanAlbedo_.assign(prefilterAux ? values : 0, 0.0f);
    cleanNormal_.assign(prefilterAux ? values : 0, 0.0f);
    auto bind = [&](oidn::Filter filter, const char* name, std::vector<float>& buffer) {
        library_->setSharedFilterImage(filter, name, buffer.data(), oidn::kFormatFloat3, size_t(width),
                                       size_t(height), 0, 0, 0);
    };
    const OidnLibrary& l = *library_;
    // OIDN's documented prefiltering: the RT filter given only an auxiliary image denoises it.
    // At balanced quality: the Cornell box at 128x128, 16 spp, denoised in half the time of high
    // quality prefilters (0.50 against 0.94-1.12 s on a loaded 2-core machine) with the same FLIP
    // (0.0443 against 0.0445 for seed 3; 0.0511 for both for seed 4).
    if (prefilterAux) {
        albedoFilter_ = l.newFilter(device_, "RT");
        bind(albedoFilter_, "albedo", albedo_);
        bind(albedoFilter_, "output", cleanAlbedo_);
        l.setFilterInt(albedoFilter_, "quality", oidn::kQualityBalanced);
        l.commitFilter(albedoFilter_);
        normalFilter_ = l.newFilter(device_, "RT");
        bind(normalFilter_, "normal", normal_);
        bind(normalFilter_, "output", cleanNormal_);
        l.setFilterInt(normalFilter_, "quality", oidn::kQualityBalanced);
        l.commitFilter(normalFilter_);
    }
    beauty_ = l.newFilter(device_, "RT");
    bind(beauty_, "color", color_);
    bind(beauty_, "albedo", prefilterAux ? cleanAlbedo_ : albedo_);
    bind(beauty_, "normal", prefilterAux ? cleanNormal_ : normal_);
    bind(beauty_, "output", output_);
    l.setFilterBool(beauty_, "hdr", true);  // linear radiance, not [0, 1] display values
    l.setFilterBool(beauty_, "cleanAux", prefilterAux);
    l.setFilterInt(beauty_, "quality", oidn::kQualityHigh);
    l.commitFilter(beauty_);
    width_ = width, height_ = height, prefilterAux_ = prefilterAux;
    try {
        check("set up its filters");
    } catch (...) {
        releaseFilters();
        throw;
    }
}

std::vector<float> Denoiser::denoise(const std::vector<float>& color, const std::vector<float>& albedo,
                                     const std::vector<float>& normal, int width, int height, bool prefilterAux) {
    size_t values = size_t(std::max(width, 0)) * size_t(std::max(height, 0)) * 3;
    if (width <= 0 || height <= 0 || color.size() != values || albedo.size() != values || normal.size() != values)
        throw std::invalid_argument("denoise: colour, albedo and normal must each hold " + std::to_string(width) +
                                    "x" + std::to_string(height) + "x3 values");
    prepare(width, height, prefilterAux);
    for (size_t i = 0; i < values; ++i) {
        color_[i] = std::max(finiteOr0(color[i]), 0.0f);
        albedo_[i] = std::clamp(finiteOr0(albedo[i]), 0.0f, 1.0f);
        normal_[i] = std::clamp(finiteOr0(normal[i]), -1.0f, 1.0f);
    }
    if (prefilterAux) {
        library_->executeFilter(albedoFilter_);
        library_->executeFilter(normalFilter_);
    }
    library_->executeFilter(beauty_);
    check("denoise");
    size_t nonFinite = size_t(std::count_if(output_.begin(), output_.end(), [](float v) { return !std::isfinite(v); }));
    if (nonFinite > 0)
        throw std::runtime_error("Open Image Denoise returned " + std::to_string(nonFinite) + " non-finite values");
    return output_;
}

std::vector<float> Denoiser::denoise(const Film& film, bool prefilterAux) {
    return denoise(film.color(), film.albedo(), film.normal(), film.width(), film.height(), prefilterAux);
}

}  // namespace gi
