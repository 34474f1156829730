// The view camera is not the document: every kind of navigation leaves the text, the
// undo history and the modified mark alone; "Set scene camera from view" is the one
// way the view gets into the file (one undo step, exact through the text).
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "default_scene.h"
#include "document.h"
#include "camera_control.h"
#include "navigator.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "test_util.h"
#include "world.h"

using namespace rtview;

namespace {

struct Snapshot {
    std::string text;
    std::size_t undo_depth;
    bool modified, can_redo;
    std::uint64_t scene_version, text_version;
    rt::Scene scene;
    explicit Snapshot(const Document& d)
        : text(d.editor_text()),
          undo_depth(d.undo_depth()),
          modified(d.modified()),
          can_redo(d.can_redo()),
          scene_version(d.scene_version()),
          text_version(d.text_version()),
          scene(d.scene()) {}
    void check_same(const Document& d) const {
        CHECK(d.editor_text() == text);
        CHECK(d.undo_depth() == undo_depth);
        CHECK(d.modified() == modified);
        CHECK(d.can_redo() == can_redo);
        CHECK(d.scene_version() == scene_version);
        CHECK(d.text_version() == text_version);
        CHECK(d.scene() == scene);
        CHECK(d.title().find('*') == std::string::npos);
    }
};

ViewGeometry geometry() { return {Rect{0, 20, 800, 450}, 800, 450, false}; }

}  // namespace

TEST_CASE("navigation moves the view and leaves the document untouched") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    REQUIRE(d.has_scene());
    auto world = rt::compile_world(d.scene());
    Navigator nav;
    nav.follow(d.scene().camera);
    const Snapshot before(d);
    const rt::Camera start = nav.camera();
    ViewGeometry g = geometry();

    // Orbit: press and drag with the left button.
    nav.press(0, false, 400, 245, world.get(), g);
    CHECK(nav.drag(460, 260, world.get(), g));
    CHECK_FALSE(nav.release());  // a drag, not a click
    CHECK_FALSE(nav.camera() == start);
    rt::Camera after_orbit = nav.camera();
    // Pan with the right button.
    nav.press(1, false, 300, 200, world.get(), g);
    CHECK(nav.drag(340, 230, world.get(), g));
    nav.release();
    CHECK_FALSE(nav.camera() == after_orbit);
    // Wheel, fly, frame, turn, direct placement.
    rt::Camera c = nav.camera();
    nav.wheel(3, 400, 245, world.get(), g);
    CHECK(rt::length(nav.camera().position - c.position) > 1e-6);
    c = nav.camera();
    nav.fly({0, 0, 1}, 0.05, false, 10);
    CHECK(rt::length(nav.camera().position - c.position) > 1e-6);
    nav.frame(world->bounds(), g);
    nav.orbit_degrees(30);
    rt::Camera placed = nav.camera();
    placed.position = placed.position + rt::Vec3{0.5, 0, 0};
    CHECK(nav.set(placed));
    CHECK(nav.differs_from(d.scene().camera));

    before.check_same(d);
    // The view is kept while the document's camera stays what it was.
    nav.follow(d.scene().camera);
    CHECK(nav.camera() == placed);
    // R: back to the scene camera.
    nav.reset(d.scene().camera);
    CHECK(nav.camera() == d.scene().camera);
    before.check_same(d);
}

TEST_CASE("an orbit begun on a far point of the floor turns about a point within the scene") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    auto world = rt::compile_world(d.scene());
    const ViewGeometry g = geometry();
    Navigator nav;
    nav.follow(d.scene().camera);
    // Up the left edge of the picture to where the floor is far away (near the horizon).
    double y = g.image.y + g.image.h - 1, far = 0;
    for (; y > g.image.y; y -= 0.25) {
        rt::PickResult r = pick_at(*world, nav.camera(), g.image, g.film_w, g.film_h, 5, y);
        if (r.hit && r.plane == 0 && r.t > 200) {
            far = r.t;
            break;
        }
    }
    REQUIRE(far > 200);
    const rt::Camera start = nav.camera();
    nav.press(0, false, 5, y, world.get(), g);
    REQUIRE(nav.drag(65, y, world.get(), g));  // 60 pixels: 18 degrees
    nav.release();
    // Turned about a point no farther than the scene reaches: the eye moves at most
    // the chord of 18 degrees on that circle, not on one of the floor point's radius.
    const double reach = scene_reach(start, world->bounds());
    const double moved = rt::length(nav.camera().position - start.position);
    CHECK(moved > 0);
    CHECK(moved <= 2 * reach * std::sin(9 * M_PI / 180) + 1e-9);
}

TEST_CASE("F frames the objects, not the lamps far from them; the lamps only when there are no objects") {
    const std::string objects = "thing { sphere { position 10 0 0 radius 1 } }\n";
    const std::string rest = "light { lamp { colour 99 99 99 position -20 30 20 size 0.1 }\n"
                             "        spotlight { colour 9 9 9 position 0 -5 8 } }\n"
                             "camera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 64 y_max 48 }\nend\n";
    rt::Aabb b = frame_target(*rt::compile_world(rt_test::parse_ok(objects + rest)));
    CHECK(b.lo == rt::Vec3{9, -1, -1});
    CHECK(b.hi == rt::Vec3{11, 1, 1});
    b = frame_target(*rt::compile_world(rt_test::parse_ok(rest)));
    CHECK(b.lo == rt::Vec3{-20, -5, 8});
    CHECK(b.hi == rt::Vec3{0, 30, 20});
    const std::string nothing = "camera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 60 angle_y 45 }\n"
                                "picture_size { x_max 64 y_max 48 }\nend\n";
    CHECK(frame_target(*rt::compile_world(rt_test::parse_ok(nothing))).empty());
}

TEST_CASE("a degenerate view is refused and the last good one kept") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    Navigator nav;
    nav.follow(d.scene().camera);
    rt::Camera bad = nav.camera();
    bad.centre = bad.position;  // no view direction
    CHECK_FALSE(nav.set(bad));
    CHECK(nav.camera() == d.scene().camera);
}

TEST_CASE("Set scene camera from view is one undo step and round-trips through the text") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    auto world = rt::compile_world(d.scene());
    Navigator nav;
    nav.follow(d.scene().camera);
    const std::string original_text = d.editor_text();
    const rt::Camera original = d.scene().camera;
    ViewGeometry g = geometry();
    nav.press(0, false, 400, 245, world.get(), g);
    nav.drag(517, 281, world.get(), g);  // an orbit to coordinates no text holds yet
    nav.release();
    nav.wheel(1.5, 410, 250, world.get(), g);
    const rt::Camera view = nav.camera();
    REQUIRE_FALSE(view == original);
    REQUIRE(d.undo_depth() == 0);

    REQUIRE(d.set_camera(view));
    CHECK(d.undo_depth() == 1);
    CHECK(d.modified());
    CHECK(d.scene().camera == view);
    // The text holds exactly the view: parsing it gives the same camera, bit for bit,
    // and nothing but the camera block changed.
    rt::ParseResult back = rt::parse_scene(d.editor_text());
    REQUIRE(back.ok());
    CHECK(back.scene.camera == view);
    rt::Scene rest = back.scene;
    rest.camera = original;
    CHECK(rest == rt::parse_scene(original_text).scene);
    // In numbers a person would write: no 17 digits of an orbit's rounding noise.
    for (const rt::Vec3& p : {view.position, view.centre, view.up})
        for (double v : {p.x, p.y, p.z}) {
            CAPTURE(rt::format_number(v));
            CHECK(rt::format_number(v).size() <= 11);
        }
    // The view stays where it is (it is the scene camera now).
    nav.follow(d.scene().camera);
    CHECK(nav.camera() == view);
    CHECK_FALSE(nav.differs_from(d.scene().camera));
    // Setting it again is no step at all.
    CHECK_FALSE(d.set_camera(view));
    CHECK(d.undo_depth() == 1);

    // One undo takes the whole command back; the view follows the scene camera.
    REQUIRE(d.undo());
    CHECK(d.editor_text() == original_text);
    CHECK_FALSE(d.modified());
    CHECK(d.undo_depth() == 0);
    nav.follow(d.scene().camera);
    CHECK(nav.camera() == original);
    REQUIRE(d.redo());
    CHECK(d.scene().camera == view);
}

TEST_CASE("Focus here: the distance along the line of sight, written into the camera as one undo step") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    rt::Camera cam = d.scene().camera;
    const rt::Vec3 f = rt::normalize(cam.centre - cam.position);
    // A point 3 units ahead and 2 to the side: its focus distance is 3.
    rt::Vec3 side = rt::normalize(rt::cross(f, rt::Vec3{0, 0, 1}));
    const rt::Vec3 p = cam.position + f * 3 + side * 2;
    CHECK(focus_distance_to(cam, p) == doctest::Approx(3));
    CHECK(focus_distance_to(cam, cam.position - f) < 0);  // behind: refused by the caller
    const std::size_t depth = d.undo_depth();
    cam.focus_distance = focus_distance_to(cam, p);
    REQUIRE(d.set_camera(cam));
    CHECK(d.undo_depth() == depth + 1);
    CHECK(d.editor_text().find("focus_distance 3") != std::string::npos);
    // The text reads back to the same camera.
    rt::ParseResult r = rt::parse_scene(d.editor_text());
    REQUIRE(r.ok());
    CHECK(r.scene.camera.focus_distance == cam.focus_distance);
    d.undo();
    CHECK(d.editor_text().find("focus_distance") == std::string::npos);
    CHECK(d.scene().camera.focus_distance == 0);
}
