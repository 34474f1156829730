// Tests for the primitives in core/shapes.cpp: the inside intervals (spans) that
// Geometry::spans reports along random lines agree with inside tests written here
// straight from each shape's definition (docs/rendering.md §7), span ends lie on the
// surface, normals are unit and outward, and a few hits have a known distance.
// The torus is also checked against a sphere-traced march of its distance function.
// All randomness is seeded, so a failure repeats.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "shapes.h"
#include "test_models.h"
#include "test_random.h"
#include "test_util.h"

using namespace rt;
using rt_test::Failures;
using rt_test::Rng;
using rt_test::fmt;

namespace {

using Model = rt_test::Prim;

Model random_sphere(Rng& rng) {
    Model m;
    m.kind = Model::Sph;
    m.c = {rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    m.r = rng.uni(0.2, 2);
    return m;
}

Model random_tetra(Rng& rng) {
    Model m;
    m.kind = Model::Tet;
    Vec3 base{rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    for (;;) {
        for (Vec3& p : m.v) p = base + rng.in_ball(1.5);
        // Avoid slivers: every corner at least 0.1 from the opposite face.
        bool ok = true;
        for (int i = 0; i < 4; ++i) ok = ok && m.height(i) > 0.1;
        if (ok) return m;
    }
}

Model random_cylinder(Rng& rng) {
    Model m;
    m.kind = Model::Cyl;
    m.e1 = {rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    m.e2 = m.e1 + rng.unit() * rng.uni(0.2, 3);
    m.r = rng.uni(0.1, 1.5);
    return m;
}

// Ring tori (minor < major) with any axis; oblique axes are the common case.
Model random_torus(Rng& rng) {
    Model m;
    m.kind = Model::Tor;
    m.c = {rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    m.axis = rng.unit() * rng.uni(0.5, 3);  // not normalised: the format normalises it
    m.R = rng.uni(0.5, 2);
    m.r = rng.uni(0.1, 0.9) * m.R;
    return m;
}

Model random_box(Rng& rng) {
    Model m;
    m.kind = Model::Bx;
    m.e1 = {rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    // Corners in any order, each side at least 0.2.
    for (int k = 0; k < 3; ++k) m.e2[k] = m.e1[k] + (rng.uni() < 0.5 ? -1 : 1) * rng.uni(0.2, 2.5);
    return m;
}

// Cones pointed at either end, and frustums.
Model random_cone(Rng& rng) {
    Model m;
    m.kind = Model::Con;
    m.e1 = {rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
    m.e2 = m.e1 + rng.unit() * rng.uni(0.3, 3);
    m.r = rng.uni(0.1, 1.5);
    m.r2 = rng.uni(0.1, 1.5);
    const double pick = rng.uni();
    if (pick < 0.3) m.r2 = 0;
    else if (pick < 0.6) m.r = 0;
    return m;
}

Model random_model(Rng& rng, int kind) {
    switch (kind) {
        case Model::Bx: return random_box(rng);
        case Model::Con: return random_cone(rng);
        case Model::Sph: return random_sphere(rng);
        case Model::Tet: return random_tetra(rng);
        case Model::Cyl: return random_cylinder(rng);
        default: return random_torus(rng);
    }
}

struct Compiled : rt_test::CompiledObject {
    explicit Compiled(const Model& m) : CompiledObject(m.object()) {}
};

// A line that crosses the model's bounding ball, from outside or from inside.
struct Line {
    Vec3 o, d;
};
Line random_line(Rng& rng, const Model& m, bool from_inside) {
    Vec3 bc;
    double br = 0;
    m.bound(bc, br);
    Line l;
    if (from_inside) {
        for (int tries = 0;; ++tries) {
            l.o = bc + rng.in_ball(br);
            if (m.inside(l.o) || tries > 10000) break;
        }
        l.d = rng.unit();
    } else {
        l.o = bc + rng.unit() * (br * rng.uni(1.05, 4));
        Vec3 target = bc + rng.in_ball(br);
        l.d = rng.uni() < 0.1 ? rng.unit() : normalize(target - l.o);
    }
    return l;
}

// The shared property: membership, span order, ends on the surface, normals.
void check_spans_against_model(const Model& m, const Compiled& cg, const Line& l, Rng& rng, Failures& f,
                               int& inside_samples) {
    std::vector<Span> spans;
    SpanScratch scratch;
    cg.g.spans(cg.node, l.o, l.d, spans, scratch);
    Vec3 bc;
    double br = 0;
    m.bound(bc, br);
    rt_test::check_spans(
        spans, cg.g, l.o, l.d, bc, br, true, rng, f, inside_samples, [&](const Vec3& p) { return m.sd(p) < 0; },
        [&](const Vec3& p) { return std::fabs(m.sd(p)); },
        [&](const Vec3& p, const Vec3& n, const auto& fail) {
            const double h = 1e-4;
            if (!(m.sd(p + n * h) > 0)) fail("p + h n is not outside");
            // Near an edge, stepping back along one face's normal can leave through
            // the neighbouring face.
            if (m.near_pieces(p, 20 * h) == 1 && !(m.sd(p - n * h) < 0)) fail("p - h n is not inside");
        });
}

const char* kind_name(int kind) {
    static const char* names[] = {"sphere", "tetrahedron", "cylinder", "torus", "box", "cone"};
    return names[kind];
}

// For each primitive kind: `shapes` random primitives of that kind (seeded by `seed` and
// the kind), compiled, each given to shape(model, compiled, rng); then kind_done().
template <class Shape, class Done>
void each_random_primitive(unsigned seed, int shapes, Shape shape, Done kind_done) {
    for (int kind = Model::Sph; kind <= Model::Con; ++kind) {
        CAPTURE(kind_name(kind));
        Rng rng(seed + unsigned(kind));
        for (int inst = 0; inst < shapes; ++inst) {
            Model m = random_model(rng, kind);
            Compiled cg(m);
            shape(m, cg, rng);
        }
        kind_done();
    }
}

}  // namespace

TEST_CASE("shape: spans of random rays against random primitives agree with point membership") {
    Failures f;
    int inside_samples = 0, rays = 0;
    each_random_primitive(
        1234u, 150,
        [&](const Model& m, Compiled& cg, Rng& rng) {
            for (int k = 0; k < 8; ++k) {
                Line l = random_line(rng, m, k % 3 == 2);
                check_spans_against_model(m, cg, l, rng, f, inside_samples);
                ++rays;
            }
        },
        [&] {
            CHECK_MESSAGE(f.count == 0, f.first);
            // The property is only worth something if many samples were inside.
            CHECK(inside_samples > rays * 5);
            f = Failures();
            inside_samples = rays = 0;
        });
}

TEST_CASE("shape: hit from outside is the first span entry, exit from inside the first span end") {
    Failures f;
    int hits = 0, exits = 0;
    each_random_primitive(
        777u, 100,
        [&](const Model& m, Compiled& cg, Rng& rng) {
            SpanScratch scratch;
            for (int k = 0; k < 6; ++k) {
                bool from_inside = k % 2 == 1;
                Line l = random_line(rng, m, from_inside);
                if (from_inside && !m.inside(l.o)) continue;
                std::vector<Span> spans;
                cg.g.spans(cg.node, l.o, l.d, spans, scratch);
                std::string ray = "o=" + fmt(l.o) + " d=" + fmt(l.d);
                SpanEnd e;
                bool hit = cg.g.hit(0, l.o, l.d, kDelta, e, scratch);
                const Span* first = nullptr;
                for (const Span& s : spans)
                    if (s.in.t > kDelta) {
                        first = &s;
                        break;
                    }
                if (hit != (first != nullptr) || (hit && e.t != first->in.t)) f.add("hit disagrees with spans; " + ray);
                hits += hit;
                if (from_inside) {
                    // From inside, the ray leaves at the end of the span holding t = 0.
                    bool ex = cg.g.exit(0, l.o, l.d, e, scratch);
                    const Span* holding = nullptr;
                    for (const Span& s : spans)
                        if (s.in.t <= 0 && s.out.t > 0) holding = &s;
                    if (!holding) {
                        f.add("origin inside the model but in no span; " + ray);
                        continue;
                    }
                    if (!ex || e.t != holding->out.t) f.add("exit is not the end of the span holding the origin; " + ray);
                    exits += ex;
                }
            }
        },
        [&] {
            CHECK_MESSAGE(f.count == 0, f.first);
            CHECK(hits > 50);
            CHECK(exits > 50);
            f = Failures();
            hits = exits = 0;
        });
}

TEST_CASE("shape: ray through a sphere's centre from outside hits at distance |o - c| - radius") {
    Rng rng(42);
    Failures f;
    for (int k = 0; k < 500; ++k) {
        Model m = random_sphere(rng);
        Compiled cg(m);
        double dist = m.r * rng.uni(1.01, 20);
        Vec3 o = m.c + rng.unit() * dist;
        Vec3 d = normalize(m.c - o);
        SpanEnd e;
        SpanScratch scratch;
        if (!cg.g.hit(0, o, d, 0, e, scratch)) {
            f.add("no hit from " + fmt(o));
            continue;
        }
        double want = dist - m.r;
        if (std::fabs(e.t - want) > 1e-12 * dist) f.add("hit at the wrong distance from " + fmt(o));
        Vec3 n = cg.g.normal(e.node, e.face, o + d * e.t);
        if (length(n + d) > 1e-9) f.add("normal is not -d at the hit from " + fmt(o));
        // From the centre itself the ray leaves after one radius, and enters nothing.
        if (!cg.g.exit(0, m.c, d, e, scratch) || std::fabs(e.t - m.r) > 1e-12 * (1 + m.r)) f.add("exit from the centre");
        if (cg.g.hit(0, m.c, d, kDelta, e, scratch)) f.add("hit from inside the sphere");
    }
    CHECK_MESSAGE(f.count == 0, f.first);
}

// hit() finds the leading run of spheres by object number (Geometry::sphere_prefix) and
// the others through their nodes: spheres on both sides of a CSG and a cylinder must
// each be hit at the distance of their own surface, with their own node.
TEST_CASE("shape: spheres before and after other shapes are hit at their own surfaces") {
    Scene scene;
    auto sphere_at = [](double x) {
        Object o;
        o.shape = Sphere{{x, 0, 0}, 0.5};
        return o;
    };
    Model cyl;
    cyl.kind = Model::Cyl;
    cyl.e1 = {2, -0.5, 0};
    cyl.e2 = {2, 0.5, 0};
    cyl.r = 0.4;
    Csg csg;
    csg.type = CsgType::Difference;
    csg.operands = {sphere_at(3), sphere_at(3.2)};
    Object csg_obj;
    csg_obj.shape = std::move(csg);
    scene.objects = {sphere_at(0), sphere_at(1), cyl.object(), sphere_at(4), csg_obj, sphere_at(5)};
    Geometry g = build_geometry(scene);
    CHECK(g.sphere_prefix == 2);
    SpanScratch scratch;
    for (std::uint32_t obj : {0u, 1u, 3u, 5u}) {
        double x = obj == 0 ? 0 : obj == 1 ? 1 : obj == 3 ? 4 : 5;
        // From above, straight down onto the sphere's top.
        SpanEnd e;
        REQUIRE(g.hit(obj, {x, 0, 3}, {0, 0, -1}, 0, e, scratch));
        CHECK(e.t == 2.5);
        CHECK(e.node == g.object_node[obj]);
        CHECK(g.nodes[e.node].kind == NodeKind::Sphere);
        CHECK(g.spheres[g.nodes[e.node].index].c.x == x);
        CHECK_FALSE(g.hit(obj, {x + 2, 0, 3}, {0, 0, -1}, 0, e, scratch));
    }
    Scene none_first;
    none_first.objects = {cyl.object(), sphere_at(0)};
    CHECK(build_geometry(none_first).sphere_prefix == 0);
    Scene all_spheres;
    all_spheres.objects = {sphere_at(0), sphere_at(1), sphere_at(2)};
    Geometry a = build_geometry(all_spheres);
    CHECK(a.sphere_prefix == 3);
    REQUIRE(a.object_bounds.size() == 3);
    CHECK(a.object_bounds[2].lo.x == 1.5);
    CHECK(a.object_bounds[2].hi.x == 2.5);
}

TEST_CASE("shape: rays along a cylinder's axis hit the near cap and leave through the far one") {
    Rng rng(43);
    Failures f;
    for (int k = 0; k < 300; ++k) {
        Model m = random_cylinder(rng);
        Compiled cg(m);
        SpanScratch scratch;
        Vec3 a = normalize(m.e2 - m.e1);
        double len = length(m.e2 - m.e1);
        Vec3 perp = normalize(cross(a, rng.unit()));
        double gap = rng.uni(0.1, 5);
        SpanEnd e;
        // Inside the radius: the near cap at `gap`, the far cap at gap + len.
        Vec3 o = m.e2 + a * gap + perp * (m.r * rng.uni(0, 0.95));
        Vec3 d = -a;
        if (!cg.g.hit(0, o, d, 0, e, scratch) || std::fabs(e.t - gap) > 1e-9) {
            f.add("near cap missed from " + fmt(o));
            continue;
        }
        if (length(cg.g.normal(e.node, e.face, o + d * e.t) - a) > 1e-9) f.add("near cap normal is not +axis");
        if (!cg.g.exit(0, o + d * e.t, d, e, scratch) || std::fabs(e.t - len) > 1e-9)
            f.add("far cap not at the cylinder's length from the near one");
        else if (length(cg.g.normal(e.node, e.face, o + d * (gap + e.t)) + a) > 1e-9)
            f.add("far cap normal is not -axis");
        // Parallel to the axis but outside the radius: nothing (the original hit it).
        Vec3 o2 = m.e2 + a * gap + perp * (m.r * rng.uni(1.05, 3));
        std::vector<Span> spans;
        cg.g.spans(cg.node, o2, d, spans, scratch);
        if (!spans.empty()) f.add("a ray parallel to the axis outside the radius has spans, from " + fmt(o2));
        // Across the axis at mid-length: the side, at distance - radius.
        double dist = m.r + gap;
        Vec3 mid = (m.e1 + m.e2) / 2;
        if (!cg.g.hit(0, mid + perp * dist, -perp, 0, e, scratch) || std::fabs(e.t - gap) > 1e-9)
            f.add("side missed across the axis");
        else if (length(cg.g.normal(e.node, e.face, mid + perp * m.r) - perp) > 1e-9)
            f.add("side normal is not radial");
    }
    CHECK_MESSAGE(f.count == 0, f.first);
}

TEST_CASE("shape: a ray along a tetrahedron face's inward normal hits that face at the known distance") {
    Rng rng(44);
    Failures f;
    for (int k = 0; k < 300; ++k) {
        Model m = random_tetra(rng);
        Compiled cg(m);
        SpanScratch scratch;
        for (int face = 0; face < 4; ++face) {
            // The face opposite corner `face`; its outward normal points away from it.
            const Vec3& a = m.v[(face + 1) % 4];
            const Vec3& b = m.v[(face + 2) % 4];
            const Vec3& c = m.v[(face + 3) % 4];
            Vec3 n = normalize(cross(b - a, c - a));
            if (dot(n, m.v[face] - a) > 0) n = -n;
            // A random point well inside the face (barycentric weights >= 0.1).
            double w0 = rng.uni(0.1, 0.8), w1 = rng.uni(0.1, 0.9 - w0);
            Vec3 q = a * w0 + b * w1 + c * (1 - w0 - w1);
            double gap = rng.uni(0.05, 5);
            SpanEnd e;
            if (!cg.g.hit(0, q + n * gap, -n, 0, e, scratch) || std::fabs(e.t - gap) > 1e-9) {
                f.add("face missed or at the wrong distance");
                continue;
            }
            if (length(cg.g.normal(e.node, e.face, q) - n) > 1e-9) f.add("face normal differs from the corners' normal");
            // Leaving through it from just inside.
            if (!cg.g.exit(0, q - n * 0.01, n, e, scratch) || std::fabs(e.t - 0.01) > 1e-9)
                f.add("exit through the face at the wrong distance");
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
}

TEST_CASE("shape: torus first entry agrees with a sphere-traced march, oblique axes included") {
    Rng rng(45);
    Failures f;
    int compared = 0, hits = 0, skipped = 0;
    for (int inst = 0; inst < 120; ++inst) {
        Model m = random_torus(rng);
        if (inst % 4 == 0) m.axis = {1, 1, 0};  // the original's frame sheared exactly these
        Compiled cg(m);
        SpanScratch scratch;
        for (int k = 0; k < 10; ++k) {
            // Origins outside the torus: in its hole, near it, or far away.
            Vec3 o;
            do {
                o = m.c + rng.in_ball((m.R + m.r) * 3);
            } while (!(m.sd(o) > 1e-3));
            Vec3 d = normalize(m.c + rng.in_ball(m.R + m.r) - o);
            // sd is the exact distance to the surface, so stepping by it never
            // crosses the surface: the march converges to the first entry.
            double t = 0, tmax = length(o - m.c) + m.R + m.r + 1, closest = HUGE_VAL;
            bool entered = false, gave_up = true;
            for (int step = 0; step < 200000; ++step) {
                double s = m.sd(o + d * t);
                closest = std::min(closest, s);
                if (s < 1e-12) {
                    entered = true, gave_up = false;
                    break;
                }
                t += s;
                if (t > tmax) {
                    gave_up = false;
                    break;
                }
            }
            // Grazing rays: the march cannot decide within the step budget, and a ray
            // that only comes within rounding of the surface may go either way.
            if (gave_up || (!entered && closest < 1e-9)) {
                ++skipped;
                continue;
            }
            ++compared;
            SpanEnd e;
            bool hit = cg.g.hit(0, o, d, 0, e, scratch);
            std::string ray = "o=" + fmt(o) + " d=" + fmt(d);
            if (hit != entered) {
                f.add(std::string(entered ? "missed" : "hit") + " against the march; " + ray);
                continue;
            }
            if (hit) {
                ++hits;
                if (std::fabs(e.t - t) > 1e-6) {
                    char buf[96];
                    std::snprintf(buf, sizeof buf, "entry %.12g vs march %.12g; ", e.t, t);
                    f.add(buf + ray);
                }
            }
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
    CHECK(hits > 200);
    CHECK(skipped < compared / 20);
}

TEST_CASE("shape: torus with an oblique axis: through the hole along the axis misses, across it hits both tubes") {
    Model m;
    m.kind = Model::Tor;
    m.c = {1, -2, 0.5};
    m.axis = {1, 1, 1};
    m.R = 2;
    m.r = 0.5;
    Compiled cg(m);
    SpanScratch scratch;
    Vec3 a = normalize(m.axis);
    std::vector<Span> spans;
    cg.g.spans(cg.node, m.c + a * 10, -a, spans, scratch);
    CHECK(spans.empty());

    // In the torus's plane through its centre: tubes at |s| in [R - r, R + r].
    Vec3 u = normalize(Vec3{1, -1, 0});
    spans.clear();  // spans() appends
    cg.g.spans(cg.node, m.c + u * 5, -u, spans, scratch);
    REQUIRE(spans.size() == 2);
    CHECK(spans[0].in.t == doctest::Approx(5 - 2.5).epsilon(1e-12));
    CHECK(spans[0].out.t == doctest::Approx(5 - 1.5).epsilon(1e-12));
    CHECK(spans[1].in.t == doctest::Approx(5 + 1.5).epsilon(1e-12));
    CHECK(spans[1].out.t == doctest::Approx(5 + 2.5).epsilon(1e-12));
    Vec3 n = cg.g.normal(spans[0].in.node, spans[0].in.face, m.c + u * 2.5);
    CHECK(length(n - u) < 1e-9);
    n = cg.g.normal(spans[0].out.node, spans[0].out.face, m.c + u * 1.5);
    CHECK(length(n + u) < 1e-9);
}

// The torus's solid is (R - sqrt(x^2 + y^2))^2 + z^2 < r^2 (docs/rendering.md §7), which for
// minor > major (the format's default torus: major 1, minor 2) is a self-intersecting
// "spindle" whose inner lemon is inside as well.
TEST_CASE("shape: spindle torus (minor > major, the format default) is solid inside its inner lemon") {
    Rng rng(46);
    Failures f;
    int inside_samples = 0, rays = 0;
    for (int inst = 0; inst < 40; ++inst) {
        Model m = random_torus(rng);
        m.r = m.R * rng.uni(1.1, 2.5);
        Compiled cg(m);
        for (int k = 0; k < 8; ++k, ++rays) check_spans_against_model(m, cg, random_line(rng, m, k % 3 == 2), rng, f, inside_samples);
    }
    CHECK_MESSAGE(f.count == 0, f.first);

    // The smallest case: the default torus, a ray through its centre along the axis.
    Model d;
    d.kind = Model::Tor;
    d.c = {0, 0, 0};
    d.R = 1;
    d.r = 2;
    Compiled cg(d);
    SpanScratch scratch;
    std::vector<Span> spans;
    cg.g.spans(cg.node, {0.1, 0, -5}, {0, 0, 1}, spans, scratch);
    CHECK(spans.size() == 1);  // one solid chord, no hollow lemon
    SpanEnd e;
    bool hit = cg.g.hit(0, {0, 0, -5}, {0, 0, 1}, 0, e, scratch);
    CHECK(hit);
    if (hit) CHECK(e.t == doctest::Approx(5 - std::sqrt(3.0)).epsilon(1e-9));
}

namespace {
// The spans of one object along o + t d (d made unit here).
std::vector<Span> spans_of(const Shape& shape, const Vec3& o, const Vec3& d, rt_test::CompiledObject*& keep) {
    Object obj;
    obj.shape = shape;
    keep = new rt_test::CompiledObject(obj);
    std::vector<Span> out;
    SpanScratch scratch;
    keep->g.spans(keep->node, o, normalize(d), out, scratch);
    return out;
}
bool near(const Vec3& a, const Vec3& b, double tol = 1e-12) { return length(a - b) <= tol; }
}  // namespace

TEST_CASE("shape: box spans and normals at hand-computed points, corners in any order") {
    rt_test::CompiledObject* c = nullptr;
    for (const Box& box : {Box{{1, 2, 3}, {3, 5, 4}}, Box{{3, 5, 4}, {1, 2, 3}}, Box{{1, 5, 3}, {3, 2, 4}}}) {
        auto s = spans_of(box, {0, 3, 3.5}, {1, 0, 0}, c);
        REQUIRE(s.size() == 1);
        CHECK(s[0].in.t == 1);
        CHECK(s[0].out.t == 3);
        CHECK(near(c->g.normal(s[0].in.node, s[0].in.face, {1, 3, 3.5}), {-1, 0, 0}));
        CHECK(near(c->g.normal(s[0].out.node, s[0].out.face, {3, 3, 3.5}), {1, 0, 0}));
        delete c;
        s = spans_of(box, {2, 3.5, 10}, {0, 0, -1}, c);
        REQUIRE(s.size() == 1);
        CHECK(s[0].in.t == 6);
        CHECK(s[0].out.t == 7);
        CHECK(near(c->g.normal(s[0].in.node, s[0].in.face, {2, 3.5, 4}), {0, 0, 1}));
        // Bounds are the box itself.
        const Aabb b = c->g.bounds(c->node);
        CHECK(b.lo == Vec3{1, 2, 3});
        CHECK(b.hi == Vec3{3, 5, 4});
        delete c;
        // A line beside it misses; one along a face's plane, outside, too.
        CHECK(spans_of(box, {0, 6, 3.5}, {1, 0, 0}, c).empty());
        delete c;
        // Diagonal: enters through x = 1 at y = 3 (t = sqrt 2), leaves through y = 5 at x = 3.
        s = spans_of(box, {0, 2, 3.5}, {1, 1, 0}, c);
        REQUIRE(s.size() == 1);
        CHECK(s[0].in.t == doctest::Approx(std::sqrt(2.0)).epsilon(1e-14));
        CHECK(s[0].out.t == doctest::Approx(3 * std::sqrt(2.0)).epsilon(1e-14));
        delete c;
    }
}

TEST_CASE("shape: cone and frustum spans and normals at hand-computed points") {
    rt_test::CompiledObject* c = nullptr;
    // Radius 1 at the origin to a point at z = 2: radius 0.5 at z = 1.
    const Cone cone{{0, 0, 0}, {0, 0, 2}, 1, 0};
    auto s = spans_of(cone, {-5, 0, 1}, {1, 0, 0}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == doctest::Approx(4.5).epsilon(1e-14));
    CHECK(s[0].out.t == doctest::Approx(5.5).epsilon(1e-14));
    CHECK(near(c->g.normal(s[0].in.node, s[0].in.face, {-0.5, 0, 1}), Vec3{-1, 0, 0.5} / std::sqrt(1.25), 1e-14));
    const Aabb b = c->g.bounds(c->node);
    CHECK(near(b.lo, {-1, -1, 0}));
    CHECK(near(b.hi, {1, 1, 2}));
    delete c;
    // Down at x = 0.25: the side where the radius is 0.25 (z = 1.5), out through the base.
    s = spans_of(cone, {0.25, 0, 10}, {0, 0, -1}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == doctest::Approx(8.5).epsilon(1e-14));
    CHECK(s[0].out.t == 10);
    CHECK(near(c->g.normal(s[0].out.node, s[0].out.face, {0.25, 0, 0}), {0, 0, -1}));
    delete c;
    // Above the tip: the mirror image of the cone past its point is not part of it.
    CHECK(spans_of(cone, {-5, 0, 3}, {1, 0, 0}, c).empty());
    delete c;
    CHECK(spans_of(cone, {0.5, 0, 10}, {0, 0, -1}, c).size() == 1);  // (through the base's edge region)
    delete c;
    // Along the axis, point first: enters at the tip, leaves through the base.
    s = spans_of(cone, {0, 0, 5}, {0, 0, -1}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == doctest::Approx(3).epsilon(1e-14));
    CHECK(s[0].out.t == 5);
    delete c;
    // A frustum, radius 1 at z 0 to 0.5 at z 2, along its axis: cap to cap.
    const Cone frustum{{0, 0, 0}, {0, 0, 2}, 1, 0.5};
    s = spans_of(frustum, {0, 0, -3}, {0, 0, 1}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == 3);
    CHECK(s[0].out.t == 5);
    CHECK(near(c->g.normal(s[0].in.node, s[0].in.face, {0, 0, 0}), {0, 0, -1}));
    CHECK(near(c->g.normal(s[0].out.node, s[0].out.face, {0, 0, 2}), {0, 0, 1}));
    delete c;
    // Across at z = 1 (radius 0.75), and a cone whose point is at end_1.
    s = spans_of(frustum, {0, -4, 1}, {0, 1, 0}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == doctest::Approx(3.25).epsilon(1e-14));
    CHECK(s[0].out.t == doctest::Approx(4.75).epsilon(1e-14));
    delete c;
    s = spans_of(Cone{{0, 0, 2}, {0, 0, 0}, 0, 1}, {-5, 0, 1}, {1, 0, 0}, c);
    REQUIRE(s.size() == 1);
    CHECK(s[0].in.t == doctest::Approx(4.5).epsilon(1e-14));
    delete c;
}
