// Command-line parsing and --help for both viewer binaries (see options.h).
#include "options.h"

#include <sys/resource.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <utility>

#include "arg_table.h"
#include "render_request.h"
#include "scene.h"

namespace rtview {

namespace {

rt::Status usage(const std::string& message) { return rt::Status::error(message, rt::kExitUsage); }

// Whether two names are one file: the same inode, or (not created yet) the same name.
bool same_file(const std::string& a, const std::string& b) {
    struct stat sa, sb;
    if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    return a == b;
}

rtargs::Option flag(const char* names, const char* help, bool& out) {
    return rtargs::flag_option(names, help, [&out] { out = true; });
}

// An option whose value is a file name or word; an empty one is missing.
rtargs::Option text(const char* name, const char* value, const char* help, std::string& out,
                    std::function<rt::Status(const std::string&)> check = nullptr) {
    return rtargs::value_option(name, value, "a value", help, [&out, check](const std::string& n, const std::string& v) {
        if (v.empty()) return usage("option '" + n + "' needs a value");
        if (check)
            if (rt::Status st = check(v); !st) return st;
        out = v;
        return rt::Status();
    });
}

rtargs::Option whole(const char* name, std::string help, int lo, int hi, int& out) {
    return rtargs::value_option(name, "N", "a number", std::move(help), [lo, hi, &out](const std::string& n, const std::string& v) {
        const std::optional<long> x = rtargs::integer_in(v, lo, hi);
        if (!x) return usage("option '" + n + "' must be a whole number in range (got '" + v + "')");
        out = int(*x);
        return rt::Status();
    });
}

rtargs::Option real(const char* name, const char* value, const char* help, double& out, bool non_negative) {
    return rtargs::value_option(name, value, "a number", help, [&out, non_negative](const std::string& n, const std::string& v) {
        const std::optional<double> x = rtargs::decimal(v);
        if (!x) return usage("option '" + n + "' needs a number (got '" + v + "')");
        if (non_negative && *x < 0) return usage(n + " must not be negative");
        out = *x;
        return rt::Status();
    });
}

// A default as --help writes it: "0.02".
std::string shown(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

rt::Status set_size(const std::string& v, Options& o) {
    const auto x = v.find('x');
    const int lo = kMinWindowSide, hi = rt::Limits::max_picture_side;
    const auto w = x == std::string::npos ? std::nullopt : rtargs::integer_in(v.substr(0, x), lo, hi);
    const auto h = x == std::string::npos ? std::nullopt : rtargs::integer_in(v.substr(x + 1), lo, hi);
    if (!w || !h)
        return usage("--size must be WIDTHxHEIGHT, each " + std::to_string(lo) + ".." + std::to_string(hi) + " (got '" +
                     v + "')");
    o.width = int(*w);
    o.height = int(*h);
    o.size_given = true;
    return {};
}

// Both binaries' options, in --help's order.
rtargs::Table option_table(Options& o) {
    rtargs::Table t;
    t.help_column = 23;
    t.unknown_shows_value = false;
    t.options = {
        flag("--headless", "no window: render the UI offscreen and write --screenshot", o.headless),
        text("--screenshot", "FILE", "headless: write the whole window as PNG (or PPM by extension)", o.screenshot),
        text("--render", "FILE",
             "headless: render the scene at its picture_size to FILE (.png or\n"
             ".ppm), the same bytes as `raytracer --samples N SCENE FILE`\n"
             "(default 1 sample, or as many as --time-limit allows)",
             o.render),
        rtargs::value_option("--size", "WxH", "WIDTHxHEIGHT", "window (or headless image) size in pixels (default 1280x800)",
                             [&o](const std::string&, const std::string& v) { return set_size(v, o); }),
        whole("--samples",
              "samples per pixel to stop at (default " + std::to_string(kDefaultSamplesWindow) + " in a window, " +
                  std::to_string(kDefaultSamplesHeadless) + " headless)",
              1, rt::kMaxSamples, o.samples),
        real("--time-limit", "SEC", "stop refining after SEC seconds (default: no limit)", o.time_limit, true),
        rtargs::value_option("--aa-threshold", "T", "a number",
                             "adaptive anti-aliasing threshold, 0.." + std::to_string(int(rt::kMaxAaThreshold)) +
                                 " (default " + shown(kDefaultAaThreshold) + "; 0:\n"
                             "every pixel gets every sample; off: every pixel the\n"
                             "same samples, in passes); with --render, as raytracer's\n"
                             "(default: off)",
                             [&o](const std::string& n, const std::string& v) {
                                 if (v == "off") {
                                     o.aa_threshold = -1;
                                     return rt::Status();
                                 }
                                 const std::optional<double> x = rtargs::decimal(v);
                                 if (!x || *x < 0 || *x > rt::kMaxAaThreshold)
                                     return usage(n + " must be a number from 0 to " +
                                                  std::to_string(int(rt::kMaxAaThreshold)) + " or 'off' (got '" + v +
                                                  "')");
                                 o.aa_threshold = *x;
                                 return rt::Status();
                             }),
        real("--orbit", "DEG", "orbit the camera DEG degrees around its centre first", o.orbit, false),
        rtargs::value_option("--fit", "picture|window", "window or picture",
                             "show exactly the scene's picture, letterboxed at its\n"
                             "picture_size aspect (default), or fill the window",
                             [&o](const std::string&, const std::string& v) {
                                 if (v != "window" && v != "picture")
                                     return usage("--fit must be window or picture (got '" + v + "')");
                                 o.fit = v == "window" ? FitMode::Window : FitMode::Picture;
                                 return rt::Status();
                             }),
        whole("--threads", "render threads (default: all hardware threads)", 0, rt::kMaxThreads, o.threads),
        text("--tab", "NAME", "sidebar tab to show: objects (default), text or render", o.tab,
             [](const std::string& v) {
                 return v == "objects" || v == "text" || v == "render" ? rt::Status()
                                                                      : usage("--tab must be objects, text or render");
             }),
        text("--select", "WHAT",
             "select 'object N', 'plane N' or 'light N' (1-based); 'object N\n"
             "left right' selects a CSG operand below object N",
             o.select),
        text("--handle", "MODE", "the selection's handle: move (default), turn or size (G, Y, U)", o.handle,
             [](const std::string& v) {
                 return v == "move" || v == "turn" || v == "size" ? rt::Status()
                                                                  : usage("--handle must be move, turn or size");
             }),
        text("--view-scene", "FILE",
             "write the scene exactly as the image area shows it\n"
             "(view camera, picture size = image area): `raytracer FILE`\n"
             "renders the same pixels",
             o.view_scene),
        flag("--print-layout", "print the image and panel rectangles on stdout (for scripts)", o.print_layout),
        flag("-v, --verbose", "print render timings on stderr", o.verbose),
        flag("-h, --help", "show this help", o.help),
        flag("--version", "show the version", o.version),
    };
    t.positional = [&o](const std::string& a) {
        if (!o.scene.empty()) return usage("more than one scene file given ('" + o.scene + "' and '" + a + "')");
        o.scene = a;
        return rt::Status();
    };
    return t;
}

}  // namespace

rt::Status parse_options(int argc, const char* const* argv, Options& o) {
    if (rt::Status st = rtargs::parse(option_table(o), argc, argv); !st) return st;
    // As raytracer refuses to render over its scene: an output naming the scene file
    // would destroy it.
    for (const auto& [opt, path] : {std::pair<const char*, const std::string*>{"--screenshot", &o.screenshot},
                                    {"--view-scene", &o.view_scene}})
        if (!path->empty() && !o.scene.empty() && same_file(*path, o.scene))
            return usage(std::string(opt) + " '" + *path + "' is the scene file itself");
    if (!o.screenshot.empty() && !o.view_scene.empty() && same_file(o.screenshot, o.view_scene))
        return usage("--screenshot and --view-scene name the same file ('" + o.screenshot + "')");
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
    Options unused;
    s += "Options:\n" + rtargs::help_lines(option_table(unused));
    if (!headless_binary) {
        s += "\nMouse and keys (in the image area):\n"
             "  left drag            orbit around the point under the cursor\n"
             "  right/middle drag, shift+left drag   pan\n"
             "  wheel                dolly towards the point under the cursor\n"
             "  (moving the view never edits the file; Ctrl+K sets the scene camera from it)\n"
             "  click                select the object under the cursor\n"
             "  Shift+click          add it to the selection, or take it out (also in the list;\n"
             "                       Ctrl+click there too)\n"
             "  Ctrl+Shift+left drag box select: add what the box sees (planes only if nothing\n"
             "                       else); several selected: one handle at their centre moves\n"
             "                       all (one undo step), Ctrl+D / Delete act on all\n"
             "  right click          add here / duplicate / delete / lamp<->spotlight / CSG menu\n"
             "  Ctrl+D / Delete      duplicate / delete the selected object, plane or light\n"
             "  drag the handle      move the selection (its outline shows it): an arrow moves\n"
             "                       along x/y/z, the square in the view plane; Shift snaps to\n"
             "                       a grid scaled to the scene, Esc cancels; one undo step\n"
             "  G / Y / U            the handle moves / turns / sizes the selected object:\n"
             "                       Y: a ring turns about x/y/z, the outer circle about the\n"
             "                       view (Shift: 15 degrees); U: a box sizes along the\n"
             "                       object's own axis, the middle one all three (Shift:\n"
             "                       tenths); they write rotation/scale/translate, never the\n"
             "                       shape's own numbers\n"
             "  W A S D / Q E        fly (shift: faster)     F  frame the objects\n"
             "  R                    reset the view to the scene camera\n"
             "  Esc                  close a menu; cancel opening a file (the old scene stays);\n"
             "                       else select nothing\n"
             "  Space                pause / resume rendering\n"
             "  Ctrl+Z / Ctrl+Y      undo / redo (Edit > Undo history: every step by name)\n"
             "  Ctrl+Enter           apply the scene text\n"
             "  Ctrl+S               save (Ctrl+Shift+S: save as)  Ctrl+O  open  Ctrl+N  new\n"
             "  Ctrl+E               edit the scene text   Ctrl+P  save the image (the picture\n"
             "                       at picture_size in the picture frame, whatever the zoom)\n"
             "  in the text: Ctrl+F find (Enter next, Shift+Enter previous), Ctrl+G go to line;\n"
             "                       Enter keeps the indentation, one level more after {, a }\n"
             "                       on a blank line one less (tabs or spaces, as the file has)\n"
             "  Ctrl+Q               quit (asks about unsaved changes)\n"
             "  F12                  screenshot of the whole window\n"
             "  Tab                  hide / show the sidebar (drag its edge to resize it)\n"
             "The picture (display only; saved images are unchanged):\n"
             "  + / - / 0            exposure one stop up / down / back to 0\n"
             "  T                    soft tone curve / clip     O  stripe clipped pixels\n"
             "  hover                pixel, linear RGB, samples, object hit and distance\n"
             "  Ctrl+C               copy that readout to the clipboard (or: right click, Copy pixel)\n"
             "  Ctrl+wheel           zoom about the cursor      1  1:1    Home  fit\n"
             "                       (the same render: zoom and pan only place it on the screen)\n"
             "  Ctrl+right drag      pan the picture (not the camera)\n"
             "  K                    keep a snapshot            B  compare: split / difference / off\n"
             "                                                  Shift+B  compare with the snapshot before\n"
             "  Ctrl+left drag       render only that region    C  clear the region\n"
             "  Ctrl+R               render to file at the scene's picture_size\n"
             "  Ctrl+= / Ctrl+- / Ctrl+0   UI size larger / smaller / 100%\n"
             "Recent files: $XDG_CONFIG_HOME/raytracer-view/recent.txt (or ~/.config/...),\n"
             "the UI size and the sidebar's width: settings.txt beside it.\n";
    }
    return s;
}

}  // namespace rtview

namespace rtview {

rt::Status memory_problem(int width, int height, bool headless) {
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
    return usage(text);
}

}  // namespace rtview
