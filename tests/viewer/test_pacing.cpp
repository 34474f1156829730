// Preview pacing: the block size of a preview is chosen from measured costs so that
// it fits the frame budget.
#include <doctest/doctest.h>

#include "default_scene.h"
#include "film.h"
#include "mirror_box.h"
#include "pacing.h"
#include "scene_parser.h"
#include "test_util.h"

using namespace rtview;

TEST_CASE("before any measurement the usual 8x8 first pass") {
    PreviewPacer p;
    CHECK(p.coarse_block(1280, 800, 0.025) == 8);
}

TEST_CASE("the first block is the finest whose expected cost fits the budget") {
    PreviewPacer p;
    // 1000 rays in 10 ms: 10 us a ray.
    p.measured(1000, 0.010);
    CHECK(p.seconds_per_ray() == doctest::Approx(1e-5));
    // 1000x800 film, 25 ms budget = 2500 rays: 2x2 gives 200000, 4x4 50000, 8x8 12500,
    // 16x16 3125, 32x32 782 rays.
    CHECK(p.coarse_block(1000, 800, 0.025) == 32);
    // A cheap scene: 0.1 us a ray -> 250000 rays fit, so 2x2 blocks (200000).
    PreviewPacer q;
    q.measured(1e6, 0.1);
    CHECK(q.coarse_block(1000, 800, 0.025) == 2);
    // Hopelessly slow: never coarser than 64.
    PreviewPacer r;
    r.measured(1, 1.0);
    CHECK(r.coarse_block(1000, 800, 0.025) == 64);
}

TEST_CASE("faster passes are believed at once, slower ones halfway") {
    PreviewPacer p;
    p.measured(100, 0.01);  // 1e-4
    p.measured(100, 0.03);  // 3e-4: halfway -> 2e-4
    CHECK(p.seconds_per_ray() == doctest::Approx(2e-4));
    p.measured(100, 0.001);  // 1e-5: at once
    CHECK(p.seconds_per_ray() == doctest::Approx(1e-5));
    p.measured(0, 1.0);  // nonsense is ignored
    p.measured(10, -1.0);
    CHECK(p.seconds_per_ray() == doctest::Approx(1e-5));
}

TEST_CASE("a preview is the picture's block corners, traced as the camera ray through each") {
    rt::ParseResult r = rt::parse_scene(rt::kDefaultScene);
    REQUIRE(r.ok());
    // The scene as it is, and with its lights so bright that most channels clip at 255.
    for (double gain : {1.0, 100.0}) {
        CAPTURE(gain);
        rt::Scene scene = r.scene;
        for (rt::Light& l : scene.lights) l.colour = l.colour * gain;
        auto world = rt::compile_world(scene);
        const int w = 101, h = 67, b = 8;
        std::vector<std::uint8_t> rgba;
        int pw = 0, ph = 0;
        rt::ThreadPool renderer_pool(3);
        rt::Renderer renderer(renderer_pool);
        trace_preview(renderer, world, scene.camera, w, h, b, 0, rgba, pw, ph);
        CHECK(pw == 13);  // ceil(101 / 8)
        CHECK(ph == 9);   // ceil(67 / 8)
        REQUIRE(rgba.size() == std::size_t(pw * ph * 4));
        rt::CameraBasis basis = rt::CameraBasis::make(scene.camera, w, h, false);
        int distinct = 0, clipped = 0;
        for (int by = 0; by < ph; ++by)
            for (int bx = 0; bx < pw; ++bx) {
                rt::RayStats stats;
                rt::Colour c = world->trace_camera(basis, bx * b, by * b, stats);
                const std::uint8_t* p = &rgba[std::size_t(by * pw + bx) * 4];
                CHECK(int(p[0]) == int(rt::to_byte(float(c.x))));
                CHECK(int(p[1]) == int(rt::to_byte(float(c.y))));
                CHECK(int(p[2]) == int(rt::to_byte(float(c.z))));
                CHECK(p[3] == 255);
                distinct += p[0] != rgba[0] || p[1] != rgba[1] || p[2] != rgba[2];
                clipped += c.x > 1 || c.y > 1 || c.z > 1;
            }
        CHECK(distinct > 20);  // a picture, not a flat colour
        if (gain > 1) CHECK(clipped > 20);
    }
}

TEST_CASE("the viewer's own preview blocks need not be powers of 2: twice the speed, a finer block") {
    PreviewPacer p;
    CHECK(p.preview_block(1280, 720, 0.010) == 8);  // nothing measured yet
    // 1280x720 at 8x8 (160x90 = 14400 rays) just within 10 ms on one core...
    p.measured(14400, 0.0099);
    CHECK(p.preview_block(1280, 720, 0.010) == 8);
    // ...and with two cores each ray costs half the wall time: 6x6 fits (214x120 =
    // 25680 rays, 8.8 ms); a power of 2 would have stayed at 8 (4x4 needs 17.6 ms).
    PreviewPacer q;
    q.measured(14400, 0.0099 / 2);
    CHECK(q.preview_block(1280, 720, 0.010) == 6);
    CHECK(q.coarse_block(1280, 720, 0.010) == 8);
    PreviewPacer slow;
    slow.measured(1, 1.0);
    CHECK(slow.preview_block(1280, 720, 0.010) == 64);
}

TEST_CASE("a preview traced by three threads has the same bytes as by one") {
    rt::ParseResult r = rt::parse_scene(rt::kDefaultScene);
    REQUIRE(r.ok());
    auto world = rt::compile_world(r.scene);
    for (int b : {1, 3, 8}) {
        std::vector<std::uint8_t> alone, pooled;
        int aw = 0, ah = 0, qw = 0, qh = 0;
        rt::ThreadPool single_pool(2), three_pool(4);
        rt::Renderer single(single_pool), three(three_pool);
        PreviewResult one = trace_preview(single, world, r.scene.camera, 161, 97, b, 0, alone, aw, ah);
        PreviewResult many = trace_preview(three, world, r.scene.camera, 161, 97, b, 0, pooled, qw, qh);
        CHECK(aw == qw);
        CHECK(ah == qh);
        CHECK(one.traced == std::uint64_t(aw) * std::uint64_t(ah));
        CHECK(many.traced == one.traced);
        CHECK_FALSE(one.stopped);
        CHECK_FALSE(many.stopped);
        CHECK(alone == pooled);
    }
}

TEST_CASE("a preview of ray trees without end stops at its time limit, every pixel filled") {
    // Without a stop this preview would not end for hours: every pixel's tree is
    // endless (perfect mirrors around glass, depth 1000, no bound).
    auto world = rt_test::endless_world();
    for (int threads : {1, 3}) {
        CAPTURE(threads);
        rt::ThreadPool renderer_pool(threads + 1);
        rt::Renderer renderer(renderer_pool);
        std::vector<std::uint8_t> rgba;
        int pw = 0, ph = 0;
        rt_test::Watchdog dog("a preview did not stop at its time limit");
        PreviewResult res = trace_preview(renderer, world, world->camera, 64, 48, 1, 0.02, rgba, pw, ph);
        CHECK(res.stopped);
        CHECK(res.traced < std::uint64_t(pw) * std::uint64_t(ph));
        REQUIRE(rgba.size() == std::size_t(pw) * std::size_t(ph) * 4);
        for (std::size_t i = 3; i < rgba.size(); i += 4) REQUIRE(rgba[i] == 255);  // every row filled
    }
}
