// Denoising a rendered image with Open Image Denoise's "RT" filter (a noisy HDR beauty guided by
// the film's albedo and normal AOVs), on OIDN's CPU device with the renderer's own host buffers.
// Both hosts use it: gi render --denoise and gi study (through gi._core), and hdGi's gi:denoise.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "film.h"
#include "oidn_library.h"

namespace gi {

class Denoiser {
public:
    // Loads OIDN (see OidnLibrary::candidates for where it is looked for) and creates its CPU
    // device with `threads` threads (0 = OIDN's default: all). Throws DenoiserUnavailable, with
    // what to install, when no OIDN 2.x loads or its device cannot be created here.
    explicit Denoiser(const std::vector<std::string>& hostFolders = {}, int threads = 0);
    ~Denoiser();
    Denoiser(const Denoiser&) = delete;
    Denoiser& operator=(const Denoiser&) = delete;

    std::string version() const;  // of the loaded OIDN, e.g. "2.5.1"
    const std::string& libraryPath() const { return library_->path(); }

    // The denoised colour of `color` (linear HDR radiance, W*H*3, row 0 at the top, as Film gives
    // it) guided by `albedo` (W*H*3, clamped to OIDN's [0, 1]) and `normal` (W*H*3, any consistent
    // space; the film's are world-space unit vectors, 0 where nothing was hit).
    // prefilterAux: denoise the albedo and normal first and tell the beauty filter they are clean
    // (OIDN's documented final-frame set-up: the film's AOVs are sample means, noisy at low spp
    // wherever the first hit varies inside a pixel); off, they go in as they are with cleanAux off
    // (one filter instead of three, for interactive previews).
    // Non-finite input values become 0. Throws std::invalid_argument for sizes that do not match,
    // std::runtime_error when OIDN fails or returns a non-finite value.
    // Not thread-safe: it keeps its filters and buffers between calls of one image size.
    std::vector<float> denoise(const std::vector<float>& color, const std::vector<float>& albedo,
                               const std::vector<float>& normal, int width, int height, bool prefilterAux = true);
    std::vector<float> denoise(const Film& film, bool prefilterAux = true);

private:
    void check(const char* step) const;  // throws std::runtime_error with OIDN's message
    void prepare(int width, int height, bool prefilterAux);
    void releaseFilters();

    std::shared_ptr<const OidnLibrary> library_;
    oidn::Device device_ = nullptr;
    // Filters bound to the buffers below for one image size and set-up (rebuilt when they change).
    int width_ = 0, height_ = 0;
    bool prefilterAux_ = false;
    oidn::Filter beauty_ = nullptr, albedoFilter_ = nullptr, normalFilter_ = nullptr;
    std::vector<float> color_, albedo_, normal_, cleanAlbedo_, cleanNormal_, output_;
};

}  // namespace gi
