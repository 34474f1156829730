// Window <-> film mapping and picking through the core's World.
#include <doctest/doctest.h>

#include <cmath>

#include "camera_control.h"
#include "scene_parser.h"
#include "viewport.h"

using namespace rtview;

TEST_CASE("letterboxing keeps the picture's aspect, centred on whole pixels") {
    Rect area{0, 20, 800, 600};
    Rect r = letterbox(area, 320, 240);
    CHECK(r.w == 800);
    CHECK(r.h == 600);
    r = letterbox(area, 1000, 250);
    CHECK(r.w == 800);
    CHECK(r.h == 200);
    CHECK(r.y == 20 + 200);
    CHECK(r.x == 0);
    r = letterbox({10, 10, 500, 500}, 100, 400);
    CHECK(r.w == 125);
    CHECK(r.x == 10 + 187);
}

TEST_CASE("a texel's centre maps to the film coordinate its sample was taken at") {
    Rect img{100, 50, 400, 300};
    double i, j;
    window_to_film(img, 400, 300, 100.5, 50.5, i, j);
    CHECK(i == doctest::Approx(0));
    CHECK(j == doctest::Approx(0));
    window_to_film(img, 800, 600, 300, 200, i, j);  // a 2x film (hi-DPI)
    CHECK(i == doctest::Approx(399.5));
    CHECK(j == doctest::Approx(299.5));
}

TEST_CASE("picking finds the object, plane or lamp glow under a window point") {
    const char* text = R"(
thing { sphere { position 10 0 1 radius 1 } }
special_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 10 5 1 colour 10 10 10 size 0.5 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 200 y_max 150 }
end)";
    rt::ParseResult r = rt::parse_scene(text);
    REQUIRE(r.ok());
    auto world = rt::compile_world(r.scene);
    Rect img{0, 0, 200, 150};
    rt::Camera cam = r.scene.camera;
    rt::PickResult p = pick_at(*world, cam, img, 200, 150, 100.5, 75.5);  // the centre: the sphere
    CHECK(p.hit);
    CHECK(p.object == 0);
    CHECK(p.point.x == doctest::Approx(9).epsilon(1e-3));
    p = pick_at(*world, cam, img, 200, 150, 100.5, 149.5);  // bottom row: the ground plane
    CHECK(p.hit);
    CHECK(p.plane == 0);
    CHECK(p.point.z == doctest::Approx(0).epsilon(1e-9));
    p = pick_at(*world, cam, img, 200, 150, 100.5, 2.5);  // the sky
    CHECK_FALSE(p.hit);
    // The lamp's glow: project the lamp position to find its pixel.
    double i, j;
    REQUIRE(project(rt::CameraBasis::make(cam, 200, 150, false), {10, 5, 1}, i, j));
    p = pick_at(*world, cam, img, 200, 150, i + 0.5, j + 0.5);
    CHECK(p.light == 0);
}
