// Preview pacing: the first coarse pass is chosen from measured costs so that it fits
// the frame budget, and an unshown preview is only replaced once overdue.
#include <doctest/doctest.h>

#include "pacing.h"

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

TEST_CASE("an unshown preview is replaced only once overdue, and once per picture shown") {
    CHECK(PreviewPacer::may_replace(true, 0.0, 0.025, false));
    CHECK(PreviewPacer::may_replace(true, 0.0, 0.025, true));
    CHECK_FALSE(PreviewPacer::may_replace(false, 0.01, 0.025, false));
    CHECK_FALSE(PreviewPacer::may_replace(false, 0.049, 0.025, false));
    CHECK(PreviewPacer::may_replace(false, 0.05, 0.025, false));
    // One was thrown away already since the last picture: wait for this one.
    CHECK_FALSE(PreviewPacer::may_replace(false, 10.0, 0.025, true));
}
