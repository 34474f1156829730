// renderer_bench: micro-benchmarks of what the viewer feels rather than of throughput:
// how soon a coarse preview appears after a camera change, how fast cancel() returns
// mid-pass, and what the BVH costs to build and hold for 100,000 spheres.
//
//   renderer_bench [WIDTH HEIGHT] [--scene FILE] [--repeats N] [--threads N] [--spheres N]
#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bench_scene.h"
#include "image_io.h"
#include "renderer.h"
#include "shapes.h"
#include "scene_parser.h"
#include "world.h"

// Live heap bytes, counted by replacing the global allocation functions. Unlike
// mallinfo2() this sees allocations made on any thread (a parallel BVH build).
// malloc_usable_size on both sides keeps the books balanced without a size header.
static std::atomic<long long> g_live_bytes{0};

static void* counted_alloc(std::size_t n, std::size_t align) {
    if (n == 0) n = 1;  // a distinct pointer even for zero bytes
    void* p = align > alignof(std::max_align_t) ? std::aligned_alloc(align, (n + align - 1) / align * align)
                                                : std::malloc(n);
    if (!p) throw std::bad_alloc();
    g_live_bytes += (long long)malloc_usable_size(p);
    return p;
}
static void counted_free(void* p) noexcept {
    if (!p) return;
    g_live_bytes -= (long long)malloc_usable_size(p);
    std::free(p);
}
void* operator new(std::size_t n) { return counted_alloc(n, 0); }
void* operator new[](std::size_t n) { return counted_alloc(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) { return counted_alloc(n, std::size_t(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted_alloc(n, std::size_t(a)); }
// The nothrow forms too: sanitizers replace every form, so a missing one pairs their
// allocation with our free.
static void* counted_alloc_nothrow(std::size_t n, std::size_t align) noexcept {
    try {
        return counted_alloc(n, align);
    } catch (...) {
        return nullptr;
    }
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc_nothrow(n, 0); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc_nothrow(n, 0); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
    return counted_alloc_nothrow(n, std::size_t(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
    return counted_alloc_nothrow(n, std::size_t(a));
}
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { counted_free(p); }

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Summary {
    double median = 0, min = 0, max = 0;
};
Summary summarise(std::vector<double> v) {
    Summary s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.min = v.front();
    s.max = v.back();
    s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    return s;
}

void row(const char* what, const std::vector<double>& seconds) {
    Summary s = summarise(seconds);
    std::printf("| %-52s | %9.2f | %9.2f | %9.2f |\n", what, s.median * 1e3, s.min * 1e3, s.max * 1e3);
}


rt::Scene random_spheres(int n) {
    rt::Scene s;
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> pos(-50, 50), rad(0.05, 0.6), col(0, 1);
    s.objects.reserve(std::size_t(n));
    for (int i = 0; i < n; ++i) {
        // (Made in place: a local Object moved in makes GCC 12 warn falsely.)
        rt::Object& o = s.objects.emplace_back();
        o.shape.emplace<rt::Sphere>(rt::Sphere{{pos(rng), pos(rng), pos(rng)}, rad(rng)});
        o.material.colour = {col(rng), col(rng), col(rng)};
        o.has_material = true;
    }
    rt::Light l;
    l.position = {0, 0, 80};
    l.colour = {5000, 5000, 5000};
    s.lights.push_back(l);
    s.camera.position = {-120, 0, 0};
    s.camera.centre = {0, 0, 0};
    s.camera.up = {0, 0, 1};
    s.width = 640;
    s.height = 480;
    return s;
}

int usage() {
    std::fprintf(stderr,
                 "usage: renderer_bench [WIDTH HEIGHT] [--scene FILE] [--repeats N] [--threads N] [--spheres N]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene_path = RT_SOURCE_DIR "/bench/scenes/things-like.txt";
    int width = 1280, height = 720, repeats = 20, threads = 0, spheres = 100000;
    std::vector<int> sizes;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&](int& out) {
            if (i + 1 >= argc) return false;
            out = std::atoi(argv[++i]);
            return out > 0 || (a == "--threads" && out == 0);
        };
        if (a == "--scene" && i + 1 < argc) scene_path = argv[++i];
        else if (a == "--repeats") { if (!value(repeats)) return usage(); }
        else if (a == "--threads") { if (!value(threads)) return usage(); }
        else if (a == "--spheres") { if (!value(spheres)) return usage(); }
        else if (!a.empty() && a[0] != '-' && std::atoi(a.c_str()) > 0) sizes.push_back(std::atoi(a.c_str()));
        else return usage();
    }
    if (sizes.size() == 2) {
        width = sizes[0];
        height = sizes[1];
    } else if (!sizes.empty()) {
        return usage();
    }

    rt::set_process_threads(threads);  // the one pool, sized before its first use
    int exit_code = 0;
    std::optional<rt::Scene> read = bench::read_scene("renderer_bench", scene_path, exit_code);
    if (!read) return exit_code;
    rt::Scene scene = std::move(*read);

    rt::Renderer renderer(rt::process_pool());
    std::printf("renderer_bench: %s at %dx%d, %d threads, %d repeats\n\n", scene_path.c_str(), width, height,
                renderer.threads(), repeats);
    std::printf("| %-52s | %9s | %9s | %9s |\n", "measurement (ms)", "median", "min", "max");
    std::printf("|%s|%s|%s|%s|\n", std::string(54, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str(), std::string(11, '-').c_str());

    // (a) Camera change -> first coarse preview. Each repeat moves the camera, compiles
    // a new World reusing the BVH (as the viewer does) and starts a coarse render.
    std::vector<double> compile_s, first_coarse_reported, first_coarse_observed, first_full;
    std::shared_ptr<const rt::World> world = rt::compile_world(scene);
    for (int r = 0; r < repeats; ++r) {
        rt::Scene moved = scene;
        moved.camera = bench::orbited(scene.camera, 0.01 * (r + 1));
        auto t0 = Clock::now();
        world = rt::compile_world(moved, world.get());
        compile_s.push_back(since(t0));

        rt::RenderSettings st;
        st.width = width;
        st.height = height;
        st.coarse = true;
        st.max_samples = 1;
        t0 = Clock::now();
        renderer.start(world, st);
        rt::RenderProgress p;
        // Poll rather than wait: the point is when a preview could first be shown.
        for (;;) {
            p = renderer.progress();
            if (p.first_coarse_time >= 0 || p.done || !p.running) break;
            std::this_thread::sleep_for(std::chrono::microseconds(100));
        }
        first_coarse_observed.push_back(since(t0));
        if (p.first_coarse_time >= 0) first_coarse_reported.push_back(p.first_coarse_time);
        renderer.wait();
        first_full.push_back(since(t0));
    }
    row("camera change: compile_world reusing the BVH", compile_s);
    row("start() -> first coarse pass (RenderProgress)", first_coarse_reported);
    row("start() -> first coarse pass (seen by polling)", first_coarse_observed);
    row("start() -> coarse passes + 1 full sample done", first_full);

    // The same full sample without the coarse passes: what the previews cost.
    std::vector<double> full_only;
    for (int r = 0; r < repeats; ++r) {
        rt::Scene moved = scene;
        moved.camera = bench::orbited(scene.camera, 0.01 * (r + 1));
        world = rt::compile_world(moved, world.get());
        rt::RenderSettings st;
        st.width = width;
        st.height = height;
        st.coarse = false;
        st.max_samples = 1;
        auto t0 = Clock::now();
        renderer.start(world, st);
        renderer.wait();
        full_only.push_back(since(t0));
    }
    row("start() -> 1 full sample done, no coarse passes", full_only);

    // (b) cancel() in the middle of a full-resolution pass -> every worker idle.
    std::vector<double> cancel_s;
    int not_running = 0;
    for (int r = 0; r < repeats; ++r) {
        rt::RenderSettings st;
        st.width = width;
        st.height = height;
        st.coarse = false;
        st.max_samples = 1 << 16;  // far more than fits before the cancel
        renderer.start(world, st);
        // Vary the moment so the cancel lands at different points of a tile.
        std::this_thread::sleep_for(std::chrono::milliseconds(30 + 7 * (r % 7)));
        if (!renderer.progress().running) ++not_running;
        auto t0 = Clock::now();
        renderer.cancel();
        cancel_s.push_back(since(t0));
    }
    row("cancel() mid full-res pass -> all workers idle", cancel_s);
    if (not_running) std::printf("(warning: %d of %d renders were not running when cancelled)\n", not_running, repeats);

    // (c) BVH build time and memory for many random spheres.
    rt::Scene many = random_spheres(spheres);
    std::vector<double> build_s;
    long long bytes = 0;
    std::size_t material_bytes = 0, bvh_bytes = 0;
    for (int r = 0; r < 3; ++r) {
        long long before = g_live_bytes.load();
        auto t0 = Clock::now();
        auto w = rt::compile_world(many);
        build_s.push_back(since(t0));
        bytes = g_live_bytes.load() - before;
        material_bytes = w->materials.memory_bytes();
        bvh_bytes = w->geometry->bvh.memory_bytes();
    }
    char label[96];
    std::snprintf(label, sizeof label, "compile_world, %d random spheres (BVH build)", spheres);
    row(label, build_s);
    std::printf("\nWorld for %d spheres: %.1f MB on the heap, %.0f bytes per sphere\n", spheres, bytes / 1e6,
                double(bytes) / spheres);
    std::printf("  of which per-object materials %.0f bytes/sphere, geometry + BVH %.0f bytes/sphere\n",
                double(material_bytes) / spheres, double(bytes - (long long)material_bytes) / spheres);
    std::printf("  the BVH itself (nodes + item indices): %.1f bytes per sphere\n", double(bvh_bytes) / spheres);
    return 0;
}
