// A render to a file's settings: the defaults every front end (raytracer,
// raytracer-mpi, the viewer's final render) derives from what was asked for.
#include <doctest/doctest.h>

#include "render_request.h"

TEST_CASE("max_samples: the count asked for, else as many as fit in a time limit, else the threshold's, else 1") {
    rt::RenderRequest r;
    CHECK(rt::max_samples(r) == 1);  // the original's one ray per pixel
    r.aa_threshold = 0.3;
    CHECK(rt::max_samples(r) == rt::kDefaultAaMaxSamples);
    r.time_limit = 2;
    CHECK(rt::max_samples(r) == rt::kMaxSamples);  // the time limit decides
    r.samples = 7;
    CHECK(rt::max_samples(r) == 7);  // what was asked for, whatever else was
    r.aa_threshold.reset();
    r.time_limit = 0;
    CHECK(rt::max_samples(r) == 7);
}

TEST_CASE("final_settings: no previews; one pass without a time limit, passes with one") {
    rt::RenderRequest r;
    r.samples = 9;
    r.mirror = true;
    const rt::RenderSettings one = rt::final_settings(r, 64, 48);
    CHECK(one.width == 64);
    CHECK(one.height == 48);
    CHECK_FALSE(one.coarse);
    CHECK(one.mirror);
    CHECK(one.max_samples == 9);
    CHECK(one.samples_per_pass == 9);
    CHECK(one.aa_threshold < 0);  // uniform
    r.time_limit = 1.5;
    r.aa_threshold = 0;
    const rt::RenderSettings timed = rt::final_settings(r, 64, 48);
    CHECK(timed.time_limit == 1.5);
    CHECK(timed.samples_per_pass == 0);  // the renderer's growing passes: it may stop between them
    CHECK(timed.aa_threshold == 0);
}
