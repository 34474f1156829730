// raytracer: the headless command-line renderer, used like the 2013 program
// (`raytracer SCENE OUT`, prompting for whatever is missing) plus options.
// It drives the same progressive rt::Renderer as the viewer; it links no GL.
#include <signal.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.h"
#include "diagnostic_text.h"
#include "image_io.h"
#include "parallel.h"
#include "renderer.h"
#include "scene.h"
#include "scene_parser.h"
#include "world.h"

// What a finished run leaves to the process's exit, reachable (for leak checkers)
// through these. Not static: a store to a global nobody else could read may be dropped.
rt::Scene* g_kept_scene = nullptr;
std::shared_ptr<const rt::World>* g_kept_world = nullptr;

namespace {

using namespace rtcli;

const Program kProgram{
    "raytracer",
    "Usage: raytracer [OPTIONS] [SCENE [OUT]]\n"
    "Render a raytracer2 scene file to an image. Missing SCENE or OUT are asked for\n"
    "on the terminal, as the 2013 program did.\n"
    "\n"
    "  OUT ends in .ppm (binary PPM, P6) or .png.\n"
    "\n"
    "Options:\n",
    "worker threads",
    "all cores",
    "Exit status: 0 success, 1 the scene has errors, 2 usage or I/O error,\n"
    "128+N interrupted by signal N (130 for Ctrl+C). An interrupted or failed run\n"
    "leaves OUT untouched.\n"};

rt::Status usage_error(const std::string& message) { return rtcli::usage_error(kProgram, message); }

// A signal that came while the output was being written (the signal handler ends
// the process itself in every other phase).
rt::Status interrupted() {
    const int sig = caught_signal();
    return failure(kProgram,
                   std::string("interrupted (") +
                       (sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "signal") +
                       "); nothing written",
                   128 + sig);
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

using Clock = std::chrono::steady_clock;

// Phase 1: the scene and output paths, from the command line or asked for.
rt::Status settle_paths(const Options& opt, std::string& scene_path, std::string& out_path) {
    if (opt.positional.size() > 2) return usage_error("too many arguments");
    if (opt.flatten && !opt.print_scene) return usage_error("--flatten goes with --print-scene");
    if (opt.print_scene && opt.positional.size() != 1)
        return usage_error("--print-scene takes exactly one scene file and no output");

    // As in the 2013 program: ask for what the command line did not give.
    if (!opt.positional.empty()) {
        scene_path = opt.positional[0];
    } else if (!prompt("Scene file: ", scene_path)) {
        return usage_error("no scene file given");
    }
    if (scene_path.empty()) return usage_error("no scene file given");

    if (!opt.print_scene) {
        if (opt.positional.size() >= 2) {
            out_path = opt.positional[1];
        } else if (!prompt("Output picture (.ppm, .png, .pfm or .exr): ", out_path)) {
            return usage_error("no output file given");
        }
        if (out_path.empty()) return usage_error("no output file given");
    }
    return {};
}

// What the render phase hands on to the write and the statistics.
struct Rendered {
    rt::RenderProgress progress;
    rt::ZeroedArray<std::uint8_t> pixels;
    rt::Image film;  // for a float picture (.pfm, .exr): the film's values instead
    int width = 0, height = 0;
    int threads = 0;
};

// Phase 4: renders with the progress bar.
rt::Status render(const std::shared_ptr<const rt::World>& world, const rt::Scene& scene, const Options& opt,
           bool floats, Rendered& out) {
    rt::RenderSettings settings = render_settings(opt, scene.width, scene.height);
    settings.bytes_only = !floats;  // the picture is written once, as bytes

    rt::Renderer renderer(rt::process_pool());
    ProgressBar bar(!opt.quiet && isatty(STDERR_FILENO));
    renderer.start(world, settings);
    // SIGINT and SIGTERM end the process from the signal handler, in this phase too.
    while (!renderer.wait_for(0.1)) {
        rt::RenderProgress p = renderer.progress();
        double fraction = rt::progress_fraction(p, settings.max_samples);
        if (opt.render.time_limit > 0) fraction = std::max(fraction, p.elapsed / opt.render.time_limit);
        bar.update(fraction, p.elapsed);
    }
    bar.clear();
    out.progress = renderer.progress();
    out.threads = renderer.threads();
    // A render thread that ran out of memory ended the render: nothing is written.
    if (!out.progress.error.empty()) return failure(kProgram, out.progress.error, kExitUsage);
    if (floats) {
        out.film = renderer.snapshot();
        out.width = out.film.width, out.height = out.film.height;
    } else {
        renderer.take_rgb8(out.pixels, out.width, out.height);  // written once: no copy of the film
    }
    if (out.width != scene.width || out.height != scene.height || out.progress.samples < 1)
        return failure(kProgram,
                       "internal error: the renderer returned a " + std::to_string(out.width) + "x" +
                           std::to_string(out.height) + " picture with " + std::to_string(out.progress.samples) +
                           " samples per pixel",
                       kExitUsage);
    return {};
}

// Phase 5: writes OUT.
rt::Status write_picture(const std::string& out_path, const Rendered& r) {
    const rt::Status st = r.film.rgb.empty() ? rt::write_rgb8(out_path, r.width, r.height, r.pixels.data(), r.pixels.size())
                                             : rt::write_image(out_path, r.film);
    if (!st) {
        if (caught_signal()) return interrupted();  // the temporary file is gone
        return failure(kProgram, "cannot write '" + rt::escape_text(out_path) + "': " + st.message(), kExitUsage);
    }
    if (const int sig = caught_signal()) {
        // Too late to stop: the complete new picture is already in place.
        return failure(kProgram,
                       std::string("interrupted (") + (sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP") +
                           ") just after the picture was written",
                       128 + sig);
    }
    return {};
}

// Seconds each phase took, for --stats.
struct Times {
    double parse = 0, compile = 0, render = 0, write = 0, total = 0;
};

void print_stats(const std::string& scene_path, const rt::Scene& scene, const Rendered& r, const Times& t) {
    char line[256];
    std::cerr << scene_path << ": " << scene.width << "x" << scene.height << ", ";
    if (r.progress.refining >= 0) {
        // Adaptive: how the samples went.
        const double pixels = double(scene.width) * scene.height;
        std::snprintf(line, sizeof line, "%.3f samples per pixel on average (adaptive, %lld not settled)",
                      double(r.progress.film_samples) / pixels, static_cast<long long>(r.progress.refining));
        std::cerr << line;
    } else {
        std::cerr << r.progress.samples << (r.progress.samples == 1 ? " sample" : " samples") << " per pixel";
    }
    std::snprintf(line, sizeof line, "time: parse %.3f s, compile %.3f s, render %.3f s, write %.3f s, total %.3f s\n",
                  t.parse, t.compile, t.render, t.write, t.total);
    std::cerr << ", " << r.threads << (r.threads == 1 ? " thread" : " threads") << "\n"
              << line << "rays: " << with_commas(r.progress.rays);
    std::snprintf(line, sizeof line, " (%.2f M rays/s)\n", t.render > 0 ? r.progress.rays / t.render / 1e6 : 0.0);
    std::cerr << line;
}

rt::Status run(int argc, char** argv) {
    Options opt;
    if (rt::Status st = parse_args(kProgram, argc, argv, opt); !st) return st;
    if (print_help_or_version(kProgram, opt)) return {};
    if (opt.check) return check_scene(kProgram, opt);
    std::string scene_path, out_path;
    if (rt::Status st = settle_paths(opt, scene_path, out_path); !st) return st;

    // Installed only now: at a prompt, Ctrl+C should just end the program. Before the
    // output check, which creates (and removes) a temporary file.
    install_signal_handlers(kProgram);
    // The pool the reading, the build, the render and the writing share (its threads
    // started after the handlers, so that they block the signals too).
    rt::set_process_threads(opt.render.threads);
    if (!opt.print_scene) {
        if (rt::Status st = check_output(kProgram, out_path, scene_path); !st) return st;
        if (caught_signal()) return interrupted();  // came during the check
    }

    // Phase 2: read and parse.
    Times times;
    const auto t_start = Clock::now();
    rt::Scene scene;
    if (rt::Status st = load_scene(kProgram, scene_path, scene); !st) return st;
    if (opt.width) scene.width = *opt.width;
    if (opt.height) scene.height = *opt.height;
    times.parse = seconds_since(t_start);
    if (opt.print_scene) return print_scene(kProgram, std::move(scene), opt.flatten);

    const auto t_compile0 = Clock::now();
    const std::shared_ptr<const rt::World> world = build_world(scene, opt.render.max_depth);
    times.compile = seconds_since(t_compile0);

    const auto t_render0 = Clock::now();
    Rendered rendered;
    if (rt::Status st = render(world, scene, opt, rt::is_float_format(rt::format_from_path(out_path)), rendered); !st)
        return st;
    times.render = seconds_since(t_render0);

    const auto t_write0 = Clock::now();
    if (rt::Status st = write_picture(out_path, rendered); !st) return st;
    times.write = seconds_since(t_write0);

    if (opt.stats) {
        times.total = seconds_since(t_start);
        print_stats(scene_path, scene, rendered, times);
    }
    // The process ends here and its memory goes back whole: a million-object scene and
    // its world need not be taken apart object by object first.
    g_kept_scene = new rt::Scene(std::move(scene));
    g_kept_world = new std::shared_ptr<const rt::World>(world);
    return {};
}

}  // namespace

// A big scene's phases each allocate and free hundreds of MB (the file's text, the
// parser's pieces, the build's scratch). Kept in one heap and never handed back,
// each freed block serves the next phase: fresh pages from the system would cost a
// first-touch fault each, more than the writing that fills them. Threads share the
// heap (their scratch is as big as the main thread's); the process's peak grows by
// only what is freed and not reused.
static void keep_freed_memory() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
    mallopt(M_ARENA_MAX, 1);
#endif
}

int main(int argc, char** argv) {
    keep_freed_memory();
    // Cancelling and reporting is all we do on an exception; the output stays untouched.
    try {
        return report(run(argc, argv));
    } catch (const std::bad_alloc&) {
        std::cerr << "raytracer: out of memory\n";
    } catch (const std::exception& e) {
        std::cerr << "raytracer: " << e.what() << "\n";
    }
    return kExitUsage;
}
