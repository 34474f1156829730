// Where new items go: the point under a window point (on a surface, with its normal,
// or in the air) and the menu's Add, which looks for a clear spot near the centre.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "placement.h"
#include "scene_parser.h"
#include "world.h"

using namespace rtview;

namespace {

// A floor z = 0 seen from (0, -10, 10) looking at the origin, with `objects` on it.
rt::Scene floor_scene(const std::string& objects) {
    const std::string text = "thing {" + objects + R"(}
special_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 0 0 8 colour 1 1 1 size 0.5 } }
camera { position 0 -10 10 centre 0 0 0 up 0 -10 11 angle_x 60 angle_y 45 }
picture_size { x_max 200 y_max 150 }
end)";
    rt::ParseResult r = rt::parse_scene(text);
    REQUIRE(r.ok());
    return r.scene;
}

}  // namespace

TEST_CASE("a placement under a window point: on the surface with its normal, else in the air") {
    const rt::Scene s = floor_scene("");
    auto world = rt::compile_world(s);
    const PictureView view{world.get(), s.camera, Rect{0, 0, 200, 150}, 200, 150};
    // The image's centre looks at the origin, on the floor.
    const Placement at = placement_at(view, 100, 75);
    CHECK(at.point.x == doctest::Approx(0).epsilon(1e-6));
    CHECK(at.point.y == doctest::Approx(0).epsilon(1e-6));
    CHECK(at.point.z == doctest::Approx(0).epsilon(1e-9));
    CHECK(at.normal.z == doctest::Approx(1));  // the floor's normal, facing the camera
    CHECK(at.toward.y == doctest::Approx(-10).epsilon(1e-6));
    CHECK(at.toward.z == doctest::Approx(10).epsilon(1e-6));
    // With nothing compiled: in the air on the point's ray, as far along it as the
    // camera's centre is from its eye (sqrt(200)), with no normal.
    const Placement air = placement_at({nullptr, s.camera, Rect{0, 0, 200, 150}, 200, 150}, 100, 75);
    const rt::Ray ray = ray_at(s.camera, Rect{0, 0, 200, 150}, 200, 150, 100, 75);
    CHECK(rt::length(rt::cross(rt::normalize(air.point - ray.origin), ray.dir)) < 1e-9);
    CHECK(rt::length(air.point - ray.origin) == doctest::Approx(std::sqrt(200.0)));
    CHECK(rt::length2(air.normal) == 0);
}

TEST_CASE("the menu's Add puts an object on the floor clear of the one in the middle, in the picture") {
    const rt::Scene s = floor_scene("sphere { position 0 0 1 radius 1 }");
    auto world = rt::compile_world(s);
    const PictureView view{world.get(), s.camera, Rect{0, 0, 200, 150}, 200, 150};
    // Pointed at: exactly there (the sphere's surface under the centre).
    const Placement pointed = new_item_placement(view, &s, true, std::pair<double, double>{100, 75});
    CHECK(rt::length(pointed.point - placement_at(view, 100, 75).point) == 0);
    // A light from the menu: the centre too, clear or not.
    const Placement light = new_item_placement(view, &s, false, std::nullopt);
    CHECK(rt::length(light.point - pointed.point) == 0);
    // An object from the menu: on the floor (normal +z), its middle one size (1) above
    // it, at least 1.5 sizes from the sphere's box [-1, 1] x [-1, 1] x [0, 2].
    const Placement obj = new_item_placement(view, &s, true, std::nullopt);
    CHECK(obj.normal.z == doctest::Approx(1));
    CHECK(obj.point.z == doctest::Approx(0).epsilon(1e-9));
    const rt::Vec3 middle = obj.point + rt::Vec3{0, 0, 1};
    const rt::Vec3 nearest{std::clamp(middle.x, -1.0, 1.0), std::clamp(middle.y, -1.0, 1.0), std::clamp(middle.z, 0.0, 2.0)};
    CHECK(rt::length(middle - nearest) >= 1.5);
    // Near the centre: within the picture's ground, a few sizes away, not at its edge.
    CHECK(rt::length(obj.point) < 6);
}
