// Helpers the test files share: a temporary folder per test, reading and writing
// whole files, shell quoting, collecting failures of a property test, parsing a scene
// that must parse, moving an object, the raytracer binary's path, restoring the ISA
// path, a watchdog for calls that would hang when broken, what another process is
// doing (from /proc). Header-only, for every test program (they all link
// the core).
#pragma once

#include <doctest/doctest.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "scene_parser.h"
#include "simd.h"

namespace rt_test {

namespace fs = std::filesystem;

#ifdef RT_BIN_DIR
// The command-line renderer these tests were built with.
inline const std::string kRaytracer = RT_BIN_DIR "/raytracer";
#endif

// Restores the instruction-set path active when it was made (tests force each in turn).
struct IsaGuard {
    rt::Isa saved = rt::active_isa();
    ~IsaGuard() { rt::set_isa(saved); }
};

// The whole file as bytes ("" if it cannot be read).
inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Writes `data` as the whole file; the test fails if that does not work.
inline void put(const fs::path& p, const std::string& data) {
    std::ofstream out(p, std::ios::binary);
    out << data;
    REQUIRE(out.good());
}

// Options that read a scene's models from `folder`, every parse sharing one store, so
// that meshes naming the same file hold the same model (and compare equal) across
// parses, as in one viewer session.
inline rt::ParseOptions options_for(const std::string& folder) {
    static rt::ModelStore store;
    static rt::TextureStore textures;
    rt::ParseOptions o;
    o.base_dir = folder;
    o.models = &store;
    o.textures = &textures;
    return o;
}
#ifdef RT_SOURCE_DIR
// Those of the example scenes (scenes/, whose models are in scenes/models/).
inline rt::ParseOptions scenes_options() { return options_for(RT_SOURCE_DIR "/scenes"); }
#endif

// The scene `text` describes; the test stops here, with the parser's messages and the
// text, if it does not parse. Models are read as for scenes/ (from `options`).
inline rt::Scene parse_ok(const std::string& text, const rt::ParseOptions& options) {
    rt::ParseResult r = rt::parse_scene(text, options);
    const rt::Status st = r.status("scene");
    INFO("text:\n" << text);
    REQUIRE_MESSAGE(st.ok(), st.message());
    return std::move(r.scene);
}
#ifdef RT_SOURCE_DIR
inline rt::Scene parse_ok(const std::string& text) { return parse_ok(text, scenes_options()); }
#else
inline rt::Scene parse_ok(const std::string& text) { return parse_ok(text, rt::ParseOptions()); }
#endif

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// `s` as one word for /bin/sh.
inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The names in a folder, sorted.
inline std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Collects failures so that one CHECK reports the count and the first case.
struct Failures {
    int count = 0;
    std::string first;
    void add(const std::string& what) {
        if (count++ == 0) first = what;
    }
};

// A fresh folder (mode 0700) per test, removed afterwards with everything in it; made
// writable again first, in case a test took the write permission away.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& prefix = "rt-test") {
        std::string tmpl = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
        REQUIRE(::mkdtemp(tmpl.data()) != nullptr);
        path = tmpl;
    }
    ~TempDir() {
        ::chmod(path.c_str(), 0700);
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    fs::path operator/(const std::string& name) const { return path / name; }
    std::vector<std::string> files() const { return listing(path); }
};

// Whether process `pid` (a `raytracer` started by the test) has a handler for `sig`,
// from the SigCgt mask in /proc: its signal handlers are in place. (CPU time alone is
// no sign of that: a sanitizer build's start-up takes 0.1 s of CPU on some machines
// before main runs.)
inline bool catches_signal(pid_t pid, int sig) {
    // Not before the exec: the forked test process has doctest's handlers.
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/" + std::to_string(pid) + "/exe", ec);
    if (ec || exe.filename() != "raytracer") return false;
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1;
    return false;
}

// CPU seconds (user and system) process `pid` has used, from /proc/PID/stat; -1 if
// it is gone. Unlike the time on the clock, it only grows while the process runs.
inline double process_cpu_seconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const std::size_t paren = stat.rfind(')');  // the name before it may hold spaces
    if (paren == std::string::npos) return -1;
    std::istringstream fields(stat.substr(paren + 1));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> field; ++i) {  // utime and stime are fields 14 and 15
        if (i == 14) utime = std::stoull(field);
        if (i == 15) stime = std::stoull(field);
    }
    return double(utime + stime) / double(::sysconf(_SC_CLK_TCK));
}

// Whether process `pid` is blocked opening a FIFO that nobody has opened from the
// other side (the kernel's wait_for_partner).
inline bool blocked_opening_fifo(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/wchan");
    std::string wchan;
    std::getline(in, wchan);
    return wchan == "wait_for_partner";
}

// Whether a thread of this process is asleep in poll() (a reader waiting for a FIFO's
// writer, rt::read_file's strict mode).
inline bool a_thread_polling() {
    std::error_code ec;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
        std::ifstream in(task.path() / "wchan");
        std::string wchan;
        std::getline(in, wchan);
        if (wchan.find("poll") != std::string::npos) return true;
    }
    return false;
}

// Whether thread `tid` of this process is asleep (state S in /proc: blocked, waiting
// for something, not running nor ready to run).
inline bool thread_asleep(pid_t tid) {
    std::ifstream in("/proc/self/task/" + std::to_string(tid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const std::size_t paren = stat.rfind(')');
    return paren != std::string::npos && paren + 2 < stat.size() && stat[paren + 2] == 'S';
}

// Guards a call that returns at once when it works and never when it is broken (a
// cancel that cannot reach a ray tree without end): if the guarded scope is still
// running after `limit`, says `what` and ends the test program, which would otherwise
// hang. Not a timing check: no limit is close to what a working call takes.
class Watchdog {
public:
    explicit Watchdog(std::string what, std::chrono::seconds limit = std::chrono::seconds(120))
        : what_(std::move(what)), thread_([this, limit] {
              std::unique_lock<std::mutex> lock(mutex_);
              if (cv_.wait_for(lock, limit, [this] { return done_; })) return;
              std::fprintf(stderr, "FATAL: %s (still running after %lld s)\n", what_.c_str(),
                           static_cast<long long>(limit.count()));
              std::fflush(nullptr);
              std::_Exit(3);
          }) {}
    ~Watchdog() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            done_ = true;
        }
        cv_.notify_all();
        thread_.join();
    }
    Watchdog(const Watchdog&) = delete;
    Watchdog& operator=(const Watchdog&) = delete;

private:
    std::string what_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool done_ = false;
    std::thread thread_;  // last: started once the rest exists
};

// Polls `condition` (every millisecond, leaving the CPU to the threads it waits for)
// until it holds. One that never comes ends the program through a Watchdog, saying
// what it waited for: a broken render then fails instead of hanging the run.
template <class Condition>
void wait_until(Condition condition, const std::string& what,
                std::chrono::seconds limit = std::chrono::seconds(120)) {
    Watchdog dog("waited in vain for " + what, limit);
    while (!condition()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

// Moves an object by d: every point of its shape (a CSG's operands too), as the
// viewer's move handle does, without the viewer's clamping of far points.
inline void translate(rt::Object& o, const rt::Vec3& d) {
    std::visit(
        [&](auto& x) {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, rt::Sphere> || std::is_same_v<T, rt::Torus> || std::is_same_v<T, rt::Mesh>)
                x.position = x.position + d;
            else if constexpr (std::is_same_v<T, rt::Cylinder> || std::is_same_v<T, rt::Cone>)
                x.end1 = x.end1 + d, x.end2 = x.end2 + d;
            else if constexpr (std::is_same_v<T, rt::Box>)
                x.corner1 = x.corner1 + d, x.corner2 = x.corner2 + d;
            else if constexpr (std::is_same_v<T, rt::Tetrahedron>)
                for (rt::Vec3& v : x.v) v = v + d;
            else if constexpr (std::is_same_v<T, rt::Instance>)
                o.transform.edit().translate = o.transform.get().translate + d;
            else
                for (rt::Object& op : x.operands) translate(op, d);
        },
        o.shape);
}

}  // namespace rt_test
