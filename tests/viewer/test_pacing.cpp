// Preview pacing: the block size of a preview is chosen from measured costs so that
// it fits the frame budget.
#include <doctest/doctest.h>

#include "default_scene.h"
#include "film.h"
#include "pacing.h"
#include "scene_parser.h"

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
    auto world = rt::compile_world(r.scene);
    const int w = 101, h = 67, b = 8;
    std::vector<std::uint8_t> rgba;
    int pw = 0, ph = 0;
    trace_preview(*world, r.scene.camera, w, h, b, rgba, pw, ph);
    CHECK(pw == 13);  // ceil(101 / 8)
    CHECK(ph == 9);   // ceil(67 / 8)
    REQUIRE(rgba.size() == std::size_t(pw * ph * 4));
    rt::CameraBasis basis = rt::CameraBasis::make(r.scene.camera, w, h, false);
    int distinct = 0;
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
        }
    CHECK(distinct > 20);  // a picture, not a flat colour
}
