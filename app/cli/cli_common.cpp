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
#include <initializer_list>
#include <iostream>
#include <optional>
#include <thread>

#include "arg_table.h"
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

// A limit as --help and the messages write it: "3", "65536".
std::string limit(double v) { return std::to_string(long(v)); }

// Usage errors name the option: "--width expects a whole decimal number, got 'x'".
rt::Status bad_value(const std::string& message) { return rt::Status::error(message, kExitUsage); }

// A whole-token integer in [lo, hi] into `out`.
rt::Status set_int(const std::string& opt, const std::string& text, long lo, long hi, int& out) {
    const std::string shown = rt::escape_text(text);
    if (!rtargs::is_integer_token(text))
        return bad_value(opt + " expects a whole decimal number, got '" + shown + "'");
    const std::optional<long> v = rtargs::integer_in(text, lo, hi);
    if (!v) return bad_value(opt + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + shown);
    out = int(*v);
    return {};
}

rt::Status set_seconds(const std::string& opt, const std::string& text, double& out) {
    const std::string shown = rt::escape_text(text);
    if (!rtargs::is_decimal_token(text))
        return bad_value(opt + " expects a decimal number of seconds such as 2 or 0.5, got '" + shown + "'");
    const std::optional<double> v = rtargs::decimal(text);
    if (!v || *v <= 0 || *v > rt::kMaxTimeLimit)
        return bad_value(opt + " must be more than 0 and at most " + std::to_string(long(rt::kMaxTimeLimit)) +
                         " seconds, got " + shown);
    out = *v;
    return {};
}

// --aa-threshold: a decimal token in [0, rt::kMaxAaThreshold].
rt::Status set_threshold(const std::string& opt, const std::string& text, std::optional<double>& out) {
    const std::string shown = rt::escape_text(text);
    if (!rtargs::is_decimal_token(text))
        return bad_value(opt + " expects a decimal number such as 0.3, got '" + shown + "'");
    const std::optional<double> v = rtargs::decimal(text);
    if (!v || *v < 0 || *v > rt::kMaxAaThreshold)
        return bad_value(opt + " must be between 0 and " + limit(rt::kMaxAaThreshold) + ", got " + shown);
    out = *v;
    return {};
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

namespace {

// An option with a whole-number value in [lo, hi].
rtargs::Option number(const char* name, std::string help, long lo, long hi, int& out) {
    return rtargs::value_option(name, "N", "a number", std::move(help), [lo, hi, &out](const std::string& n, const std::string& v) {
        return set_int(n, v, lo, hi, out);
    });
}

rtargs::Option optional_number(const char* name, std::string help, long lo, long hi, std::optional<int>& out) {
    return rtargs::value_option(name, "N", "a number", std::move(help), [lo, hi, &out](const std::string& n, const std::string& v) {
        int x = 0;
        rt::Status st = set_int(n, v, lo, hi, x);
        if (st) out = x;
        return st;
    });
}

rtargs::Option flag(const char* name, const char* help, bool& out, bool stops = false) {
    return rtargs::flag_option(name, help, [&out] { out = true; }, stops);
}

// The options of both renderers, in --help's order; --tile only where the program has
// tiles. `o` receives the values.
rtargs::Table option_table(const Program& program, Options& o) {
    const long side = rt::Limits::max_picture_side;
    rt::RenderRequest& r = o.render;
    rtargs::Table t;
    t.options = {
        optional_number("--width", "picture width in pixels, overriding the scene (1.." + limit(side) + ")", 1, side,
                        o.width),
        optional_number("--height", "picture height in pixels, overriding the scene (1.." + limit(side) + ")", 1, side,
                        o.height),
        optional_number("--samples",
                        "samples per pixel (1.." + limit(rt::kMaxSamples) +
                            ", default 1: the original's\n"
                            "single ray through each pixel corner); with --aa-threshold\n"
                            "the most a pixel gets (default " + limit(rt::kDefaultAaMaxSamples) + ")",
                        1, rt::kMaxSamples, r.samples),
        rtargs::value_option("--aa-threshold", "T", "a threshold such as 0.3",
                             "adaptive anti-aliasing: more samples only where a pixel's\n"
                             "colour differs from a neighbour's by T or more (the sum of the\n"
                             "red, green and blue differences in 0..1 units, 0.." + limit(rt::kMaxAaThreshold) +
                                 ", as\n"
                                 "POV-Ray's +A) or its samples still spread",
                             [&r](const std::string& n, const std::string& v) {
                                 return set_threshold(n, v, r.aa_threshold);
                             }),
        number("--threads",
               std::string(program.threads_what) + " (1.." + limit(rt::kMaxThreads) +
                   ", default: " + program.threads_default + ")",
               1, rt::kMaxThreads, r.threads),
        number("--max-depth",
               "recursion limit (1.." + limit(rt::kMaxRecursion) + ", default " + limit(rt::kDefaultMaxDepth) +
                   " as in the original;\n"
                   "a reflection costs 2 levels, a refraction 3)",
               1, rt::kMaxRecursion, r.max_depth),
        rtargs::value_option("--time-limit", "SEC", "a number of seconds",
                             "stop adding samples after SEC seconds (every pixel still gets\n"
                             "at least one); without --samples, render as many as fit",
                             [&r](const std::string& n, const std::string& v) { return set_seconds(n, v, r.time_limit); }),
    };
    if (program.tile_option)
        t.options.push_back(number("--tile",
                                   "side of the square tiles handed out (" + limit(rt::kMinTile) + ".." +
                                       limit(rt::kMaxTile) + ", default " + limit(rt::kDefaultTile) + ")",
                                   rt::kMinTile, rt::kMaxTile, r.tile));
    for (rtargs::Option opt : std::initializer_list<rtargs::Option>{
             flag("--mirror", "mirror the picture left-right, as the 2013 program did", r.mirror),
             flag("--quiet", "no progress bar", o.quiet),
             flag("--stats", "print times, ray count and rays per second to stderr", o.stats),
             rtargs::value_option("--check", "SCENE", "a scene file",
                                  "parse SCENE and report errors and warnings; render nothing",
                                  [&o](const std::string&, const std::string& v) {
                                      o.check = v;
                                      return rt::Status();
                                  }),
             flag("--print-scene", "print SCENE in normalised form to stdout; render nothing", o.print_scene),
             flag("--flatten", "with --print-scene: named materials and included files\n"
                               "written out in full, as one scene file", o.flatten),
             flag("--help-format", "print the scene format in brief (every block and key, its\n"
                                   "default and its rules) and exit", o.help_format, true),
             flag("--version", "print the version and exit", o.version, true),
             flag("-h, --help", "print this help and exit", o.help, true),
         })
        t.options.push_back(std::move(opt));
    t.positional = [&o](const std::string& a) {
        o.positional.push_back(a);
        return rt::Status();
    };
    return t;
}

}  // namespace

std::string help_text(const Program& program) {
    Options unused;
    return program.help_head + rtargs::help_lines(option_table(program, unused)) + "\n" + program.help_tail;
}

rt::Status failure(const Program& program, const std::string& message, int exit_code) {
    return rt::Status::error(std::string(program.name) + ": " + message + "\n", exit_code);
}

rt::Status usage_error(const Program& program, const std::string& message) {
    return failure(program,
                   message + "\nTry '" + program.name + " --help' for more information.", kExitUsage);
}

int report(const rt::Status& st) {
    std::cerr << st.message() << std::flush;
    return st.exit_code();
}

rt::Status parse_args(const Program& program, int argc, char** argv, Options& o) {
    if (rt::Status st = rtargs::parse(option_table(program, o), argc, argv); !st)
        return usage_error(program, st.message());
    return {};
}

bool print_help_or_version(const Program& program, const Options& o) {
    if (o.help) std::cout << help_text(program);
    else if (o.version) std::cout << program.name << " " RT_VERSION "\n";
    else if (o.help_format) std::cout << rt::format_reference();
    return o.help || o.version || o.help_format;
}

namespace {

template <class Text>
rt::Status read_and_parse(const Program& program, const std::string& path, Text& text, rt::Scene& scene) {
    const std::string shown = rt::escape_text(path);
    if (const rt::Status st = rt::read_file(path, text, rt::Limits::max_file_size); !st)
        return failure(program, "cannot read '" + shown + "': " + st.message(), kExitUsage);
    const std::string_view view(text.data(), text.size());
    if (const rt::Status st = rt::check_encoding(view); !st)
        return rt::Status::error(shown + ":1:1: error: " + st.message() + "\n", st.exit_code());
    rt::ParseOptions popts;
    popts.max_errors = kMaxShownDiagnostics;
    popts.base_dir = rt::folder_of(path);  // mesh files are named relative to the scene
    popts.scene_file = path;              // (an include of the scene itself is a cycle)
    rt::ParseResult result = rt::parse_scene(view, popts);
    if (rt::Status st = result.status(path, kMaxShownDiagnostics); !st) return st;
    std::cerr << rt::diagnostics_report(path, result.diagnostics, kMaxShownDiagnostics);  // the warnings
    scene = std::move(result.scene);
    return {};
}

}  // namespace

rt::Status load_scene(const Program& program, const std::string& path, std::string& text, rt::Scene& scene) {
    return read_and_parse(program, path, text, scene);
}

rt::Status load_scene(const Program& program, const std::string& path, rt::Scene& scene) {
    rt::FileText text;
    return read_and_parse(program, path, text, scene);
}

rt::Status check_scene(const Program& program, const Options& o) {
    if (!o.positional.empty()) return usage_error(program, "--check takes only the scene file");
    rt::Scene scene;
    if (rt::Status st = load_scene(program, *o.check, scene); !st) return st;
    if (!o.quiet)
        std::cerr << rt::escape_text(*o.check) << ": ok: " << count(scene.objects.size(), "object") << ", "
                  << count(scene.planes.size(), "plane") << ", " << count(scene.lights.size(), "light") << ", "
                  << scene.width << "x" << scene.height << "\n";
    return {};
}

namespace {

// Whether OUT can be written, by the rules of rt::check_writable; if not, why, in the
// words of the system's error, with the folder named when it is the folder that is
// missing or closed to us.
rt::Status writable_output(const std::string& out, const std::string& scene_path) {
    auto refuse = [](std::string why) { return rt::Status::error(std::move(why), kExitUsage); };
    struct stat st, ss;
    if (stat(out.c_str(), &st) == 0 && stat(scene_path.c_str(), &ss) == 0 && ss.st_dev == st.st_dev &&
        ss.st_ino == st.st_ino)
        return refuse("it is the scene file itself");
    const rt::Status writable = rt::check_writable(out);
    if (writable) return writable;
    const std::string& err = writable.message();
    const auto slash = out.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : out.substr(0, slash));
    const int dir_errno = stat(dir.c_str(), &st) != 0 ? errno : !S_ISDIR(st.st_mode) ? ENOTDIR : 0;
    const std::string shown = rt::escape_text(dir);
    if (dir_errno == ENOENT) return refuse("folder '" + shown + "' does not exist (" + err + ")");
    if (dir_errno == ENOTDIR) return refuse("'" + shown + "' is not a folder (" + err + ")");
    if (dir_errno == 0 && err == std::strerror(EACCES) && access(dir.c_str(), W_OK | X_OK) != 0)
        return refuse("folder '" + shown + "' is not writable (" + err + ")");
    if (err == std::strerror(EACCES) && lstat(out.c_str(), &st) == 0)
        return refuse("the file is read-only (" + err + "); it is not replaced");
    if (err == std::strerror(EPERM))
        return refuse("another user's file in a sticky folder cannot be replaced (" + err + ")");
    return refuse(err);
}

}  // namespace

rt::Status check_output(const Program& program, const std::string& out, const std::string& scene_path) {
    if (rt::format_from_path(out) == rt::ImageFormat::Unknown)
        return usage_error(program, "cannot write '" + rt::escape_text(out) + "': the output must end in .ppm, .png, .pfm or .exr");
    if (const rt::Status st = writable_output(out, scene_path); !st)
        return failure(program, "cannot write '" + rt::escape_text(out) + "': " + st.message(), st.exit_code());
    return {};
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

rt::RenderSettings render_settings(const Options& o, int width, int height) {
    return rt::final_settings(o.render, width, height);
}

rt::Status print_scene(const Program& program, rt::Scene scene, bool flatten) {
    for (rt::Object& o : scene.objects) o.has_material = true;
    for (rt::Plane& p : scene.planes) p.has_material = p.has_material2 = true;
    return print_to_stdout(program, rt::write_scene(scene, flatten));
}

rt::Status print_to_stdout(const Program& program, const std::string& text) {
    // stdio rather than std::cout: errno then says why (a full disk, a closed stdout).
    errno = 0;
    const bool ok = std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0;
    if (ok) return {};
    const int err = errno;
    return failure(program, std::string("cannot write to standard output: ") + (err ? std::strerror(err) : "write error"),
                   kExitUsage);
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
    // The handler runs on a thread that only waits for them; every other thread blocks
    // them (threads started later inherit the mask). A signal then runs the handler as
    // soon as it comes, even while the main thread sits in a long write() or fsync():
    // were it pending there, a second signal coming meanwhile could be taken first (the
    // kernel hands out pending signals lowest number first), and the exit status
    // would not tell the first signal. A thread blocked in open() on a FIFO needs no
    // EINTR either: with no temporary file the handler ends the process itself.
    static bool waiter_started = false;
    if (waiter_started) return;
    waiter_started = true;
    sigset_t set;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
    std::thread([] {
        for (;;) ::pause();
    }).detach();
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
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
