// aa_bench: what adaptive anti-aliasing saves the viewer. Renders a scene as the
// viewer's renderer does (coarse previews, then progressive passes up to --samples)
// once uniformly and once adaptively for each threshold, and prints the time until
// each is done (adaptive: every pixel settled), the samples spent and how far each
// adaptive picture is from the uniform one (RMSE in 8-bit units).
//
//   aa_bench [SCENE] [--size WxH] [--samples N] [--threads N] [--repeats N] [--threshold T]...
//
// Defaults: scenes/default.txt at 1280x800, 64 samples, all threads, 3 repeats (the
// median is printed), thresholds 0.05 and 0.02 (the viewer's).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "adaptive.h"
#include "diagnostic_text.h"
#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "world.h"

namespace {

struct Run {
    double seconds = 0;
    double mean_samples = 0;
    std::vector<std::uint8_t> picture;
};

Run render(rt::Renderer& r, const std::shared_ptr<const rt::World>& world, const rt::RenderSettings& s) {
    const auto t0 = std::chrono::steady_clock::now();
    r.start(world, s);
    r.wait();
    Run run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const rt::RenderProgress p = r.progress();
    run.mean_samples = double(p.film_samples) / (double(p.width) * p.height);
    run.picture = rt::to_rgb8(r.snapshot());
    return run;
}

double rmse(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    double sq = 0;
    for (std::size_t i = 0; i < a.size(); ++i) sq += double(int(a[i]) - int(b[i])) * (int(a[i]) - int(b[i]));
    return std::sqrt(sq / double(a.size()));
}

// The median run of `repeats` (by time).
Run median_run(rt::Renderer& r, const std::shared_ptr<const rt::World>& world, const rt::RenderSettings& s,
               int repeats) {
    std::vector<Run> runs;
    for (int i = 0; i < repeats; ++i) runs.push_back(render(r, world, s));
    std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.seconds < b.seconds; });
    return runs[runs.size() / 2];
}

struct Args {
    std::string scene = std::string(RT_SOURCE_DIR) + "/scenes/default.txt";
    int width = 1280, height = 800, samples = 64, threads = 0, repeats = 3;
    std::vector<double> thresholds;
};

bool parse(int argc, char** argv, Args& a) {
    for (int i = 1; i < argc; ++i) {
        const std::string o = argv[i];
        const bool more = i + 1 < argc;
        if (o == "--size" && more) {
            if (std::sscanf(argv[++i], "%dx%d", &a.width, &a.height) != 2) return false;
        } else if (o == "--samples" && more) {
            a.samples = std::atoi(argv[++i]);
        } else if (o == "--threads" && more) {
            a.threads = std::atoi(argv[++i]);
        } else if (o == "--repeats" && more) {
            a.repeats = std::max(1, std::atoi(argv[++i]));
        } else if (o == "--threshold" && more) {
            a.thresholds.push_back(std::atof(argv[++i]));
        } else if (o[0] != '-') {
            a.scene = o;
        } else {
            return false;
        }
    }
    if (a.thresholds.empty()) a.thresholds = {0.05, 0.02};
    return a.width > 0 && a.height > 0 && a.samples > 0;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    if (!parse(argc, argv, a)) {
        std::fprintf(stderr, "usage: aa_bench [SCENE] [--size WxH] [--samples N] [--threads N] [--repeats N] "
                             "[--threshold T]...\n");
        return 2;
    }
    std::string text;
    if (!rt::read_file(a.scene, text, rt::Limits::max_file_size).ok()) {
        std::fprintf(stderr, "aa_bench: cannot read %s\n", a.scene.c_str());
        return 2;
    }
    rt::set_process_threads(a.threads);  // the one pool, sized before its first use
    rt::ParseResult parsed = rt::parse_scene(text);
    if (!parsed.ok()) {
        std::fprintf(stderr, "aa_bench: %s has errors\n", a.scene.c_str());
        return 1;
    }
    const auto world = rt::compile_world(parsed.scene);
    rt::Renderer renderer(rt::process_pool());
    rt::RenderSettings s;  // the viewer's: coarse previews, progressive passes
    s.width = a.width;
    s.height = a.height;
    s.max_samples = a.samples;
    std::printf("aa_bench: %s at %dx%d, at most %d samples, %d threads, median of %d\n\n", a.scene.c_str(), a.width,
                a.height, a.samples, renderer.threads(), a.repeats);
    std::printf("| render | time to done (s) | / uniform | samples per pixel | RMSE against uniform |\n");
    std::printf("|---|---|---|---|---|\n");
    const Run uniform = median_run(renderer, world, s, a.repeats);
    std::printf("| uniform %d samples | %.3f | 1.00 | %.2f | 0 |\n", a.samples, uniform.seconds, uniform.mean_samples);
    for (double t : a.thresholds) {
        s.aa_threshold = t;
        const Run run = median_run(renderer, world, s, a.repeats);
        std::printf("| adaptive, threshold %.3g | %.3f | %.2f | %.2f | %.3f |\n", t, run.seconds,
                    run.seconds / uniform.seconds, run.mean_samples, rmse(run.picture, uniform.picture));
    }
    return 0;
}
