// Render region: the rectangle a drag selects at several zooms, region pixels equal
// to the full renderer's pixels at the same sample count, and a cancel while a worker
// is inside the region (placed there through the renderer's task hook) that waits for it.
#include <doctest/doctest.h>

#include <atomic>
#include <new>
#include <chrono>
#include <thread>
#include <vector>

#include "readout.h"
#include "parallel.h"
#include "region.h"
#include "renderer.h"
#include "scene_parser.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

const char* kScene = R"(
thing { sphere { material { colour 1 0.2 0.2 } position 10 0 1 radius 1 }
        sphere { material { reflection 0.5 scattering 0.5 } position 12 2.5 1.5 radius 1.5 } }
special_thing { chess_plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 4 -3 4 colour 30 30 30 size 0.3 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 64 y_max 48 }
end)";

bool wait_done(const RegionRenderer& rr) {
    for (int k = 0; k < 24000 && !rr.done(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return rr.done();
}

// The full renderer's picture of `scene` at `samples` samples per pixel.
rt::Image full_render(const std::shared_ptr<const rt::World>& world, int samples) {
    rt::ThreadPool full_pool(3);
    rt::Renderer full(full_pool);
    rt::RenderSettings st;
    st.max_samples = samples;
    full.start(world, st);
    full.wait();
    return full.snapshot();
}

// How many pixels of `rect` differ from the same pixels of `ref`.
int differing(const RegionPicture& pic, const PixelRect& rect, const rt::Image& ref) {
    int different = 0;
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x)
            for (int c = 0; c < 3; ++c) {
                float a = pic.image.rgb[3 * (std::size_t(y - rect.y0) * rect.width() + (x - rect.x0)) + c];
                float b = ref.rgb[3 * (std::size_t(y) * ref.width + x) + c];
                different += a != b;
            }
    return different;
}

// A glass ball in a closed box of perfect mirrors, depth 1000 and the ray tree's bound
// off: a pixel's tree doubles at every pass through the ball and never ends.
std::shared_ptr<const rt::World> endless_world(rt::Scene& scene) {
    std::string planes;
    const char* const kPlanes[6] = {"-3 0 0  point 2 -3 1 0  point 3 -3 0 1", "3 0 0  point 2 3 1 0  point 3 3 0 1",
                                    "0 -3 0  point 2 0 -3 1  point 3 1 -3 0", "0 3 0  point 2 0 3 1  point 3 1 3 0",
                                    "0 0 -3  point 2 1 0 -3  point 3 0 1 -3", "0 0 3  point 2 1 0 3  point 3 0 1 3"};
    for (const char* p : kPlanes)
        planes += std::string("  plane { material { reflection 1 scattering 0 colour 0.9 0.9 0.9 } point 1 ") + p +
                  "  point 4 0 0 0.5 }\n";
    scene = rtview_test::parse_ok(
        "thing { sphere { material { reflection 0.45 refraction 0.45 scattering 0.1 translusans 1 refractive_index 1.5 "
        "colour 1 1 1 } position 0 0 0 radius 1.2 } }\n"
        "special_thing {\n" + planes + "}\n"
        "light { spotlight { colour 20 20 20 position 1.5 2 2.2 } }\n"
        "camera { position -2.5 -2 1 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
        "picture_size { x_max 16 y_max 12 }\nend\n");
    auto world = std::make_shared<rt::World>(*rt::compile_world(scene));
    world->options.max_depth = 1000;
    world->omit_weight = 0;
    return world;
}

}  // namespace

TEST_CASE("a drag selects the pixels under both ends and everything between") {
    Rect area{0, 0, 640, 480};
    ImageView v;  // 64x48 fitted: 10 units a pixel
    ViewTransform t = v.transform(area, 64, 48);
    PixelRect r = region_from_drag(t, 64, 48, 105, 52, 299, 141);
    CHECK(r == PixelRect{10, 5, 30, 15});
    CHECK(region_from_drag(t, 64, 48, 299, 141, 105, 52) == r);  // dragged the other way
    CHECK(region_from_drag(t, 64, 48, -50, -50, 15, 15) == PixelRect{0, 0, 2, 2});
    CHECK(region_from_drag(t, 64, 48, 600, 400, 9999, 9999) == PixelRect{60, 40, 64, 48});
    // Zoomed to 1:1 about the centre: the picture spans 288..352 x 216..264.
    v.one_to_one(area, 64, 48, 1, 320, 240);
    t = v.transform(area, 64, 48);
    CHECK(region_from_drag(t, 64, 48, 290.5, 220.5, 299.5, 223.5) == PixelRect{2, 4, 12, 8});
    CHECK(region_from_drag(t, 64, 48, 0, 0, 100, 100).empty());  // all outside
}

TEST_CASE("region pixels are the full render's pixels at the same sample count") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::Image ref = full_render(world, 5);
    REQUIRE(ref.width == 64);

    rt::ThreadPool rr_pool(3);

    RegionRenderer rr(rr_pool);
    const PixelRect rect{7, 9, 41, 30};
    rr.start(world, s.camera, 64, 48, rect, 5);
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 5);
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK_FALSE(rr.snapshot(pic, version));  // nothing new since
    REQUIRE(pic.rect == rect);
    CHECK(differing(pic, rect, ref) == 0);

    // Pasted into an old picture: the region's pixels change, the rest stays.
    rt::Image old;
    old.width = 64;
    old.height = 48;
    old.rgb.assign(64 * 48 * 3, -1.f);
    paste_region(pic, old);
    CHECK(old.at(7, 9).x == ref.at(7, 9).x);
    CHECK(old.at(40, 29).y == ref.at(40, 29).y);
    CHECK(old.at(6, 9).x == -1.f);
    CHECK(old.at(41, 29).x == -1.f);
    CHECK(old.at(20, 30).x == -1.f);
}

TEST_CASE("a region raised to more samples goes on from its own: the full render's pixels at the new count") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    const rt::Image ref = full_render(world, 7);
    rt::ThreadPool rr_pool(3);
    RegionRenderer rr(rr_pool);
    const PixelRect rect{3, 4, 30, 40};
    rr.start(world, s.camera, 64, 48, rect, 2);
    REQUIRE(wait_done(rr));
    REQUIRE(rr.samples() == 2);
    CHECK(rr.raise_samples(7));
    CHECK_FALSE(rr.raise_samples(7));  // already that many
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 7);
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK(differing(pic, rect, ref) == 0);
    // Raised while it runs: the same pixels.
    rr.start(world, s.camera, 64, 48, rect, 3);
    CHECK(rr.raise_samples(7));
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 7);
    REQUIRE(rr.snapshot(pic, version));
    CHECK(differing(pic, rect, ref) == 0);
    // Under a time limit it starts again instead.
    rr.start(world, s.camera, 64, 48, rect, 2, 100);
    REQUIRE(wait_done(rr));
    CHECK_FALSE(rr.raise_samples(7));
}

TEST_CASE("a region render can be cancelled and started again") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::ThreadPool rr_pool(3);
    RegionRenderer rr(rr_pool);
    std::atomic<int> tasks{0};
    rr.renderer().task_hook = [&] { ++tasks; };
    rr.start(world, s.camera, 64, 48, {0, 0, 64, 48}, 4096);
    rt_test::wait_until([&] { return tasks.load() >= 10; }, "10 tiles taken");  // under way
    rr.cancel();
    CHECK_FALSE(rr.active());
    CHECK(rr.rect().empty());
    rr.start(world, s.camera, 64, 48, {1, 1, 3, 3}, 2);
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 2);
    // A rectangle outside the picture starts nothing.
    rr.start(world, s.camera, 64, 48, {60, 40, 70, 50}, 2);
    CHECK_FALSE(rr.active());
}

TEST_CASE("a cancel while a worker is inside the region waits for it, and commits nothing of its tile") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::ThreadPool rr_pool(2);
    RegionRenderer rr(rr_pool);  // one worker: the tiles come in a known order
    // 4 x 2 pixels (one tile) to 8 samples, in passes of samples [0, 1), [1, 2), [2, 4),
    // [4, 8): the cancel comes as the worker takes the third pass's tile.
    const PixelRect rect{20, 10, 24, 12};
    std::atomic<int> tasks{0};
    std::atomic<bool> at_cancel{false}, cancel_returned{false};
    bool returned_before_the_worker_left = false;
    rr.renderer().task_hook = [&] {
        if (++tasks != 3) return;
        at_cancel = true;
        // Until the cancel has begun: the tile is traced after it.
        while (rr.active()) std::this_thread::yield();
        returned_before_the_worker_left = cancel_returned.load();
    };
    rr.start(world, s.camera, 64, 48, rect, 8);
    rt_test::wait_until([&] { return at_cancel.load(); }, "the third pass's tile");
    rr.cancel();
    cancel_returned = true;
    CHECK(tasks.load() == 3);
    CHECK_FALSE(returned_before_the_worker_left);
    CHECK_FALSE(rr.active());
    CHECK(rr.rect().empty());
    CHECK(rr.renderer().sample_count(21, 10) == 2);  // the two passes done; none of the third

    // Started again, the region renders as if nothing had happened.
    rr.renderer().task_hook = nullptr;
    rr.start(world, s.camera, 64, 48, rect, 8);
    REQUIRE(wait_done(rr));
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK(pic.samples == 8);
    CHECK(differing(pic, rect, full_render(world, 8)) == 0);
}

TEST_CASE("a cancel stops a pixel inside a ray tree that would never end") {
    rt::Scene s;
    auto world = endless_world(s);
    rt::ThreadPool rr_pool(2);
    RegionRenderer rr(rr_pool);
    std::atomic<int> tasks{0};
    rr.renderer().task_hook = [&] { ++tasks; };
    rr.start(world, s.camera, 16, 12, {7, 5, 9, 7}, 1);
    // The worker has taken the region's one tile, whose first sample never ends by itself.
    rt_test::wait_until([&] { return tasks.load() > 0; }, "the tile taken");
    {
        rt_test::Watchdog dog("RegionRenderer::cancel() did not stop a ray tree without end");
        rr.cancel();
    }
    CHECK(tasks.load() == 1);
    CHECK_FALSE(rr.active());
    CHECK_FALSE(rr.done());
}

TEST_CASE("a region on a shared pool, beside a render on the same pool: both the full render's pixels") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    const rt::Image ref = full_render(world, 5);
    rt::ThreadPool pool(3);
    RegionRenderer rr(pool);
    rt::Renderer full(pool);
    rt::RenderSettings st;
    st.max_samples = 5;
    const PixelRect rect{3, 20, 60, 44};
    full.start(world, st);
    rr.start(world, s.camera, 64, 48, rect, 5);
    full.wait();
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 5);
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK(differing(pic, rect, ref) == 0);
    const rt::Image film = full.snapshot();
    CHECK(film.rgb == ref.rgb);
}

TEST_CASE("a region's time limit stops it in the middle of a pass, once every pixel has its first sample") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::ThreadPool rr_pool(2);
    RegionRenderer rr(rr_pool);
    const double limit = 0.02;
    using Clock = std::chrono::steady_clock;
    Clock::time_point first{};
    int tasks = 0;  // (one worker)
    rr.renderer().task_hook = [&] {
        if (++tasks == 1) first = Clock::now();  // after start() set the deadline
        // The second pass's tile begins once the limit has passed: its trace must stop
        // there, and the pass with it.
        if (tasks == 2)
            while (Clock::now() < first + std::chrono::duration<double>(limit)) std::this_thread::yield();
    };
    rr.start(world, s.camera, 64, 48, {20, 10, 24, 12}, 4, limit);
    REQUIRE(wait_done(rr));
    CHECK(rr.error().empty());
    CHECK(rr.samples() == 1);
    CHECK(tasks == 2);
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK(pic.row_samples == std::vector<int>{1, 1});  // the stopped pass leaves the first sample
}

TEST_CASE("the readout names what a pixel's ray hit as the outline does") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    // The picture's centre looks straight at sphere 1 (at x 9 from a camera at x 0).
    rt::PickResult hit = pick_pixel(*world, s.camera, 64, 48, 32, 24);
    REQUIRE(hit.hit);
    CHECK(outline_name(s, hit) == "object 1 (sphere)");
    CHECK(hit.t == doctest::Approx(9).epsilon(0.01));
    rt::PickResult floor = pick_pixel(*world, s.camera, 64, 48, 32, 47);
    CHECK(outline_name(s, floor) == "plane 1 (chess_plane)");
    rt::PickResult sky = pick_pixel(*world, s.camera, 64, 48, 2, 0);
    CHECK_FALSE(sky.hit);
    CHECK(outline_name(s, sky).empty());

    PixelReadout r;
    r.x = 32;
    r.y = 24;
    r.has_colour = true;
    r.linear = {0.5, 0.25, 1.75};
    r.samples = 64;
    r.hit = hit;
    r.hit_name = outline_name(s, hit);
    std::string line = format_readout(r);
    CHECK(line.find("x 32 y 24") != std::string::npos);
    CHECK(line.find("RGB 0.500 0.250 1.750") != std::string::npos);
    CHECK(line.find("64 spp") != std::string::npos);
    CHECK(line.find("object 1 (sphere) at 9") != std::string::npos);
}

TEST_CASE("a region worker that runs out of memory stops the region with a message, not the program") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::ThreadPool rr_pool(3);
    RegionRenderer rr(rr_pool);
    std::atomic<int> tasks{0};
    rr.renderer().task_hook = [&] {
        if (++tasks == 2) throw std::bad_alloc();  // the second pass's tile
    };
    rr.start(world, s.camera, 64, 48, {20, 10, 24, 12}, 8);
    REQUIRE(wait_done(rr));
    CHECK(rr.error() == "out of memory while rendering");
    CHECK(rr.samples() == 1);
    rr.cancel();
    // Started again without the failure: no message, every sample.
    rr.renderer().task_hook = nullptr;
    rr.start(world, s.camera, 64, 48, {20, 10, 24, 12}, 8);
    REQUIRE(wait_done(rr));
    CHECK(rr.error().empty());
    CHECK(rr.samples() == 8);
}
