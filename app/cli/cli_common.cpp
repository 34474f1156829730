// The shared part of raytracer's and raytracer-mpi's command lines (cli_common.h).
#include "cli_common.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include "image_io.h"
#include "scene_parser.h"

#ifndef RT_VERSION
#define RT_VERSION "1.0.0"
#endif

namespace rtcli {

namespace {

constexpr int kMaxShownDiagnostics = 20;

// Whole-token integer in [lo, hi]; anything else is a usage error naming the option.
bool parse_int(const std::string& opt, const std::string& text, long lo, long hi, int& out, std::string& err) {
    errno = 0;
    char* end = nullptr;
    long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE) {
        err = opt + " expects a whole number, got '" + text + "'";
        return false;
    }
    if (v < lo || v > hi) {
        err = opt + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + text;
        return false;
    }
    out = int(v);
    return true;
}

bool parse_seconds(const std::string& opt, const std::string& text, double& out, std::string& err) {
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v <= 0 || v > 1e7) {
        err = opt + " expects a positive number of seconds, got '" + text + "'";
        return false;
    }
    out = v;
    return true;
}

volatile sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) { g_signal = sig; }

}  // namespace

int usage_error(const Program& program, const std::string& message) {
    std::cerr << program.name << ": " << message << "\n";
    std::cerr << "Try '" << program.name << " --help' for more information.\n";
    return kExitUsage;
}

int parse_args(const Program& program, int argc, char** argv, Options& o) {
    auto fail = [&](const std::string& message) { return usage_error(program, message); };
    bool only_positional = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (only_positional || a.size() < 2 || a[0] != '-') {
            o.positional.push_back(a);
            continue;
        }
        if (a == "--") {
            only_positional = true;
            continue;
        }
        // Accept both `--opt VALUE` and `--opt=VALUE`.
        std::string name = a, value;
        bool has_inline_value = false;
        if (auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
            name = a.substr(0, eq);
            value = a.substr(eq + 1);
            has_inline_value = true;
        }
        auto take_value = [&](std::string& v) -> bool {
            if (has_inline_value) {
                v = value;
                return true;
            }
            if (i + 1 >= argc) return false;
            v = argv[++i];
            return true;
        };
        auto flag = [&](bool& f) -> int {
            if (has_inline_value) return fail("option '" + name + "' takes no value");
            f = true;
            return -1;
        };
        const bool tile = program.tile_option && name == "--tile";
        std::string v, err;
        int n = 0;
        if (name == "-h" || name == "--help") {
            std::cout << program.help;
            return kExitOk;
        } else if (name == "--version") {
            std::cout << program.name << " " RT_VERSION "\n";
            return kExitOk;
        } else if (name == "--mirror") {
            if (int r = flag(o.mirror); r >= 0) return r;
        } else if (name == "--quiet") {
            if (int r = flag(o.quiet); r >= 0) return r;
        } else if (name == "--stats") {
            if (int r = flag(o.stats); r >= 0) return r;
        } else if (name == "--print-scene") {
            if (int r = flag(o.print_scene); r >= 0) return r;
        } else if (name == "--width" || name == "--height" || name == "--samples" || name == "--threads" ||
                   name == "--max-depth" || tile) {
            if (!take_value(v)) return fail("option '" + name + "' needs a number");
            long lo = 1, hi = rt::Limits::max_picture_side;
            if (name == "--samples") hi = 65536;
            if (name == "--threads") hi = 256;
            if (name == "--max-depth") hi = 1000;
            if (tile) lo = 8, hi = 256;
            if (!parse_int(name, v, lo, hi, n, err)) return fail(err);
            if (name == "--width") o.width = n;
            else if (name == "--height") o.height = n;
            else if (name == "--samples") o.samples = n;
            else if (name == "--threads") o.threads = n;
            else if (tile) o.tile = n;
            else o.max_depth = n;
        } else if (name == "--time-limit") {
            if (!take_value(v)) return fail("option '--time-limit' needs a number of seconds");
            if (!parse_seconds(name, v, o.time_limit, err)) return fail(err);
        } else if (name == "--check") {
            if (!take_value(v)) return fail("option '--check' needs a scene file");
            o.check = v;
        } else {
            return fail("unknown option '" + a + "'");
        }
    }
    return -1;
}

int load_scene(const Program& program, const std::string& path, std::string& text, rt::Scene& scene) {
    std::string err = rt::read_file(path, text, rt::Limits::max_file_size);
    if (!err.empty()) {
        std::cerr << program.name << ": cannot read '" << path << "': " << err << "\n";
        return kExitUsage;
    }
    rt::ParseOptions popts;
    popts.max_errors = kMaxShownDiagnostics;
    rt::ParseResult result = rt::parse_scene(text, popts);
    int errors = 0, warnings = 0;
    for (const auto& d : result.diagnostics) {
        int& shown = d.is_error() ? errors : warnings;
        if (++shown <= kMaxShownDiagnostics) std::cerr << rt::format_diagnostic(path, d) << "\n";
    }
    if (warnings > kMaxShownDiagnostics)
        std::cerr << path << ": " << warnings - kMaxShownDiagnostics << " more warnings not shown\n";
    if (!result.ok()) {
        if (errors >= kMaxShownDiagnostics) std::cerr << path << ": too many errors; stopped reading\n";
        return kExitScene;
    }
    scene = std::move(result.scene);
    return -1;
}

int check_scene(const Program& program, const Options& o) {
    if (!o.positional.empty()) return usage_error(program, "--check takes only the scene file");
    rt::Scene scene;
    std::string text;
    if (int r = load_scene(program, *o.check, text, scene); r >= 0) return r;
    if (!o.quiet)
        std::cerr << *o.check << ": ok: " << count(scene.objects.size(), "object") << ", "
                  << count(scene.planes.size(), "plane") << ", " << count(scene.lights.size(), "light") << ", "
                  << scene.width << "x" << scene.height << "\n";
    return kExitOk;
}

namespace {

// "" or why OUT could not be written by the final rename.
std::string output_problem(const std::string& out, const std::string& scene_path) {
    struct stat st;
    if (stat(out.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) return "'" + out + "' is a directory";
        struct stat ss;
        if (stat(scene_path.c_str(), &ss) == 0 && ss.st_dev == st.st_dev && ss.st_ino == st.st_ino)
            return "output '" + out + "' is the scene file itself";
    }
    auto slash = out.find_last_of('/');
    std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : out.substr(0, slash));
    if (stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) return "folder '" + dir + "' does not exist";
    if (access(dir.c_str(), W_OK | X_OK) != 0) return "folder '" + dir + "' is not writable";
    return "";
}

}  // namespace

int check_output(const Program& program, const std::string& out, const std::string& scene_path) {
    if (rt::format_from_path(out) == rt::ImageFormat::Unknown)
        return usage_error(program, "cannot write '" + out + "': the output must end in .ppm or .png");
    if (std::string e = output_problem(out, scene_path); !e.empty()) {
        std::cerr << program.name << ": cannot write '" << out << "': " << e << "\n";
        return kExitUsage;
    }
    return -1;
}

std::string count(std::size_t n, const char* noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string with_commas(std::uint64_t v) {
    std::string s = std::to_string(v);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void install_signal_handlers() {
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int caught_signal() { return g_signal; }

void ProgressBar::update(double fraction, double elapsed, const std::string& detail) {
    if (!enabled_) return;
    // Passes can be regrouped by the renderer; never let the bar run backwards.
    shown_ = std::max(shown_, std::clamp(fraction, 0.0, 1.0));
    static const char kHashes[] = "########################################";
    const int width = detail.empty() ? 40 : 30;  // room for the detail
    int filled = int(shown_ * width);
    char line[256];
    int n = detail.empty()
                ? std::snprintf(line, sizeof line, "\r[%.*s%*s] %3d%%  %.1f s", filled, kHashes, width - filled, "",
                                int(shown_ * 100), elapsed)
                : std::snprintf(line, sizeof line, "\r[%.*s%*s] %3d%%  %s, %.1f s", filled, kHashes, width - filled,
                                "", int(shown_ * 100), detail.c_str(), elapsed);
    if (n > 0 && std::size_t(n) < sizeof line && shown_ > 0.02 && shown_ < 1) {
        double eta = elapsed * (1 - shown_) / shown_;
        std::snprintf(line + n, sizeof line - std::size_t(n), ", ETA %.1f s", eta);
    }
    std::fputs(line, stderr);
    std::fputs("\033[K", stderr);  // erase leftovers of a longer previous line
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::clear() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
}

}  // namespace rtcli
