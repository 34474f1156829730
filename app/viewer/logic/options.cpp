// Command-line parsing and --help for both viewer binaries (see options.h).
#include "options.h"

#include <sys/resource.h>
#include <sys/stat.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string_view>
#include <utility>

namespace rtview {

namespace {

bool parse_int(std::string_view s, int lo, int hi, int& out) {
    int v = 0;
    auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v < lo || v > hi) return false;
    out = v;
    return true;
}

// A whole decimal token, as numbers in scene files: no spaces, hex, inf or nan.
bool is_decimal_token(const std::string& s) {
    std::size_t i = 0, n = s.size(), mantissa = 0;
    auto digits = [&] {
        std::size_t k = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++k;
        return k;
    };
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    mantissa = digits();
    if (i < n && s[i] == '.') ++i, mantissa += digits();
    if (mantissa == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        if (digits() == 0) return false;
    }
    return i == n;
}

bool parse_real(const std::string& s, double& out) {
    if (!is_decimal_token(s)) return false;
    char* end = nullptr;
    double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || !std::isfinite(v)) return false;
    out = v;
    return true;
}

// Whether two names are one file: the same inode, or (not created yet) the same name.
bool same_file(const std::string& a, const std::string& b) {
    struct stat sa, sb;
    if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    return a == b;
}

}  // namespace

std::string parse_options(int argc, const char* const* argv, Options& o) {
    bool only_positional = false;
    for (int k = 1; k < argc; ++k) {
        std::string a = argv[k];
        std::string value;
        bool has_value = false;
        if (!only_positional && a.rfind("--", 0) == 0 && a.size() > 2) {
            if (auto eq = a.find('='); eq != std::string::npos) {
                value = a.substr(eq + 1);
                a = a.substr(0, eq);
                has_value = true;
            }
        }
        auto take = [&](std::string& v) {
            if (has_value) {
                v = value;
                return true;
            }
            if (k + 1 >= argc) return false;
            v = argv[++k];
            return true;
        };
        std::string v;
        if (only_positional || a.empty() || a[0] != '-' || a == "-") {
            if (!o.scene.empty()) return "more than one scene file given ('" + o.scene + "' and '" + a + "')";
            o.scene = a;
        } else if (a == "--") {
            only_positional = true;
        } else if (a == "-h" || a == "--help") {
            o.help = true;
        } else if (a == "--version") {
            o.version = true;
        } else if (a == "--headless") {
            o.headless = true;
        } else if (a == "--print-layout") {
            o.print_layout = true;
        } else if (a == "--verbose" || a == "-v") {
            o.verbose = true;
        } else if (a == "--screenshot" || a == "--view-scene" || a == "--tab" || a == "--select" ||
                   a == "--render") {
            if (!take(v) || v.empty()) return "option '" + a + "' needs a value";
            if (a == "--screenshot") o.screenshot = v;
            else if (a == "--render") o.render = v;
            else if (a == "--view-scene") o.view_scene = v;
            else if (a == "--select") o.select = v;
            else {
                if (v != "objects" && v != "text" && v != "render") return "--tab must be objects, text or render";
                o.tab = v;
            }
        } else if (a == "--size") {
            if (!take(v)) return "option '--size' needs WIDTHxHEIGHT";
            auto x = v.find('x');
            if (x == std::string::npos || !parse_int(std::string_view(v).substr(0, x), 64, 16384, o.width) ||
                !parse_int(std::string_view(v).substr(x + 1), 64, 16384, o.height))
                return "--size must be WIDTHxHEIGHT, each 64..16384 (got '" + v + "')";
            o.size_given = true;
        } else if (a == "--samples" || a == "--threads") {
            if (!take(v)) return "option '" + a + "' needs a number";
            int n = 0;
            if (!parse_int(v, a == "--samples" ? 1 : 0, a == "--samples" ? 65536 : 256, n))
                return "option '" + a + "' must be a whole number in range (got '" + v + "')";
            (a == "--samples" ? o.samples : o.threads) = n;
        } else if (a == "--time-limit" || a == "--orbit") {
            if (!take(v)) return "option '" + a + "' needs a number";
            double d = 0;
            if (!parse_real(v, d)) return "option '" + a + "' needs a number (got '" + v + "')";
            if (a == "--time-limit") {
                if (d < 0) return "--time-limit must not be negative";
                o.time_limit = d;
            } else {
                o.orbit = d;
            }
        } else if (a == "--fit") {
            if (!take(v)) return "option '--fit' needs window or picture";
            if (v == "window") o.fit = FitMode::Window;
            else if (v == "picture") o.fit = FitMode::Picture;
            else return "--fit must be window or picture (got '" + v + "')";
        } else {
            return "unknown option '" + a + "'";
        }
        if (has_value && (a == "--headless" || a == "--help" || a == "--version" || a == "--print-layout" ||
                          a == "--verbose"))
            return "option '" + a + "' takes no value";
    }
    // As raytracer refuses to render over its scene: an output naming the scene file
    // would destroy it.
    for (const auto& [opt, path] : {std::pair<const char*, const std::string*>{"--screenshot", &o.screenshot},
                                    {"--view-scene", &o.view_scene}})
        if (!path->empty() && !o.scene.empty() && same_file(*path, o.scene))
            return std::string(opt) + " '" + *path + "' is the scene file itself";
    if (!o.screenshot.empty() && !o.view_scene.empty() && same_file(o.screenshot, o.view_scene))
        return "--screenshot and --view-scene name the same file ('" + o.screenshot + "')";
    return {};
}

std::string help_text(bool headless_binary) {
    std::string s;
    if (headless_binary) {
        s += "Usage: raytracer-view-headless [SCENE] --screenshot OUT [OPTIONS]\n"
             "       raytracer-view-headless [SCENE] --render OUT [--samples N] [--time-limit SEC]\n"
             "Draws the raytracer-view window (image and panels) into an offscreen OSMesa\n"
             "buffer, without X or a GPU, waits for the samples and writes OUT.\n"
             "`raytracer-view --headless ...` runs this program.\n\n";
    } else {
        s += "Usage: raytracer-view [OPTIONS] [SCENE]\n"
             "       raytracer-view --headless [SCENE] --screenshot OUT [OPTIONS]\n"
             "       raytracer-view --headless [SCENE] --render OUT [--samples N]\n"
             "Interactive previewer for raytracer scene files. Without SCENE it opens the\n"
             "built-in default scene.\n\n";
    }
    s += "Options:\n"
         "  --headless           no window: render the UI offscreen and write --screenshot\n"
         "  --screenshot FILE    headless: write the whole window as PNG (or PPM by extension)\n"
         "  --render FILE        headless: render the scene at its picture_size to FILE (.png or\n"
         "                       .ppm), the same bytes as `raytracer --samples N SCENE FILE`\n"
         "                       (default 1 sample, or as many as --time-limit allows)\n"
         "  --size WxH           window (or headless image) size in pixels (default 1280x800)\n"
         "  --samples N          samples per pixel to stop at (default 64 in a window, 16 headless)\n"
         "  --time-limit SEC     stop refining after SEC seconds (default: no limit)\n"
         "  --orbit DEG          orbit the camera DEG degrees around its centre first\n"
         "  --fit picture|window show exactly the scene's picture, letterboxed at its\n"
         "                       picture_size aspect (default), or fill the window\n"
         "  --threads N          render threads (default: all hardware threads)\n"
         "  --tab NAME           sidebar tab to show: objects (default), text or render\n"
         "  --select WHAT        select 'object N', 'plane N' or 'light N' (1-based); 'object N\n"
         "                       left right' selects a CSG operand below object N\n"
         "  --view-scene FILE    write the scene exactly as the image area shows it\n"
         "                       (view camera, picture size = image area): `raytracer FILE`\n"
         "                       renders the same pixels\n"
         "  --print-layout       print the image and panel rectangles on stdout (for scripts)\n"
         "  -v, --verbose        print render timings on stderr\n"
         "  -h, --help           show this help\n"
         "  --version            show the version\n";
    if (!headless_binary) {
        s += "\nMouse and keys (in the image area):\n"
             "  left drag            orbit around the point under the cursor\n"
             "  right/middle drag, shift+left drag   pan\n"
             "  wheel                dolly towards the point under the cursor\n"
             "  (moving the view never edits the file; Ctrl+K sets the scene camera from it)\n"
             "  click                select the object under the cursor\n"
             "  right click          add here / duplicate / delete / lamp<->spotlight / CSG menu\n"
             "  Ctrl+D / Delete      duplicate / delete the selected object, plane or light\n"
             "  drag the handle      move the selection (its outline shows it): an arrow moves\n"
             "                       along x/y/z, the square in the view plane; Shift snaps to\n"
             "                       a grid scaled to the scene, Esc cancels; one undo step\n"
             "  W A S D / Q E        fly (shift: faster)     F  frame the scene\n"
             "  R                    reset the view to the scene camera\n"
             "  Esc                  cancel opening a file (the old scene stays)\n"
             "  Space                pause / resume rendering\n"
             "  Ctrl+Z / Ctrl+Y      undo / redo           Ctrl+Enter  apply the scene text\n"
             "  Ctrl+S               save (Ctrl+Shift+S: save as)  Ctrl+O  open\n"
             "  Ctrl+E               edit the scene text   Ctrl+P  save the image\n"
             "  in the text: Ctrl+F find (Enter next, Shift+Enter previous), Ctrl+G go to line\n"
             "  Ctrl+Q               quit (asks about unsaved changes)\n"
             "  F12                  screenshot of the whole window\n"
             "The picture (display only; saved images are unchanged):\n"
             "  + / - / 0            exposure one stop up / down / back to 0\n"
             "  T                    soft tone curve / clip     O  stripe clipped pixels\n"
             "  hover                pixel, linear RGB, samples, object hit and distance\n"
             "  Ctrl+wheel           zoom about the cursor      1  1:1    Home  fit\n"
             "  Ctrl+right drag      pan the picture (not the camera)\n"
             "  K                    keep a snapshot            B  compare: split / difference / off\n"
             "  Ctrl+left drag       render only that region    C  clear the region\n"
             "  Ctrl+R               render to file at the scene's picture_size\n"
             "  Ctrl+= / Ctrl+- / Ctrl+0   UI size larger / smaller / 100%\n"
             "Recent files: $XDG_CONFIG_HOME/raytracer-view/recent.txt (or ~/.config/...),\n"
             "the UI size: settings.txt beside it.\n";
    }
    return s;
}

}  // namespace rtview

namespace rtview {

std::string memory_problem(int width, int height, bool headless) {
    // Measured peak use of raytracer-view-headless is about 43 bytes per pixel of the
    // window (OSMesa's buffer, the film's sums and bytes, the texture, the screenshot),
    // plus the libraries' and threads' address space (Mesa's LLVM alone maps hundreds
    // of MiB). Rounded up, so that a picture that passes does fit.
    const double bytes_per_pixel = 48, base = headless ? 1024.0 * 1024 * 1024 : 512.0 * 1024 * 1024;
    const double need = base + bytes_per_pixel * double(width) * double(height);
    double limit = 0;  // 0: none known
    auto lower = [&](double v) {
        if (v > 0 && (limit == 0 || v < limit)) limit = v;
    };
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        struct rlimit rl;
        if (::getrlimit(resource, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) lower(double(rl.rlim_cur));
    }
    // RAM plus swap: more than that can never be had, whatever the limits say.
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double kb = 0, total = 0;
    std::string unit;
    while (meminfo >> key >> kb >> unit)
        if (key == "MemTotal:" || key == "SwapTotal:") total += kb * 1024;
    lower(total);
    if (limit == 0 || need <= limit) return {};
    char text[256];
    std::snprintf(text, sizeof text,
                  "out of memory: a %dx%d %s needs about %.1f GiB, and this process may use %.1f GiB; "
                  "use a smaller --size",
                  width, height, headless ? "image" : "window", need / (1 << 30), limit / (1 << 30));
    return text;
}

}  // namespace rtview
