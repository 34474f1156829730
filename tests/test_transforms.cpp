// Transforms (rotation, scale, translate on every object and CSG): hits, normals and
// bounds against coordinates worked out by hand, the rotation order against matrices
// written here, nested CSGs composing, and a transformed CSG rendering as the same CSG
// written out in world coordinates.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "renderer.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "shapes.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

const std::string kTail =
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\npicture_size { x_max 8 y_max 8 }\nend\n";

struct Placed {
    Scene scene;
    Geometry g;
    explicit Placed(const std::string& things) : scene(parse_ok("thing {\n" + things + "\n}\n" + kTail)) {
        g = build_geometry(scene);
    }
    // The first entry of object `obj` along o + t d (d made unit) with t > 0; t < 0 if none.
    double hit(const Vec3& o, const Vec3& d, std::uint32_t obj = 0, Vec3* normal = nullptr) const {
        SpanScratch s;
        SpanEnd e;
        const Vec3 u = normalize(d);
        if (!g.hit(obj, o, u, 0.0, e, s)) return -1;
        if (normal) *normal = g.surface_normal(obj, e, o + u * e.t);
        return e.t;
    }
};

bool near(const Vec3& a, const Vec3& b, double tol = 1e-12) { return length(a - b) <= tol; }

}  // namespace

TEST_CASE("transform: a rotated box's face and corner are where they are worked out by hand") {
    // The cube [-1, 1]^3 turned 45 degrees about z and moved 3 along x: its corner
    // (1, -1) goes to (3 + sqrt 2, 0), its face x = 1 to the line x + y = sqrt 2 (+3).
    Placed p("box { corner_1 -1 -1 -1  corner_2 1 1 1  rotation 0 0 45  translate 3 0 0 }");
    const double r2 = std::sqrt(2.0);
    CHECK(p.hit({10, 0, 0}, {-1, 0, 0}) == doctest::Approx(10 - (3 + r2)).epsilon(1e-14));
    Vec3 n;
    CHECK(p.hit({10, 0.2, 0}, {-1, 0, 0}, 0, &n) == doctest::Approx(10 - (3 + r2 - 0.2)).epsilon(1e-14));
    CHECK(near(n, Vec3{1, 1, 0} / r2, 1e-14));
    // Top face still at z = 1.
    CHECK(p.hit({3.3, 0.1, 5}, {0, 0, -1}, 0, &n) == doctest::Approx(4).epsilon(1e-14));
    CHECK(near(n, {0, 0, 1}, 1e-14));
    // Where the unturned box would have been hit, beside the turned one's edge: nothing.
    CHECK(p.hit({3.9, 0.9, 5}, {0, 0, -1}) < 0);
    // Its box for the BVH holds the turned corners and is no larger than them.
    const Aabb b = p.g.object_bounds[0];
    CHECK(b.lo.x == doctest::Approx(3 - r2).epsilon(1e-8));
    CHECK(b.hi.x == doctest::Approx(3 + r2).epsilon(1e-8));
    CHECK(b.lo.y == doctest::Approx(-r2).epsilon(1e-8));
    CHECK(b.hi.z == doctest::Approx(1).epsilon(1e-8));
    CHECK(b.lo.x <= 3 - r2);
    CHECK(b.hi.x >= 3 + r2);
}

TEST_CASE("transform: a scaled sphere is an ellipsoid, traced exactly") {
    // Semi-axes 2, 1, 0.5 about (1, 2, 3).
    Placed p("sphere { position 0 0 0  radius 1  scale 2 1 0.5  translate 1 2 3 }");
    CHECK(p.hit({-5, 2, 3}, {1, 0, 0}) == doctest::Approx(4).epsilon(1e-14));      // x = -1
    CHECK(p.hit({1, -5, 3}, {0, 1, 0}) == doctest::Approx(6).epsilon(1e-14));      // y = 1
    CHECK(p.hit({1, 2, 10}, {0, 0, -1}) == doctest::Approx(6.5).epsilon(1e-14));   // z = 3.5
    // Off the axis: x^2 / 4 + 0.5^2 = 1 at x = -sqrt 3; the normal is the gradient
    // (x / 4, y, z / 0.25) made unit.
    Vec3 n;
    CHECK(p.hit({-5, 2.5, 3}, {1, 0, 0}, 0, &n) == doctest::Approx(6 - std::sqrt(3.0)).epsilon(1e-14));
    CHECK(near(n, normalize(Vec3{-std::sqrt(3.0) / 4, 0.5, 0}), 1e-13));
    // A slanted ray: the point it meets solves x^2 / 4 + y^2 + z^2 / 0.25 = 1 (about the centre).
    const Vec3 o{-3, 1, 2}, d = normalize(Vec3{2, 0.5, 0.6});
    const double t = p.hit(o, d);
    REQUIRE(t > 0);
    const Vec3 q = o + d * t - Vec3{1, 2, 3};
    CHECK(q.x * q.x / 4 + q.y * q.y + q.z * q.z / 0.25 == doctest::Approx(1).epsilon(1e-12));
    // The BVH box is the ellipsoid's own.
    const Aabb b = p.g.object_bounds[0];
    CHECK(near(b.lo, {-1, 1, 2.5}, 1e-8));
    CHECK(near(b.hi, {3, 3, 3.5}, 1e-8));
    // A sphere away from the origin is scaled about the origin: its centre moves too.
    Placed q2("sphere { position 1 0 0  radius 1  scale 2 }");
    CHECK(q2.hit({-5, 0, 0}, {1, 0, 0}) == doctest::Approx(5).epsilon(1e-14));  // centre 2, radius 2
}

TEST_CASE("transform: rotation turns about x, then y, then z, as a mesh's does") {
    // A bar along +x, [0, 2] x [-0.1, 0.1]^2.
    const std::string bar = "box { corner_1 0 -0.1 -0.1  corner_2 2 0.1 0.1  rotation ";
    auto rot = [](const Vec3& deg, const Vec3& p) {
        // Rz Ry Rx p, written out here.
        const double k = 3.14159265358979323846 / 180;
        const double cx = std::cos(deg.x * k), sx = std::sin(deg.x * k), cy = std::cos(deg.y * k),
                     sy = std::sin(deg.y * k), cz = std::cos(deg.z * k), sz = std::sin(deg.z * k);
        Vec3 a{p.x, cx * p.y - sx * p.z, sx * p.y + cx * p.z};
        Vec3 b{cy * a.x + sy * a.z, a.y, -sy * a.x + cy * a.z};
        return Vec3{cz * b.x - sz * b.y, sz * b.x + cz * b.y, b.z};
    };
    // 0 90 90: y first takes +x to -z, then z leaves it: the bar hangs down from 0.
    CHECK(near(rot({0, 90, 90}, {2, 0, 0}), {0, 0, -2}, 1e-14));
    Placed a(bar + "0 90 90 }");
    CHECK(a.hit({0, 0, -5}, {0, 0, 1}) == doctest::Approx(3).epsilon(1e-14));
    CHECK(a.hit({0, -5, -1}, {0, 1, 0}) == doctest::Approx(4.9).epsilon(1e-14));
    CHECK(a.hit({0, -5, 1}, {0, 1, 0}) < 0);
    // 90 0 90: x leaves it, then z takes it to +y.
    Placed b(bar + "90 0 90 }");
    CHECK(b.hit({0, 5, 0}, {0, -1, 0}) == doctest::Approx(3).epsilon(1e-14));
    // Odd angles: the far end of the bar where the matrices written here put it.
    const Vec3 deg{30, -50, 110};
    Placed c(bar + "30 -50 110 }");
    const Vec3 tip = rot(deg, {2, 0, 0}), out = normalize(tip);
    CHECK(c.hit(tip + out * 5, -out) == doctest::Approx(5).epsilon(1e-12));
    // And a mesh turned by the same numbers puts its model's points there too.
    const MeshInstance m = MeshInstance::make({0, 0, 0}, {1, 1, 1}, deg);
    CHECK(near(m.point_to_world({2, 0, 0}), tip, 1e-14));
}

TEST_CASE("transform: nested CSGs compose, the innermost first") {
    // A ball of radius 0.5 at the origin, moved 1 along x by the inner CSG, then turned
    // 90 degrees about z by the outer: it ends at (0, 1, 0). (Turned first and moved
    // after, it would be at (1, 0, 0).)
    const std::string inner =
        "constructive_solid_geometry { type U left { sphere { position 0 0 0 radius 0.5 } }"
        " right { sphere { position 0 0 50 radius 0.5 } } translate 1 0 0 }";
    Placed p("constructive_solid_geometry { type U left { " + inner + " } right { sphere { position 0 0 -50 radius 0.1 } }"
             " rotation 0 0 90 }");
    CHECK(p.hit({0, -5, 0}, {0, 1, 0}) == doctest::Approx(5.5).epsilon(1e-14));
    CHECK(p.hit({1, -5, 0}, {0, 1, 0}) < 0);
    // An operand's own transform comes before its CSG's: scaled by 2 (radius 1 at the
    // origin), then moved by the CSG to (5, 0, 0).
    Placed q("constructive_solid_geometry { type I left { sphere { position 0 0 0 radius 0.5 scale 2 } }"
             " right { box { corner_1 -3 -3 -3 corner_2 3 3 3 } } translate 5 0 0 }");
    CHECK(q.hit({0, 0, 0}, {1, 0, 0}) == doctest::Approx(4).epsilon(1e-14));
    // A difference keeps its subtracted part's surface facing out of the solid.
    Placed d("constructive_solid_geometry { type C left { box { corner_1 -1 -1 -1 corner_2 1 1 1 } }"
             " right { sphere { position 1 0 0 radius 0.5 scale 1 1 1 } } rotation 0 0 180 translate 4 0 0 }");
    Vec3 n;
    // The bite is now on the -x side (at x = 3): the ray meets its bottom at x = 3.5.
    CHECK(d.hit({0, 0, 0}, {1, 0, 0}, 0, &n) == doctest::Approx(3.5).epsilon(1e-14));
    CHECK(near(n, {-1, 0, 0}, 1e-14));
}

TEST_CASE("transform: a transformed CSG renders as the same CSG written out in world coordinates") {
    // Turned 90 degrees about z and moved: (x, y, z) -> (5 - y, x, z + 1). The world
    // copy's numbers are that map applied by hand; the ball's scale 0.5 is its radius.
    const std::string placed = R"(
thing {
  constructive_solid_geometry {
    type C
    left { box { corner_1 -1 -0.5 -0.5  corner_2 1 0.5 0.5 } }
    right {
      constructive_solid_geometry {
        type U
        left { cylinder { end_1 0 0 -1  end_2 0 0 1  radius 0.3 } }
        right { sphere { position 0 0 0  radius 1.2  scale 0.5  translate 0.9 0 0.5 } }
      }
    }
    material { reflection 0.2 scattering 0.8 colour 0.9 0.5 0.2 }
    rotation 0 0 90  translate 5 0 1
  }
  cone { end_1 0 0 0  end_2 0 0 1  radius_1 0.4  radius_2 0  rotation 0 -90 0  translate 4 1.5 0.4 }
}
)";
    const std::string world = R"(
thing {
  constructive_solid_geometry {
    type C
    left { box { corner_1 5.5 -1 0.5  corner_2 4.5 1 1.5 } }
    right {
      constructive_solid_geometry {
        type U
        left { cylinder { end_1 5 0 0  end_2 5 0 2  radius 0.3 } }
        right { sphere { position 5 0.9 1.5  radius 0.6 } }
      }
    }
    material { reflection 0.2 scattering 0.8 colour 0.9 0.5 0.2 }
  }
  cone { end_1 4 1.5 0.4  end_2 3 1.5 0.4  radius_1 0.4  radius_2 0 }
}
)";
    const std::string rest = R"(
special_thing { plane { material { colour 0.6 0.6 0.6 } point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 1 } }
light { lamp { position 2 3 6  colour 50 50 50  size 0.2 } }
camera { position 0 -1 2.5  centre 5 0 0.8  up 5 0 1.8  angle_x 50  angle_y 40 }
picture_size { x_max 96 y_max 72 }
end
)";
    auto render = [](const std::string& text) {
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        RenderSettings s;
        r.start(compile_world(parse_ok(text)), s);
        r.wait();
        return r.snapshot();
    };
    const Image a = render(placed + rest), b = render(world + rest);
    REQUIRE(a.rgb.size() == b.rgb.size());
    // Rounding differs (a ray taken into the shape's space, against the shape placed by
    // hand), so a pixel whose ray grazes an edge may go either way; nothing else may.
    int differ = 0, lit = 0;
    for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
        double d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, double(std::fabs(a.rgb[i + c] - b.rgb[i + c])));
        differ += d > 1e-4;
        lit += a.rgb[i] > 0.01f;
    }
    CHECK(differ <= 3);
    CHECK(lit > 1000);
    // And the same scene with the transforms gone is a different picture (the test
    // sees the objects at all).
    std::string unplaced = placed;
    for (const char* key : {"rotation 0 0 90  translate 5 0 1", "rotation 0 -90 0  translate 4 1.5 0.4"})
        unplaced.replace(unplaced.find(key), std::strlen(key), "");
    const Image c = render(unplaced + rest);
    CHECK(std::memcmp(c.rgb.data(), a.rgb.data(), a.rgb.size() * sizeof(float)) != 0);
}

TEST_CASE("transform: scale 0 or negative, and rotations that are not numbers, are errors at the value") {
    auto first_error = [](const std::string& thing) {
        ParseResult r = parse_scene("thing {\n" + thing + "\n}\n" + kTail);
        for (const Diagnostic& d : r.diagnostics)
            if (d.is_error()) return std::to_string(d.line) + ":" + std::to_string(d.col) + ": " + d.message;
        return std::string("no error");
    };
    const std::string refused = "scale must be 1e-9 .. 1e9 on every axis (0 and negative scales, mirrors, are refused)";
    CHECK(first_error("sphere { scale 0 }") == "2:16: " + refused);
    CHECK(first_error("box { scale 1 -2 1 }") == "2:13: " + refused);
    CHECK(first_error("cone { scale 1 1 1e10 }") == "2:14: " + refused);
    CHECK(first_error("constructive_solid_geometry { left { sphere { } } right { sphere { } } scale -1 }") ==
          "2:78: " + refused);
    CHECK(first_error("torus { rotation nan 0 0 }") == "2:18: expected 3 numbers after 'rotation', got 'nan'");
    CHECK(first_error("torus { rotation 0 inf 0 }") == "2:20: expected 3 numbers after 'rotation', got 'inf'");
    CHECK(first_error("torus { rotation 0 0 1e16 }") == "2:22: number '1e16' is out of range (magnitude at most 1e15)");
    CHECK(first_error("sphere { translate 1 2 }") == "2:24: expected 3 numbers after 'translate', got '}'");
    CHECK(first_error("sphere { scale 1e-9 rotation 1e15 -1e15 0 translate -1e15 0 1e15 }") == "no error");
    CHECK(first_error("mesh { file a.obj scale -1 translate 1 2 3 rotation 0 0 0 }") != "no error");  // (no a.obj)
}

TEST_CASE("transform: written back as given, and only where given") {
    const Scene s = parse_ok("thing {\n sphere { radius 2 scale 3 }\n box { corner_1 0 0 0 corner_2 1 2 3 rotation 10 20 30 "
                             "translate -1 0 1 scale 1 2 3 }\n sphere { }\n}\n" + kTail);
    const std::string text = write_scene(s);
    CHECK(rt_test::contains(text, "    radius 2\n    scale 3\n"));
    CHECK(rt_test::contains(text, "    rotation 10 20 30\n    scale 1 2 3\n    translate -1 0 1\n"));
    // The third sphere, and every 2013 scene, has no transform keys.
    CHECK(text.find("sphere {\n    position 1 1 1\n    radius 1\n  }") != std::string::npos);
    CHECK(parse_ok(text) == s);
    // A transform written at its defaults places nothing, and is left out.
    const Scene d = parse_ok("thing { sphere { scale 1 rotation 0 0 0 translate 0 0 0 } }\n" + kTail);
    CHECK_FALSE(d.objects[0].transform.set());
    CHECK(d == parse_ok("thing { sphere { } }\n" + kTail));
    CHECK_FALSE(rt_test::contains(write_scene(d), "scale"));
}
