// Recovery files are named by a hash of the document's absolute path, so two
// viewers on different files never share one; the first line holds the path itself.
// The held edit's file names the text it belongs to by that text's hash, so that it
// is never written into another text (whose items may be others at those indices).
#include "recovery.h"

#include <cinttypes>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

#include "default_scene.h"
#include "document.h"
#include "new_scene.h"
#include "image_io.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "scene_writer.h"

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

constexpr std::size_t kMaxRecoveryBytes = std::size_t(256) << 20;

// "objects 3 7": the indices after the list's name.
std::string index_line(const char* name, const std::vector<std::size_t>& v) {
    std::string s = name;
    for (std::size_t i : v) s += " " + std::to_string(i);
    return s + "\n";
}

bool read_index_line(std::istream& in, const char* name, std::vector<std::size_t>& v) {
    std::string line;
    if (!std::getline(in, line)) return false;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word) || word != name) return false;
    for (std::size_t i; words >> i;) v.push_back(i);
    return words.eof();
}

// A held edit's file: the document's path, the hash of its text, the indices, then the
// items as a scene text (with the camera, so that it parses on its own).
std::string held_file_text(const std::string& doc, const HeldEdit& held, std::uint64_t base_hash) {
    char hash[40];
    std::snprintf(hash, sizeof hash, "held %016" PRIx64 "\n", base_hash);
    return doc + "\n" + hash + index_line("objects", held.objects) + index_line("planes", held.planes) +
           index_line("lights", held.lights) + (held.camera ? "camera 1\n" : "camera 0\n") + rt::write_scene(held.items);
}

bool parse_held_file(const std::string& data, const std::string& doc, HeldEdit& held, std::uint64_t& base_hash) {
    std::istringstream in(data);
    std::string line, word;
    if (!std::getline(in, line) || line != doc || !std::getline(in, line)) return false;
    std::istringstream head(line);
    if (!(head >> word) || word != "held" || !(head >> std::hex >> base_hash)) return false;
    int camera = 0;
    if (!read_index_line(in, "objects", held.objects) || !read_index_line(in, "planes", held.planes) ||
        !read_index_line(in, "lights", held.lights) || !std::getline(in, line) ||
        std::sscanf(line.c_str(), "camera %d", &camera) != 1)
        return false;
    held.camera = camera == 1;
    const std::size_t at = std::size_t(in.tellg());
    rt::ParseResult r = rt::parse_scene(std::string_view(data).substr(std::min(at, data.size())));
    if (!r.ok()) return false;
    held.items = std::move(r.scene);
    return held.items.objects.size() == held.objects.size() && held.items.planes.size() == held.planes.size() &&
           held.items.lights.size() == held.lights.size();
}

}  // namespace

std::string with_held_edit(const std::string& text, const HeldEdit& held) {
    // The models a mesh names are not read: only the text is patched.
    rt::ParseOptions o;
    o.read_models = false;
    const rt::ParseResult r = rt::parse_scene(text, o);
    if (!r.ok()) return text;
    const ItemIndices at{held.objects, held.planes, held.lights, held.camera};
    std::optional<std::string> patched = patch_scene_items(text, r.scene, at, held.items);
    return patched ? std::move(*patched) : text;
}

Recovery::Recovery(std::string dir) : dir_(dir.empty() ? default_dir() : std::move(dir)) {}

std::string Recovery::file_for(const std::string& doc_path) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (unsigned char c : absolute(doc_path)) h = (h ^ c) * 1099511628211ull;
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.txt", static_cast<unsigned long long>(h));
    return dir_ + "/" + name;
}

std::string Recovery::held_file_for(const std::string& doc_path) const {
    std::string f = file_for(doc_path);
    return f.substr(0, f.size() - 4) + ".held";
}

rt::Status Recovery::update(const std::string& doc_path, const std::string& text, bool modified) {
    if (doc_path != last_path_) {
        // Another document (Save As, Open): what was unsaved in the last one has been
        // saved or let go by the user, so its copy would only raise a false alarm.
        if (written_ || held_written_) discard(last_path_);
        last_path_ = doc_path;
        last_hash_ = 0;
        written_ = false;
        held_written_ = false;
    }
    if (!modified) {
        // (A held edit's file, for a text as saved, is update_held()'s to keep.)
        std::error_code ec;
        if (written_) fs::remove(file_for(doc_path), ec);
        written_ = false;
        last_hash_ = 0;
        return {};
    }
    std::uint64_t h = text_hash(text);
    if (written_ && h == last_hash_) return {};
    std::error_code ec;
    fs::create_directories(dir_, ec);
    const rt::Status written =
        rt::write_file_atomic(file_for(doc_path), absolute(doc_path) + "\n" + text, rt::WhileWriting::NoName);
    if (!written) return written;
    last_hash_ = h;
    written_ = true;
    return {};
}

rt::Status Recovery::update_held(const std::string& doc_path, const HeldEdit& held, std::uint64_t base_hash) {
    std::error_code ec;
    if (held.empty()) {
        if (held_written_) fs::remove(held_file_for(doc_path), ec);
        held_written_ = false;
        return {};
    }
    fs::create_directories(dir_, ec);
    const rt::Status st = rt::write_file_atomic(held_file_for(doc_path), held_file_text(absolute(doc_path), held, base_hash),
                                                rt::WhileWriting::NoName);
    if (st) held_written_ = true;
    return st;
}

std::optional<std::string> Recovery::find(const std::string& doc_path) const {
    std::optional<std::string> text;
    std::string data;
    if (rt::read_file(file_for(doc_path), data, kMaxRecoveryBytes).ok()) {
        const std::size_t nl = data.find('\n');
        if (nl != std::string::npos && data.compare(0, nl, absolute(doc_path)) == 0) text = data.substr(nl + 1);
    }
    HeldEdit held;
    std::uint64_t base = 0;
    if (!rt::read_file(held_file_for(doc_path), data, kMaxRecoveryBytes).ok() ||
        !parse_held_file(data, absolute(doc_path), held, base))
        return text;
    if (text && text_hash(*text) == base) return with_held_edit(*text, held);
    // A drag in a text as it was saved: its base is the document's file (for a
    // document never saved, the text it started from).
    if (doc_path.empty()) {
        for (const char* start : {rt::kDefaultScene, kNewScene})
            if (text_hash(start) == base) return with_held_edit(start, held);
        return text;
    }
    std::string file;
    if (!rt::read_file(doc_path, file, kMaxRecoveryBytes).ok()) return text;
    if (text_hash(file) == base) return with_held_edit(file, held);
    return text;
}

void Recovery::discard(const std::string& doc_path) {
    std::error_code ec;
    fs::remove(file_for(doc_path), ec);
    fs::remove(held_file_for(doc_path), ec);
    if (doc_path == last_path_) {
        written_ = false;
        held_written_ = false;
        last_hash_ = 0;
    }
}

}  // namespace rtview
