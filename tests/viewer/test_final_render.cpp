// The final render's command line and settings: --render parses, and the renderer is
// asked for what `raytracer` asks (the byte-for-byte check of the files themselves
// is render_test.sh).
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cli_common.h"
#include "final_render.h"
#include "image_io.h"
#include "options.h"
#include "scene_parser.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

const auto parse = rtview_test::parse_args;

// The settings `raytracer ARGS scene.txt out.ppm` renders a width x height picture
// with, made by the command line's own code.
rt::RenderSettings cli_settings(std::vector<std::string> args, int width, int height) {
    const rtcli::Program program{"raytracer", "", "", "", ""};
    args.insert(args.begin(), "raytracer");
    args.push_back("scene.txt");
    args.push_back("out.ppm");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    rtcli::Options o;
    const rt::Status st = rtcli::parse_args(program, int(argv.size()), argv.data(), o);
    REQUIRE_MESSAGE(st.ok(), st.message());
    return rtcli::render_settings(o, width, height);
}

// Every field of RenderSettings, each compared on its own so that a failure names it.
void check_same(const rt::RenderSettings& viewer, const rt::RenderSettings& cli) {
    CHECK(viewer.width == cli.width);
    CHECK(viewer.height == cli.height);
    CHECK(viewer.max_samples == cli.max_samples);
    CHECK(viewer.time_limit == cli.time_limit);
    CHECK(viewer.hard_time_limit == cli.hard_time_limit);
    CHECK(viewer.coarse == cli.coarse);
    CHECK(viewer.mirror == cli.mirror);
    CHECK(viewer.tile_size == cli.tile_size);
    CHECK(viewer.samples_per_pass == cli.samples_per_pass);
    CHECK(viewer.order == cli.order);
    CHECK(viewer.camera == cli.camera);
    CHECK(viewer.coarse_block == cli.coarse_block);
    CHECK(viewer.aa_threshold == cli.aa_threshold);
}

}  // namespace

TEST_CASE("--render takes a file name, with or without =") {
    Options o;
    CHECK(parse({"--headless", "scene.txt", "--render", "out.png", "--samples", "4"}, o).empty());
    CHECK(o.render == "out.png");
    CHECK(o.samples == 4);
    CHECK(o.scene == "scene.txt");
    Options p;
    CHECK(parse({"--render=x.ppm"}, p).empty());
    CHECK(p.render == "x.ppm");
    Options q;
    CHECK_FALSE(parse({"--render"}, q).empty());
    Options r;
    CHECK_FALSE(parse({"--render="}, r).empty());
}

TEST_CASE("the final render's settings are the command line's") {
    // The viewer's samples, time limit and adaptive threshold (0, 0, -1: not given)
    // and the same on raytracer's command line, at two picture sizes.
    struct Case {
        int samples;
        double time_limit, aa_threshold;
        std::vector<std::string> args;
    };
    const Case cases[] = {
        {0, 0, -1, {}},  // the original's one ray per pixel
        {16, 0, -1, {"--samples", "16"}},
        {1, 0, -1, {"--samples", "1"}},
        {0, 2.5, -1, {"--time-limit", "2.5"}},  // as many samples as fit
        {4, 1.5, -1, {"--samples", "4", "--time-limit", "1.5"}},
        {0, 0, 0.3, {"--aa-threshold", "0.3"}},  // adaptive, up to the default count
        {64, 0, 0.1, {"--samples", "64", "--aa-threshold", "0.1"}},
        {0, 2, 0, {"--time-limit", "2", "--aa-threshold", "0"}},
    };
    for (const Case& c : cases) {
        for (auto [w, h] : {std::pair{640, 480}, std::pair{37, 21}}) {
            CAPTURE(c.samples);
            CAPTURE(c.time_limit);
            CAPTURE(c.aa_threshold);
            CAPTURE(w);
            check_same(rt::final_settings(final_render_request(c.samples, c.time_limit, c.aa_threshold), w, h),
                       cli_settings(c.args, w, h));
        }
    }
    // The comparison can tell settings apart: a mirrored picture is not the viewer's.
    const rt::RenderSettings mirrored = cli_settings({"--mirror"}, 640, 480);
    CHECK(mirrored.mirror != rt::final_settings(final_render_request(0, 0), 640, 480).mirror);
}

TEST_CASE("a final render writes the scene's picture size and refuses bad names") {
    const char* text = R"(
thing { sphere { position 10 0 1 radius 1 } }
light { spotlight { position 0 5 5 colour 1 1 1 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 37 y_max 21 }
end)";
    rt::ParseResult r = rt::parse_scene(text);
    REQUIRE(r.ok());
    rt::ThreadPool fr_pool(3);
    FinalRender fr(fr_pool);
    CHECK_FALSE(fr.start(r.scene, "out.jpg", final_render_request(2, 0)).ok());
    CHECK_FALSE(fr.active());
    const std::string out = "test_final_render_out.ppm";
    std::remove(out.c_str());
    REQUIRE(fr.start(r.scene, out, final_render_request(2, 0)).ok());
    while (!fr.wait_for(1)) {
    }
    CHECK(fr.fraction() == 1);
    CHECK(fr.write().ok());
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgb;
    REQUIRE(rt::read_ppm(out, w, h, rgb).ok());
    CHECK(w == 37);
    CHECK(h == 21);
    std::remove(out.c_str());
}

TEST_CASE("a final render's summary says the samples a pixel got: uniform, or adaptive's most and average") {
    // A dark sphere's sharp rim on a grey wall: with adaptive sampling the rim's pixels
    // take more samples and the flat ones stop at the first, so the most (8) lies above
    // the average, which lies above 1.
    const char* text = R"(
thing { sphere { material { colour 0 0 0 } position 10 0 1 radius 1.5 } }
special_thing { plane { material { colour 0.8 0.8 0.8 } point 1 14 0 0 point 2 14 1 0 point 3 14 0 1 point 4 0 0 0 } }
light { spotlight { position 0 0 1 colour 200 200 200 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 40 y_max 30 }
end)";
    rt::ParseResult r = rt::parse_scene(text);
    REQUIRE(r.ok());
    const std::string out = "test_final_render_summary.ppm";
    {
        rt::ThreadPool fr_pool(3);
        FinalRender fr(fr_pool);
        REQUIRE(fr.start(r.scene, out, final_render_request(4, 0)).ok());
        while (!fr.wait_for(1)) {
        }
        CHECK(fr.summary().rfind("40x30, 4 samples per pixel, ", 0) == 0);
    }
    rt::ThreadPool fr_pool(3);
    FinalRender fr(fr_pool);
    REQUIRE(fr.start(r.scene, out, final_render_request(8, 0, 0.05)).ok());
    while (!fr.wait_for(1)) {
    }
    const std::string s = fr.summary();
    CAPTURE(s);
    REQUIRE(s.rfind("40x30, adaptive: up to 8 samples per pixel, ", 0) == 0);
    const double mean = std::stod(s.substr(s.find("per pixel, ") + 11));
    CHECK(mean > 1.0);
    CHECK(mean < 8.0);
    std::remove(out.c_str());
}

TEST_CASE("the time left goes by the last seconds' pace, not the pace since the start") {
    TimeLeft t;
    CHECK(t.seconds() < 0);  // nothing to go by
    // 1 % a second for 90 s, then 0.5 % a second (adaptive passes slow down).
    for (int s = 0; s <= 90; ++s) t.add(s, s * 0.01);
    CHECK(t.seconds() == doctest::Approx(10).epsilon(1e-6));
    for (int s = 1; s <= 10; ++s) t.add(90 + s, 0.9 + s * 0.005);
    // 5 % left at 0.5 % a second: 10 s (the pace since the start says 5.5 s).
    CHECK(t.seconds() == doctest::Approx(10).epsilon(1e-6));
    // The same time again or a step back changes nothing; no progress: not known.
    t.add(100, 0.95);
    CHECK(t.seconds() == doctest::Approx(10).epsilon(1e-6));
    TimeLeft stuck;
    stuck.add(0, 0.5);
    stuck.add(3, 0.5);
    CHECK(stuck.seconds() < 0);
}
