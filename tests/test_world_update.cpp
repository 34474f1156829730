// Tests for World::update (core/world.h): random sequences of edits, each given to the
// world as a SceneDelta, give the world a full compile of the edited scene gives,
// table for table (bit for bit) and picture for picture (the films compared byte for
// byte, on both instruction-set paths); the BVH alone may differ in shape. An edit
// shares every table and chunk of a table it does not touch with the world before.
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "renderer.h"
#include "shapes.h"
#include "simd.h"
#include "test_random.h"
#include "test_util.h"
#include "test_world_compare.h"
#include "world.h"

using namespace rt;
using rt_test::Rng;
using rt_test::check_same_pictures;
using rt_test::check_same_world;

namespace {

// The share of glass among the materials: shadow rays through several of them are
// tinted in an order that must not depend on the BVH's shape.
double g_glass = 0.3;

Material random_material(Rng& rng) {
    Material m;
    m.reflection = rng.uni() < 0.4 ? rng.uni(0, 1) : 0;
    m.refraction = rng.uni() < g_glass ? rng.uni(0.2, 1) : 0;
    m.scattering = rng.uni(0, 1);
    m.translusans = rng.uni(0.3, 1);
    m.refractive_index = rng.uni(1, 1.8);
    m.colour = {rng.uni(0.1, 1), rng.uni(0.1, 1), rng.uni(0.1, 1)};
    return m;
}

Object random_object(Rng& rng, const Vec3& c, double s) {
    Object o{rt_test::random_primitive_shape(rng, c, s), random_material(rng), true, SourceLoc{}};
    if (rng.uni() < 0.15) {
        Csg csg;
        csg.type = rng.uni() < 0.5 ? CsgType::Union : rng.uni() < 0.5 ? CsgType::Difference : CsgType::Intersection;
        csg.operands = {Object{rt_test::random_primitive_shape(rng, c, s), Material::object_default(), false, SourceLoc{}},
                        Object{rt_test::random_primitive_shape(rng, c + rng.in_ball(s), s), Material::object_default(), false, SourceLoc{}}};
        o.shape = csg;
    }
    return o;
}

Light random_light(Rng& rng, double size) {
    Light l;
    l.lamp = rng.uni() < 0.6;
    l.position = rng.in_ball(size) + Vec3{0, 0, size};
    l.colour = Vec3{rng.uni(1, 4), rng.uni(1, 4), rng.uni(1, 4)} * (size * size * 0.3);
    l.size = rng.uni() < 0.7 ? rng.uni(0.2, 1.0) : 0;
    return l;
}

Scene random_scene(Rng& rng, std::size_t objects, std::size_t lights) {
    Scene s;
    const double size = std::cbrt(double(objects)) * 1.2;
    for (std::size_t i = 0; i < objects; ++i)
        s.objects.push_back(random_object(rng, rng.in_ball(size), rng.uni(0.2, 0.7)));
    Plane floor;
    floor.chess = true;
    floor.point[0] = {0, 0, -size};
    floor.point[1] = {1, 0, -size};
    floor.point[2] = {0, 1, -size};
    floor.point[3] = {0, 0, 0};
    floor.material = random_material(rng);
    floor.material2 = random_material(rng);
    s.planes.push_back(floor);
    for (std::size_t k = 0; k < lights; ++k) s.lights.push_back(random_light(rng, size));
    s.camera.position = {2.5 * size, -1.5 * size, 1.2 * size};
    s.camera.centre = {0, 0, 0};
    s.camera.up = s.camera.centre + Vec3{0, 0, 1};
    s.width = 40;
    s.height = 30;
    return s;
}

// One edit in place, as the viewer makes them, noted in `delta`.
void edit_in_place(Rng& rng, Scene& s, SceneDelta& delta) {
    const double size = std::cbrt(double(s.objects.size())) * 1.2;
    const std::uint32_t i = std::uint32_t(rng.index(s.objects.size()));
    switch (rng.index(7)) {
        case 0:  // a move handle: near or far, now and then out of the scene's bounds
        case 1: rt_test::translate(s.objects[i], rng.in_ball(rng.uni() < 0.7 ? 0.5 : 3 * size)); break;
        case 2: s.objects[i].material = random_material(rng); break;
        case 3: {
            if (s.lights.empty()) return;
            const std::uint32_t k = std::uint32_t(rng.index(s.lights.size()));
            Light& l = s.lights[k];
            if (rng.uni() < 0.5) l.position = l.position + rng.in_ball(1.5);
            else if (rng.uni() < 0.5) l.colour = l.colour * rng.uni(0.5, 1.5);
            else l.size = l.size > 0 ? 0 : 0.5;  // a glow disc comes or goes
            delta.lights.push_back(k);
            return;
        }
        case 4: {
            Plane& p = s.planes[0];
            if (rng.uni() < 0.5) p.material2 = random_material(rng);
            else p.point[3] = p.point[3] + rng.in_ball(0.5);
            delta.planes.push_back(0);
            return;
        }
        case 5:
            s.camera.position = s.camera.position + rng.in_ball(1);
            delta.camera = true;
            return;
        default:  // the same structure, other sizes
            if (auto* sp = std::get_if<Sphere>(&s.objects[i].shape)) sp->radius *= rng.uni(0.5, 1.5);
            else rt_test::translate(s.objects[i], {0, 0, 0.25});
            break;
    }
    delta.objects.push_back(i);
}

// An edit that changes the lists or an object's structure: no update in place.
void edit_structure(Rng& rng, Scene& s) {
    const double size = std::cbrt(double(s.objects.size())) * 1.2;
    if (rng.uni() < 0.4) s.objects.push_back(random_object(rng, rng.in_ball(size), 0.5));
    else if (rng.uni() < 0.5) s.objects.erase(s.objects.begin() + std::ptrdiff_t(rng.index(s.objects.size())));
    else s.objects[rng.index(s.objects.size())].shape = Cylinder{{0, 0, 0}, {0, 0, 1}, 0.3};
}

// Every step compares the updated world with a full compile table for table; every
// picture_every-th step also their pictures (the slow part: both ISA paths, both worlds).
void check_edit_sequences(unsigned seed, std::size_t objects, std::size_t lights, int steps, int picture_every = 3) {
    Rng rng(seed);
    Scene scene = random_scene(rng, objects, lights);
    std::shared_ptr<const World> world = compile_world(scene);
    int updated = 0, refused = 0;
    bool glow_bvhs = false;
    for (int step = 0; step < steps; ++step) {
        CAPTURE(step);
        SceneDelta delta;
        const bool structural = rng.uni() < 0.08;
        if (structural) {
            edit_structure(rng, scene);
            delta = SceneDelta::all();
        } else {
            for (std::size_t k = 1 + rng.index(3); k > 0; --k) edit_in_place(rng, scene, delta);
            delta.normalize();
        }
        std::shared_ptr<const World> next = world->update(scene, delta);
        std::shared_ptr<const World> fresh = compile_world(scene);
        if (structural) {
            CHECK(!next);  // the lists changed: a full compile
            ++refused;
            world = fresh;
            continue;
        }
        REQUIRE(bool(next));
        ++updated;
        check_same_world(*next, *fresh);
        if (step % picture_every == 0) check_same_pictures(next, fresh);
        glow_bvhs = glow_bvhs || bool(next->glow_bvh);
        world = next;
    }
    CHECK(updated > steps / 2);
    CHECK(glow_bvhs == (lights >= 16));  // (the scenes with many lamps have enough glow discs for one)
    MESSAGE(updated << " updates in place, " << refused << " full compiles");
}

}  // namespace

TEST_CASE("world update: random edits through deltas give the world of a full compile, table for table and picture "
          "for picture (small scene: light buffers)") {
    check_edit_sequences(1, 60, 3, 40);
}

TEST_CASE("world update: the same with tables of several chunks and a BVH of glow discs") {
    check_edit_sequences(2, 2600, 24, 30, 7);
}

TEST_CASE("world update: the same among much glass (shadow rays tinted by several objects)") {
    g_glass = 0.85;
    check_edit_sequences(5, 150, 2, 30);
    g_glass = 0.3;
}

TEST_CASE("world update: an object whose structure changed takes a new slot; other numbers of objects are refused") {
    Rng rng(3);
    Scene scene = random_scene(rng, 50, 2);
    scene.objects[3].shape = Sphere{{0, 0, 0}, 1};
    std::shared_ptr<const World> world = compile_world(scene);
    SceneDelta delta;
    delta.objects = {3};
    scene.objects[3].shape = Cylinder{{0, 0, 0}, {1, 0, 0}, 1};
    std::shared_ptr<const World> reshaped = world->update(scene, delta);
    REQUIRE(bool(reshaped));
    CHECK(reshaped->slot_of(3) == 50);
    CHECK(reshaped->object_of(3) == -1);
    check_same_pictures(reshaped, compile_world(scene));
    delta.objects = {50};  // no such object
    CHECK(!world->update(scene, delta));
    scene.objects.pop_back();
    delta.objects.clear();
    CHECK(!world->update(scene, delta));
    CHECK(!world->update(scene, SceneDelta::all()));
}

TEST_CASE("world update: an edit shares every table and chunk of a table it does not touch") {
    Rng rng(4);
    Scene scene;
    for (int i = 0; i < 5000; ++i)
        scene.objects.push_back(Object{Sphere{{double(i % 100), double(i / 100), 0.5}, 0.4}, random_material(rng), true, {}});
    scene.lights.push_back(random_light(rng, 50));
    scene.camera.position = {50, -80, 60};
    scene.camera.centre = {50, 25, 0};
    scene.camera.up = scene.camera.centre + Vec3{0, 0, 1};
    std::shared_ptr<const World> world = compile_world(scene);
    auto unshared = [](const auto& a, const auto& b) {
        std::size_t n = 0;
        for (std::size_t c = 0; c < a.chunk_count(); ++c) n += !a.shares_chunk(b, c);
        return n;
    };

    // A material: that object's chunk of the materials, nothing else.
    scene.objects[2500].material.colour = {0.1, 0.2, 0.3};
    SceneDelta delta;
    delta.objects = {2500};
    std::shared_ptr<const World> coloured = world->update(scene, delta);
    REQUIRE(bool(coloured));
    CHECK(coloured->geometry.get() == world->geometry.get());
    CHECK(unshared(coloured->materials, world->materials) == 1);
    CHECK(unshared(coloured->lights, world->lights) == 0);

    // A move: its sphere's and box's chunks, and the chunks of the BVH nodes on its way
    // up the tree; the materials not at all.
    rt_test::translate(scene.objects[2500], {0.3, -0.2, 0.1});
    std::shared_ptr<const World> moved = coloured->update(scene, delta);
    REQUIRE(bool(moved));
    const Geometry &g = *moved->geometry, &before = *coloured->geometry;
    CHECK(unshared(g.spheres, before.spheres) == 1);
    CHECK(unshared(g.object_bounds, before.object_bounds) == 1);
    CHECK(g.object_node.shares(before.object_node));
    CHECK(g.bvh.items.shares(before.bvh.items));
    const std::size_t nodes = unshared(g.bvh.nodes, before.bvh.nodes);
    CHECK(nodes >= 1);
    CHECK(nodes <= 16);
    CHECK(unshared(moved->materials, coloured->materials) == 0);
    CHECK(world->geometry->spheres.flat() != nullptr);  // a compiled world's arrays are one block each
    CHECK(g.spheres.flat() == nullptr);

    // A light: its chunk of the lights; the geometry and materials shared.
    scene.lights[0].position = scene.lights[0].position + Vec3{1, 0, 0};
    SceneDelta lit;
    lit.lights = {0};
    std::shared_ptr<const World> relit = moved->update(scene, lit);
    REQUIRE(bool(relit));
    CHECK(relit->geometry.get() == moved->geometry.get());
    CHECK(unshared(relit->materials, moved->materials) == 0);
    CHECK(unshared(relit->lights, moved->lights) == 1);
    check_same_world(*relit, *compile_world(scene));
}
