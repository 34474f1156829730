// The New: realism keys against closed forms: a sphere light's lit fraction behind a
// sphere (spherical caps), the thin lens's circle of confusion, the highlight's
// Blinn-Phong value, the background; and the pixel samples' independence from the
// order, threads and ISA path they are traced on.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "renderer.h"
#include "sampler.h"
#include "scene_parser.h"
#include "simd.h"
#include "test_util.h"
#include "test_world_compare.h"
#include "world.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

// A white plane z = 0 lit by one light; whatever else the caller adds.
Scene plane_scene(const Light& light) {
    Scene s = parse_ok(
        "special_thing { plane { material { colour 1 1 1 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 } }\n"
        "camera { position 3 0 1 centre 0 0 0 up 0 0 1 angle_x 40 angle_y 30 }\n"
        "picture_size { x_max 64 y_max 48 }\nend\n");
    s.lights.push_back(light);
    return s;
}

Object sphere(const Vec3& c, double r) {
    Object o;
    o.shape = Sphere{c, r};
    o.has_material = true;
    return o;
}

// The mean colour of n samples of the camera ray of `world` toward `target`.
Colour mean_toward(const World& world, const Vec3& target, int n, int pixel_x = 7) {
    CameraBasis cam = CameraBasis::make(world.camera, world.width, world.height, false);
    const Vec3 d = normalize(target - cam.origin);
    std::vector<Vec3> dirs(std::size_t(n), d);
    std::vector<PixelSample> keys;
    for (int s = 0; s < n; ++s) keys.push_back({pixel_x, 3, s});
    std::vector<Colour> out(static_cast<std::size_t>(n));
    RayStats stats;
    world.trace_samples(cam, dirs.data(), keys.data(), std::size_t(n), stats, out.data());
    Colour sum;
    for (const Colour& c : out) sum += c;
    return sum * (1.0 / n);
}

}  // namespace

TEST_CASE("sphere light: the lit share of a point behind a coaxial sphere converges to the caps' closed form") {
    // The light (centre H above the point p = origin, radius R) fills the cone of half
    // angle tmax; a sphere on the same axis hides the inner cone of half angle tocc.
    // Samples are uniform over the light's cone of directions, so the direct term's mean
    // is e (0.1 + 0.9 E[cos t; t > tocc]) with cos t uniform on [cos tmax, 1]:
    // E = (cos^2 tocc - cos^2 tmax) / (2 (1 - cos tmax)).
    const double H = 6, R = 2, h = 3, ro = 0.6;
    Light l;
    l.lamp = false;
    l.position = {0, 0, H};
    l.colour = {36, 36, 36};  // e = 1 at p
    l.radius = R;
    Scene s = plane_scene(l);
    s.objects.push_back(sphere({0, 0, h}, ro));
    auto world = compile_world(s);
    REQUIRE(world->area_lights);
    const double cmax = std::sqrt(1 - R * R / (H * H)), cocc = std::sqrt(1 - ro * ro / (h * h));
    REQUIRE(cocc > cmax);
    const double expect = 0.1 + 0.9 * (cocc * cocc - cmax * cmax) / (2 * (1 - cmax));
    const Colour got = mean_toward(*world, {0, 0, 0}, 4096);
    CHECK(got.x == doctest::Approx(expect).epsilon(0.005));
    CHECK(got.y == got.x);
    // Without the occluder: all of the cone, E = (1 - cos^2 tmax) / (2 (1 - cos tmax)).
    s.objects.clear();
    auto open = compile_world(s);
    const Colour all = mean_toward(*open, {0, 0, 0}, 4096);
    CHECK(all.x == doctest::Approx(0.1 + 0.9 * (1 + cmax) / 2).epsilon(0.002));
    // A point light (radius 0) there is hidden whole: only the tenth remains.
    s.lights[0].radius = 0;
    s.objects.push_back(sphere({0, 0, h}, ro));
    auto point = compile_world(s);
    CHECK_FALSE(point->area_lights);
    CHECK(mean_toward(*point, {0, 0, 0}, 4).x == doctest::Approx(0.1));
}

TEST_CASE("sphere light: the light buffer's grown cells find every blocker the BVH finds") {
    // The same picture with the buffers and without (shadow rays through the BVH):
    // many small occluders around a sphere light, points all over the plane.
    Light l;
    l.position = {0, 0, 8};
    l.colour = {60, 60, 60};
    l.radius = 0.6;
    Scene s = plane_scene(l);
    for (int i = 0; i < 60; ++i) {
        const double a = i * 0.7, r = 0.5 + 0.05 * i;
        s.objects.push_back(sphere({r * std::cos(a), r * std::sin(a), 2 + 0.02 * i}, 0.15));
    }
    s.camera.position = {0, -6, 8};
    s.camera.centre = {0, 0, 0};
    s.camera.up = {0, 0, 1};
    auto with = compile_world(s);
    REQUIRE(with->light_buffers);
    REQUIRE((*with->light_buffers)[0].n > 0);
    auto without = std::make_shared<World>(*with);
    without->light_buffers = nullptr;
    CameraBasis cam = CameraBasis::make(s.camera, 64, 48, false);
    int differ = 0, shadowed = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int k = 0; k < 4; ++k) {
                const Vec3 d = normalize(cam.direction(x, y));
                const PixelSample key{x, y, k};
                Colour a, b;
                RayStats st;
                with->trace_samples(cam, &d, &key, 1, st, &a);
                without->trace_samples(cam, &d, &key, 1, st, &b);
                differ += !(a == b);
                shadowed += a.x < 0.5;
            }
    CHECK(differ == 0);
    CHECK(shadowed > 100);  // the test sees shadows at all
}

TEST_CASE("depth of field: the focus plane stays sharp, twice as far blurs by the lens radius") {
    Camera c;
    c.position = {0, 0, 0};
    c.centre = {10, 0, 0};
    c.up = {10, 0, 1};
    c.angle_x = 60;
    c.angle_y = 45;
    c.aperture = 0.4;
    CameraBasis cam = CameraBasis::make(c, 100, 80, false);
    CHECK(cam.focus == doctest::Approx(10));  // the centre's distance by default
    CHECK(cam.lens == doctest::Approx(0.2));
    const Vec3 d = normalize(cam.direction(30, 20));
    const double along = dot(d, cam.forward);
    const Vec3 sharp = cam.origin + d * (cam.focus / along);
    const Vec3 far = cam.origin + d * (2 * cam.focus / along);
    double widest = 0;
    for (int s = 0; s < 256; ++s) {
        PathSampler sampler(PixelSample{30, 20, s});
        double u, v;
        sampler.next(u, v);
        const Ray r = cam.lens_ray(d, u, v);
        const Vec3 off = r.origin - cam.origin;
        CHECK(length(off) <= cam.lens * (1 + 1e-12));
        CHECK(dot(off, cam.forward) == doctest::Approx(0).scale(1));
        // Where the ray crosses the focus plane: the pinhole ray's point.
        const double t1 = (cam.focus - dot(r.origin - cam.origin, cam.forward)) / dot(r.dir, cam.forward);
        CHECK(length(r.origin + r.dir * t1 - sharp) < 1e-9);
        // At twice the distance: off by the lens point mirrored, |off| <= the lens radius.
        const double t2 = (2 * cam.focus - dot(r.origin - cam.origin, cam.forward)) / dot(r.dir, cam.forward);
        const Vec3 miss = r.origin + r.dir * t2 - far;
        CHECK(length(miss + off) < 1e-9);
        widest = std::max(widest, length(miss));
    }
    // The samples cover the disc: the circle of confusion is nearly the lens.
    CHECK(widest > 0.9 * cam.lens);
}

TEST_CASE("depth of field: a sphere at the focus distance is as sharp as with a pinhole, one nearer is not") {
    const std::string base =
        "thing { sphere { material { colour 1 1 1 } position 10 0 0 radius 1 }\n"
        "        sphere { material { colour 1 1 1 } position 4 1 0 radius 0.4 } }\n"
        "light { lamp { position 0 0 20 colour 400 400 400 size 0 } }\n"
        "camera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 40 angle_y 30 APERTURE }\n"
        "picture_size { x_max 80 y_max 60 }\nend\n";
    auto render = [&](const std::string& aperture) {
        std::string text = base;
        text.replace(text.find("APERTURE"), 8, aperture);
        return rt_test::render(compile_world(parse_ok(text)), 64);
    };
    const Image pin = render(""), lens = render("aperture 0.3");
    // Edge of the far sphere (in focus), near its left rim on the middle row; the near
    // sphere's rim (out of focus) around its image.
    auto diff = [&](int x0, int x1, int y0, int y1) {
        double d = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c) d += 255 * std::fabs(pin.at(x, y)[c] - lens.at(x, y)[c]);
        return d / ((x1 - x0) * (y1 - y0) * 3);
    };
    const double focused = diff(27, 53, 18, 42), near = diff(0, 27, 0, 60) + diff(53, 80, 0, 60);
    CHECK(focused < 2.0);
    CHECK(near > 3 * focused);
}

TEST_CASE("highlight: Blinn-Phong at the mirror point of a plane, zero where the half vector leaves the normal") {
    // The eye and a point light at the same height over the plane, symmetric about the
    // point p: there the half vector is the normal, so the highlight is specular * e.
    Light l;
    l.lamp = false;
    l.position = {-3, 0, 1};
    l.colour = {10, 10, 10};
    Scene s = plane_scene(l);
    s.planes[0].material.scattering = 0;
    s.planes[0].material.reflection = 0;
    s.planes[0].material.refraction = 0;
    s.planes[0].material.specular = 0.5;
    s.planes[0].material.shininess = 20;
    auto world = compile_world(s);
    REQUIRE(world->highlights);
    const double e = 10.0 / 10.0;  // |light - p|^2 = 10
    CHECK(mean_toward(*world, {0, 0, 0}, 1).x == doctest::Approx(0.5 * e));
    // Off the mirror point: cos(angle between n and h)^20 times as much.
    const Vec3 q{1, 0, 0};
    const Vec3 vl = normalize(l.position - q), ve = normalize(s.camera.position - q);
    const double nh = normalize(vl + ve).z;
    const double el = 10.0 / length2(l.position - q);
    CHECK(mean_toward(*world, q, 1).x == doctest::Approx(0.5 * el * std::pow(nh, 20)));
}

TEST_CASE("background: rays that meet nothing take its colour; the 2013 black without it") {
    Light l;
    l.position = {0, 0, 5};
    Scene s = plane_scene(l);
    s.planes.clear();
    s.camera.background = {0.25, 0.5, 0.75};
    auto world = compile_world(s);
    const Colour c = mean_toward(*world, {0, 0, 0}, 1);
    CHECK(c == Colour{0.25, 0.5, 0.75});
    s.camera.background = {};
    CHECK(mean_toward(*compile_world(s), {0, 0, 0}, 1) == Colour{});
}

TEST_CASE("pixel samples: a sample's colour depends on its pixel and number only") {
    Light l;
    l.position = {0, 0, 5};
    l.colour = {30, 30, 30};
    l.radius = 1;
    Scene s = plane_scene(l);
    s.objects.push_back(sphere({0.3, 0, 2}, 0.5));
    s.camera.aperture = 0.2;
    auto world = compile_world(s);
    CameraBasis cam = CameraBasis::make(s.camera, 64, 48, false);
    std::vector<Vec3> dirs;
    std::vector<PixelSample> keys;
    for (int k = 0; k < 40; ++k) {
        keys.push_back({k % 8, k / 8, k % 5});
        dirs.push_back(normalize(cam.direction(k % 8, k / 8)));
    }
    std::vector<Colour> batch(keys.size());
    RayStats st;
    world->trace_samples(cam, dirs.data(), keys.data(), keys.size(), st, batch.data());
    // One at a time, in reverse: the same colours.
    for (std::size_t k = keys.size(); k-- > 0;) {
        Colour one;
        world->trace_samples(cam, &dirs[k], &keys[k], 1, st, &one);
        CHECK(one == batch[k]);
    }
    // Different samples of one pixel differ (the lens and light points move).
    int distinct = 0;
    for (std::size_t k = 1; k < keys.size(); ++k) distinct += !(batch[k] == batch[0]);
    CHECK(distinct > 20);
}

TEST_CASE("sampler: the points of one pixel are stratified (one in each of 16 cells of 16 samples)") {
    for (int pixel = 0; pixel < 20; ++pixel) {
        for (int dim = 0; dim < 3; ++dim) {
            bool cell[4][4] = {};
            for (int s = 0; s < 16; ++s) {
                PathSampler p(PixelSample{pixel, 2 * pixel, s});
                double u = 0, v = 0;
                for (int d = 0; d <= dim; ++d) p.next(u, v);
                REQUIRE(u >= 0);
                REQUIRE(u < 1);
                REQUIRE(v >= 0);
                REQUIRE(v < 1);
                cell[int(u * 4)][int(v * 4)] = true;
            }
            int filled = 0;
            for (auto& row : cell)
                for (bool c : row) filled += c;
            CHECK(filled == 16);
        }
    }
}

TEST_CASE("sampler: the scramble is nested (a bit's flip depends on lower bits only) and a permutation") {
    std::uint32_t x = 987654321u, seed = 0x2545F491u;
    int changed = 0;
    for (int k = 0; k < 20000; ++k) {
        x = x * 1664525u + 1013904223u, seed = seed * 22695477u + 1u;
        const std::uint32_t y = sampling::nested_scramble(x, seed);
        const int j = k % 32;
        const std::uint32_t z = sampling::nested_scramble(x ^ (1u << j), seed);
        // Changing bit j changes bit j and no bit below it.
        CHECK(((y ^ z) & ((2u << j) - 1)) == (1u << j));
        changed += ((y ^ z) >> j) != 1;  // (and usually some above it)
    }
    CHECK(changed > 15000);
    // On the 256 values of the low byte, a permutation for any seed.
    for (std::uint32_t s : {0u, 1u, 0xFFFFFFFFu, 0x9e3779b9u}) {
        bool seen[256] = {};
        for (std::uint32_t v = 0; v < 256; ++v) seen[sampling::nested_scramble(v, s) & 255] = true;
        CHECK(std::count(seen, seen + 256, true) == 256);
    }
}

TEST_CASE("sampler: Sobol dimension 1 by the superset sum equals the bit-by-bit sum of its columns") {
    std::uint32_t x = 12345;
    for (int k = 0; k < 20000; ++k) {
        x = x * 1664525u + 1013904223u;
        CHECK(sampling::sobol1(x) == sampling::sobol1_slow(x));
    }
    CHECK(sampling::sobol1(0xFFFFFFFFu) == sampling::sobol1_slow(0xFFFFFFFFu));
    for (std::uint32_t i = 0; i < 64; ++i) CHECK(sampling::sobol1(i) == sampling::sobol1_slow(i));
    // The first points: 1/2, then 3/4 and 1/4 (the Pascal matrix's columns).
    CHECK(sampling::sobol1(1) == 0x80000000u);
    CHECK(sampling::sobol1(2) == 0xC0000000u);
    CHECK(sampling::sobol1(3) == 0x40000000u);
}

TEST_CASE("sampler: cos_sin_turn matches std::cos and std::sin of 2 pi v over the whole turn") {
    double worst = 0;
    for (int k = 0; k <= 100000; ++k) {
        const double v = k / 100000.0, phi = 2 * M_PI * v;
        double c, s;
        sampling::cos_sin_turn(v, c, s);
        worst = std::max({worst, std::abs(c - std::cos(phi)), std::abs(s - std::sin(phi))});
    }
    CHECK(worst < 1e-13);
    // The quarter turns exactly, signs included.
    double c, s;
    sampling::cos_sin_turn(0.25, c, s);
    CHECK(c == 0.0);
    CHECK(s == 1.0);
    sampling::cos_sin_turn(0.5, c, s);
    CHECK(c == -1.0);
    CHECK(s == 0.0);
    sampling::cos_sin_turn(0.75, c, s);
    CHECK(s == -1.0);
}

TEST_CASE("packets: sphere lights, highlights, a lens and a background give the scalar path's bits") {
    // The AVX2 packets (shade_avx2.cpp) draw each lane's light points from its own
    // sampler and must match the scalar path bit for bit: lights seen from outside and
    // (the plane under the low lamp) from inside their sphere, a light of radius 0 beside
    // them, a point light's glow disc in view and casting shadows, mirrors, glass,
    // highlights on some materials and not others.
    rt_test::IsaGuard guard;
    if (!isa_supported(Isa::Avx2)) {
        MESSAGE("no AVX2 here: nothing to compare the scalar path with");
        return;
    }
    const std::string text =
        "thing { sphere { material { reflection 0.5 scattering 0.5 colour 1 0.8 0.6 specular 0.6 shininess 120 }"
        " position 0 0 1 radius 1 } }\n"
        "thing { sphere { material { refraction 0.9 reflection 0.1 refractive_index 1.5 colour 1 1 1 }"
        " position 1.5 -1.5 0.6 radius 0.6 } }\n"
        "thing { sphere { material { scattering 1 colour 0.3 0.9 0.4 } position -1.2 1.4 0.5 radius 0.5 } }\n"
        "special_thing { plane { material { scattering 0.9 reflection 0.1 colour 1 1 1 specular 0.3 shininess 30 }"
        " point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 } }\n"
        "light { lamp { colour 30 28 25 position 3 2 4 radius 0.8 size 0 }\n"
        "  spotlight { colour 2 2 2 position -1 -1 0.3 radius 0.5 }\n"
        "  lamp { colour 10 10 14 position 2 -1 3.2 size 0.4 } }\n"
        "camera { position 7 -2 3 centre 0 0 0.7 up 0 0 1.7 projection linear angle_x 50 angle_y 38\n"
        "  aperture 0.2 background 0.1 0.2 0.3 }\n"
        "picture_size { x_max 48 y_max 36 }\nend\n";
    const Scene scene = parse_ok(text);
    std::vector<Colour> out[2];
    for (int path = 0; path < 2; ++path) {
        REQUIRE(set_isa(path == 0 ? Isa::Sse2 : Isa::Avx2));
        auto world = compile_world(scene);
        REQUIRE(world->area_lights);
        REQUIRE(world->glows.size() == 1);
        const CameraBasis cam = CameraBasis::make(world->camera, world->width, world->height, false);
        std::vector<Vec3> dirs;
        std::vector<PixelSample> keys;
        for (int s = 0; s < 3; ++s)
            for (int y = 0; y < world->height; ++y)
                for (int x = 0; x < world->width; ++x) {
                    dirs.push_back(normalize(cam.direction(x, y)));
                    keys.push_back({x, y, s});
                }
        out[path].resize(dirs.size());
        RayStats stats;
        world->trace_samples(cam, dirs.data(), keys.data(), dirs.size(), stats, out[path].data());
    }
    std::size_t differ = 0, lit = 0;
    for (std::size_t i = 0; i < out[0].size(); ++i) {
        if (std::memcmp(&out[0][i], &out[1][i], sizeof(Colour)) != 0) ++differ;
        if (out[0][i].x > 0.2) ++lit;
    }
    CHECK(differ == 0);
    CHECK(lit > out[0].size() / 4);  // (a picture, not a black frame)
}
