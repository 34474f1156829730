// Recent files (see recent_files.h). Saved atomically like every other file the
// viewer writes, so two viewers closing at once cannot leave half a list.
#include "recent_files.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "image_io.h"

namespace rtview {

std::string absolute_path(const std::string& path) {
    if (path.empty()) return path;
    std::error_code ec;
    std::filesystem::path p = std::filesystem::absolute(path, ec);
    return ec ? path : p.lexically_normal().string();
}

std::string RecentFiles::default_path() {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    std::string base;
    if (xdg && *xdg == '/') {
        base = xdg;
    } else if (const char* home = std::getenv("HOME"); home && *home) {
        base = std::string(home) + "/.config";
    } else {
        return {};
    }
    return base + "/raytracer-view/recent.txt";
}

RecentFiles::RecentFiles(std::string file) : file_(file.empty() ? default_path() : std::move(file)) { load(); }

void RecentFiles::load() {
    paths_.clear();
    if (file_.empty()) return;
    std::string text;
    if (!rt::read_file(file_, text, 1 << 20).ok()) return;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line) && paths_.size() < kMax) {
        if (!line.empty() && std::find(paths_.begin(), paths_.end(), line) == paths_.end()) paths_.push_back(line);
    }
}

rt::Status save_config_file(const std::string& file, const std::string& text) {
    if (file.empty()) return {};
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::path(file).parent_path();
    std::filesystem::create_directories(dir, ec);
    if (ec) return rt::Status::error("cannot create " + dir.string() + ": " + ec.message(), rt::kExitUsage);
    return rt::write_file_atomic(file, text);
}

rt::Status RecentFiles::save() const {
    std::string text;
    for (const auto& p : paths_) text += p + "\n";
    return save_config_file(file_, text);
}

rt::Status RecentFiles::add(const std::string& path) {
    if (path.empty()) return {};
    // Another viewer may have added files since we loaded; merge rather than clobber.
    load();
    std::string abs = absolute_path(path);
    paths_.erase(std::remove(paths_.begin(), paths_.end(), abs), paths_.end());
    paths_.insert(paths_.begin(), abs);
    if (paths_.size() > kMax) paths_.resize(kMax);
    return save();
}

rt::Status RecentFiles::remove(const std::string& path) {
    load();
    paths_.erase(std::remove(paths_.begin(), paths_.end(), path), paths_.end());
    return save();
}

}  // namespace rtview
