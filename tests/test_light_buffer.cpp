// Light buffers (world.h): per light, the objects each cell of directions may meet.
// The shadow rays trust them to hold every object that can block a segment toward the
// light, so the property tested first is exactly that, against brute force: every
// object that the exact hit test finds on a random segment ending at the light is
// listed in that segment's cell (or among the ones every ray tests) with a least
// distance no larger than the segment's length. Then whole pictures: with the
// buffers, and with every shadow and camera ray walking the BVH instead (the any-hit
// and ordered searches), on each instruction-set path, the bytes are the same.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "simd.h"
#include "test_random.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::Rng;

namespace {

Object make(Shape s) {
    Object o;
    o.shape = std::move(s);
    o.has_material = true;
    return o;
}

// Spheres, tetrahedra, cylinders and tori of many sizes, some huge (seen in most
// directions from the light) and some around the light itself.
Scene random_scene(Rng& rng, const Vec3& light, int count) {
    Scene s;
    for (int i = 0; i < count; ++i) {
        Vec3 c = rng.in_ball(20);
        if (i % 17 == 3) c = light + rng.in_ball(0.5);  // next to (or around) the light
        double size = i % 23 == 5 ? rng.uni(10, 40) : rng.uni(0.05, 2);
        switch (i % 4) {
            case 0:
                s.objects.push_back(make(Sphere{c, size}));
                break;
            case 1: {
                Tetrahedron t;
                for (Vec3& v : t.v) v = c + rng.in_ball(size);
                s.objects.push_back(make(t));
                break;
            }
            case 2:
                s.objects.push_back(make(Cylinder{c, c + rng.unit() * size * 2, size / 3}));
                break;
            default: {
                Torus t;
                t.position = c;
                t.direction = rng.unit();
                t.major = size;
                t.minor = size / 4;
                s.objects.push_back(make(t));
            }
        }
    }
    return s;
}

// Checks that every object the exact hit test finds on the shadow segment from p to q
// (a point of the light, whose buffer lb is centred at `light`) is listed in the cell
// toward p, [first, last), or among lb.always, with a distance no larger than reach.
// Counts the objects found in `hits`.
void check_segment(const Geometry& g, const LightBuffer& lb, const Vec3& light, const Vec3& p, const Vec3& q,
                   double reach, int& hits, const LightBuffer::Entry*& first, const LightBuffer::Entry*& last) {
    const Vec3 v = q - p;
    const double r = length(v);
    const Vec3 vh = v / r, o = p + vh * kDelta;
    const double limit = r - 10 * kDelta;
    lb.cell(p - light, first, last);
    SpanScratch scratch;
    auto has = [&](std::uint32_t obj, const LightBuffer::Entry* a, const LightBuffer::Entry* b) {
        for (; a != b; ++a)
            if (a->obj == obj) return !(double(a->dmin) > reach);
        return false;
    };
    for (std::uint32_t obj = 0; obj < g.object_bounds.size(); ++obj) {
        SpanEnd e;
        if (!g.hit(obj, o, vh, 0.0, e, scratch) || !(e.t < limit)) continue;
        ++hits;
        if (!has(obj, first, last) && !has(obj, lb.always.data(), lb.always.data() + lb.always.size())) {
            CAPTURE(rt_test::fmt(p));
            CAPTURE(rt_test::fmt(q));
            CAPTURE(rt_test::fmt(light));
            CAPTURE(obj);
            CAPTURE(e.t);
            FAIL("an object on the segment is missing from its cell");
        }
    }
}

}  // namespace

TEST_CASE("light buffer: every object on a segment to the light is listed in its cell") {
    Rng rng(2026);
    int checked = 0, hits = 0, listed_total = 0;
    for (int round = 0; round < 6; ++round) {
        Vec3 light = rng.in_ball(15);
        Scene scene = random_scene(rng, light, 40 + 30 * round);
        Geometry g = build_geometry(scene);
        int n = round % 2 ? 64 : 16;
        LightBuffer lb = LightBuffer::build(g.object_bounds, light, n);
        REQUIRE(lb.n == n);
        REQUIRE(lb.start.size() == 6 * std::size_t(n) * n + 1);
        for (int k = 0; k < 3000; ++k) {
            // Points on and near objects (where shadow rays start) and anywhere.
            Vec3 p = k % 2 ? rng.in_ball(30) : g.object_bounds[rng.index(g.object_bounds.size())].centre() +
                                                    rng.in_ball(3);
            Vec3 v = light - p;
            double r = length(v);
            if (!(r > 1e-3)) continue;
            if (!lb.usable(p, r)) continue;
            const LightBuffer::Entry *first, *last;
            check_segment(g, lb, light, p, light, r, hits, first, last);
            listed_total += int(last - first);
            ++checked;
        }
    }
    // The property was exercised: many segments were blocked, and the cells hold far
    // fewer objects than the scenes (or the buffer would be pointless).
    CHECK(checked > 15000);
    CHECK(hits > 3000);
    CHECK(double(listed_total) / checked < 40);
}

TEST_CASE("light buffer: a sphere light's cells hold every object on a segment from p to the sphere, sorted") {
    // A sphere light's entries take a larger distance where only the box grown by much of
    // the radius reaches the cell (light_buffer.cpp): a ray from a point nearer the light
    // stops before them. Every object that the exact hit test finds on a segment from p
    // to a point of the sphere must still be listed in the cell toward p (from the
    // centre), with a distance no larger than p's from the centre.
    Rng rng(3841);
    int checked = 0, hits = 0;
    std::size_t culled = 0, kept = 0;
    for (int round = 0; round < 6; ++round) {
        const Vec3 light = rng.in_ball(15);
        const double R = round % 3 == 2 ? rng.uni(2, 4) : rng.uni(0.05, 1);
        Scene scene = random_scene(rng, light, 40 + 30 * round);
        Geometry g = build_geometry(scene);
        const int n = round % 2 ? 64 : 16;
        LightBuffer lb = LightBuffer::build(g.object_bounds, light, n, R);
        REQUIRE(lb.n == n);
        for (std::size_t c = 0; c + 1 < lb.start.size(); ++c)
            for (std::uint32_t k = lb.start[c]; k + 1 < lb.start[c + 1]; ++k)
                REQUIRE(!(lb.entries[k + 1].dmin < lb.entries[k].dmin));
        for (int k = 0; k < 4000; ++k) {
            const Vec3 p = k % 2 ? rng.in_ball(30)
                                 : g.object_bounds[rng.index(g.object_bounds.size())].centre() + rng.in_ball(3);
            const double d = length(light - p);
            if (!(d > R) || !lb.usable(p, d)) continue;
            // A point of the sphere, or inside it.
            const Vec3 q = light + (k % 3 ? rng.unit() * R : rng.in_ball(R));
            const LightBuffer::Entry *first, *last;
            check_segment(g, lb, light, p, q, d, hits, first, last);
            ++checked;
            for (const LightBuffer::Entry* e = first; e != last; ++e) {
                const Aabb& b = g.object_bounds[e->obj];
                const Vec3 gap = vmax(vmax(b.lo - light, light - b.hi), Vec3{0, 0, 0});
                if (!(length(gap) > d)) ++(double(e->dmin) > d ? culled : kept);
            }
        }
    }
    CHECK(checked > 15000);
    CHECK(hits > 3000);
    // The larger distances spare many of the tests that the grown boxes alone would ask.
    CHECK(culled > kept / 3);
}

TEST_CASE("light buffer: each cell lists its objects once, nearest box first (ties: earlier object first)") {
    // Shadow rays stop reading a cell at the first box beyond their reach: that is only
    // right if no nearer box follows it.
    Rng rng(404);
    std::size_t listed = 0, ties = 0;
    for (int round = 0; round < 4; ++round) {
        Vec3 light = rng.in_ball(10);
        Scene scene = random_scene(rng, light, 60 + 40 * round);
        Geometry g = build_geometry(scene);
        // Some objects twice over, so that equal distances occur.
        std::vector<Aabb> boxes = g.object_bounds.to_vector();
        for (std::size_t k = 0; k < g.object_bounds.size(); k += 3) boxes.push_back(g.object_bounds[k]);
        int n = round % 2 ? 32 : 8;
        LightBuffer lb = LightBuffer::build(boxes, light, n);
        REQUIRE(lb.n == n);
        REQUIRE(lb.start.size() == 6 * std::size_t(n) * n + 1);
        CHECK(lb.start.front() == 0);
        CHECK(lb.start.back() == lb.entries.size());
        for (std::size_t c = 0; c + 1 < lb.start.size(); ++c) {
            REQUIRE(lb.start[c] <= lb.start[c + 1]);
            for (std::uint32_t k = lb.start[c]; k + 1 < lb.start[c + 1]; ++k) {
                const LightBuffer::Entry &a = lb.entries[k], &b = lb.entries[k + 1];
                CHECK((a.dmin < b.dmin || (a.dmin == b.dmin && a.obj < b.obj)));
                if (a.dmin == b.dmin) ++ties;
            }
            listed += lb.start[c + 1] - lb.start[c];
        }
    }
    CHECK(listed > 1000);
    CHECK(ties > 100);
}

TEST_CASE("light buffer: cell_toward(v) finds cell(-v), on cell and face borders too") {
    // A buffer whose cell c holds the one entry c, so that the entry names the cell.
    for (int n : {1, 16, 64, 200}) {
        LightBuffer lb;
        lb.n = n;
        lb.half_n = 0.5 * n;
        const std::uint32_t cells = 6u * std::uint32_t(n) * std::uint32_t(n);
        for (std::uint32_t c = 0; c <= cells; ++c) lb.start.push_back(c);
        for (std::uint32_t c = 0; c < cells; ++c) lb.entries.push_back({c, 0.0f});
        auto same = [&](const Vec3& v) {
            const LightBuffer::Entry *a0, *a1, *b0, *b1;
            lb.cell(-v, a0, a1);
            lb.cell_toward(v, b0, b1);
            REQUIRE(a1 - a0 == 1);
            CAPTURE(rt_test::fmt(v));
            CHECK(b0 == a0);
            CHECK(b1 == a1);
        };
        Rng rng(std::uint64_t(n) + 5);
        for (int k = 0; k < 20000; ++k) same(rng.unit() * std::exp(rng.uni(-20, 20)));
        // Directions through cell borders (b / a = 2 i / n - 1 exactly), the edges and
        // corners of the cube (ties of the major axis), and signed zeros.
        for (int i = 0; i <= n; ++i)
            for (double a : {1.0, -1.0, 3.0})
                for (double sb : {1.0, -1.0}) {
                    double u = sb * (2.0 * i / n - 1) * a;
                    same({a, u, 0.25 * a});
                    same({u, a, -0.0});
                    same({0.0, u, a});
                    same({a, a, u});
                    same({u, -a, -a});
                }
        for (double x : {0.0, -0.0, 1.0, -1.0})
            for (double y : {0.0, -0.0, 1.0, -1.0})
                for (double z : {0.0, -0.0, 1.0, -1.0})
                    if (x != 0 || y != 0 || z != 0) same({x, y, z});
    }
}

TEST_CASE("light buffer: none for scenes or lights beyond float range, nor without objects") {
    std::vector<Aabb> boxes{{{0, 0, 0}, {1, 1, 1}}};
    CHECK(LightBuffer::build(boxes, {1e31, 0, 0}, 16).n == 0);
    CHECK(LightBuffer::build(boxes, {NAN, 0, 0}, 16).n == 0);
    CHECK(LightBuffer::build({{{0, 0, 0}, {HUGE_VAL, 1, 1}}}, {5, 5, 5}, 16).n == 0);
    CHECK(LightBuffer::build({Aabb{}}, {5, 5, 5}, 16).n == 0);
    LightBuffer lb = LightBuffer::build(boxes, {5, 5, 5}, 16);
    CHECK(lb.n == 16);
    // A box around the light is tested by every ray.
    LightBuffer around = LightBuffer::build(boxes, {0.5, 0.5, 0.5}, 16);
    REQUIRE(around.n == 16);
    CHECK(around.always.size() == 1);
    CHECK(around.entries.empty());
    // Many lights over a few objects: no buffers (their cells alone would take over
    // 100 MB), the BVH serves the shadow rays; the camera still has one.
    Scene many;
    many.objects.push_back(make(Sphere{{0, 0, 0}, 1}));
    for (int i = 0; i < 1000; ++i) {
        Light l;
        l.position = {double(i % 10) * 3, double(i / 10) * 3, 10};
        many.lights.push_back(l);
    }
    auto world = compile_world(many);
    CHECK(!world->light_buffers);
    CHECK(bool(world->camera_buffer));
    many.lights.resize(8);
    CHECK(bool(compile_world(many)->light_buffers));
}

namespace {

using rt_test::IsaGuard;

std::vector<std::uint8_t> render(std::shared_ptr<const World> world, int w, int h) {
    rt::ThreadPool renderer_pool(3);
    Renderer renderer(renderer_pool);
    RenderSettings settings;
    settings.width = w;
    settings.height = h;
    settings.coarse = false;
    renderer.start(std::move(world), settings);
    renderer.wait();
    return to_rgb8(renderer.snapshot());
}

// Glass and opaque objects mixed and overlapping, so that shadow rays meet several
// refractive objects (their tints multiply in order) as well as opaque ones.
Scene glass_scene() {
    Rng rng(77);
    Scene s;
    for (int i = 0; i < 60; ++i) {
        Vec3 c{rng.uni(-6, 6), rng.uni(-6, 6), rng.uni(0, 4)};
        Object o = make(i % 3 ? Shape(Sphere{c, rng.uni(0.3, 1.5)}) : Shape(Cylinder{c, c + rng.unit() * 2, 0.4}));
        if (i % 2) {
            o.material.refraction = 0.8;
            o.material.reflection = 0.1;
            o.material.scattering = 0.1;
            o.material.refractive_index = 1.4;
            o.material.colour = {rng.uni(0.5, 1), rng.uni(0.5, 1), rng.uni(0.5, 1)};
        } else {
            o.material.reflection = 0.3;
            o.material.scattering = 0.7;
            o.material.colour = {rng.uni(0, 1), rng.uni(0, 1), rng.uni(0, 1)};
        }
        s.objects.push_back(std::move(o));
    }
    for (Vec3 p : {Vec3{-8, -9, 12}, Vec3{7, -3, 9}, Vec3{0, 0, 2}}) {
        Light l;
        l.position = p;
        l.colour = {60, 60, 60};
        s.lights.push_back(l);
    }
    s.camera.position = {-14, -10, 8};
    s.camera.centre = {0, 0, 1};
    s.camera.up = {0, 0, 1};
    s.width = 160;
    s.height = 90;
    return s;
}

}  // namespace

TEST_CASE("light buffer: pictures are the same bytes as with the BVH alone, on every path") {
    IsaGuard guard;
    std::vector<std::pair<std::string, Scene>> scenes{{"glass", glass_scene()}};
    for (const char* name : {"things-like", "spheres-10k", "csg-400", "glass-stack"}) {
        std::string path = std::string(RT_SOURCE_DIR) + "/bench/scenes/" + name + ".txt", text;
        REQUIRE(read_file(path, text, Limits::max_file_size).ok());
        ParseResult parsed = parse_scene(text);
        REQUIRE(parsed.ok());
        scenes.push_back({name, parsed.scene});
    }
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        if (!set_isa(isa)) continue;
        for (const auto& [name, scene] : scenes) {
            CAPTURE(name);
            CAPTURE(isa_name(isa));
            auto world = compile_world(scene);
            REQUIRE(bool(world->light_buffers));
            REQUIRE(bool(world->camera_buffer));
            for (const LightBuffer& lb : *world->light_buffers) CHECK(lb.n > 0);
            auto plain = std::make_shared<World>(*world);
            plain->light_buffers.reset();
            plain->camera_buffer.reset();
            int w = std::max(16, scene.width / 8), h = std::max(9, scene.height / 8);
            CHECK(render(world, w, h) == render(plain, w, h));
        }
    }
}

TEST_CASE("light buffer: a view away from the scene's camera gets a buffer of its own, the same bytes") {
    IsaGuard guard;
    Scene scene = glass_scene();
    auto world = compile_world(scene);
    REQUIRE(bool(world->camera_buffer));
    CHECK(with_camera_at(world, scene.camera.position).get() == world.get());
    Camera view = scene.camera;
    view.position = {-12, 11, 7};
    auto moved = with_camera_at(world, view.position);
    REQUIRE(moved.get() != world.get());
    REQUIRE(bool(moved->camera_buffer));
    CHECK(moved->camera_buffer->position == view.position);
    CHECK(moved->camera_buffer->n > 0);
    CHECK(moved->geometry.get() == world->geometry.get());
    CHECK(world->camera_buffer->position == scene.camera.position);
    auto through = [&](std::shared_ptr<const World> w) {
        rt::ThreadPool renderer_pool(3);
        Renderer renderer(renderer_pool);
        RenderSettings settings;
        settings.width = 160;
        settings.height = 90;
        settings.coarse = false;
        settings.camera = view;
        renderer.start(std::move(w), settings);
        renderer.wait();
        return to_rgb8(renderer.snapshot());
    };
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        if (!set_isa(isa)) continue;
        CAPTURE(isa_name(isa));
        CHECK(through(moved) == through(world));
    }
    // A scene too big to make one in passing, and one without a camera buffer, keep theirs.
    Scene big;
    for (std::size_t i = 0; i <= kQuickCameraBuffer; ++i)
        big.objects.push_back(make(Sphere{{double(i % 40), double(i / 40), 0}, 0.3}));
    big.camera = scene.camera;
    auto big_world = compile_world(big);
    REQUIRE(bool(big_world->camera_buffer));
    CHECK(with_camera_at(big_world, view.position).get() == big_world.get());
    auto none = std::make_shared<World>(*world);
    none->camera_buffer.reset();
    std::shared_ptr<const World> none_c = none;
    CHECK(with_camera_at(none_c, view.position).get() == none_c.get());
}
