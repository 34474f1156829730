// The handles and framing of things placed by `rotation`, `scale` and `translate`:
// where the handle sits, which keys a move writes, and the boxes the view frames,
// against coordinates worked out by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "move_handle.h"
#include "navigator.h"
#include "placement.h"
#include "scene_edits.h"
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
