// Tests for how much work a picture can cost and how it is stopped (core/world.h,
// core/renderer.h): a trace stops within RayStats::kPollRays rays of a stop flag or a
// deadline at any depth; the renderer's cancel() and time limit act in the middle of
// a pixel's ray tree; the ray tree's bound changes no pixel by half a display step and
// makes a deep glass-and-mirror scene cheap; lamps' glow discs cost log(lamps) per ray.
// Nothing here depends on how fast the machine is at the moment: the traces' own
// checks are counted in polls and rays (on an injected clock), a render that must stop
// is one that could never finish by itself, and costs are CPU time.
#include <doctest/doctest.h>
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <thread>

#include "renderer.h"
#include "scene_parser.h"
#include "mirror_box.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::endless_world;
using rt_test::mirror_box;
using rt_test::parse_ok;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double cpu_seconds(const rusage& r) {
    return double(r.ru_utime.tv_sec + r.ru_stime.tv_sec) + double(r.ru_utime.tv_usec + r.ru_stime.tv_usec) * 1e-6;
}

// CPU seconds used by this process's threads other than the calling one (the
// renderer's workers): it only grows while they work, however loaded the machine.
double workers_cpu_seconds() {
    rusage all{}, self{};
    getrusage(RUSAGE_SELF, &all);
    getrusage(RUSAGE_THREAD, &self);
    return cpu_seconds(all) - cpu_seconds(self);
}

// TraceStop::now for one trace on this thread: one millisecond from the epoch per read,
// that is per poll (every RayStats::kPollRays rays). At read `flag_at` it raises
// `flag` and notes the rays traced so far.
struct PollClock {
    static inline int reads = 0;
    static inline int flag_at = 0;
    static inline std::atomic<bool>* flag = nullptr;
    static inline const RayStats* stats = nullptr;
    static inline std::uint64_t rays_at_flag = 0;
    static void use(RayStats& st, std::atomic<bool>& f, int raise_at) {
        reads = 0, flag_at = raise_at, flag = &f, stats = &st, rays_at_flag = 0;
        st.stop.flag = &f;
        st.stop.now = now;
    }
    static Clock::time_point now() {
        if (++reads == flag_at) {
            flag->store(true);
            rays_at_flag = stats->rays;
        }
        return at(reads);
    }
    static Clock::time_point at(int read) { return Clock::time_point{} + std::chrono::milliseconds(read); }
};

// The ball of the finite trees: glass that both reflects and refracts.
const char* kGlass = "reflection 0.3 refraction 0.6 scattering 0.1";

Vec3 centre_ray(const World& w) { return normalize(w.camera.centre - w.camera.position); }

// Traces the endless world's centre ray on the injected clock, its stop flag raised at
// the poll numbered flag_at and its deadline at the poll numbered deadline_at, under a
// watchdog (a trace that never stops fails the test).
void trace_endless(const World& world, RayStats& stats, std::atomic<bool>& stop, int flag_at, int deadline_at) {
    PollClock::use(stats, stop, flag_at);
    stats.stop.deadline = PollClock::at(deadline_at);
    rt_test::Watchdog dog("a trace without end did not stop");
    world.trace(world.camera.position, centre_ray(world), 0, stats);
}

}  // namespace

TEST_CASE("ray tree: a trace of any depth stops within kPollRays rays of its stop flag") {
    auto world = endless_world();
    std::atomic<bool> stop{false};
    RayStats stats;
    // The flag goes up at the 100th poll, 400,000 rays into the tree; the deadline,
    // at the 1,000th, would end the trace if the flag did not.
    trace_endless(*world, stats, stop, 100, 1000);
    CHECK(stats.stopped);
    CHECK(PollClock::reads == 100);  // the next poll saw the flag (and read no clock)
    CAPTURE(stats.rays);
    CAPTURE(PollClock::rays_at_flag);
    CHECK(PollClock::rays_at_flag > 99 * RayStats::kPollRays);
    CHECK(stats.rays - PollClock::rays_at_flag <= RayStats::kPollRays);
    // A stopped RayStats ends every later trace at once.
    std::uint64_t rays = stats.rays;
    world->trace(world->camera.position, centre_ray(*world), 0, stats);
    CHECK(stats.rays == rays);
}

TEST_CASE("ray tree: a trace stops at the first poll at or past its deadline") {
    auto world = endless_world();
    std::atomic<bool> stop{false};
    RayStats stats;
    // The clock reads 1 ms at the first poll, 300 ms at the 300th: the deadline. The
    // flag, at the 1,000th read, ends the trace if a wrong comparison lets the deadline
    // pass; a deadline never looked at leaves it to the watchdog.
    trace_endless(*world, stats, stop, 1000, 300);
    CHECK(stats.stopped);
    CHECK(PollClock::reads == 300);
    CAPTURE(stats.rays);
    CHECK(stats.rays > 299 * RayStats::kPollRays);
    CHECK(stats.rays <= 300 * RayStats::kPollRays);

    // On the real clock (no injected one), a deadline already past stops the trace at
    // its first poll, the first ray.
    RayStats real;
    real.stop.deadline = Clock::now();
    {
        rt_test::Watchdog dog("a trace without end did not stop at its deadline");
        world->trace(world->camera.position, centre_ray(*world), 0, real);
    }
    CHECK(real.stopped);
    CHECK(real.rays == 1);
}

TEST_CASE("renderer: cancel() in the middle of one pixel's ray tree returns") {
    auto world = endless_world();
    for (int threads : {1, 2}) {
        CAPTURE(threads);
        rt::ThreadPool r_pool(threads + 1);
        Renderer r(r_pool);
        RenderSettings s;
        const double cpu0 = workers_cpu_seconds();
        r.start(world, s);
        // Setting up takes microseconds and no pixel ever finishes: workers that have
        // used 50 ms of CPU are inside a ray tree.
        while (workers_cpu_seconds() - cpu0 < 0.05) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        CHECK_FALSE(r.progress().done);
        {
            rt_test::Watchdog dog("Renderer::cancel() did not stop a ray tree without end");
            r.cancel();
        }
        CHECK_FALSE(r.progress().running);
        CHECK_FALSE(r.progress().done);
    }
}

// A first pass of one cheap sample per pixel, then passes of 4096 samples that take
// far longer than the limit (a 128x96 picture: 50 million camera rays a pass, many
// seconds even on a fast idle machine): a limit checked only between passes would
// finish the second pass (4097 samples), one not checked at all would not end.
TEST_CASE("renderer: the time limit stops a render in the middle of a pass; every pixel has a sample") {
    const char* text = R"(
thing {
  sphere { material { reflection 0.2 refraction 0.7 scattering 0.1 translusans 0.9 refractive_index 1.5 colour 1 1 1 } position 5 0 1 radius 1 }
  sphere { material { reflection 0.5 scattering 0.5 colour 0.9 0.3 0.2 } position 8 1.5 1 radius 1 }
}
special_thing { plane { material { reflection 0.3 scattering 0.7 colour 0.6 0.7 0.9 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { colour 60 60 60 position 3 3 5 size 0.3 } }
camera { position 0 0 1.5 centre 5 0 1 up 5 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 128 y_max 96 }
end
)";
    auto world = compile_world(parse_ok(text));
    for (double limit : {0.3, 1.0}) {
        CAPTURE(limit);
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        RenderSettings s;
        s.max_samples = 65536;
        s.samples_per_pass = 4096;
        s.time_limit = limit;
        s.coarse = false;
        auto t0 = Clock::now();
        r.start(world, s);
        // (Bounds a render that would not end; a working one ends at the limit.)
        bool done = r.wait_for(limit + 120);
        double took = seconds_since(t0);
        REQUIRE(done);
        CAPTURE(took);
        CHECK(took >= limit);
        RenderProgress p = r.progress();
        CHECK(p.done);
        CHECK(p.samples == 1);  // the first pass is complete, the second is not
        CHECK(p.elapsed >= limit);
        // Every pixel has its first sample: the same as a one-sample render.
        Image got = r.snapshot();
        RenderSettings one;
        one.coarse = false;
        rt::ThreadPool ref_pool(2);
        Renderer ref(ref_pool);
        ref.start(world, one);
        ref.wait();
        Image want = ref.snapshot();
        REQUIRE(got.rgb.size() == want.rgb.size());
        int lit = 0, far = 0;
        for (std::size_t i = 0; i < got.rgb.size(); ++i) {
            lit += got.rgb[i] > 0;
            // Pixels that got more samples are averages close to the first sample; no pixel is empty.
            far += want.rgb[i] > 0.05f && !(got.rgb[i] > 0);
        }
        CHECK(far == 0);
        CHECK(lit > int(got.rgb.size()) / 2);
    }
}

TEST_CASE("renderer: a time limit over the coarse previews goes on to the first sample and stops there") {
    // A pixel costs about a thousand rays, so the first preview (4 x 4 blocks) takes
    // longer than the limit.
    auto world = std::make_shared<World>(*compile_world(parse_ok(mirror_box(0.9, 0.1, kGlass))));
    world->options.max_depth = 1000;
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings s;
    s.width = 8;
    s.height = 6;
    s.max_samples = 65536;
    s.time_limit = 1e-4;
    r.start(world, s);
    REQUIRE(r.wait_for(60));
    RenderProgress p = r.progress();
    CHECK(p.done);
    CHECK(p.samples == 1);
    CHECK(p.coarse_level == 4);  // the 2 x 2 preview was skipped
}

TEST_CASE("renderer: a hard time limit stops even the first sample") {
    auto world = endless_world();  // no pixel ever finishes: done means stopped by the limit
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings s;
    s.time_limit = 0.3;
    s.hard_time_limit = true;
    auto t0 = Clock::now();
    r.start(world, s);
    REQUIRE(r.wait_for(120));  // (bounds a render that would not end)
    double took = seconds_since(t0);
    CAPTURE(took);
    CHECK(took >= 0.3);
    RenderProgress p = r.progress();
    CHECK(p.done);
    CHECK(p.samples == 0);
}

TEST_CASE("ray tree: the bound changes no pixel by half a display step and cuts the work") {
    // The tree doubles at every glass surface and shrinks by 0.8 at every mirror. At
    // depth 160 it is still small enough to trace in full, which is the reference.
    const int w = 4, h = 3;
    auto bounded = std::make_shared<World>(*compile_world(parse_ok(mirror_box(0.8, 0.2, kGlass, w, h))));
    bounded->options.max_depth = 160;
    REQUIRE(bounded->omit_weight > 0);
    REQUIRE(std::isfinite(bounded->radiance_bound));
    auto full = std::make_shared<World>(*bounded);
    full->omit_weight = 0;
    CameraBasis cam = CameraBasis::make(bounded->camera, w, h, false);
    RayStats bounded_stats, full_stats;
    double worst = 0, brightest = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Colour a = bounded->trace_camera(cam, x, y, bounded_stats);
            Colour b = full->trace_camera(cam, x, y, full_stats);
            for (int k = 0; k < 3; ++k) {
                worst = std::max(worst, std::fabs(a[k] - b[k]));
                brightest = std::max(brightest, b[k]);
            }
        }
    CAPTURE(worst);
    CAPTURE(bounded_stats.rays);
    CAPTURE(full_stats.rays);
    CHECK(brightest > 0.2);  // a picture, not black
    CHECK(worst < 0.5 / 255);
    CHECK(bounded_stats.rays * 2 < full_stats.rays);
    // The bound holds: no pixel is brighter than it.
    CHECK(brightest <= bounded->radiance_bound);
}

TEST_CASE("ray tree: a glass ball among mirrors at depth 1000 finishes quickly") {
    auto world = std::make_shared<World>(*compile_world(parse_ok(mirror_box(0.8, 0.2, kGlass))));
    world->options.max_depth = 1000;
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings s;
    s.coarse = false;
    auto t0 = Clock::now();
    r.start(world, s);
    REQUIRE(r.wait_for(30));
    RenderProgress p = r.progress();
    CAPTURE(seconds_since(t0));
    CAPTURE(p.rays);
    CHECK(p.samples == 1);
    // About 1,500 rays per pixel: the tree stops where its weight does.
    CHECK(p.rays < 16 * 12 * 5000);
    // Without the bound the same picture is far from done after a second.
    auto unbounded = std::make_shared<World>(*world);
    unbounded->omit_weight = 0;
    RayStats stats;
    stats.stop.deadline = Clock::now() + std::chrono::seconds(1);
    CameraBasis cam = CameraBasis::make(world->camera, 16, 12, false);
    for (int y = 0; y < 12 && !stats.stopped; ++y)
        for (int x = 0; x < 16 && !stats.stopped; ++x) unbounded->trace_camera(cam, x, y, stats);
    CHECK(stats.stopped);
}

TEST_CASE("ray tree: no bound where a colour could grow along a ray; an unlit world is black at once") {
    const char* lit = R"(
thing { sphere { material { reflection 0.5 scattering 0.5 colour 1 1 1 } position 5 0 0 radius 1 } }
light { spotlight { colour 10 10 10 position 0 0 3 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }
picture_size { x_max 8 y_max 6 }
end
)";
    Scene scene = parse_ok(lit);
    auto w = compile_world(scene);
    // One light at (0, 0, 3): 10 / r^2 with r at least its distance to the sphere's
    // box [4, 6] x [-1, 1] x [-1, 1], sqrt(4^2 + 2^2).
    CHECK(w->radiance_bound == doctest::Approx(10.0 / 20).epsilon(0.001));
    CHECK(w->radiance_bound >= 10.0 / 20);
    CHECK(w->omit_weight == doctest::Approx(0.5 / 255 / w->radiance_bound));
    // A tint above 1 in a refractive material: light may come out brighter than it went in.
    Scene bright = scene;
    bright.objects[0].material.refraction = 0.5;
    bright.objects[0].material.translusans = 1;
    bright.objects[0].material.colour = {1.5, 1, 1};
    CHECK(compile_world(bright)->omit_weight == 0);
    // A negative weight makes another above 1 after normalising.
    Scene negative = scene;
    negative.objects[0].material.scattering = -0.25;
    CHECK(compile_world(negative)->omit_weight == 0);
    // A light inside an object's box: no bound on 1/r^2.
    Scene inside = scene;
    inside.lights[0].position = {5, 0, 0.5};
    CHECK(compile_world(inside)->omit_weight == 0);
    // Nothing can be lit: every ray is black, and none is followed.
    Scene dark = scene;
    dark.lights.clear();
    auto wd = compile_world(dark);
    RayStats stats;
    CHECK(wd->trace_camera(CameraBasis::make(wd->camera, 8, 6, false), 4, 3, stats) == Colour{});
    CHECK(stats.rays == 0);
}

namespace {
// n lamps scattered over a room with a glass ball, a mirror ball and a chess floor.
std::string lamp_room(int n) {
    std::string lamps;
    std::uint32_t h = 12345;
    auto next = [&] {
        h = h * 1664525u + 1013904223u;
        return (h >> 8) / double(1 << 24);
    };
    for (int i = 0; i < n; ++i) {
        double x = 2 + 18 * next(), y = -8 + 16 * next(), z = 0.5 + 5.5 * next();
        lamps += "  lamp { colour 0.5 0.4 0.3 position " + std::to_string(x) + " " + std::to_string(y) + " " +
                 std::to_string(z) + " size 0.05 }\n";
    }
    // Lamps in a row along the camera's line of sight: their discs hide each other.
    for (int i = 0; i < 4; ++i) lamps += "  lamp { colour 2 2 2 position " + std::to_string(4 + i) + " 0 1 size 0.2 }\n";
    return R"(
thing {
  sphere { material { reflection 0.3 scattering 0.7 colour 0.8 0.8 0.8 } position 8 0 1 radius 1 }
  sphere { material { reflection 0.1 refraction 0.8 scattering 0.1 translusans 0.9 refractive_index 1.5 colour 1 1 1 } position 6 2 1 radius 0.8 }
}
special_thing {
  chess_plane { material 1 { colour 0.9 0.9 0.9 } material 2 { colour 0.2 0.2 0.2 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 }
}
light {
)" + lamps + R"(}
camera { position -2 0 1 centre 8 0 1 up 8 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 24 y_max 18 }
end
)";
}

// The lamp room's world, and a copy that tests every glow disc one by one (no BVH).
struct GlowWorlds {
    std::shared_ptr<const World> world, looped;
    explicit GlowWorlds(int lamps) {
        auto w = compile_world(parse_ok(lamp_room(lamps)));
        REQUIRE(w->glow_bvh.get() != nullptr);
        auto l = std::make_shared<World>(*w);
        l->glow_bvh.reset();
        world = w;
        looped = l;
    }
};

RenderSettings straight(int width, int height) {
    RenderSettings s;
    s.coarse = false;
    s.width = width;
    s.height = height;
    return s;
}
}  // namespace

TEST_CASE("ray tree: glow discs through their BVH give the same picture as one by one") {
    const auto [world, looped] = GlowWorlds(100);
    RenderSettings s = straight(16, 12);
    s.max_samples = 2;
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    r.start(world, s);
    r.wait();
    Image a = r.snapshot();
    r.start(looped, s);
    r.wait();
    Image b = r.snapshot();
    REQUIRE(a.rgb.size() == b.rgb.size());
    CHECK(a.rgb == b.rgb);
    // Glows are in view (the row of lamps ahead), and shadows of discs too: the picture
    // differs from the one with the discs removed.
    Scene no_glow = parse_ok(lamp_room(100));
    for (Light& l : no_glow.lights) l.size = 0;
    r.start(compile_world(no_glow), s);
    r.wait();
    CHECK(r.snapshot().rgb != a.rgb);
    // pick() finds the nearest of the row's discs.
    CameraBasis cam = CameraBasis::make(world->camera, 16, 12, false);
    PickResult hit = pick(*world, cam.ray(8, 6));
    CHECK(hit.light == 100);
    CHECK(pick(*looped, cam.ray(8, 6)).light == 100);
}

TEST_CASE("ray tree: the cost of lamps grows with lamps + lights, not their product") {
    // Every point is lit by every lamp (that part is lights x points), but each light's
    // shadow ray meets only the discs near it, found through the discs' BVH. Testing
    // every disc instead (the product) costs 30 times as much CPU at 5,000 lamps. CPU
    // time, of two renders on the same machine at the same moment: neither the load
    // nor a sanitizer's slowness changes their ratio much.
    const auto [world, looped] = GlowWorlds(5000);
    const RenderSettings s = straight(8, 6);
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    auto cpu_of = [&](const std::shared_ptr<const World>& w) {
        const double cpu0 = workers_cpu_seconds();
        r.start(w, s);
        r.wait();
        return workers_cpu_seconds() - cpu0;
    };
    const double bvh = cpu_of(world), every_disc = cpu_of(looped);
    CAPTURE(bvh);
    CAPTURE(every_disc);
    CHECK(bvh * 5 < every_disc);
}
