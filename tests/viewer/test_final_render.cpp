// The final render's command line and settings: --render parses, and the renderer is
// asked for what `raytracer` asks (the byte-for-byte check of the files themselves
// is render_test.sh).
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "final_render.h"
#include "image_io.h"
#include "options.h"
#include "scene_parser.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

const auto parse = rtview_test::parse_args;

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
    // raytracer: no --samples means the original's one ray per pixel, one pass.
    rt::RenderSettings s = final_render_settings(640, 480, 0, 0);
    CHECK(s.width == 640);
    CHECK(s.height == 480);
    CHECK(s.max_samples == 1);
    CHECK(s.samples_per_pass == 1);
    CHECK_FALSE(s.coarse);
    CHECK_FALSE(s.mirror);
    s = final_render_settings(640, 480, 16, 0);
    CHECK(s.max_samples == 16);
    CHECK(s.samples_per_pass == 16);
    // A time limit alone: as many samples as fit, in growing passes.
    s = final_render_settings(640, 480, 0, 2.5);
    CHECK(s.max_samples == 65536);
    CHECK(s.samples_per_pass == 0);
    CHECK(s.time_limit == 2.5);
    CHECK(s.aa_threshold < 0);
    // A threshold: adaptive, up to raytracer's default of 16 samples unless given more.
    s = final_render_settings(640, 480, 0, 0, 0.3);
    CHECK(s.aa_threshold == 0.3);
    CHECK(s.max_samples == 16);
    s = final_render_settings(640, 480, 64, 0, 0.1);
    CHECK(s.max_samples == 64);
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
    FinalRender fr(2);
    CHECK_FALSE(fr.start(r.scene, "out.jpg", 2, 0, -1).ok());
    CHECK_FALSE(fr.active());
    const std::string out = "test_final_render_out.ppm";
    std::remove(out.c_str());
    REQUIRE(fr.start(r.scene, out, 2, 0, -1).ok());
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
