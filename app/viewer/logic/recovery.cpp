// Recovery files are named by a hash of the document's absolute path, so two
// viewers on different files never share one; the first line holds the path itself.
// The held edit's file names the text it belongs to by that text's hash, so that it
// is never written into another text (whose items may be others at those indices).
#include "recovery.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdlib>
#include <cstring>
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

// Opens `path` (creating it if `create`) and takes its flock without waiting: the
// descriptor, or -1, with `held` true when another process holds the lock.
int try_lock(const std::string& path, bool create, bool& held) {
    held = false;
    for (int attempt = 0; attempt < 8; ++attempt) {
        const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC | (create ? O_CREAT : 0), 0644);
        if (fd < 0) return -1;
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            held = errno == EWOULDBLOCK;
            ::close(fd);
            return -1;
        }
        // A viewer closing removes its lock file while holding the lock: a lock taken on
        // a file removed since it was opened holds nothing. Then again, on the new file.
        struct stat a {}, b {};
        if (::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev)
            return fd;
        ::close(fd);
        if (!create) return -1;
    }
    return -1;
}

// The pid a lock file names (-1: none).
long lock_pid(const std::string& path) {
    std::string text;
    if (!rt::read_file(path, text, 64).ok()) return -1;
    const long pid = std::strtol(text.c_str(), nullptr, 10);
    return pid > 0 ? pid : -1;
}

// The first line of a copy (its document's path), read alone.
std::string first_line(const std::string& path) {
    std::string line;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return line;
    char buf[4096];
    const ssize_t n = ::read(fd, buf, sizeof buf);
    ::close(fd);
    if (n <= 0) return line;
    const char* nl = static_cast<const char*>(std::memchr(buf, '\n', std::size_t(n)));
    return nl ? std::string(buf, std::size_t(nl - buf)) : std::string();
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

Recovery::~Recovery() { release(); }

std::string Recovery::lock_file_for(const std::string& doc_path) const {
    std::string f = file_for(doc_path);
    return f.substr(0, f.size() - 4) + ".lock";
}

long Recovery::claim(const std::string& doc_path) {
    if (lock_fd_ >= 0 && doc_path == lock_path_) return 0;
    release();
    blocked_path_.clear();
    blocked_pid_ = 0;
    std::error_code ec;
    fs::create_directories(dir_, ec);
    // Several viewers may each show an unsaved default scene: each takes the first slot
    // no live viewer holds (a copy of its own); a file has one slot.
    const int slots = doc_path.empty() ? kDefaultSceneSlots : 1;
    int fd = -1;
    long first_pid = 0;
    for (slot_ = 0; slot_ < slots; ++slot_) {
        const std::string lock = lock_file_for(doc_path);
        bool held = false;
        fd = try_lock(lock, true, held);
        if (fd >= 0) break;
        if (!held) {
            slot_ = 0;
            return 0;  // no lock to be had (a read-only folder): copies as before
        }
        if (slot_ == 0) first_pid = lock_pid(lock);
    }
    if (fd < 0) {
        slot_ = 0;
        blocked_path_ = doc_path;
        blocked_pid_ = first_pid;
        return blocked_pid_;
    }
    lock_fd_ = fd;
    lock_path_ = doc_path;
    const std::string pid = std::to_string(long(::getpid())) + "\n";
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
        // (The lock holds all the same; the other viewer cannot say whose it is.)
    }
    return 0;
}

void Recovery::release() {
    if (lock_fd_ < 0) return;
    // Removed while still locked: a viewer that opened it meanwhile sees the change.
    ::unlink(lock_file_for(lock_path_).c_str());
    ::close(lock_fd_);
    lock_fd_ = -1;
    lock_path_.clear();
}

std::optional<std::string> Recovery::read_orphan(const Orphan& o) const {
    std::string data;
    if (!rt::read_file(o.file, data, kMaxRecoveryBytes).ok()) return std::nullopt;
    const std::size_t nl = data.find('\n');
    if (nl == std::string::npos || data.compare(0, nl, absolute(o.doc_path)) != 0) return std::nullopt;
    return data.substr(nl + 1);
}

std::vector<Recovery::Orphan> Recovery::orphans(const std::string& except) const {
    std::vector<Orphan> out;
    std::error_code ec;
    const std::string skip = file_for(except), skip_held = held_file_for(except);
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string file = it->path().string();
        const std::string ext = it->path().extension().string();
        if (ext != ".txt" && ext != ".held") continue;
        const std::string stem = file.substr(0, file.size() - ext.size());
        // A drag's file alone (its text as saved) counts; beside a copy, the copy does.
        if (ext == ".held" && fs::exists(stem + ".txt", ec)) continue;
        if (file == skip || file == skip_held) continue;
        if (lock_fd_ >= 0 && stem + ".txt" == file_for(lock_path_)) continue;  // this viewer's own
        bool held = false;
        const int fd = try_lock(stem + ".lock", false, held);
        if (fd >= 0) ::close(fd);
        if (held) continue;  // a live viewer's
        struct stat st {};
        if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
        Orphan o;
        o.doc_path = first_line(file);
        if (o.doc_path.empty()) continue;  // not a copy
        if (o.doc_path == absolute("")) o.doc_path.clear();
        o.file = file;
        o.mtime = std::int64_t(st.st_mtim.tv_sec);
        o.bytes = std::uint64_t(st.st_size) - std::min<std::uint64_t>(std::uint64_t(st.st_size), absolute(o.doc_path).size() + 1);
        out.push_back(std::move(o));
    }
    std::sort(out.begin(), out.end(), [](const Orphan& a, const Orphan& b) { return a.mtime > b.mtime; });
    return out;
}

bool Recovery::discard_orphan(const Orphan& o) {
    const std::string stem = o.file.substr(0, o.file.size() - fs::path(o.file).extension().string().size());
    bool held = false;
    const int fd = try_lock(stem + ".lock", false, held);
    if (held) return false;  // a viewer has it open now: its copy
    std::error_code ec;
    fs::remove(stem + ".txt", ec);
    fs::remove(stem + ".held", ec);
    if (fd >= 0) {
        ::unlink((stem + ".lock").c_str());
        ::close(fd);
    }
    return true;
}

std::string Recovery::file_for(const std::string& doc_path) const {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a
    // The unsaved default scene of the viewer in slot k > 0 (see claim()) has a name of its own.
    const std::string key = absolute(doc_path) + (doc_path.empty() && slot_ > 0 ? " #" + std::to_string(slot_) : "");
    for (unsigned char c : key) h = (h ^ c) * 1099511628211ull;
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.txt", static_cast<unsigned long long>(h));
    return dir_ + "/" + name;
}

std::string Recovery::held_file_for(const std::string& doc_path) const {
    std::string f = file_for(doc_path);
    return f.substr(0, f.size() - 4) + ".held";
}

rt::Status Recovery::update(const std::string& doc_path, const std::string& text, bool modified) {
    if (blocked(doc_path)) return {};  // the live viewer's copy, not this one's
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
    if (blocked(doc_path)) return {};
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
    if (blocked(doc_path)) return std::nullopt;  // a live viewer's unsaved text, not an earlier session's
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
    if (blocked(doc_path)) return;
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
