// The handles and framing of things placed by `rotation`, `scale` and `translate`:
// where the handle sits, which keys a move writes, and the boxes the view frames,
// against coordinates worked out by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "document.h"
#include "move_handle.h"
#include "navigator.h"
#include "placement.h"
#include "scene_edits.h"
#include "transform_handle.h"
#include "viewer_test_util.h"
#include "world.h"

using namespace rtview;
using rt::Vec3;

namespace {

const char* kCamera = "camera { position -20 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
                      "picture_size { x_max 8 y_max 8 }\nend\n";

rt::Scene scene_of(const std::string& things) { return rt_test::parse_ok("thing {\n" + things + "}\n" + kCamera); }

bool near(Vec3 a, Vec3 b, double eps = 1e-9) {
    return std::fabs(a.x - b.x) <= eps && std::fabs(a.y - b.y) <= eps && std::fabs(a.z - b.z) <= eps;
}

const SceneItem kFirst{SceneItem::Kind::Object, 0};

}  // namespace

TEST_CASE("handles: a transformed thing's handle sits where its transform puts it") {
    // (1 0 0) scaled by 2: (2 0 0); turned 90 degrees about z: (0 2 0); moved: (5 2 0).
    rt::Scene s = scene_of("sphere { position 1 0 0 radius 0.5 scale 2 rotation 0 0 90 translate 5 0 0 }\n");
    CHECK(near(*item_anchor(s, kFirst), {5, 2, 0}));
    // A box's centre (1 1 1), turned 90 about z: (-1 1 1), moved: (4 1 1).
    s = scene_of("box { corner_1 0 0 0 corner_2 2 2 2 rotation 0 0 90 translate 5 0 0 }\n");
    CHECK(near(*item_anchor(s, kFirst), {4, 1, 1}, 1e-6));
    // A torus's centre, scaled per axis: (2 3 4) * (1 2 0.5) = (2 6 2).
    s = scene_of("torus { position 2 3 4 major 1 minor 0.2 scale 1 2 0.5 }\n");
    CHECK(near(*item_anchor(s, kFirst), {2, 6, 2}));
    // Operands of a turned, moved CSG: the left (1 0 0) -> (0 1 0) -> (0 1 1); the
    // right, moved by its own translate first, (3 1 0) -> (-1 3 0) -> (-1 3 1).
    s = scene_of("constructive_solid_geometry { type U rotation 0 0 90 translate 0 0 1\n"
                 "  left { sphere { position 1 0 0 radius 0.5 } }\n"
                 "  right { sphere { position 3 0 0 radius 0.5 translate 0 1 0 } } }\n");
    CHECK(near(*item_anchor(s, kFirst, {0}), {0, 1, 1}));
    CHECK(near(*item_anchor(s, kFirst, {1}), {-1, 3, 1}));
}

TEST_CASE("handles: a move of a transformed thing writes its translate, and lands where the drag went") {
    rt::Scene s = scene_of("sphere { position 1 0 0 radius 0.5 scale 2 rotation 0 0 90 translate 5 0 0 }\n");
    rt::Object o = s.objects[0];
    translate_operand(o, {}, {1, 2, 3});
    CHECK(std::get<rt::Sphere>(o.shape).position == Vec3{1, 0, 0});  // the user's numbers stay
    CHECK(o.transform.get().translate == Vec3{6, 2, 3});
    CHECK(o.transform.get().rotation == Vec3{0, 0, 90});
    s.objects[0] = o;
    CHECK(near(*item_anchor(s, kFirst), {6, 4, 3}));

    // Without a transform a move still moves the shape's own points (no translate key).
    s = scene_of("cylinder { end_1 0 0 0 end_2 0 0 1 radius 0.5 }\n");
    o = s.objects[0];
    translate_operand(o, {}, {1, 0, 0});
    CHECK(std::get<rt::Cylinder>(o.shape).end1 == Vec3{1, 0, 0});
    CHECK_FALSE(o.transform.set());

    // An operand of a turned CSG: a world move of (0 1 0) is (1 0 0) in the CSG's frame
    // (turned back by 90 degrees about z), and the operand's handle moves by (0 1 0).
    s = scene_of("constructive_solid_geometry { type U rotation 0 0 90 translate 0 0 1\n"
                 "  left { sphere { position 1 0 0 radius 0.5 } }\n"
                 "  right { sphere { position 3 0 0 radius 0.5 translate 0 1 0 } } }\n");
    o = s.objects[0];
    REQUIRE(translate_operand(o, {0}, {0, 1, 0}));
    CHECK(near(std::get<rt::Sphere>(operand_of(o, {0})->shape).position, {2, 0, 0}));
    CHECK(o.transform.get().translate == Vec3{0, 0, 1});  // the CSG stays
    // The right operand moves by its own translate: (0 1 0) + (0 0 2) turned back = (2 0 0) -> (2 1 0).
    REQUIRE(translate_operand(o, {1}, {0, 0, 2}));
    CHECK(near(operand_of(o, {1})->transform.get().translate, {0, 1, 2}));
    CHECK(std::get<rt::Sphere>(operand_of(o, {1})->shape).position == Vec3{3, 0, 0});
    s.objects[0] = o;
    CHECK(near(*item_anchor(s, kFirst, {0}), {0, 2, 1}));
    CHECK(near(*item_anchor(s, kFirst, {1}), {-1, 3, 3}));
}

TEST_CASE("framing: the scene's size and F's box follow the transforms") {
    // A unit sphere scaled by 10 and moved to (100 0 0): the box (90..110, -10..10, -10..10).
    const rt::Scene s = scene_of("sphere { position 0 0 0 radius 1 scale 10 translate 100 0 0 }\n");
    CHECK(scene_extent(s) == doctest::Approx(std::sqrt(3.0) * 20).epsilon(1e-6));
    CHECK(typical_object_size(s) == doctest::Approx(10).epsilon(1e-6));
    const rt::Aabb b = frame_target(*rt::compile_world(s));
    CHECK(near(b.lo, {90, -10, -10}, 1e-6));
    CHECK(near(b.hi, {110, 10, 10}, 1e-6));
    CHECK(scene_extent(s, rt::compile_world(s).get()) == doctest::Approx(std::sqrt(3.0) * 20).epsilon(1e-6));
    // An instance: its definition's box, placed by the instance's transform.
    const rt::Scene in = rt_test::parse_ok("define { object cube { box { corner_1 0 0 0 corner_2 1 1 1 } } }\n"
                                           "thing { instance { object cube scale 4 translate 0 0 10 } }\n" +
                                           std::string(kCamera));
    CHECK(scene_extent(in) == doctest::Approx(std::sqrt(3.0) * 4).epsilon(1e-6));
    CHECK(near(*item_anchor(in, kFirst), {2, 2, 12}, 1e-6));
}

// ---- turn and size handles ------------------------------------------------------

#include "transform_handle.h"

namespace {

// Looking straight down -z from (0 0 10), y up on screen: x to the right, y up. A film
// of 801 x 801 in an image of 801 x 801: the anchor (0 0 0) is at film coordinate
// 400.5, drawn at that texel's centre (viewport.h): window (401, 401).
ScreenView top_view() {
    rt::Camera c;
    c.position = {0, 0, 10};
    c.centre = {0, 0, 0};
    c.up = {0, 1, 0};
    c.angle_x = 60;
    c.angle_y = 60;
    return ScreenView(c, Rect{0, 0, 801, 801}, 801, 801);
}

}  // namespace

TEST_CASE("turn: rotations as written and back") {
    for (Vec3 v : {Vec3{0, 0, 90}, Vec3{10, 20, 30}, Vec3{-45, 30, 170}, Vec3{90, 0, 0}, Vec3{0, -60, 0}})
        CHECK(near(rotation_degrees(rotation_matrix(v)), v, 1e-6));
    // Rz(90) takes x to y; Rx(90) takes y to z.
    CHECK(near(rotation_matrix({0, 0, 90}) * Vec3{1, 0, 0}, {0, 1, 0}));
    CHECK(near(rotation_matrix({90, 0, 0}) * Vec3{0, 1, 0}, {0, 0, 1}));
    // About the diagonal by 120 degrees: x -> y -> z -> x.
    const Vec3 d = rt::normalize(Vec3{1, 1, 1});
    CHECK(near(axis_rotation(d, 120) * Vec3{1, 0, 0}, {0, 1, 0}, 1e-12));
    CHECK(near(axis_rotation({0, 0, 1}, 90) * Vec3{1, 0, 0}, {0, 1, 0}));
}

TEST_CASE("turn: a thing turns about its handle's point, writing rotation and translate only") {
    // The box [0,2]^3 turned 90 degrees about z through its centre (1 1 1): translate
    // = Rz(90) (0 - (1 1 1)) + (1 1 1) = (1 -1 -1) + (1 1 1) = (2 0 0); its corner
    // (2 0 0) goes to Rz(90)(2 0 0) + (2 0 0) = (2 2 0).
    rt::Scene s = scene_of("box { corner_1 0 0 0 corner_2 2 2 2 }\n");
    rt::Object o = s.objects[0];
    const Vec3 a = *item_anchor(s, kFirst);
    CHECK(near(a, {1, 1, 1}));
    turn_object(o, {0, 0, 1}, 90, a);
    CHECK(std::get<rt::Box>(o.shape).corner1 == Vec3{0, 0, 0});  // the shape's keys stay
    CHECK(std::get<rt::Box>(o.shape).corner2 == Vec3{2, 2, 2});
    CHECK(o.transform.get().rotation == Vec3{0, 0, 90});
    CHECK(o.transform.get().translate == Vec3{2, 0, 0});
    CHECK(o.transform.get().scale == Vec3{1, 1, 1});
    CHECK(near(own_placement(o).point_to_world({2, 0, 0}), {2, 2, 0}));
    s.objects[0] = o;
    CHECK(near(*item_anchor(s, kFirst), {1, 1, 1}, 1e-9));
    // Two more quarter turns about x on top: Rx(180) Rz(90), written back as angles
    // that give the same matrix.
    turn_object(o, {1, 0, 0}, 180, a);
    const Mat3 want = rotation_matrix({180, 0, 0}) * rotation_matrix({0, 0, 90});
    const Mat3 got = rotation_matrix(o.transform.get().rotation);
    for (int i = 0; i < 3; ++i) CHECK(near(got.column(i), want.column(i), 1e-9));
    s.objects[0] = o;
    CHECK(near(*item_anchor(s, kFirst), {1, 1, 1}, 1e-9));

    // A cylinder's ends stay as written: the turn goes into its transform.
    s = scene_of("cylinder { end_1 0 0 0 end_2 0 0 2 radius 0.5 }\n");
    o = s.objects[0];
    turn_object(o, {1, 0, 0}, 90, {0, 0, 1});
    CHECK(std::get<rt::Cylinder>(o.shape).end2 == Vec3{0, 0, 2});
    CHECK(o.transform.get().rotation == Vec3{90, 0, 0});
    // The top end (0 0 2) turns about x through (0 0 1): to (0 -1 1).
    CHECK(near(own_placement(o).point_to_world({0, 0, 2}), {0, -1, 1}));
}

TEST_CASE("size: a thing sizes about its handle's point along its own axes") {
    // A unit sphere at (1 0 0) doubled about its centre: scale 2, translate (1 0 0) -
    // 2 (1 0 0) = (-1 0 0); its centre stays at 2 (1 0 0) + (-1 0 0) = (1 0 0), and the
    // ray from (-10 0 0) along +x meets it at x = 1 - 2 = -1: 9 from the eye.
    rt::Scene s = scene_of("sphere { position 1 0 0 radius 1 }\n");
    rt::Object o = s.objects[0];
    size_object(o, {2, 2, 2}, {1, 0, 0});
    CHECK(std::get<rt::Sphere>(o.shape).position == Vec3{1, 0, 0});
    CHECK(std::get<rt::Sphere>(o.shape).radius == 1);
    CHECK(o.transform.get().scale == Vec3{2, 2, 2});
    CHECK(o.transform.get().translate == Vec3{-1, 0, 0});
    s.objects[0] = o;
    CHECK(near(*item_anchor(s, kFirst), {1, 0, 0}));
    const rt::PickResult hit = rt::pick(*rt::compile_world(s), rt::Ray{{-10, 0, 0}, {1, 0, 0}});
    REQUIRE(hit.hit);
    CHECK(hit.t == doctest::Approx(9));
    // Along its own x, which a turn of 90 about z points along the world's y: the
    // sphere becomes 3 long in y, 1 in x.
    o = scene_of("sphere { position 0 0 0 radius 1 rotation 0 0 90 }\n").objects[0];
    size_object(o, {3, 1, 1}, {0, 0, 0});
    CHECK(o.transform.get().scale == Vec3{3, 1, 1});
    s.objects[0] = o;
    const rt::Aabb b = frame_target(*rt::compile_world(s));
    CHECK(b.hi.y == doctest::Approx(3).epsilon(1e-6));
    CHECK(b.hi.x == doctest::Approx(1).epsilon(1e-6));
}

TEST_CASE("turn and size drags: angles and factors from the pointer, snapped with Shift") {
    const ScreenView v = top_view();
    const TurnShape t = turn_shape(v, {0, 0, 0}, 90);
    REQUIRE(t.visible);
    CHECK(t.origin.x == doctest::Approx(401));
    CHECK(t.origin.y == doctest::Approx(401));
    // From above, the z ring is a circle of 90 about the middle; the x ring (in the y z
    // plane) an upright line through it, the y ring a level one.
    const double r45 = 90 * std::sqrt(0.5);
    CHECK(hit_turn(t, 401 + r45, 401 - r45, 4) == HandlePart::Z);
    CHECK(hit_turn(t, 401, 401 - 60, 4) == HandlePart::X);
    CHECK(hit_turn(t, 401 - 60, 401, 4) == HandlePart::Y);
    CHECK(hit_turn(t, 401 + 112.5, 401, 4) == HandlePart::Plane);
    CHECK(hit_turn(t, 401 + 150, 401 + 150, 4) == HandlePart::None);

    // z points at the eye: a counter-clockwise drag on screen from +x to +y is +90.
    TurnDrag d(HandlePart::Z, {0, 0, 0}, v, 401 + 90, 401);
    CHECK(d.axis() == Vec3{0, 0, 1});
    CHECK(d.degrees(401, 401 - 90, false) == doctest::Approx(90));
    const double c80 = 90 * std::cos(80 * 3.14159265358979 / 180), s80 = 90 * std::sin(80 * 3.14159265358979 / 180);
    CHECK(d.degrees(401 + c80, 401 - s80, false) == doctest::Approx(80));
    CHECK(d.degrees(401 + c80, 401 - s80, true) == 75);
    // On round past 180 it keeps counting: to -x (180), then -y (270).
    CHECK(d.degrees(401 - 90, 401 - 1, true) == 180);
    CHECK(d.degrees(401, 401 + 90, true) == 270);
    // The view circle turns about the axis towards the eye: here +z, the same way.
    TurnDrag w(HandlePart::Plane, {0, 0, 0}, v, 401 + 112.5, 401);
    CHECK(near(w.axis(), {0, 0, 1}, 1e-9));
    CHECK(w.degrees(401, 401 - 112.5, true) == 90);

    // Size: the x box at 90 to the right; dragged to 180, twice as long.
    const SizeShape z = size_shape(v, {0, 0, 0}, Mat3{}, 90);
    REQUIRE(z.axis_shown[0]);
    CHECK_FALSE(z.axis_shown[2]);  // z points at the eye
    CHECK(z.tip[0].x == doctest::Approx(401 + 90));
    CHECK(z.tip[1].y == doctest::Approx(401 - 90));  // y up on screen
    CHECK(hit_size(z, 401 + 90, 401, 4) == HandlePart::X);
    CHECK(hit_size(z, 401, 401, 4) == HandlePart::Plane);
    SizeDrag sx(HandlePart::X, z, 90, 401 + 90, 401);
    CHECK(sx.factors(401 + 180, 401, false) == Vec3{2, 1, 1});
    CHECK(sx.factors(401 + 175, 401, false).x == doctest::Approx(1.94));
    CHECK(sx.factors(401 + 175, 401, true).x == doctest::Approx(1.9));
    CHECK(sx.factors(401 - 300, 401, false).x == 0.01);  // never through 0
    SizeDrag all(HandlePart::Plane, z, 90, 401, 401);
    CHECK(all.factors(401 + 90, 401, true) == Vec3{2, 2, 2});
    CHECK(all.factors(401 + 45, 401 + 45, true) == Vec3{1, 1, 1});  // right and down: no change
}

TEST_CASE("turn: the translate written is the one a person would write") {
    // The default scene's tetrahedron, its middle (10.75 -3.1 0.9) kept by a quarter
    // turn about z: translate (10.75 -3.1 0.9) - (3.1 10.75 0.9) = (7.65 -13.85 0).
    rt::Scene s = scene_of("tetrahedron { vect1 10 -4 0  vect2 11.5 -3 0  vect3 10.2 -2.2 0  vect4 10.6 -3 1.8 }\n");
    rt::Object o = s.objects[0];
    const Vec3 a = *item_anchor(s, kFirst);
    CHECK(near(a, {10.75, -3.1, 0.9}, 1e-12));
    turn_object(o, {0, 0, 1}, 90, a);
    CHECK(o.transform.get().translate == Vec3{7.65, -13.85, 0});
    CHECK(o.transform.get().rotation == Vec3{0, 0, 90});
}

namespace {

// Where the operand `path` of object 0 puts its shape's point `local` in the world.
Vec3 operand_point(const rt::Scene& s, const std::vector<int>& path, Vec3 local) {
    const rt::Object& top = s.objects[0];
    return parent_placement(top, path).point_to_world(own_placement(*operand_of(top, path)).point_to_world(local));
}

const char* kTurnedCsg =
    "constructive_solid_geometry { type U rotation 0 0 90 translate 10 0 0\n"
    "  left { box { corner_1 0 0 0 corner_2 2 1 1 } }\n"
    "  right { sphere { position 5 5 5 radius 1 } } }\n";

}  // namespace

TEST_CASE("turn and size a CSG operand: its own transform changes, about the world axis and point") {
    rt::Scene s = scene_of(kTurnedCsg);
    const rt::Object before = s.objects[0];
    // The CSG maps (x, y, z) to (10 - y, x, z): the box's corner (2 0 0) is at (10 2 0),
    // its centre (1 0.5 0.5) at (9.5 1 0.5).
    CHECK(near(operand_point(s, {0}, {2, 0, 0}), {10, 2, 0}));
    const Vec3 centre{9.5, 1, 0.5};
    REQUIRE(turn_operand(s.objects[0], {0}, {0, 0, 1}, 90, centre));
    // (10 2 0) - centre = (0.5 1 -0.5), turned 90 about z: (-1 0.5 -0.5), + centre.
    CHECK(near(operand_point(s, {0}, {2, 0, 0}), {8.5, 1.5, 0}, 1e-9));
    CHECK(near(operand_point(s, {0}, {1, 0.5, 0.5}), centre, 1e-9));
    // The CSG and the other operand are as they were.
    const rt::Csg& g = std::get<rt::Csg>(s.objects[0].shape), &g0 = std::get<rt::Csg>(before.shape);
    CHECK(s.objects[0].transform == before.transform);
    CHECK(g.operands[1] == g0.operands[1]);
    CHECK(g.operands[0].shape == g0.operands[0].shape);  // the box's corners stay the user's
    CHECK(!(g.operands[0].transform == g0.operands[0].transform));

    // Sizing by 2 along the operand's own x (the world's y here) about its centre.
    s = scene_of(kTurnedCsg);
    const Mat3 axes = operand_axes(s.objects[0], {0});
    CHECK(near(axes.column(0), {0, 1, 0}, 1e-12));
    CHECK(near(axes.column(1), {-1, 0, 0}, 1e-12));
    REQUIRE(size_operand(s.objects[0], {0}, {2, 1, 1}, centre));
    // Along x the box runs 1 each side of its centre, 2 when sized: (2 0 0) -> (3 0 0)
    // in the CSG's frame, (10 3 0) in the world.
    CHECK(near(operand_point(s, {0}, {2, 0, 0}), {10, 3, 0}, 1e-9));
    CHECK(near(operand_point(s, {0}, {1, 0.5, 0.5}), centre, 1e-9));
    CHECK(!turn_operand(s.objects[0], {0, 1}, {0, 0, 1}, 90, centre));  // a box has no operands

    // Written into the text and read back: the same operand.
    Document doc;
    doc.load_text(std::string("thing {\n") + kTurnedCsg + "}\n" + kCamera, "", "csg");
    REQUIRE(turn_operand(doc.edit_object(0), {0}, {0, 0, 1}, 90, centre));
    doc.commit();
    CHECK(doc.take_refusal() == "");
    const rt::Scene back = rt_test::parse_ok(doc.editor_text());
    CHECK(back == doc.scene());
    CHECK(near(operand_point(back, {0}, {2, 0, 0}), {8.5, 1.5, 0}, 1e-9));
}

namespace {

// The eight corners of a box operand's own corners, in its shape's coordinates.
std::vector<Vec3> corners(const rt::Object& o) {
    const rt::Box& b = std::get<rt::Box>(o.shape);
    std::vector<Vec3> out;
    for (int k = 0; k < 8; ++k)
        out.push_back({(k & 1 ? b.corner2 : b.corner1).x, (k & 2 ? b.corner2 : b.corner1).y,
                       (k & 4 ? b.corner2 : b.corner1).z});
    return out;
}

// Turns operand `path` of the CSG in `things` by `degrees` about the world `axis`
// through `centre`; where it can be written, checks that every corner of the operand
// went where that turn takes it in the world, and that the text reads back the same.
// Returns whether it was made.
bool turned_exactly(const std::string& things, const std::vector<int>& path, Vec3 axis, double degrees, Vec3 centre) {
    rt::Scene s = scene_of(things);
    const rt::Object before = s.objects[0];
    std::vector<Vec3> want;
    const Mat3 q = axis_rotation(axis, degrees);
    for (const Vec3& c : corners(*operand_of(before, path))) want.push_back(q * (operand_point(s, path, c) - centre) + centre);
    std::string why;
    if (!turn_operand(s.objects[0], path, axis, degrees, centre, &why)) {
        CHECK(why.find("scales unequally") != std::string::npos);
        CHECK(s.objects[0] == before);  // nothing changed
        return false;
    }
    CHECK(why.empty());
    const std::vector<Vec3> local = corners(*operand_of(s.objects[0], path));
    for (std::size_t k = 0; k < local.size(); ++k) {
        INFO("corner " << k << " of " << things);
        CHECK(near(operand_point(s, path, local[k]), want[k], 1e-6));
    }
    Document doc;
    doc.load_text("thing {\n" + things + "}\n" + kCamera, "", "csg");
    REQUIRE(turn_operand(doc.edit_object(0), path, axis, degrees, centre));
    doc.commit();
    CHECK(doc.take_refusal() == "");
    const rt::Scene back = rt_test::parse_ok(doc.editor_text());
    for (std::size_t k = 0; k < local.size(); ++k) CHECK(near(operand_point(back, path, local[k]), want[k], 1e-6));
    return true;
}

}  // namespace

TEST_CASE("turn a CSG operand under an uneven scale: exact where its keys can hold it, else refused") {
    // The CSG doubles y. A quarter turn about z through the box's middle (1 1 0.5): its
    // corner (2 0 0), at (2 0 0) in the world, goes to (1 1 -0.5) turned, (2 2 0).
    const std::string stretched = "constructive_solid_geometry { type U scale 1 2 1\n"
                                  "  left { box { corner_1 0 0 0 corner_2 2 1 1 } }\n"
                                  "  right { sphere { position 5 5 5 radius 1 } } }\n";
    CHECK(turned_exactly(stretched, {0}, {0, 0, 1}, 90, {1, 1, 0.5}));
    rt::Scene s = scene_of(stretched);
    REQUIRE(turn_operand(s.objects[0], {0}, {0, 0, 1}, 90, {1, 1, 0.5}));
    CHECK(near(operand_point(s, {0}, {2, 0, 0}), {2, 2, 0}, 1e-9));
    // The box's own x now lies along the CSG's y, which the CSG doubles: its own scale
    // halves it, and doubles its own y (along the CSG's x, which stays), so that the
    // box is 2 by 2 by 1 in the world as before.
    const rt::Transform& t = std::get<rt::Csg>(s.objects[0].shape).operands[0].transform.get();
    CHECK(t.scale == Vec3{0.5, 2, 1});
    CHECK(t.rotation == Vec3{0, 0, 90});
    // A turn about the axis the scale leaves alone, and half turns, are exact too.
    CHECK(turned_exactly(stretched, {0}, {0, 1, 0}, 180, {1, 1, 0.5}));
    CHECK(turned_exactly(stretched, {0}, {0, 0, 1}, 180, {1, 1, 0.5}));
    // 45 degrees would shear the box in the CSG's frame: refused, nothing changed.
    CHECK(!turned_exactly(stretched, {0}, {0, 0, 1}, 45, {1, 1, 0.5}));
    CHECK(!turned_exactly(stretched, {0}, {1, 0, 0}, 30, {1, 1, 0.5}));
    // Uneven scales on both, the CSG turned too: a quarter turn about the CSG's own x
    // (the world's y after its 90 degrees about z) keeps its axes on its axes.
    const std::string both = "constructive_solid_geometry { type U scale 1 2 1 rotation 0 0 90 translate 1 2 3\n"
                              "  left { box { corner_1 0 0 0 corner_2 2 1 1 scale 3 1 1 rotation 0 0 90 } }\n"
                              "  right { sphere { position 5 5 5 radius 1 } } }\n";
    CHECK(turned_exactly(both, {0}, {0, 1, 0}, 90, {0, 2, 3}));
    CHECK(!turned_exactly(both, {0}, {0, 1, 0}, 60, {0, 2, 3}));
    // The operand's own uneven scale under an even one: any turn is exact.
    const std::string even = "constructive_solid_geometry { type U scale 2 rotation 0 0 30\n"
                             "  left { box { corner_1 0 0 0 corner_2 2 1 1 scale 1 3 1 rotation 0 0 20 } }\n"
                             "  right { sphere { position 5 5 5 radius 1 } } }\n";
    CHECK(turned_exactly(even, {0}, {1, 0, 0}, 37, {1, 1, 1}));
    CHECK(turned_exactly(even, {0}, rt::normalize(Vec3{1, 2, 3}), 71.5, {0, 0, 0}));
}
