// Tests for the BVH (core/bvh.h, core/bvh.cpp): traversal with pruning finds the same
// nearest hit as trying every object, an any-hit query agrees with brute-force
// occlusion, the float boxes never lose an item the ray crosses, nodes stay 112 bytes (four children),
// memory per object stays small and the work per ray grows like log(objects).
// All randomness is seeded, so a failure repeats.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "test_bvh_nesting.h"
#include "bvh.h"
#include "shapes.h"
#include "test_brute.h"
#include "test_random.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::Failures;
using rt_test::Hit;
using rt_test::Rng;
using rt_test::brute_nearest;
using rt_test::fmt;

namespace {

Object sphere(const Vec3& c, double r) {
    Object o;
    o.shape = Sphere{c, r};
    return o;
}

// N spheres in a 20-unit box with radii from 1e-4 to 3, a few huge (holding most ray
// origins) and some exact duplicates of earlier ones.
Scene random_spheres(Rng& rng, std::size_t n) {
    Scene s;
    for (std::size_t i = 0; i < n; ++i) {
        double u = rng.uni();
        if (i > 0 && u < 0.15) {
            s.objects.push_back(s.objects[rng.index(i)]);  // duplicate
            continue;
        }
        Vec3 c{rng.uni(-10, 10), rng.uni(-10, 10), rng.uni(-10, 10)};
        double r = u < 0.2 ? rng.uni(1e-4, 1e-3) : (u > 0.98 ? rng.uni(20, 1000) : std::exp(rng.uni(std::log(0.05), std::log(3.0))));
        s.objects.push_back(sphere(c, r));
    }
    return s;
}

Hit bvh_nearest(const Geometry& g, const Vec3& o, const Vec3& d, std::size_t* calls = nullptr) {
    Hit h;
    SpanScratch scratch;
    g.bvh.traverse(o, d, HUGE_VAL, [&](std::uint32_t item, double tmax) -> double {
        if (calls) ++*calls;
        SpanEnd e;
        if (g.hit(item, o, d, kDelta, e, scratch) && (e.t < h.t || (e.t == h.t && item < h.obj))) h = {true, item, e.t};
        return std::min(tmax, h.t);
    });
    return h;
}

// Some rays aim at a random sphere (so they hit), some go anywhere; some run along an
// axis, where the slab test divides by zero.
void random_ray(Rng& rng, const Scene& s, Vec3& o, Vec3& d) {
    o = {rng.uni(-15, 15), rng.uni(-15, 15), rng.uni(-15, 15)};
    double u = rng.uni();
    if (u < 0.6) {
        const Sphere& sp = std::get<Sphere>(s.objects[rng.index(s.objects.size())].shape);
        d = normalize(sp.position + rng.unit() * (sp.radius * rng.uni(0, 0.99)) - o);
        if (length2(d) == 0) d = {1, 0, 0};
    } else if (u < 0.9) {
        d = rng.unit();
    } else {
        d = Vec3{};
        d[int(rng.index(3))] = rng.uni() < 0.5 ? 1 : -1;
    }
}

}  // namespace

TEST_CASE("bvh: nearest hit through the BVH with pruning equals trying every sphere (object and t)") {
    for (std::size_t n : {1u, 2u, 10u, 1000u}) {
        CAPTURE(n);
        Rng rng(unsigned(100 + n));
        Scene scene = random_spheres(rng, n);
        Geometry g = build_geometry(scene);
        Failures f;
        int hits = 0;
        const int rays = n >= 1000 ? 3000 : 1000;
        for (int k = 0; k < rays; ++k) {
            Vec3 o, d;
            random_ray(rng, scene, o, d);
            Hit a = bvh_nearest(g, o, d), b = brute_nearest(g, o, d);
            hits += b.hit;
            if (a.hit != b.hit || a.obj != b.obj || a.t != b.t) {
                char buf[160];
                std::snprintf(buf, sizeof buf, "bvh: %d obj %u t %.17g, brute force: %d obj %u t %.17g; ", a.hit, a.obj, a.t,
                              b.hit, b.obj, b.t);
                f.add(buf + ("o=" + fmt(o) + " d=" + fmt(d)));
            }
        }
        CHECK_MESSAGE(f.count == 0, f.first);
        CHECK(hits > rays / 3);
    }
}

using rt_test::boxes_nested;

// The same big nodes' bins must hold every item: each item's box lies inside its
// leaf's float box, and each node's boxes inside its parent's, for boxes listed in
// rows (long runs of the same bins) and in random order.
TEST_CASE("bvh: a big tree's boxes nest and hold their items, its items in order or not") {
    std::vector<Aabb> rows, random;
    for (int j = 0; j < 150; ++j)
        for (int i = 0; i < 150; ++i) {
            Aabb b;
            b.lo = {i - 75.4, j - 75.4, 0.0};
            b.hi = {i - 74.6, j - 74.6, 0.8 + 1e-4 * (j * 150 + i)};  // each taller than the last
            rows.push_back(b);
        }
    Rng rng(808);
    for (int i = 0; i < 20000; ++i) {
        Aabb b;
        b.lo = {rng.uni(-50, 50), rng.uni(-50, 50), rng.uni(-50, 50)};
        b.hi = b.lo + Vec3{rng.uni(0, 3), rng.uni(0, 3), rng.uni(0, 3)};
        random.push_back(b);
    }
    for (const std::vector<Aabb>* boxes : {&rows, &random}) {
        for (int threads : {1, 2}) {
            Bvh bvh;
            bvh.build(*boxes, threads);
            REQUIRE(bvh.items.size() == boxes->size());
            const int bad = boxes_nested(bvh.nodes, [&](std::uint32_t s, const float* box) {
                const Aabb& b = (*boxes)[bvh.items[s]];
                for (int k = 0; k < 3; ++k)
                    if (!(box[k] <= b.lo[k] && b.hi[k] <= box[3 + k])) return false;
                return true;
            });
            CHECK(bad == 0);
        }
    }
}

// Big nodes (8192+ items) are binned a run of items with the same bins at a time:
// items listed in order (a grid's rows, sorted by x) make long runs, random ones short.
TEST_CASE("bvh: a big scene's nearest hits equal trying every sphere, its items in order or not") {
    for (bool sorted : {false, true}) {
        CAPTURE(sorted);
        Rng rng(sorted ? 4711u : 4712u);
        Scene scene = random_spheres(rng, 20000);
        if (sorted)
            std::stable_sort(scene.objects.begin(), scene.objects.end(), [](const Object& a, const Object& b) {
                return std::get<Sphere>(a.shape).position.x < std::get<Sphere>(b.shape).position.x;
            });
        Geometry g = build_geometry(scene);
        Failures f;
        int hits = 0;
        const int rays = 2000;
        for (int k = 0; k < rays; ++k) {
            Vec3 o, d;
            random_ray(rng, scene, o, d);
            Hit a = bvh_nearest(g, o, d), b = brute_nearest(g, o, d);
            hits += b.hit;
            if (a.hit != b.hit || a.obj != b.obj || a.t != b.t)
                f.add("bvh and brute force differ: o=" + fmt(o) + " d=" + fmt(d));
        }
        CHECK_MESSAGE(f.count == 0, f.first);
        CHECK(hits > rays / 3);
    }
}

TEST_CASE("bvh: any-hit below a distance, stopping at the first hit, agrees with brute-force occlusion") {
    for (std::size_t n : {1u, 2u, 10u, 1000u}) {
        CAPTURE(n);
        Rng rng(unsigned(200 + n));
        Scene scene = random_spheres(rng, n);
        Geometry g = build_geometry(scene);
        SpanScratch scratch;
        Failures f;
        int blocked = 0, open = 0;
        for (int k = 0; k < 2000; ++k) {
            Vec3 o, d;
            random_ray(rng, scene, o, d);
            double limit = std::exp(rng.uni(std::log(0.01), std::log(40.0)));
            bool want = false;
            for (std::uint32_t i = 0; i < n && !want; ++i) {
                SpanEnd e;
                want = g.hit(i, o, d, 0.0, e, scratch) && e.t < limit;
            }
            bool got = false;
            int calls_after_hit = 0;
            g.bvh.traverse(o, d, limit, [&](std::uint32_t item, double) -> double {
                if (got) ++calls_after_hit;
                SpanEnd e;
                if (g.hit(item, o, d, 0.0, e, scratch) && e.t < limit) {
                    got = true;
                    return -1;
                }
                return limit;
            });
            if (got != want) f.add(std::string(want ? "missed" : "invented") + " an occluder; o=" + fmt(o) + " d=" + fmt(d));
            if (calls_after_hit) f.add("traversal went on after fn returned a negative value");
            (want ? blocked : open)++;
        }
        CHECK_MESSAGE(f.count == 0, f.first);
        CHECK(blocked > 100);
        CHECK(open > 100);
    }
}

// The float boxes must be conservative: every item whose (double) box the ray crosses
// within [0, tmax] is visited when fn never prunes. Boxes far from the origin, tiny
// boxes, flat boxes and rays starting on a box face are the hard cases.
TEST_CASE("bvh: without pruning every item whose box the ray crosses is visited (unit or scaled direction), and empty boxes never are") {
    Rng rng(300);
    Failures f;
    for (int scene = 0; scene < 20; ++scene) {
        double scale = std::pow(10.0, rng.uni(-3, 6));
        std::vector<Aabb> boxes;
        for (int i = 0; i < 300; ++i) {
            Aabb b;
            if (i % 50 == 7) {
                boxes.push_back(b);  // empty
                continue;
            }
            Vec3 c{rng.uni(-1, 1) * scale, rng.uni(-1, 1) * scale, rng.uni(-1, 1) * scale};
            Vec3 e{rng.uni(0, 0.05) * scale, rng.uni(0, 0.05) * scale, rng.uni(0, 0.05) * scale};
            if (i % 7 == 0) e[i % 3] = 0;  // flat
            if (i % 11 == 0) e = Vec3{} + e * 1e-9;  // a dot
            b.grow(c - e);
            b.grow(c + e);
            boxes.push_back(b);
        }
        Bvh bvh;
        bvh.build(boxes);
        for (int k = 0; k < 300; ++k) {
            Vec3 o{rng.uni(-1.2, 1.2) * scale, rng.uni(-1.2, 1.2) * scale, rng.uni(-1.2, 1.2) * scale};
            const Aabb& target = boxes[rng.index(boxes.size())];
            Vec3 d = rng.unit();
            if (!target.empty()) {
                Vec3 p{rng.uni(target.lo.x, target.hi.x), rng.uni(target.lo.y, target.hi.y), rng.uni(target.lo.z, target.hi.z)};
                if (k % 4 == 0) {
                    // Start on one of the target's faces, running along an axis.
                    int axis = int(rng.index(3));
                    o = p;
                    o[axis] = target.lo[axis];
                    d = Vec3{};
                    d[(axis + 1) % 3] = 1;
                } else if (length2(p - o) > 0) {
                    d = normalize(p - o);
                }
            }
            double tmax = rng.uni() < 0.5 ? HUGE_VAL : rng.uni(0, 3) * scale;
            std::vector<char> seen(boxes.size(), 0);
            // Half the rays are given as an unnormalised direction and its length, as
            // shadow rays are: the same line, so the same boxes must be visited.
            auto visit = [&](std::uint32_t item, double t) -> double {
                seen[item]++;
                return t;
            };
            if (k % 2) {
                double len = std::pow(10.0, rng.uni(-3, 3));
                bvh.traverse(o, d * len, len, tmax, visit);
            } else {
                bvh.traverse(o, d, tmax, visit);
            }
            for (std::size_t i = 0; i < boxes.size(); ++i) {
                const Aabb& b = boxes[i];
                if (b.empty()) {
                    if (seen[i]) f.add("an empty box was visited");
                    continue;
                }
                if (seen[i] > 1) f.add("an item was visited twice");
                // Double-precision slab test, inclusive.
                double t0 = 0, t1 = tmax;
                for (int a = 0; a < 3 && t0 <= t1; ++a) {
                    if (d[a] == 0) {
                        if (o[a] < b.lo[a] || o[a] > b.hi[a]) t0 = HUGE_VAL;
                        continue;
                    }
                    double ta = (b.lo[a] - o[a]) / d[a], tb = (b.hi[a] - o[a]) / d[a];
                    if (ta > tb) std::swap(ta, tb);
                    t0 = std::max(t0, ta);
                    t1 = std::min(t1, tb);
                }
                if (t0 <= t1 && !seen[i]) {
                    char buf[200];
                    std::snprintf(buf, sizeof buf, "scale %g tmax %.17g t0 %.17g t1 %.17g lo %s hi %s; ", scale, tmax, t0, t1,
                                  fmt(b.lo).c_str(), fmt(b.hi).c_str());
                    f.add(buf + ("a crossed box was not visited; o=" + fmt(o) + " d=" + fmt(d)));
                }
            }
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
}

// bvh.h promises that the float boxes never miss what the double-precision shapes hit.
// A tetrahedron's corners lie on its box's edges, so a ray that hits just inside a
// corner crosses the box within rounding of its edge; from a few units away the ray's
// origin rounded to float is already off by more than the boxes are padded.
TEST_CASE("bvh: rays hitting just inside a tetrahedron's corner from a distance are not culled by the float boxes") {
    Rng rng(450);
    Failures f;
    int hits = 0;
    for (int k = 0; k < 40; ++k) {
        Tetrahedron t;
        Vec3 base{rng.uni(-1, 1), rng.uni(-1, 1), rng.uni(-1, 1)};
        for (Vec3& v : t.v) v = base + rng.unit() * rng.uni(0.2, 0.6);
        Scene scene;
        Object o;
        o.shape = t;
        scene.objects.push_back(o);
        Geometry g = build_geometry(scene);
        Vec3 centroid = (t.v[0] + t.v[1] + t.v[2] + t.v[3]) / 4;
        for (int j = 0; j < 100; ++j) {
            const Vec3& corner = t.v[rng.index(4)];
            Vec3 target = corner + (centroid - corner) * std::pow(10.0, rng.uni(-9, -5));
            Vec3 origin = target + rng.unit() * rng.uni(5, 100);
            Vec3 d = normalize(target - origin);
            Hit a = bvh_nearest(g, origin, d), b = brute_nearest(g, origin, d);
            hits += b.hit;
            if (a.hit != b.hit) f.add("culled: o=" + fmt(origin) + " d=" + fmt(d));
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
    CHECK(hits > 2000);

    // The smallest case found: one tetrahedron, one ray aimed a millionth inside its
    // second corner from about 15 units away.
    Tetrahedron t;
    t.v[0] = {0.28, -0.14, -0.16};
    t.v[1] = {0.46, -0.24, -0.42};
    t.v[2] = {0.44, -0.35, -0.23};
    t.v[3] = {0.13, -0.44, -0.29};
    Scene scene;
    Object o;
    o.shape = t;
    scene.objects.push_back(o);
    auto world = compile_world(scene);
    Vec3 centroid = (t.v[0] + t.v[1] + t.v[2] + t.v[3]) / 4;
    Vec3 origin{-8.57, -9.38, -8.71};
    Vec3 d = normalize(t.v[1] + (centroid - t.v[1]) * 1e-6 - origin);
    Hit b = brute_nearest(*world->geometry, origin, d);
    REQUIRE(b.hit);  // t = 15.2907 with the shape's own test
    CHECK(bvh_nearest(*world->geometry, origin, d).hit);
    CHECK(pick(*world, Ray{origin, d}).hit);
}

TEST_CASE("bvh: a skewed scene (exponentially spaced spheres) still gives the brute-force nearest hit") {
    Scene scene;
    for (int i = 0; i < 400; ++i) scene.objects.push_back(sphere({std::pow(1.04, i), 0.01 * (i % 7), 0}, 0.3));
    Geometry g = build_geometry(scene);
    Rng rng(400);
    Failures f;
    for (int k = 0; k < 1000; ++k) {
        Vec3 o{rng.uni(-5, 6e6), rng.uni(-2, 2), rng.uni(-2, 2)};
        Vec3 d = k % 2 ? Vec3{k % 4 == 1 ? 1.0 : -1.0, 0, 0} : rng.unit();
        Hit a = bvh_nearest(g, o, d), b = brute_nearest(g, o, d);
        if (a.hit != b.hit || a.obj != b.obj || a.t != b.t) f.add("o=" + fmt(o) + " d=" + fmt(d));
    }
    CHECK_MESSAGE(f.count == 0, f.first);
}

TEST_CASE("bvh: the world's nearest hit on exact ties is the earlier object (file order)") {
    // Many copies of the same few spheres: which copy the BVH visits first depends on
    // how the build partitioned them, but docs/rendering.md §2 says the earlier one wins.
    Rng rng(500);
    Scene scene;
    std::vector<Object> originals;
    for (int i = 0; i < 50; ++i) originals.push_back(sphere({rng.uni(-10, 10), rng.uni(-10, 10), rng.uni(-10, 10)}, rng.uni(0.3, 1)));
    for (int i = 0; i < 1000; ++i) scene.objects.push_back(originals[rng.index(originals.size())]);
    auto world = compile_world(scene);
    Failures f;
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
        Vec3 o, d;
        random_ray(rng, scene, o, d);
        // pick() normalises the direction again; use the very same bits.
        Hit b = brute_nearest(*world->geometry, o, normalize(d));
        PickResult p = pick(*world, Ray{o, d});
        hits += b.hit;
        if (p.hit != b.hit || (b.hit && (p.object != int(b.obj) || p.t != b.t))) {
            char buf[120];
            std::snprintf(buf, sizeof buf, "pick: object %d t %.17g, first in file order: %u t %.17g; ", p.object, p.t, b.obj, b.t);
            f.add(buf + ("o=" + fmt(o) + " d=" + fmt(d)));
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
    CHECK(hits > 500);
}

TEST_CASE("bvh: nodes are 112 bytes and the BVH for 100,000 spheres takes under 64 bytes per object") {
    CHECK(sizeof(BvhNode) == 112);
    Rng rng(600);
    Scene scene;
    const std::size_t n = 100000;
    scene.objects.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
        scene.objects.push_back(sphere({rng.uni(-100, 100), rng.uni(-100, 100), rng.uni(-100, 100)}, rng.uni(0.1, 1)));
    Geometry g = build_geometry(scene);
    REQUIRE(g.bvh.items.size() == n);
    double per_object = double(g.bvh.memory_bytes()) / double(n);
    CAPTURE(per_object);
    CHECK(per_object < 64);
    // Each item appears in exactly one leaf.
    std::vector<char> seen(n, 0);
    for (const BvhNode& node : g.bvh.nodes)
        for (std::uint32_t ref : node.child)
            if (BvhNode::is_leaf(ref) && ref != BvhNode::kEmpty)
                for (std::uint32_t i = 0; i < BvhNode::leaf_count(ref); ++i) seen[g.bvh.items[BvhNode::leaf_first(ref) + i]]++;
    CHECK(std::count(seen.begin(), seen.end(), 1) == std::ptrdiff_t(n));
}

// A cubic grid of spheres, side k: k^3 objects. Rays from outside aim into the grid and
// stop at their nearest hit; the number of objects tried per ray should grow like
// log(objects), not like the grid's side or the object count.
TEST_CASE("bvh: objects tried per ray grow roughly with log(objects): 100k grid versus 1k grid") {
    auto calls_per_ray = [](int side) {
        Scene scene;
        scene.objects.reserve(std::size_t(side) * side * side);
        for (int x = 0; x < side; ++x)
            for (int y = 0; y < side; ++y)
                for (int z = 0; z < side; ++z) scene.objects.push_back(sphere({double(x), double(y), double(z)}, 0.4));
        Geometry g = build_geometry(scene);
        Rng rng(700);
        std::size_t calls = 0;
        int hits = 0;
        const int rays = 2000;
        Vec3 centre = Vec3{1, 1, 1} * ((side - 1) / 2.0);
        for (int k = 0; k < rays; ++k) {
            Vec3 o = centre + rng.unit() * (side * 1.5);
            Vec3 target{rng.uni(0, side - 1), rng.uni(0, side - 1), rng.uni(0, side - 1)};
            hits += bvh_nearest(g, o, normalize(target - o), &calls).hit;
        }
        CHECK(hits > rays * 9 / 10);
        return double(calls) / rays;
    };
    double small = calls_per_ray(10);  // 1,000 spheres
    double large = calls_per_ray(46);  // 97,336 spheres
    CAPTURE(small);
    CAPTURE(large);
    CHECK(large < 4 * small);
}

// The build splits big subtrees across threads; each thread count must give the same
// tree, node for node, or pictures would depend on the machine. A single-threaded
// build is the reference.
TEST_CASE("bvh: the tree is the same, byte for byte, whatever the number of build threads") {
    Rng rng(800);
    std::vector<Aabb> boxes;
    const std::size_t n = 70000;  // over kParallelBinItems: the records are made in two halves at once
    for (std::size_t i = 0; i < n; ++i) {
        Aabb b;
        if (i % 101 != 7) {  // some empty boxes, left out of the tree
            Vec3 c{rng.uni(-50, 50), rng.uni(-50, 50), rng.uni(-5, 5)};
            double r = rng.uni(0.01, 2);
            b.lo = c - Vec3{r, r, r};
            b.hi = c + Vec3{r, r, r};
            if (i % 13 == 0 && i > 0) b = boxes[i / 2];  // duplicates
        }
        boxes.push_back(b);
    }
    Bvh one;
    one.build(boxes, 1);
    REQUIRE(!one.nodes.empty());
    // Every non-empty box is an item exactly once, the empty ones none.
    std::vector<std::uint32_t> expected, got = one.items.to_vector();
    for (std::size_t i = 0; i < n; ++i)
        if (!boxes[i].empty()) expected.push_back(std::uint32_t(i));
    std::sort(got.begin(), got.end());
    CHECK(got == expected);
    for (int threads : {2, 3, 8}) {
        CAPTURE(threads);
        Bvh many;
        many.build(boxes, threads);
        REQUIRE(many.nodes.size() == one.nodes.size());
        REQUIRE(many.items.size() == one.items.size());
        CHECK(same_bits(many.nodes, one.nodes));
        CHECK(same_bits(many.items, one.items));
    }
}

TEST_CASE("bvh: float boxes are those of the library's nextafter, for ordinary and extreme coordinates") {
    // The reference: the rounding step written with std::nextafter.
    auto reference = [](const Aabb& b, float out[6]) {
        double m = 0;
        for (int k = 0; k < 3; ++k) m = std::max({m, std::fabs(b.lo[k]), std::fabs(b.hi[k])});
        const double pad = m * 1e-6 + 1e-30;
        for (int k = 0; k < 3; ++k) {
            float lo = float(b.lo[k] - pad), hi = float(b.hi[k] + pad);
            if (double(lo) > b.lo[k] - pad) lo = std::nextafter(lo, -INFINITY);
            if (double(hi) < b.hi[k] + pad) hi = std::nextafter(hi, INFINITY);
            out[k] = lo;
            out[3 + k] = hi;
        }
    };
    const double special[] = {0.0, -0.0, 1e-45, -1e-45, 1e-40, 1e-30, -1e-30, 1.0, -1.0, 0.1, 3.4028234e38,
                              -3.4028234e38, 3.5e38, -3.5e38, 1e300, -1e300, 1e15, -1e15, 16777217.0, -16777217.0,
                              // x - pad (or x + pad) is within half a subnormal of 0: the rounded
                              // bound is a zero, which steps to the smallest subnormal
                              1.000001000001e-30, -1.000001000001e-30, 1.0000010000010001e-30};
    for (double x : special) {
        const Aabb b{{x, x, x}, {x, x, x}};
        float want[6], got[6];
        reference(b, want);
        to_float_box(b, got);
        CAPTURE(x);
        REQUIRE(std::memcmp(want, got, sizeof want) == 0);
    }
    Rng rng(41);
    for (int round = 0; round < 200000; ++round) {
        Aabb b;
        for (int k = 0; k < 3; ++k) {
            double a, c;
            if (round % 3 == 0) {
                a = special[rng.index(std::size(special))];
                c = special[rng.index(std::size(special))];
            } else {
                const double scale = std::pow(10.0, rng.uni(-40, 40));
                a = rng.uni(-1, 1) * scale;
                c = a + rng.uni(0, 1) * scale;
            }
            if (a > c) std::swap(a, c);
            (&b.lo.x)[k] = a;
            (&b.hi.x)[k] = c;
        }
        float want[6], got[6];
        reference(b, want);
        to_float_box(b, got);
        CAPTURE(round);
        REQUIRE(std::memcmp(want, got, sizeof want) == 0);
    }
}
