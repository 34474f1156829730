// Tests for objects inserted into and removed from a compiled world (World::update with
// SceneDelta::object_splices, core/world.h): random sequences of inserts, removals and
// edits in place, given to the world as deltas, give the hits of a full compile of
// the edited scene (the same object and distance for many random rays, and the same
// pictures on small scenes), down to no object at all and up again from none; spheres,
// the other primitives, CSG, meshes and planes among them.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bvh_update.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "test_random.h"
#include "test_util.h"
#include "test_world_compare.h"
#include "world.h"

using namespace rt;
using rt_test::Rng;

namespace {

Material random_material(Rng& rng) {
    Material m;
    m.reflection = rng.uni() < 0.4 ? rng.uni(0, 1) : 0;
    m.refraction = rng.uni() < 0.3 ? rng.uni(0.2, 1) : 0;
    m.scattering = rng.uni(0, 1);
    m.translusans = rng.uni(0.3, 1);
    m.refractive_index = rng.uni(1, 1.8);
    m.colour = {rng.uni(0.1, 1), rng.uni(0.1, 1), rng.uni(0.1, 1)};
    return m;
}

// A cube model (tests/models/cube.obj) as a mesh object, read once.
const Object& cube_mesh() {
    static const Object cube = [] {
        ParseOptions o;
        o.base_dir = RT_SOURCE_DIR "/tests/models";
        ParseResult r = parse_scene("thing {\n  mesh { file cube.obj scale 0.4 0.4 0.4 }\n}\n"
                                    "camera { position 0 0 5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                                    "picture_size { x_max 8 y_max 8 }\nend\n",
                                    o);
        REQUIRE(r.ok());
        REQUIRE(r.scene.objects.size() == 1);
        return r.scene.objects[0];
    }();
    return cube;
}

// Spheres mostly (a scene of them alone keeps its sphere prefix), other primitives,
// CSG, meshes, now and then a transform.
Object random_object(Rng& rng, double size) {
    const Vec3 c = rng.in_ball(size);
    const double s = rng.uni(0.2, 0.6);
    const double u = rng.uni();
    Object o{Sphere{c, s}, random_material(rng), true, SourceLoc{}};
    if (u < 0.45) return o;
    if (u < 0.7) {
        o.shape = rt_test::random_primitive_shape(rng, c, s);
    } else if (u < 0.85) {
        Csg csg;
        csg.type = rng.uni() < 0.5 ? CsgType::Union : rng.uni() < 0.5 ? CsgType::Difference : CsgType::Intersection;
        csg.operands = {
            Object{rt_test::random_primitive_shape(rng, c, s), Material::object_default(), false, SourceLoc{}},
            Object{rt_test::random_primitive_shape(rng, c + rng.in_ball(s), s), Material::object_default(), false,
                   SourceLoc{}}};
        o.shape = csg;
    } else {
        o = cube_mesh();
        std::get<Mesh>(o.shape).position = c;
        std::get<Mesh>(o.shape).rotation = {rng.uni(0, 90), rng.uni(0, 90), 0};
        o.material = random_material(rng);
    }
    if (rng.uni() < 0.1 && !std::holds_alternative<Mesh>(o.shape)) {
        Transform& t = o.transform.edit();
        t.translate = rng.in_ball(0.5);
        t.rotation = {rng.uni(0, 90), 0, rng.uni(0, 90)};
    }
    return o;
}

Plane random_plane(Rng& rng, double size) {
    Plane p;
    p.chess = rng.uni() < 0.5;
    const double z = -size * rng.uni(1, 1.5);
    p.point[0] = {0, 0, z};
    p.point[1] = {1, 0, z};
    p.point[2] = {0, 1, z};
    p.point[3] = {0, 0, 0};
    p.material = random_material(rng);
    p.material2 = random_material(rng);
    return p;
}

Scene random_scene(Rng& rng, std::size_t objects, double size) {
    Scene s;
    for (std::size_t i = 0; i < objects; ++i) s.objects.push_back(random_object(rng, size));
    s.planes.push_back(random_plane(rng, size));
    for (int k = 0; k < 2; ++k) {
        Light l;
        l.lamp = k == 0;
        l.position = rng.in_ball(size) + Vec3{0, 0, 2 * size};
        l.colour = Vec3{2, 2, 2} * (size * size);
        l.size = k == 0 ? 0.3 : 0;
        s.lights.push_back(l);
    }
    // (The up point above the centre, the origin.)
    s.camera.position = {2.5 * size, -1.5 * size, 1.2 * size}, s.camera.centre = {0, 0, 0}, s.camera.up = {0, 0, 1};
    s.width = 32, s.height = 24;
    return s;
}

// The hits of many random rays (from around the scene and the camera's) agree: the
// same object, plane or glow, at the same distance.
void check_same_hits(const World& got, const World& want, Rng& rng, double size, int rays = 400) {
    int hits = 0;
    for (int k = 0; k < rays; ++k) {
        const Vec3 o = k % 2 ? want.camera.position : rng.in_ball(2.5 * size);
        const Vec3 d = k % 2 ? normalize(rng.in_ball(size) - o) : rng.unit();
        const PickResult a = pick(got, Ray{o, d}), b = pick(want, Ray{o, d});
        CAPTURE(k);
        REQUIRE(a.hit == b.hit);
        if (!a.hit) continue;
        ++hits;
        CHECK(a.object == b.object);
        CHECK(a.plane == b.plane);
        CHECK(a.light == b.light);
        CHECK(a.t == b.t);
    }
    CHECK(hits > 0);
}

// What no slot-independent table may differ in.
void check_same_tallies(const World& got, const World& want) {
    CHECK(got.object_count() == want.object_count());
    const Aabb a = got.bounds(), b = want.bounds();
    CHECK((a.lo == b.lo && a.hi == b.hi));
    CHECK(std::memcmp(&got.radiance_bound, &want.radiance_bound, sizeof(double)) == 0);
    CHECK(std::memcmp(&got.omit_weight, &want.omit_weight, sizeof(double)) == 0);
    CHECK(got.area_lights == want.area_lights);
    CHECK(bool(got.camera_buffer) == bool(want.camera_buffer));
    CHECK(bool(got.light_buffers) == bool(want.light_buffers));
}

// One structural edit or edit in place of `s`, as the viewer makes them, merged into
// `delta`.
void random_edit(Rng& rng, Scene& s, SceneDelta& delta, double size) {
    SceneDelta d;
    const double u = rng.uni();
    const std::size_t n = s.objects.size();
    if (u < 0.3 || n == 0) {  // Add: anywhere, the end too
        const std::uint32_t at = std::uint32_t(rng.index(n + 1));
        s.objects.insert(s.objects.begin() + at, random_object(rng, size));
        d.object_splices.push_back({at, true});
    } else if (u < 0.45) {  // Duplicate: moved a little, after the original
        const std::uint32_t i = std::uint32_t(rng.index(n));
        Object copy = s.objects[i];
        rt_test::translate(copy, rng.in_ball(0.8) + Vec3{0.05, 0, 0});
        s.objects.insert(s.objects.begin() + i + 1, copy);
        d.object_splices.push_back({i + 1, true});
    } else if (u < 0.75) {  // Delete
        const std::uint32_t i = std::uint32_t(rng.index(n));
        s.objects.erase(s.objects.begin() + i);
        d.object_splices.push_back({i, false});
    } else if (u < 0.88) {  // a move or a material in place
        const std::uint32_t i = std::uint32_t(rng.index(n));
        // (A mesh moved or made transparent is compiled anew into a new slot.)
        if (rng.uni() < 0.6) rt_test::translate(s.objects[i], rng.in_ball(1.0));
        else s.objects[i].material = random_material(rng);
        d.objects.push_back(i);
    } else if (u < 0.94) {  // a plane added or removed
        if (s.planes.size() < 3 && rng.uni() < 0.6) s.planes.insert(s.planes.begin(), random_plane(rng, size));
        else if (!s.planes.empty()) s.planes.erase(s.planes.begin());
        d.all_planes = true;
    } else {  // a light added or removed
        if (s.lights.size() < 4 && rng.uni() < 0.6) {
            Light l;
            l.position = rng.in_ball(size) + Vec3{0, 0, 2 * size};
            l.colour = Vec3{1, 1, 1} * (size * size);
            s.lights.insert(s.lights.begin(), l);
        } else if (!s.lights.empty()) {
            s.lights.erase(s.lights.begin() + std::ptrdiff_t(rng.index(s.lights.size())));
        }
        d.all_lights = true;
    }
    delta.merge(d);
}

// Steps of 1 to 3 edits each, each step's world made by update() from the last and
// compared with a full compile; pictures every picture_every-th step.
void check_splice_sequences(unsigned seed, std::size_t objects, int steps, int picture_every) {
    Rng rng(seed);
    const double size = std::cbrt(double(std::max<std::size_t>(objects, 8))) * 1.2;
    Scene scene = random_scene(rng, objects, size);
    std::shared_ptr<const World> world = compile_world(scene);
    for (int step = 0; step < steps; ++step) {
        CAPTURE(step);
        SceneDelta delta;
        for (std::size_t k = 1 + rng.index(3); k > 0; --k) random_edit(rng, scene, delta, size);
        std::shared_ptr<const World> next = world->update(scene, delta);
        REQUIRE(bool(next));
        std::shared_ptr<const World> fresh = compile_world(scene);
        REQUIRE(next->object_count() == scene.objects.size());
        check_same_tallies(*next, *fresh);
        check_same_hits(*next, *fresh, rng, size);
        if (picture_every > 0 && step % picture_every == 0) rt_test::check_same_pictures(next, fresh);
        world = next;
    }
}

// The world of `scene` after `delta`, checked against a full compile.
std::shared_ptr<const World> check_update(const std::shared_ptr<const World>& world, const Scene& scene,
                                          const SceneDelta& delta, Rng& rng, double size, bool pictures = true) {
    std::shared_ptr<const World> next = world->update(scene, delta);
    REQUIRE(bool(next));
    std::shared_ptr<const World> fresh = compile_world(scene);
    check_same_tallies(*next, *fresh);
    if (!scene.objects.empty() || !scene.planes.empty()) check_same_hits(*next, *fresh, rng, size, 100);
    if (pictures) rt_test::check_same_pictures(next, fresh);
    return next;
}

SceneDelta splice(std::uint32_t at, bool insert) {
    SceneDelta d;
    d.object_splices.push_back({at, insert});
    return d;
}

}  // namespace

TEST_CASE("world splice: the delta of splices numbers the objects changed in place as the later splices leave them") {
    SceneDelta d;
    d.objects = {1, 4, 7};
    SceneDelta later;
    later.object_splices = {{4, false}, {0, true}};  // 4 removed, then one inserted at 0
    later.objects = {2};
    d.merge(later);
    // 1 -> 1 -> 2; 4 gone; 7 -> 6 -> 7; and the later 2.
    CHECK(d.objects == std::vector<std::uint32_t>{2, 7});
    CHECK(d.object_splices == std::vector<SceneDelta::Splice>{{4, false}, {0, true}});
    CHECK(!d.in_place());
    CHECK(!d.empty());
    SceneDelta all = SceneDelta::all();
    all.merge(later);
    CHECK((all.everything && all.object_splices.empty() && all.objects.empty()));
}

TEST_CASE("world splice: random inserts, removals and edits give the hits and pictures of a full compile (small "
          "scenes: light buffers, the sphere prefix, meshes and CSG)") {
    check_splice_sequences(11, 40, 40, 4);
    check_splice_sequences(12, 3, 30, 3);
}

TEST_CASE("world splice: the same with tables of several chunks (no light buffers), many steps") {
    check_splice_sequences(13, 3000, 40, 0);
}

TEST_CASE("world splice: every object removed, the last one too, and objects inserted into the empty scene") {
    Rng rng(21);
    const double size = 3;
    Scene scene = random_scene(rng, 6, size);
    std::shared_ptr<const World> world = compile_world(scene);
    while (!scene.objects.empty()) {
        const std::uint32_t i = std::uint32_t(scene.objects.size() - 1);  // the last
        scene.objects.erase(scene.objects.begin() + i);
        world = check_update(world, scene, splice(i, false), rng, size);
    }
    CHECK(world->object_count() == 0);
    CHECK(world->spliced() == 6);
    for (int k = 0; k < 4; ++k) {
        scene.objects.insert(scene.objects.begin(), random_object(rng, size));
        world = check_update(world, scene, splice(0, true), rng, size);
    }
    // All of them at once, and one again into a world compiled from none.
    SceneDelta all_out;
    for (int k = 0; k < 4; ++k) all_out.object_splices.push_back({0, false});
    scene.objects.clear();
    world = check_update(world, scene, all_out, rng, size);
    std::shared_ptr<const World> none = compile_world(scene);
    scene.objects.push_back(random_object(rng, size));
    scene.objects.push_back(random_object(rng, size));
    SceneDelta two = splice(0, true);
    two.object_splices.push_back({1, true});
    check_update(none, scene, two, rng, size);
    // With no plane either.
    scene.planes.clear();
    SceneDelta planes;
    planes.all_planes = true;
    planes.merge(two);
    check_update(none, scene, planes, rng, size);
}

TEST_CASE("world splice: an object inserted and removed in one delta, and one changed after it was inserted") {
    Rng rng(22);
    const double size = 3;
    Scene scene = random_scene(rng, 10, size);
    std::shared_ptr<const World> world = compile_world(scene);
    SceneDelta d = splice(3, true);  // in and out again: no slot needed
    d.merge(splice(3, false));
    d.merge(splice(10, true));  // at the end
    scene.objects.push_back(Object{Sphere{{0.5, 0.5, 0.5}, 0.4}, random_material(rng), true, SourceLoc{}});
    SceneDelta moved;
    moved.objects = {10};
    d.merge(moved);
    rt_test::translate(scene.objects[10], {0.5, 0, 0});
    world = check_update(world, scene, d, rng, size);
    // Then moved again, and an object before it removed: its slot follows.
    scene.objects.erase(scene.objects.begin());
    SceneDelta e = splice(0, false);
    rt_test::translate(scene.objects[9], {0, 0.5, 0});
    SceneDelta again;
    again.objects = {9};
    e.merge(again);
    world = check_update(world, scene, e, rng, size);
    CHECK(world->slot_of(9) == 10);  // the inserted one's slot after the 10 compiled
    CHECK(world->object_of(0) == -1);  // the removed one's slot is empty
    CHECK(world->object_of(10) == 9);
}

TEST_CASE("world splice: splices that do not fit the scene are refused") {
    Rng rng(23);
    Scene scene = random_scene(rng, 5, 3);
    std::shared_ptr<const World> world = compile_world(scene);
    CHECK(!world->update(scene, splice(9, false)));  // no such object
    CHECK(!world->update(scene, splice(2, true)));   // the scene has not one more
    Scene more = scene;
    more.objects.push_back(more.objects[0]);
    CHECK(!world->update(more, SceneDelta{}));  // one more, no splice said so
}

TEST_CASE("world splice: a duplicate in place is picked as the original, as a full compile picks it") {
    Rng rng(24);
    const double size = 3;
    Scene scene = random_scene(rng, 8, size);
    std::shared_ptr<const World> world = compile_world(scene);
    scene.objects.insert(scene.objects.begin() + 4, scene.objects[3]);
    world = check_update(world, scene, splice(4, true), rng, size);
    const Aabb b = world->geometry->object_bounds[world->slot_of(4)];
    const Vec3 o = scene.camera.position;
    const PickResult p = pick(*world, Ray{o, normalize(b.centre() - o)});
    if (p.hit && (p.object == 3 || p.object == 4)) CHECK(p.object == 3);
}

TEST_CASE("world splice: a tree after many inserts holds every object within its boxes (links follow)") {
    Rng rng(25);
    Scene scene = random_scene(rng, 500, 8);
    std::shared_ptr<const World> world = compile_world(scene);
    for (int k = 0; k < 300; ++k) {
        const std::uint32_t at = std::uint32_t(rng.index(scene.objects.size() + 1));
        scene.objects.insert(scene.objects.begin() + at, random_object(rng, 8));
        world = world->update(scene, splice(at, true));
        REQUIRE(bool(world));
    }
    CHECK(world->spliced() == 300);
    // The links the tree keeps are its own: a move refits it like a built one's.
    std::uint32_t some = 0;
    while (std::holds_alternative<Mesh>(scene.objects[some].shape)) ++some;
    rt_test::translate(scene.objects[some], {1, 1, 1});
    SceneDelta delta;
    delta.objects = {some};
    delta.normalize();
    std::shared_ptr<const World> moved = world->update(scene, delta);
    REQUIRE(bool(moved));
    CHECK(moved->spliced() == world->spliced());  // refitted: no splice of its own
    CHECK(moved->geometry->bvh.links == world->geometry->bvh.links);  // the links the splices followed, kept by the refit
    check_same_hits(*moved, *compile_world(scene), rng, 8, 1000);
}
