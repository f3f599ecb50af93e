// Images shared by the scenes built one after another from the same source: a Hydra session
// rebuilds its scene on every edit, and must not read every texture again each time.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "texture.h"

namespace gi {

class ImageCache {
public:
    // The image of `file` decoded for `colorSpace`: the one already held by a live scene when
    // the file is unchanged on disk (same modification time and size), else read now (`read`
    // is then set). nullptr with `error` when it cannot be read; failures are not remembered,
    // so a file that appears later is found.
    std::shared_ptr<Image> get(const std::string& file, const std::string& colorSpace, std::string& error, bool* read);

private:
    struct Entry {
        std::weak_ptr<Image> image;  // weak: an image no scene uses any more is freed
        std::filesystem::file_time_type modified;
        uintmax_t size = 0;
    };
    std::mutex mutex_;
    std::map<std::string, Entry> entries_;
};

}  // namespace gi
