// raytracer-mpi's schedule (app/mpi/schedule.h) without an MPI job: tiles taken and
// committed by hand, at chosen times, with sums that tell the passes apart.
#include <doctest/doctest.h>

#include <vector>

#include "schedule.h"

using rtmpi::Assignment;
using rtmpi::Schedule;
using rtmpi::ScheduleSettings;

namespace {

// Every pixel of a tile given samples [s0, s1) of colour 1: sums of s1 each.
void commit_tile(Schedule& s, const Assignment& a, double elapsed) {
    const rtmpi::Tile& t = s.tiles()[std::size_t(a.tile)];
    const std::vector<float> sums(3 * std::size_t(t.pixels()), float(a.s1));
    REQUIRE(s.commit(a, sums.data(), 1, elapsed).ok());
}

// Takes every free tile of the current pass, then commits them: one whole pass.
int whole_pass(Schedule& s, double elapsed) {
    std::vector<Assignment> pass;
    Assignment a;
    while (s.take(a, elapsed)) pass.push_back(a);
    for (const Assignment& p : pass) commit_tile(s, p, elapsed);
    return int(pass.size());
}

ScheduleSettings settings() {
    ScheduleSettings st;
    st.width = 64;
    st.height = 48;  // 4 x 3 tiles of 16
    st.tile_side = 16;
    st.max_samples = 8;  // passes of 1, 1, 2, 4 samples
    st.time_limit = 1.0;
    return st;
}

}  // namespace

TEST_CASE("mpi schedule: past the time limit no tile is handed out; the render ends when the tiles out are back") {
    Schedule s(settings());
    REQUIRE(s.tiles().size() == 12);
    Assignment a;
    // The first pass is always whole, even past the limit.
    std::vector<Assignment> first;
    while (s.take(a, 5.0)) first.push_back(a);
    CHECK(first.size() == 12);
    for (const Assignment& f : first) commit_tile(s, f, 5.0);
    // (Its completion past the limit ends the render, as rt::Renderer's does.)
    CHECK(s.done());
    CHECK(s.complete());
    CHECK(s.samples_done() == 1);

    // Within the limit: the second pass starts; past it, the five tiles out are the last.
    Schedule t(settings());
    REQUIRE(whole_pass(t, 0.1) == 12);
    REQUIRE(t.samples_done() == 1);
    std::vector<Assignment> out;
    for (int k = 0; k < 5 && t.take(a, 0.5); ++k) out.push_back(a);
    REQUIRE(out.size() == 5);
    CHECK(out[0].s0 == 1);
    CHECK(out[0].s1 == 2);
    CHECK_FALSE(t.take(a, 2.0));
    CHECK_FALSE(t.done());  // five tiles are still out
    for (std::size_t k = 0; k < out.size(); ++k) {
        CHECK_FALSE(t.done());
        commit_tile(t, out[k], 2.0 + double(k));
    }
    CHECK(t.done());
    CHECK_FALSE(t.take(a, 10.0));
    REQUIRE(t.complete());
    CHECK(t.samples_done() == 1);
    // The pixels of the five tiles hold two samples, the others one: each resolves to 1.
    const rt::Image img = t.image();
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) CHECK(img.at(x, y).x == 1.0);
}

TEST_CASE("mpi schedule: with nothing out at the limit the render ends at once; no limit, every pass") {
    Schedule s(settings());
    Assignment a;
    REQUIRE(whole_pass(s, 0.0) == 12);
    CHECK_FALSE(s.done());
    CHECK_FALSE(s.take(a, 1.0));  // the limit itself is past it
    CHECK(s.done());
    CHECK(s.complete());

    ScheduleSettings st = settings();
    st.time_limit = 0;
    Schedule u(st);
    int passes = 0;
    while (!u.done()) {
        REQUIRE(whole_pass(u, 1e9) == 12);
        ++passes;
    }
    CHECK(passes == 4);
    CHECK(u.samples_done() == 8);
    CHECK(u.complete());
}
