// Tests for moving objects in a compiled world (core/bvh_update.h): after a chain of
// moves refitted into the BVH, the compiled shapes equal a fresh compile of the moved
// scene bit for bit, and every ray finds the same nearest hit as trying every object
// of that fresh compile (brute force), for spheres, tetrahedra, cylinders, tori and
// CSGs, in small (single-object leaves) and larger (up to 4 per leaf) scenes.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "bvh_update.h"
#include "shapes.h"
#include "test_brute.h"
#include "test_random.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::Hit;
using rt_test::Rng;
using rt_test::brute_nearest;

namespace {

Object random_primitive(Rng& rng, const Vec3& c, double s) {
    // (Built whole: assigning a shape to a default object trips a false
    // -Wfree-nonheap-object in GCC 12's variant.)
    return Object{rt_test::random_primitive_shape(rng, c, s), Material::object_default(), false, SourceLoc{}};
}

Scene random_scene(Rng& rng, std::size_t n, double size) {
    Scene s;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 c{rng.uni(-size, size), rng.uni(-size, size), rng.uni(-size, size)};
        double r = rng.uni(0.1, 0.8);
        if (rng.uni() < 0.15) {
            Object o;
            Csg csg;
            csg.type = rng.uni() < 0.5 ? CsgType::Union : CsgType::Difference;
            csg.operands = {random_primitive(rng, c, r), random_primitive(rng, c + rng.in_ball(r), r)};
            o.shape = csg;
            s.objects.push_back(o);
        } else {
            s.objects.push_back(random_primitive(rng, c, r));
        }
    }
    return s;
}

// A move as the viewer makes it: World::update with the moved object, `links` handed in
// and set to the new tree's.
std::shared_ptr<const World> move(const Scene& scene, const World& world, std::uint32_t obj,
                                  std::shared_ptr<const BvhLinks>& links) {
    SceneDelta delta;
    delta.objects = {obj};
    delta.normalize();
    std::shared_ptr<const World> next = world.update(scene, delta, links);
    if (next) links = next->geometry->bvh.links;
    return next;
}

void check_moves(std::size_t n, unsigned seed) {
    Rng rng(seed);
    const double size = std::cbrt(double(n)) * 1.5;
    Scene scene = random_scene(rng, n, size);
    std::shared_ptr<const World> world = compile_world(scene);
    std::shared_ptr<const BvhLinks> links;
    int refits = 0;
    for (int step = 0; step < 12; ++step) {
        // Small nudges, jumps across the scene and far outside it.
        std::uint32_t obj = std::uint32_t(rng.index(n));
        double reach = step % 3 == 0 ? 0.2 : step % 3 == 1 ? size : 6 * size;
        rt_test::translate(scene.objects[obj], rng.in_ball(reach));
        std::shared_ptr<const World> next = move(scene, *world, obj, links);
        REQUIRE(bool(next));
        ++refits;
        world = next;
        Geometry fresh = build_geometry(scene);
        CHECK(same_shapes(*world->geometry, fresh));
        int mismatches = 0;
        for (int k = 0; k < 400; ++k) {
            // Rays from around the scene toward points near objects (half of them
            // toward the moved one), so that most hit something.
            Vec3 o = rng.in_ball(3 * size) + Vec3{0, 0, 0};
            std::uint32_t target = k % 2 ? obj : std::uint32_t(rng.index(n));
            Vec3 p = fresh.object_bounds[target].centre() + rng.in_ball(0.5);
            Vec3 d = normalize(p - o);
            Hit want = brute_nearest(fresh, o, normalize(d));  // as pick() normalises it
            PickResult got = pick(*world, Ray{o, d});

            bool same = got.hit == want.hit && (!want.hit || (std::uint32_t(got.object) == want.obj && got.t == want.t));
            if (!same) ++mismatches;
        }
        CHECK(mismatches == 0);
    }
    CHECK(refits == 12);
    CHECK(bool(links));
}

}  // namespace

TEST_CASE("bvh_update: moved objects give the hits of a fresh compile (single-object leaves)") { check_moves(600, 11); }

TEST_CASE("bvh_update: moved objects give the hits of a fresh compile (leaves of up to 4)") { check_moves(6000, 12); }

TEST_CASE("bvh_update: a move that changes an object's structure gives the hits of a fresh compile") {
    Rng rng(5);
    Scene scene = random_scene(rng, 50, 5);
    scene.objects[3].shape = Sphere{{0, 0, 0}, 1};
    std::shared_ptr<const World> world = compile_world(scene);
    std::shared_ptr<const BvhLinks> links;
    scene.objects[3].shape = Cylinder{{0, 0, 0}, {1, 0, 0}, 1};
    std::shared_ptr<const World> next = move(scene, *world, 3, links);
    REQUIRE(bool(next));
    // (A refit cannot change a leaf's kind: the object leaves the tree and comes back.)
    std::shared_ptr<const World> fresh = compile_world(scene);
    int mismatches = 0, on_moved = 0;
    for (int k = 0; k < 300; ++k) {
        Vec3 o = rng.in_ball(15);
        Vec3 d = normalize(fresh->geometry->object_bounds[k % 2 ? 3 : rng.index(50)].centre() - o);
        PickResult want = pick(*fresh, Ray{o, d}), got = pick(*next, Ray{o, d});
        if (got.hit != want.hit || got.object != want.object || got.t != want.t) ++mismatches;
        on_moved += got.object == 3;
    }
    CHECK(mismatches == 0);
    CHECK(on_moved > 50);  // the rays toward the moved cylinder find it
    CHECK(!move(scene, *world, 50, links));  // no such object
}
