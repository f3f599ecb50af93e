#include "image_cache.h"

namespace gi {

std::shared_ptr<Image> ImageCache::get(const std::string& file, const std::string& colorSpace, std::string& error,
                                       bool* read) {
    *read = false;
    std::error_code ec;
    auto modified = std::filesystem::last_write_time(file, ec);
    uintmax_t size = ec ? 0 : std::filesystem::file_size(file, ec);
    if (ec) {
        error = "file not found";
        return nullptr;
    }
    std::string key = file + "|" + colorSpace;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = entries_.find(key);
        if (it != entries_.end() && it->second.modified == modified && it->second.size == size)
            if (std::shared_ptr<Image> image = it->second.image.lock()) return image;
    }
    // Read outside the lock: scenes building at once do not wait on each other's files.
    std::shared_ptr<Image> image = Image::load(file, colorSpace, error);
    if (!image) return nullptr;
    *read = true;
    std::lock_guard<std::mutex> lock(mutex_);
    entries_[key] = Entry{image, modified, size};
    for (auto it = entries_.begin(); it != entries_.end();)  // forget freed images
        it = it->second.image.expired() ? entries_.erase(it) : std::next(it);
    return image;
}

}  // namespace gi
