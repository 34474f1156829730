// raytracer: the headless command-line renderer, used like the 2013 program
// (`raytracer SCENE OUT`, prompting for whatever is missing) plus options.
// It drives the same progressive rt::Renderer as the viewer; it links no GL.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image_io.h"
#include "renderer.h"
#include "scene.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "world.h"

#ifndef RT_VERSION
#define RT_VERSION "1.0.0"
#endif

namespace {

constexpr int kExitOk = 0;
constexpr int kExitScene = 1;  // the scene file has errors
constexpr int kExitUsage = 2;  // bad arguments, unreadable input, unwritable output
constexpr int kMaxShownDiagnostics = 20;

const char* const kHelp =
    "Usage: raytracer [OPTIONS] [SCENE [OUT]]\n"
    "Render a raytracer2 scene file to an image. Missing SCENE or OUT are asked for\n"
    "on the terminal, as the 2013 program did.\n"
    "\n"
    "  OUT ends in .ppm (binary PPM, P6) or .png.\n"
    "\n"
    "Options:\n"
    "  --width N          picture width in pixels, overriding the scene (1..16384)\n"
    "  --height N         picture height in pixels, overriding the scene (1..16384)\n"
    "  --samples N        samples per pixel (1..65536, default 1: the original's\n"
    "                     single ray through each pixel corner)\n"
    "  --threads N        worker threads (1..256, default: all cores)\n"
    "  --max-depth N      recursion limit (1..1000, default 20 as in the original;\n"
    "                     a reflection costs 2 levels, a refraction 3)\n"
    "  --time-limit SEC   stop adding samples after SEC seconds (every pixel still gets\n"
    "                     at least one); without --samples, render as many as fit\n"
    "  --mirror           mirror the picture left-right, as the 2013 program did\n"
    "  --quiet            no progress bar\n"
    "  --stats            print times, ray count and rays per second to stderr\n"
    "  --check SCENE      parse SCENE and report errors and warnings; render nothing\n"
    "  --print-scene      print SCENE in normalised form to stdout; render nothing\n"
    "  --version          print the version and exit\n"
    "  -h, --help         print this help and exit\n"
    "\n"
    "Exit status: 0 success, 1 the scene has errors, 2 usage or I/O error,\n"
    "128+N interrupted by signal N (130 for Ctrl+C). An interrupted or failed run\n"
    "leaves OUT untouched.\n";

void usage_hint() { std::cerr << "Try 'raytracer --help' for more information.\n"; }

int usage_error(const std::string& message) {
    std::cerr << "raytracer: " << message << "\n";
    usage_hint();
    return kExitUsage;
}

// --- signals ---------------------------------------------------------------------
// The handler only records the signal; the main thread polls it between waits,
// cancels the render and exits without writing. SA_RESETHAND lets a second Ctrl+C
// kill the process outright should cancelling ever hang.
volatile sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) { g_signal = sig; }

void install_signal_handlers() {
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int interrupted_exit() {
    const int sig = g_signal;
    std::cerr << "raytracer: interrupted (" << (sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal")
              << "); nothing written\n";
    return 128 + sig;
}

// --- arguments ---------------------------------------------------------------------

struct Options {
    std::optional<int> width, height;
    std::optional<int> samples;
    int threads = 0;  // 0: all cores
    int max_depth = 20;
    double time_limit = 0;
    bool mirror = false, quiet = false, stats = false, print_scene = false;
    std::optional<std::string> check;
    std::vector<std::string> positional;
};

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

// Returns -1 to continue, else the exit status (for --help, --version and errors).
int parse_args(int argc, char** argv, Options& o) {
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
            if (has_inline_value) return usage_error("option '" + name + "' takes no value");
            f = true;
            return -1;
        };
        std::string v, err;
        int n = 0;
        if (name == "-h" || name == "--help") {
            std::cout << kHelp;
            return kExitOk;
        } else if (name == "--version") {
            std::cout << "raytracer " RT_VERSION "\n";
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
                   name == "--max-depth") {
            if (!take_value(v)) return usage_error("option '" + name + "' needs a number");
            long lo = 1, hi = rt::Limits::max_picture_side;
            if (name == "--samples") hi = 65536;
            if (name == "--threads") hi = 256;
            if (name == "--max-depth") hi = 1000;
            if (!parse_int(name, v, lo, hi, n, err)) return usage_error(err);
            if (name == "--width") o.width = n;
            else if (name == "--height") o.height = n;
            else if (name == "--samples") o.samples = n;
            else if (name == "--threads") o.threads = n;
            else o.max_depth = n;
        } else if (name == "--time-limit") {
            if (!take_value(v)) return usage_error("option '--time-limit' needs a number of seconds");
            if (!parse_seconds(name, v, o.time_limit, err)) return usage_error(err);
        } else if (name == "--check") {
            if (!take_value(v)) return usage_error("option '--check' needs a scene file");
            o.check = v;
        } else {
            return usage_error("unknown option '" + a + "'");
        }
    }
    return -1;
}

// One line from stdin after a prompt on stderr; false at end of input.
bool prompt(const char* question, std::string& answer) {
    std::cerr << question << std::flush;
    if (!std::getline(std::cin, answer)) {
        std::cerr << "\n";
        return false;
    }
    if (!answer.empty() && answer.back() == '\r') answer.pop_back();
    return true;
}

// --- scene -------------------------------------------------------------------------

// Reads and parses; prints diagnostics. Returns -1 on success, else the exit status.
int load_scene(const std::string& path, rt::Scene& scene) {
    std::string text;
    std::string err = rt::read_file(path, text, rt::Limits::max_file_size);
    if (!err.empty()) {
        std::cerr << "raytracer: cannot read '" << path << "': " << err << "\n";
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

// Lowercase extension including the dot, or "".
std::string extension(const std::string& path) {
    auto slash = path.find_last_of('/');
    auto dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// Fails early (before a long render) on an output the final rename could not produce.
std::string check_output_path(const std::string& out, const std::string& scene_path) {
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

// --- progress ----------------------------------------------------------------------

class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled) {}
    void update(double fraction, double elapsed) {
        if (!enabled_) return;
        // Passes can be regrouped by the renderer; never let the bar run backwards.
        shown_ = std::max(shown_, std::clamp(fraction, 0.0, 1.0));
        constexpr int kWidth = 40;
        int filled = int(shown_ * kWidth);
        char line[160];
        int n = std::snprintf(line, sizeof line, "\r[%.*s%*s] %3d%%  %.1f s", filled,
                              "########################################", kWidth - filled, "",
                              int(shown_ * 100), elapsed);
        if (shown_ > 0.02 && shown_ < 1) {
            double eta = elapsed * (1 - shown_) / shown_;
            n += std::snprintf(line + n, sizeof line - n, ", ETA %.1f s", eta);
        }
        std::fputs(line, stderr);
        std::fputs("\033[K", stderr);  // erase leftovers of a longer previous line
        std::fflush(stderr);
        drawn_ = true;
    }
    void clear() {
        if (!drawn_) return;
        std::fputs("\r\033[K", stderr);
        std::fflush(stderr);
        drawn_ = false;
    }

private:
    bool enabled_;
    bool drawn_ = false;
    double shown_ = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string count(std::size_t n, const char* noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::string with_commas(std::uint64_t v) {
    std::string s = std::to_string(v);
    for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(std::size_t(i), ",");
    return s;
}

int run(int argc, char** argv) {
    using Clock = std::chrono::steady_clock;
    Options opt;
    if (int r = parse_args(argc, argv, opt); r >= 0) return r;

    if (opt.check) {
        if (!opt.positional.empty()) return usage_error("--check takes only the scene file");
        rt::Scene scene;
        if (int r = load_scene(*opt.check, scene); r >= 0) return r;
        if (!opt.quiet)
            std::cerr << *opt.check << ": ok: " << count(scene.objects.size(), "object") << ", "
                      << count(scene.planes.size(), "plane") << ", " << count(scene.lights.size(), "light") << ", "
                      << scene.width << "x" << scene.height << "\n";
        return kExitOk;
    }
    if (opt.positional.size() > 2) return usage_error("too many arguments");
    if (opt.print_scene && opt.positional.size() != 1)
        return usage_error("--print-scene takes exactly one scene file and no output");

    // As in the 2013 program: ask for what the command line did not give.
    std::string scene_path, out_path;
    if (!opt.positional.empty()) {
        scene_path = opt.positional[0];
    } else if (!prompt("Scene file: ", scene_path)) {
        return usage_error("no scene file given");
    }
    if (scene_path.empty()) return usage_error("no scene file given");

    if (!opt.print_scene) {
        if (opt.positional.size() >= 2) {
            out_path = opt.positional[1];
        } else if (!prompt("Output picture (.ppm or .png): ", out_path)) {
            return usage_error("no output file given");
        }
        if (out_path.empty()) return usage_error("no output file given");
        const std::string ext = extension(out_path);
        if (ext != ".ppm" && ext != ".png")
            return usage_error("cannot write '" + out_path + "': the output must end in .ppm or .png");
        if (std::string e = check_output_path(out_path, scene_path); !e.empty()) {
            std::cerr << "raytracer: cannot write '" << out_path << "': " << e << "\n";
            return kExitUsage;
        }
    }

    // Installed only now: at a prompt, Ctrl+C should just end the program.
    install_signal_handlers();

    const auto t_start = Clock::now();
    rt::Scene scene;
    if (int r = load_scene(scene_path, scene); r >= 0) return r;
    if (opt.width) scene.width = *opt.width;
    if (opt.height) scene.height = *opt.height;
    const double t_parse = seconds_since(t_start);

    if (opt.print_scene) {
        // Normalised form: every default written out, including the material an
        // object gets when it has no material block (translusans 0).
        for (rt::Object& o : scene.objects) o.has_material = true;
        for (rt::Plane& p : scene.planes) p.has_material = p.has_material2 = true;
        std::cout << rt::write_scene(scene) << std::flush;
        return std::cout ? kExitOk : kExitUsage;
    }
    if (g_signal) return interrupted_exit();

    const auto t_compile0 = Clock::now();
    std::shared_ptr<const rt::World> world = rt::compile_world(scene);
    if (opt.max_depth != world->options.max_depth) {
        auto changed = std::make_shared<rt::World>(*world);  // shares the geometry
        changed->options.max_depth = opt.max_depth;
        world = std::move(changed);
    }
    const double t_compile = seconds_since(t_compile0);
    if (g_signal) return interrupted_exit();

    rt::RenderSettings settings;
    settings.width = scene.width;
    settings.height = scene.height;
    settings.coarse = false;  // nobody watches a preview here
    settings.mirror = opt.mirror;
    settings.time_limit = opt.time_limit;
    // A time limit with no sample count means "as good as fits in the time".
    settings.max_samples = opt.samples ? *opt.samples : (opt.time_limit > 0 ? 65536 : 1);
    // Without a time limit nothing is gained by stopping between passes, and one
    // pass makes pass_fraction the whole render's progress.
    if (opt.time_limit <= 0) settings.samples_per_pass = settings.max_samples;

    const auto t_render0 = Clock::now();
    rt::Renderer renderer(opt.threads);
    ProgressBar bar(!opt.quiet && isatty(STDERR_FILENO));
    renderer.start(world, settings);
    while (!renderer.wait_for(0.1)) {
        if (g_signal) {
            renderer.cancel();
            bar.clear();
            return interrupted_exit();
        }
        rt::RenderProgress p = renderer.progress();
        double fraction = (p.samples + p.pass_fraction * (settings.max_samples - p.samples)) / settings.max_samples;
        if (opt.time_limit > 0) fraction = std::max(fraction, p.elapsed / opt.time_limit);
        bar.update(fraction, p.elapsed);
    }
    bar.clear();
    if (g_signal) return interrupted_exit();
    const rt::RenderProgress progress = renderer.progress();
    rt::ZeroedArray<std::uint8_t> pixels;
    int width = 0, height = 0;
    renderer.snapshot_rgb8(pixels, width, height);
    const double t_render = seconds_since(t_render0);
    if (width != scene.width || height != scene.height || progress.samples < 1) {
        std::cerr << "raytracer: internal error: the renderer returned a " << width << "x" << height
                  << " picture with " << progress.samples << " samples per pixel\n";
        return kExitUsage;
    }

    const auto t_write0 = Clock::now();
    if (std::string err = rt::write_rgb8(out_path, width, height, pixels.data(), pixels.size()); !err.empty()) {
        std::cerr << "raytracer: cannot write '" << out_path << "': " << err << "\n";
        return kExitUsage;
    }
    const double t_write = seconds_since(t_write0);

    if (opt.stats) {
        const double total = seconds_since(t_start);
        char line[256];
        std::snprintf(line, sizeof line,
                      "time: parse %.3f s, compile %.3f s, render %.3f s, write %.3f s, total %.3f s\n", t_parse,
                      t_compile, t_render, t_write, total);
        std::cerr << scene_path << ": " << scene.width << "x" << scene.height << ", " << progress.samples
                  << (progress.samples == 1 ? " sample" : " samples") << " per pixel, " << renderer.threads()
                  << (renderer.threads() == 1 ? " thread" : " threads") << "\n"
                  << line << "rays: " << with_commas(progress.rays);
        std::snprintf(line, sizeof line, " (%.2f M rays/s)\n", t_render > 0 ? progress.rays / t_render / 1e6 : 0.0);
        std::cerr << line;
    }
    return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    // Cancelling and reporting is all we do on an exception; the output stays untouched.
    try {
        return run(argc, argv);
    } catch (const std::bad_alloc&) {
        std::cerr << "raytracer: out of memory\n";
    } catch (const std::exception& e) {
        std::cerr << "raytracer: " << e.what() << "\n";
    }
    return kExitUsage;
}
