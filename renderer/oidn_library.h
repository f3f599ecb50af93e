// Intel Open Image Denoise 2.x, loaded at run time (dlopen) so that the renderer, the CLI and the
// Hydra plugin build and run without it: only a denoise request needs it, and that fails with a
// message saying what to install. The few C API functions the denoiser uses are declared here
// from OIDN's documented C API (oidn.h), which OIDN keeps stable across 2.x.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace gi {

// Asked to denoise, but no usable OIDN 2.x library was found.
struct DenoiserUnavailable : std::runtime_error {
    using std::runtime_error::runtime_error;
};

namespace oidn {
// The C API's handles and enumerators that the denoiser uses (values from oidn.h).
using Device = struct DeviceImpl*;
using Filter = struct FilterImpl*;
enum DeviceType : int { kDeviceCpu = 1 };
enum Format : int { kFormatFloat3 = 3 };
enum Error : int { kErrorNone = 0 };
enum Quality : int { kQualityBalanced = 5, kQualityHigh = 6 };
}  // namespace oidn

class OidnLibrary {
public:
    // The library files tried, in order: $GI_OIDN_LIBRARY alone when it is set (a file, or a folder
    // holding libOpenImageDenoise.so.2); else libOpenImageDenoise.so.2 in each of `hostFolders`
    // (a host's own finding, e.g. gi's Python package passes the installed pyoidn's library
    // folder), then in the copy CMake found when the renderer was built (pyoidn's, when the
    // building Python had it), then the system loader's search (LD_LIBRARY_PATH, ld.so.cache).
    static std::vector<std::string> candidates(const std::vector<std::string>& hostFolders = {});
    // The first candidate that loads and has every function used; throws DenoiserUnavailable
    // naming each candidate and why it failed, and what to install.
    static std::shared_ptr<const OidnLibrary> load(const std::vector<std::string>& candidates);

    ~OidnLibrary();
    OidnLibrary(const OidnLibrary&) = delete;
    OidnLibrary& operator=(const OidnLibrary&) = delete;

    const std::string& path() const { return path_; }

    oidn::Device (*newDevice)(oidn::DeviceType) = nullptr;
    void (*setDeviceInt)(oidn::Device, const char*, int) = nullptr;
    int (*getDeviceInt)(oidn::Device, const char*) = nullptr;
    void (*commitDevice)(oidn::Device) = nullptr;
    oidn::Error (*getDeviceError)(oidn::Device, const char**) = nullptr;
    void (*releaseDevice)(oidn::Device) = nullptr;
    oidn::Filter (*newFilter)(oidn::Device, const char*) = nullptr;
    void (*setSharedFilterImage)(oidn::Filter, const char*, void*, oidn::Format, size_t, size_t, size_t, size_t,
                                 size_t) = nullptr;
    void (*setFilterBool)(oidn::Filter, const char*, bool) = nullptr;
    void (*setFilterInt)(oidn::Filter, const char*, int) = nullptr;
    void (*commitFilter)(oidn::Filter) = nullptr;
    void (*executeFilter)(oidn::Filter) = nullptr;
    void (*releaseFilter)(oidn::Filter) = nullptr;

private:
    OidnLibrary() = default;
    void* handle_ = nullptr;
    std::string path_;
};

// What to tell a user who asked for denoising without OIDN.
inline constexpr const char* kOidnInstallHint =
    "denoising needs Intel Open Image Denoise 2.x: install it with `pip install pyoidn` (or "
    "`pip install gi[denoise]`), or point GI_OIDN_LIBRARY at a libOpenImageDenoise.so.2";

}  // namespace gi
