// preview_bench: the viewer's preview of a moving view without a window, as
// RenderController traces it on every frame of an orbit drag: the view's world
// (rt::with_camera_at) and rtview::trace_preview, a coarse request to an rt::Renderer on
// a pool of --threads workers (the viewer's: one per hardware thread). Prints per block size the median,
// fastest and slowest frame and the time per preview ray.
//
//   preview_bench [SCENE] [--size WxH] [--frames N] [--threads N] [--blocks B,B,...]
//   preview_bench bench/scenes/things-like.txt --size 1280x720 --blocks 4,5
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "bench_scene.h"
#include "image_io.h"
#include "pacing.h"
#include "scene_parser.h"
#include "world.h"

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }


int usage() {
    std::fprintf(stderr, "usage: preview_bench [SCENE] [--size WxH] [--frames N] [--threads N] [--blocks B,B,...]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_path = RT_SOURCE_DIR "/bench/scenes/things-like.txt";
    int width = 1280, height = 720, frames = 60;
    int threads = int(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<int> blocks{3, 4, 5, 6, 8};
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--size" && has_value) {
            if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2 || width < 1 || height < 1) return usage();
        } else if (a == "--frames" && has_value) {
            if ((frames = std::atoi(argv[++i])) < 1) return usage();
        } else if (a == "--threads" && has_value) {
            if ((threads = std::atoi(argv[++i])) < 0) return usage();
        } else if (a == "--blocks" && has_value) {
            blocks.clear();
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                long b = std::strtol(p, &end, 10);
                if (end == p || b < 1 || b > 64) return usage();
                blocks.push_back(int(b));
                p = *end == ',' ? end + 1 : end;
            }
        } else if (!a.empty() && a[0] != '-') {
            scene_path = a;
        } else {
            return usage();
        }
    }
    int exit_code = 0;
    const std::optional<rt::Scene> scene = bench::read_scene("preview_bench", scene_path, exit_code);
    if (!scene) return exit_code;
    const std::shared_ptr<const rt::World> world = rt::compile_world(*scene);
    rt::ThreadPool pool(threads + 1);  // `threads` workers (the size counts a loop's caller), as the viewer's
    rt::Renderer renderer(pool);
    std::printf("preview_bench: %s at %dx%d, %d workers, %d frames a block size\n\n",
                scene_path.c_str(), width, height, threads, frames);
    std::printf("| block | rays a frame | median ms | min ms | max ms | us a ray (median) |\n");
    std::printf("|---|---|---|---|---|---|\n");
    std::vector<std::uint8_t> rgba;
    for (int b : blocks) {
        std::vector<double> t;
        std::uint64_t rays = 0;
        for (int f = 0; f < frames; ++f) {
            const rt::Camera camera = bench::orbited(world->camera, 0.01 * (f + 1));
            const Clock::time_point t0 = Clock::now();
            const std::shared_ptr<const rt::World> seen = rt::with_camera_at(world, camera.position);
            int pw = 0, ph = 0;
            rays = rtview::trace_preview(renderer, seen, camera, width, height, b, 0, rgba, pw, ph).traced;
            t.push_back(since(t0));
        }
        std::sort(t.begin(), t.end());
        const double median = t[t.size() / 2];
        std::printf("| %d | %llu | %.2f | %.2f | %.2f | %.3f |\n", b, (unsigned long long)rays, median * 1e3,
                    t.front() * 1e3, t.back() * 1e3, median / double(std::max<std::uint64_t>(rays, 1)) * 1e6);
    }
    return 0;
}
