// Shading checked against values worked out by hand from rendering.md, not against
// pictures made by the code under test: the direct-light formula at a sphere's centre
// pixel (§3), the depth a reflection costs (§2: 2 levels) counted through a corridor of
// two mirrors, and refraction through a glass slab by Snell's law with absorption
// (§5: a pass through glass costs 3 levels).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

std::shared_ptr<const World> with_depth(const std::shared_ptr<const World>& w, int depth) {
    auto c = std::make_shared<World>(*w);
    c->options.max_depth = depth;
    return c;
}

Colour trace(const World& w, const Vec3& o, const Vec3& d) {
    RayStats stats;
    return w.trace(o, d, 0, stats);
}

// The original's byte: floor(255 c), clamped.
int byte(double c) { return c <= 0 ? 0 : c >= 1 ? 255 : int(255 * c); }

// A matte sphere seen head-on: camera at the origin looking along +x at a sphere of
// radius 1 centred at (5, 0, 0), so the centre pixel's ray meets it at p = (4, 0, 0)
// with normal (-1, 0, 0). One light at (0, 3, 0) lights p; one at (10, 0, 0), behind
// the sphere, does not face p and adds only the unshadowed tenth.
const char* kSphere = R"(
thing { sphere { material { colour 0.8 0.6 0.4 } position 5 0 0 radius 1 } }
light {
  spotlight { colour 20 15 10 position 0 3 0 }
  spotlight { colour 36 72 36 position 10 0 0 }
}
camera { position 0 0 0 centre 5 0 0 up 5 0 1 angle_x 40 angle_y 30 }
picture_size { x_max 40 y_max 30 }
end
)";

Colour sphere_centre_expected() {
    const Colour cp{0.8, 0.6, 0.4};
    // Light 1: v = (0, 3, 0) - (4, 0, 0) = (-4, 3, 0), r = 5, n.v/r = 4/5.
    const Colour e1 = Colour{20, 15, 10} * (1.0 / 25);
    Colour c = mul(e1, cp) * (0.1 + 0.9 * 0.8);
    // Light 2: v = (6, 0, 0), r = 6, facing away (n.v < 0): the 0.1 term only.
    const Colour e2 = Colour{36, 72, 36} * (1.0 / 36);
    c += mul(e2, cp) * 0.1;
    return c;  // (0.6048, 0.4152, 0.1712)
}

}  // namespace

TEST_CASE("shading reference: a lit sphere's centre pixel is the direct-light formula") {
    auto world = compile_world(parse_ok(kSphere));
    const Colour want = sphere_centre_expected();
    // The ray itself.
    Colour got = trace(*world, {0, 0, 0}, {1, 0, 0});
    for (int k = 0; k < 3; ++k) CHECK(got[k] == doctest::Approx(want[k]).epsilon(1e-12));
    // The picture's centre pixel (column W/2, row H/2 looks straight along the camera
    // axis: docs/rendering.md §1), through the renderer.
    RenderSettings s;
    s.coarse = false;
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    r.start(world, s);
    r.wait();
    Image img = r.snapshot();
    REQUIRE(img.width == 40);
    Colour px = img.at(20, 15);
    for (int k = 0; k < 3; ++k) CHECK(px[k] == doctest::Approx(want[k]).epsilon(1e-6));
    // And in the file the command line writes.
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("rt-shading-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        std::FILE* f = std::fopen((dir / "sphere.txt").c_str(), "w");
        REQUIRE(f);
        std::fputs(kSphere, f);
        std::fclose(f);
    }
    std::string cmd = std::string(RT_BIN_DIR) + "/raytracer --quiet " + (dir / "sphere.txt").string() + " " +
                      (dir / "sphere.ppm").string() + " 2>/dev/null";
    REQUIRE(std::system(cmd.c_str()) == 0);
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgb;
    REQUIRE(read_ppm((dir / "sphere.ppm").string(), w, h, rgb).ok());
    REQUIRE(w == 40);
    const std::uint8_t* p = &rgb[3 * (15 * 40 + 20)];
    CHECK(int(p[0]) == byte(want.x));  // 154
    CHECK(int(p[1]) == byte(want.y));  // 105
    CHECK(int(p[2]) == byte(want.z));  // 43
    fs::remove_all(dir);
}

// Two half-silvered mirrors facing each other across x = -1 .. 3, a light at (1, 0, 0)
// between them. The camera at the origin looks along +x: its ray bounces between them
// on the axis, and every surface it meets is 2 from the light and faces it, so each
// adds 0.5 (scattering) * 2 / 2^2 times the weight of the path to it, 0.5^k after k
// reflections. With a depth limit D the ray meets ceil(D / 2) surfaces, because a
// reflection costs 2 levels: 0.25 (1 + 0.5 + ... + 0.5^(N-1)) = 0.5 (1 - 0.5^N) per
// channel, N = ceil(D / 2).
TEST_CASE("shading reference: a reflection costs two depth levels, counted between two mirrors") {
    const char* text = R"(
special_thing {
  plane { material { reflection 0.5 scattering 0.5 colour 1 1 1 } point 1 -1 0 0 point 2 -1 1 0 point 3 -1 0 1 point 4 0 0 0 }
  plane { material { reflection 0.5 scattering 0.5 colour 1 1 1 } point 1 3 0 0 point 2 3 1 0 point 3 3 0 1 point 4 0 0 0 }
}
light { spotlight { colour 2 2 2 position 1 0 0 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 40 angle_y 30 }
picture_size { x_max 8 y_max 6 }
end
)";
    auto world = compile_world(parse_ok(text));
    for (int depth = 1; depth <= 12; ++depth) {
        CAPTURE(depth);
        int surfaces = (depth + 1) / 2;
        double want = 0.5 * (1 - std::pow(0.5, surfaces));
        Colour got = trace(*with_depth(world, depth), {0, 0, 0}, {1, 0, 0});
        CHECK(got.x == doctest::Approx(want).epsilon(1e-12));
        CHECK(got.y == got.x);
        CHECK(got.z == got.x);
    }
    // The default limit, 20 levels: 10 surfaces.
    CHECK(trace(*world, {0, 0, 0}, {1, 0, 0}).x == doctest::Approx(0.5 * (1 - std::pow(0.5, 10))).epsilon(1e-12));
    // The same through the command line's --max-depth: 3 levels show two surfaces
    // (0.375: byte 95); if a reflection cost 1 level they would show three (0.4375: 111).
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("rt-mirrors-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        std::FILE* f = std::fopen((dir / "m.txt").c_str(), "w");
        REQUIRE(f);
        std::fputs(text, f);
        std::fclose(f);
    }
    for (int depth : {2, 3, 5}) {
        CAPTURE(depth);
        std::string cmd = std::string(RT_BIN_DIR) + "/raytracer --quiet --max-depth " + std::to_string(depth) + " " +
                          (dir / "m.txt").string() + " " + (dir / "m.ppm").string() + " 2>/dev/null";
        REQUIRE(std::system(cmd.c_str()) == 0);
        int w = 0, h = 0;
        std::vector<std::uint8_t> rgb;
        REQUIRE(read_ppm((dir / "m.ppm").string(), w, h, rgb).ok());
        REQUIRE(w == 8);
        int surfaces = (depth + 1) / 2;
        CHECK(int(rgb[3 * (3 * 8 + 4)]) == byte(0.5 * (1 - std::pow(0.5, surfaces))));
    }
    fs::remove_all(dir);
}

// A glass slab: a flat cylinder from x = 2 to x = 3 (radius 50, so its caps are the
// faces), index 1.5, pure refraction, absorbing per unit length by colour x
// translusans. Behind it a matte wall at x = 6 facing the camera, lit from (5, 0, 0).
// A ray at 30 degrees bends to asin(sin 30 / 1.5) inside, leaves parallel to itself
// but shifted, and meets the wall at a height found by Snell's law; the wall's colour
// there follows from §3 and the slab's absorption from the path length inside.
TEST_CASE("shading reference: refraction through a slab follows Snell's law and costs three levels") {
    const char* text = R"(
thing {
  cylinder {
    material { reflection 0 refraction 1 scattering 0 translusans 0.9 refractive_index 1.5 colour 1 0.8 0.6 }
    end_1 2 0 0 end_2 3 0 0 radius 50
  }
}
special_thing {
  plane { material { colour 1 1 1 } point 1 6 0 0 point 2 6 1 0 point 3 6 0 1 point 4 0 0 0 }
}
light { spotlight { colour 4 4 4 position 5 0 0 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 40 angle_y 30 }
picture_size { x_max 8 y_max 6 }
end
)";
    auto world = compile_world(parse_ok(text));
    const double pi = std::acos(-1.0);
    for (double degrees : {0.0, 10.0, 30.0, 50.0}) {
        CAPTURE(degrees);
        const double a = degrees * pi / 180;
        const Vec3 d{std::cos(a), std::sin(a), 0};
        // Snell: sin b = sin a / 1.5; inside, the path crosses the unit thickness.
        const double b = std::asin(std::sin(a) / 1.5);
        const double inside = 1 / std::cos(b);
        // To the slab 2 tan a, through it tan b, from x = 3 to 6 another 3 tan a.
        const double y = 2 * std::tan(a) + std::tan(b) + 3 * std::tan(a);
        // The wall point q = (6, y, 0), normal (-1, 0, 0); light v = (-1, -y, 0).
        const double r2 = 1 + y * y, r = std::sqrt(r2);
        const double lit = 4 / r2 * (0.1 + 0.9 * (1 / r));
        const Colour base{1 * 0.9, 0.8 * 0.9, 0.6 * 0.9};
        const Colour want{lit * std::pow(base.x, inside), lit * std::pow(base.y, inside), lit * std::pow(base.z, inside)};
        Colour got = trace(*world, {0, 0, 0}, d);
        for (int k = 0; k < 3; ++k) CHECK(got[k] == doctest::Approx(want[k]).epsilon(1e-9));
        // Without the bend the ray would meet the wall at 5 tan a + tan a = 6 tan a:
        // a visibly different colour, so the check above tells them apart.
        if (degrees == 30) {
            const double y0 = 6 * std::tan(a), r0 = std::sqrt(1 + y0 * y0);
            CHECK(std::fabs(4 / (r0 * r0) * (0.1 + 0.9 / r0) - lit) > 0.01);
        }
        // Depth: in at level 0, the inside walk at 2, out at 3. A limit of 3 leaves it black.
        CHECK(trace(*with_depth(world, 3), {0, 0, 0}, d) == Colour{});
        Colour four = trace(*with_depth(world, 4), {0, 0, 0}, d);
        CHECK(four.x == doctest::Approx(want.x).epsilon(1e-9));
    }
}
