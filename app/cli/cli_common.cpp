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

#include "diagnostic_text.h"
#include "image_io.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "status.h"

#ifndef RT_VERSION
#define RT_VERSION "1.0.0"
#endif

namespace rtcli {

namespace {

constexpr int kMaxShownDiagnostics = 20;

// Numbers on the command line are whole decimal tokens, as in scene files: no
// leading or trailing spaces, no hex, no "inf" or "nan" (strtol and strtod would
// accept " 12", "0x10" and "0x1p3").
bool is_integer_token(const std::string& s) {
    std::size_t i = s.size() > 1 && (s[0] == '+' || s[0] == '-') ? 1 : 0;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}

bool is_decimal_token(const std::string& s) {
    std::size_t i = 0, n = s.size();
    auto digits = [&] {
        std::size_t k = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++k;
        return k;
    };
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t mantissa = digits();
    if (i < n && s[i] == '.') ++i, mantissa += digits();
    if (mantissa == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        if (digits() == 0) return false;
    }
    return i == n;
}

// Whole-token integer in [lo, hi]; anything else is a usage error naming the option.
bool parse_int(const std::string& opt, const std::string& text, long lo, long hi, int& out, std::string& err) {
    const std::string shown = rt::escape_text(text);
    if (!is_integer_token(text)) {
        err = opt + " expects a whole decimal number, got '" + shown + "'";
        return false;
    }
    errno = 0;
    long v = std::strtol(text.c_str(), nullptr, 10);
    if (errno == ERANGE || v < lo || v > hi) {
        err = opt + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + shown;
        return false;
    }
    out = int(v);
    return true;
}

bool parse_seconds(const std::string& opt, const std::string& text, double& out, std::string& err) {
    const std::string shown = rt::escape_text(text);
    if (!is_decimal_token(text)) {
        err = opt + " expects a decimal number of seconds such as 2 or 0.5, got '" + shown + "'";
        return false;
    }
    double v = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(v) || v <= 0 || v > 1e7) {
        err = opt + " must be more than 0 and at most 10000000 seconds, got " + shown;
        return false;
    }
    out = v;
    return true;
}

volatile sig_atomic_t g_signal = 0;
volatile sig_atomic_t g_bar_drawn = 0;  // a progress line to erase before a message
const char* g_program_name = "raytracer";

void append(char* buf, std::size_t size, std::size_t& len, const char* text) {
    while (*text && len + 1 < size) buf[len++] = *text++;
    buf[len] = '\0';
}

// Only async-signal-safe calls. With no temporary file in existence, nothing needs
// cleaning up whatever the main thread is doing (blocked opening a FIFO, parsing,
// building, rendering, encoding): the process ends here, at once, without writing.
// During the atomic write the flag stops it instead: it removes its temporary file
// and the main thread exits. Neither SA_RESTART (a blocking open() must not swallow
// the signal) nor SA_RESETHAND (a second signal during the write must not kill the
// process before the temporary file is gone).
extern "C" void on_signal(int sig) {
    const int saved_errno = errno;
    if (!g_signal) g_signal = sig;  // the exit status tells the first
    if (rt::interrupt_writes()) {
        errno = saved_errno;
        return;
    }
    char msg[256];
    std::size_t len = 0;
    msg[0] = '\0';
    if (g_bar_drawn) append(msg, sizeof msg, len, "\r\033[K");
    append(msg, sizeof msg, len, g_program_name);
    const int first = g_signal;  // a later signal (after a cancelled write) keeps the first's status
    append(msg, sizeof msg, len,
           first == SIGINT    ? ": interrupted (SIGINT)"
           : first == SIGTERM ? ": interrupted (SIGTERM)"
           : first == SIGHUP  ? ": interrupted (SIGHUP)"
                              : ": interrupted (signal)");
    append(msg, sizeof msg, len, "; nothing written\n");
    [[maybe_unused]] ssize_t ignored = ::write(STDERR_FILENO, msg, len);
    _exit(128 + first);
}

}  // namespace

std::string help_text(const Program& program) {
    std::string s = program.help_head;
    s += "  --width N          picture width in pixels, overriding the scene (1..16384)\n"
         "  --height N         picture height in pixels, overriding the scene (1..16384)\n"
         "  --samples N        samples per pixel (1..65536, default 1: the original's\n"
         "                     single ray through each pixel corner)\n";
    s += program.threads_help;
    s += "  --max-depth N      recursion limit (1..1000, default 20 as in the original;\n"
         "                     a reflection costs 2 levels, a refraction 3)\n"
         "  --time-limit SEC   stop adding samples after SEC seconds (every pixel still gets\n"
         "                     at least one); without --samples, render as many as fit\n";
    if (program.tile_option) s += "  --tile N           side of the square tiles handed out (8..256, default 32)\n";
    s += "  --mirror           mirror the picture left-right, as the 2013 program did\n"
         "  --quiet            no progress bar\n"
         "  --stats            print times, ray count and rays per second to stderr\n"
         "  --check SCENE      parse SCENE and report errors and warnings; render nothing\n"
         "  --print-scene      print SCENE in normalised form to stdout; render nothing\n"
         "  --version          print the version and exit\n"
         "  -h, --help         print this help and exit\n"
         "\n";
    return s + program.help_tail;
}

namespace {

// What the option with a value expects, as "needs ..." says it, or null if `name`
// takes no value.
const char* value_kind(const Program& program, const std::string& name) {
    if (name == "--width" || name == "--height" || name == "--samples" || name == "--threads" ||
        name == "--max-depth" || (program.tile_option && name == "--tile"))
        return "a number";
    if (name == "--time-limit") return "a number of seconds";
    if (name == "--check") return "a scene file";
    return nullptr;
}

// Sets the option `name` (one value_kind knows) from `v`, or says why not.
rt::Status set_value(const Program& program, const std::string& name, const std::string& v, Options& o) {
    std::string err;
    if (name == "--time-limit") {
        if (!parse_seconds(name, v, o.time_limit, err)) return rt::Status::error(err, kExitUsage);
        return {};
    }
    if (name == "--check") {
        o.check = v;
        return {};
    }
    const bool tile = program.tile_option && name == "--tile";
    long lo = 1, hi = rt::Limits::max_picture_side;
    if (name == "--samples") hi = 65536;
    if (name == "--threads") hi = 256;
    if (name == "--max-depth") hi = 1000;
    if (tile) lo = 8, hi = 256;
    int n = 0;
    if (!parse_int(name, v, lo, hi, n, err)) return rt::Status::error(err, kExitUsage);
    if (name == "--width") o.width = n;
    else if (name == "--height") o.height = n;
    else if (name == "--samples") o.samples = n;
    else if (name == "--threads") o.threads = n;
    else if (tile) o.tile = n;
    else o.max_depth = n;
    return {};
}

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
        std::string v;
        if (name == "-h" || name == "--help") {
            std::cout << help_text(program);
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
        } else if (const char* wants = value_kind(program, name)) {
            if (!take_value(v)) return fail("option '" + name + "' needs " + wants);
            if (rt::Status st = set_value(program, name, v, o); !st) return fail(st.message());
        } else {
            return fail("unknown option '" + a + "'");
        }
    }
    return -1;
}

int load_scene(const Program& program, const std::string& path, std::string& text, rt::Scene& scene) {
    const std::string shown = rt::escape_text(path);
    std::string err = rt::read_file(path, text, rt::Limits::max_file_size);
    if (!err.empty()) {
        std::cerr << program.name << ": cannot read '" << shown << "': " << err << "\n";
        return kExitUsage;
    }
    if (std::string problem = rt::encoding_problem(text); !problem.empty()) {
        std::cerr << shown << ":1:1: error: " << problem << "\n";
        return kExitScene;
    }
    rt::ParseOptions popts;
    popts.max_errors = kMaxShownDiagnostics;
    rt::ParseResult result = rt::parse_scene(text, popts);
    int errors = 0;
    for (const auto& d : result.diagnostics) errors += d.is_error();
    std::cerr << rt::diagnostics_report(path, result.diagnostics, kMaxShownDiagnostics,
                                        errors >= kMaxShownDiagnostics);
    if (!result.ok()) return kExitScene;
    scene = std::move(result.scene);
    return -1;
}

int check_scene(const Program& program, const Options& o) {
    if (!o.positional.empty()) return usage_error(program, "--check takes only the scene file");
    rt::Scene scene;
    std::string text;
    if (int r = load_scene(program, *o.check, text, scene); r >= 0) return r;
    if (!o.quiet)
        std::cerr << rt::escape_text(*o.check) << ": ok: " << count(scene.objects.size(), "object") << ", "
                  << count(scene.planes.size(), "plane") << ", " << count(scene.lights.size(), "light") << ", "
                  << scene.width << "x" << scene.height << "\n";
    return kExitOk;
}

namespace {

// "" or why OUT cannot be written: the rules of rt::check_writable, in the words of
// the system's error, with the folder named when it is the folder that is missing or
// closed to us.
std::string output_problem(const std::string& out, const std::string& scene_path) {
    struct stat st, ss;
    if (stat(out.c_str(), &st) == 0 && stat(scene_path.c_str(), &ss) == 0 && ss.st_dev == st.st_dev &&
        ss.st_ino == st.st_ino)
        return "it is the scene file itself";
    const std::string err = rt::check_writable(out);
    if (err.empty()) return err;
    const auto slash = out.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : out.substr(0, slash));
    const int dir_errno = stat(dir.c_str(), &st) != 0 ? errno : !S_ISDIR(st.st_mode) ? ENOTDIR : 0;
    const std::string shown = rt::escape_text(dir);
    if (dir_errno == ENOENT) return "folder '" + shown + "' does not exist (" + err + ")";
    if (dir_errno == ENOTDIR) return "'" + shown + "' is not a folder (" + err + ")";
    if (dir_errno == 0 && err == std::strerror(EACCES) && access(dir.c_str(), W_OK | X_OK) != 0)
        return "folder '" + shown + "' is not writable (" + err + ")";
    if (err == std::strerror(EACCES) && lstat(out.c_str(), &st) == 0)
        return "the file is read-only (" + err + "); it is not replaced";
    if (err == std::strerror(EPERM))
        return "another user's file in a sticky folder cannot be replaced (" + err + ")";
    return err;
}

}  // namespace

int check_output(const Program& program, const std::string& out, const std::string& scene_path) {
    if (rt::format_from_path(out) == rt::ImageFormat::Unknown)
        return usage_error(program, "cannot write '" + rt::escape_text(out) + "': the output must end in .ppm or .png");
    if (std::string e = output_problem(out, scene_path); !e.empty()) {
        std::cerr << program.name << ": cannot write '" << rt::escape_text(out) << "': " << e << "\n";
        return kExitUsage;
    }
    return -1;
}

std::shared_ptr<const rt::World> build_world(const rt::Scene& scene, int max_depth) {
    std::shared_ptr<const rt::World> world = rt::compile_world(scene);
    if (max_depth != world->options.max_depth) {
        auto changed = std::make_shared<rt::World>(*world);  // shares the geometry
        changed->options.max_depth = max_depth;
        world = std::move(changed);
    }
    return world;
}

int print_scene(const Program& program, rt::Scene scene) {
    for (rt::Object& o : scene.objects) o.has_material = true;
    for (rt::Plane& p : scene.planes) p.has_material = p.has_material2 = true;
    return print_to_stdout(program, rt::write_scene(scene));
}

int print_to_stdout(const Program& program, const std::string& text) {
    // stdio rather than std::cout: errno then says why (a full disk, a closed stdout).
    errno = 0;
    const bool ok = std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0;
    if (ok) return kExitOk;
    const int err = errno;
    std::cerr << program.name << ": cannot write to standard output: "
              << (err ? std::strerror(err) : "write error") << "\n";
    return kExitUsage;
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

void install_signal_handlers(const Program& program) {
    g_program_name = program.name;
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    // SIGHUP too: a closed terminal must not leave a temporary file either.
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, sig);  // one handler at a time
    sa.sa_flags = 0;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
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
    g_bar_drawn = 1;
}

void ProgressBar::clear() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
    g_bar_drawn = 0;
}

}  // namespace rtcli
