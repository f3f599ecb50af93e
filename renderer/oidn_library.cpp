#include "oidn_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace gi {

namespace {

constexpr const char* kLibraryName = "libOpenImageDenoise.so.2";

// A folder names the library inside it; a file (or a bare name for the system loader) stands.
std::string libraryIn(const std::string& place) {
    std::error_code ignored;
    if (std::filesystem::is_directory(place, ignored)) return (std::filesystem::path(place) / kLibraryName).string();
    return place;
}

template <typename Function>
bool resolve(void* handle, const char* name, Function& out, std::string& missing) {
    out = reinterpret_cast<Function>(dlsym(handle, name));
    if (!out) missing += std::string(missing.empty() ? "" : ", ") + name;
    return out != nullptr;
}

}  // namespace

std::vector<std::string> OidnLibrary::candidates(const std::vector<std::string>& hostFolders) {
    if (const char* chosen = std::getenv("GI_OIDN_LIBRARY"); chosen && *chosen) return {libraryIn(chosen)};
    std::vector<std::string> out;
    for (const std::string& folder : hostFolders)
        if (!folder.empty()) out.push_back(libraryIn(folder));
#ifdef GI_OIDN_BUILD_LIBRARY
    out.push_back(GI_OIDN_BUILD_LIBRARY);
#endif
    out.push_back(kLibraryName);
    return out;
}

std::shared_ptr<const OidnLibrary> OidnLibrary::load(const std::vector<std::string>& candidates) {
    std::string tried;
    for (const std::string& path : candidates) {
        // RTLD_NODELETE: OIDN's CPU device keeps TBB worker state that must outlive dlclose.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        if (!handle) {
            const char* why = dlerror();
            tried += "\n  " + path + ": " + (why ? why : "cannot be loaded");
            continue;
        }
        std::shared_ptr<OidnLibrary> library(new OidnLibrary());
        library->handle_ = handle;
        library->path_ = path;
        std::string missing;
        OidnLibrary& l = *library;
        resolve(handle, "oidnNewDevice", l.newDevice, missing);
        resolve(handle, "oidnSetDeviceInt", l.setDeviceInt, missing);
        resolve(handle, "oidnGetDeviceInt", l.getDeviceInt, missing);
        resolve(handle, "oidnCommitDevice", l.commitDevice, missing);
        resolve(handle, "oidnGetDeviceError", l.getDeviceError, missing);
        resolve(handle, "oidnReleaseDevice", l.releaseDevice, missing);
        resolve(handle, "oidnNewFilter", l.newFilter, missing);
        resolve(handle, "oidnSetSharedFilterImage", l.setSharedFilterImage, missing);
        resolve(handle, "oidnSetFilterBool", l.setFilterBool, missing);
        resolve(handle, "oidnSetFilterInt", l.setFilterInt, missing);
        resolve(handle, "oidnCommitFilter", l.commitFilter, missing);
        resolve(handle, "oidnExecuteFilter", l.executeFilter, missing);
        resolve(handle, "oidnReleaseFilter", l.releaseFilter, missing);
        if (missing.empty()) return library;
        tried += "\n  " + path + ": not Open Image Denoise 2.x (lacks " + missing + ")";
    }
    throw DenoiserUnavailable(std::string(kOidnInstallHint) + "; tried:" + tried);
}

OidnLibrary::~OidnLibrary() {
    if (handle_) dlclose(handle_);
}

}  // namespace gi
