// Recovery files are named by a hash of the document's absolute path, so two
// viewers on different files never share one; the first line holds the path itself.
#include "recovery.h"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "document.h"
#include "image_io.h"

namespace rtview {
namespace fs = std::filesystem;

namespace {

std::string default_dir() {
    if (const char* state = std::getenv("XDG_STATE_HOME"); state && *state)
        return std::string(state) + "/raytracer-view/recovery";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::string(home) + "/.local/state/raytracer-view/recovery";
    return "/tmp/raytracer-view-recovery";
}

std::string absolute(const std::string& path) {
    if (path.empty()) return "(default scene)";
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    return ec ? path : p.lexically_normal().string();
}

}  // namespace

Recovery::Recovery(std::string dir) : dir_(dir.empty() ? default_dir() : std::move(dir)) {}

std::string Recovery::file_for(const std::string& doc_path) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (unsigned char c : absolute(doc_path)) h = (h ^ c) * 1099511628211ull;
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.txt", static_cast<unsigned long long>(h));
    return dir_ + "/" + name;
}

rt::Status Recovery::update(const std::string& doc_path, const std::string& text, bool modified, double now,
                            double interval) {
    if (doc_path != last_path_) {
        // Another document (Save As, Open): what was unsaved in the last one has been
        // saved or let go by the user, so its copy would only raise a false alarm.
        if (written_) discard(last_path_);
        last_path_ = doc_path;
        last_hash_ = 0;
        written_ = false;
    }
    if (!modified) {
        if (written_) discard(doc_path);
        return {};
    }
    std::uint64_t h = text_hash(text);
    if (written_ && h == last_hash_) return {};
    if (now - last_write_ < interval) return {};
    std::error_code ec;
    fs::create_directories(dir_, ec);
    const rt::Status written = rt::write_file_atomic(file_for(doc_path), absolute(doc_path) + "\n" + text);
    last_write_ = now;
    if (!written) return written;
    last_hash_ = h;
    written_ = true;
    return {};
}

std::optional<std::string> Recovery::find(const std::string& doc_path) const {
    std::string data;
    if (!rt::read_file(file_for(doc_path), data, std::size_t(256) << 20).ok()) return std::nullopt;
    std::size_t nl = data.find('\n');
    if (nl == std::string::npos || data.compare(0, nl, absolute(doc_path)) != 0) return std::nullopt;
    return data.substr(nl + 1);
}

void Recovery::discard(const std::string& doc_path) {
    std::error_code ec;
    fs::remove(file_for(doc_path), ec);
    if (doc_path == last_path_) {
        written_ = false;
        last_hash_ = 0;
    }
}

}  // namespace rtview
