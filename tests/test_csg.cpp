// Tests for CSG (core/csg.cpp and the CSG nodes of core/shapes.cpp): the spans of
// random union / intersection / difference trees agree with point membership under
// the boolean combination of inside tests written here from each primitive's
// definition, and the cases the 2013 program got wrong (docs/rendering.md §8) come out
// right: non-convex operands, a difference subtracted from a difference, tori.
// All randomness is seeded, so a failure repeats.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "csg.h"
#include "shapes.h"
#include "test_models.h"
#include "test_random.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::Failures;
using rt_test::Rng;
using rt_test::fmt;

namespace {

using rt_test::Prim;

// Primitives near the origin, so that operands overlap.
Prim random_prim(Rng& rng) {
    Prim p;
    p.kind = Prim::Kind(int(rng.uni() * 6) % 6);
    switch (p.kind) {
        case Prim::Sph:
            p.c = rng.in_ball(1);
            p.r = rng.uni(0.3, 1.3);
            break;
        case Prim::Tet:
            for (;;) {
                Vec3 base = rng.in_ball(0.8);
                for (Vec3& q : p.v) q = base + rng.in_ball(1.5);
                bool ok = true;
                for (int i = 0; i < 4; ++i) ok = ok && p.height(i) > 0.15;
                if (ok) break;
            }
            break;
        case Prim::Cyl:
            p.e1 = rng.in_ball(1.2);
            p.e2 = p.e1 + rng.unit() * rng.uni(0.4, 2.5);
            p.r = rng.uni(0.15, 0.9);
            break;
        case Prim::Tor:
            p.c = rng.in_ball(0.8);
            p.axis = rng.unit();
            p.R = rng.uni(0.5, 1.3);
            p.r = rng.uni(0.15, 0.8) * p.R;
            break;
        case Prim::Bx:
            p.e1 = rng.in_ball(1.2);
            for (int k = 0; k < 3; ++k) p.e2[k] = p.e1[k] + (rng.uni() < 0.5 ? -1 : 1) * rng.uni(0.3, 2);
            break;
        case Prim::Con:
            p.e1 = rng.in_ball(1.2);
            p.e2 = p.e1 + rng.unit() * rng.uni(0.4, 2.5);
            p.r = rng.uni() < 0.3 ? 0.0 : rng.uni(0.15, 1.1);
            p.r2 = p.r == 0 || rng.uni() < 0.4 ? rng.uni(0.15, 1.1) : 0.0;
            break;
    }
    return p;
}

// A CSG tree mirrored by the model: leaves are primitives, inner nodes U / I / C.
struct Tree {
    bool leaf = true;
    Prim prim;
    CsgType type = CsgType::Union;
    std::vector<Tree> kids;  // 0 or 2

    Object object() const {
        Object o;
        if (leaf) {
            o.shape = prim.shape();
        } else {
            Csg c;
            c.type = type;
            c.operands = {kids[0].object(), kids[1].object()};
            o.shape = std::move(c);
        }
        return o;
    }
    bool inside(const Vec3& p) const {
        if (leaf) return prim.sd(p) < 0;
        bool a = kids[0].inside(p), b = kids[1].inside(p);
        switch (type) {
            case CsgType::Union: return a || b;
            case CsgType::Intersection: return a && b;
            case CsgType::Difference: return a && !b;
        }
        return false;
    }
    // The leaf surface nearest to p, and how near.
    void nearest_surface(const Vec3& p, double& best, double& second, const Prim*& which) const {
        if (leaf) {
            double s = std::fabs(prim.sd(p));
            if (s < best) {
                second = best, best = s, which = &prim;
            } else if (s < second) {
                second = s;
            }
            return;
        }
        for (const Tree& k : kids) k.nearest_surface(p, best, second, which);
    }
    void bound(Vec3& centre, double& radius) const {
        if (leaf) return prim.bound(centre, radius);
        Vec3 c0, c1;
        double r0 = 0, r1 = 0;
        kids[0].bound(c0, r0);
        kids[1].bound(c1, r1);
        centre = (c0 + c1) / 2;
        radius = std::max(length(c0 - centre) + r0, length(c1 - centre) + r1);
    }
    int count_leaves() const { return leaf ? 1 : kids[0].count_leaves() + kids[1].count_leaves(); }
};

Tree leaf(const Prim& p) {
    Tree t;
    t.prim = p;
    return t;
}
Tree node(CsgType type, Tree a, Tree b) {
    Tree t;
    t.leaf = false;
    t.type = type;
    t.kids.push_back(std::move(a));
    t.kids.push_back(std::move(b));
    return t;
}

Tree random_tree(Rng& rng, int depth) {
    if (depth == 0) return leaf(random_prim(rng));
    static const CsgType types[] = {CsgType::Union, CsgType::Intersection, CsgType::Difference};
    CsgType type = types[int(rng.uni() * 3) % 3];
    // Some branches stop early so trees are not all perfectly balanced.
    Tree a = random_tree(rng, rng.uni() < 0.25 ? 0 : depth - 1);
    Tree b = random_tree(rng, rng.uni() < 0.25 ? 0 : depth - 1);
    return node(type, std::move(a), std::move(b));
}

struct Compiled : rt_test::CompiledObject {
    explicit Compiled(const Tree& t) : CompiledObject(t.object()) {}
};

// Spans of the tree's node along o + t d against membership sampling; span ends on
// some operand's surface; normals unit, against the ray at entries and outward.
void check_tree_line(const Tree& tree, const Compiled& cg, const Vec3& o, const Vec3& d, Rng& rng, Failures& f,
                     int& inside_samples) {
    std::vector<Span> spans;
    SpanScratch scratch;
    cg.g.spans(cg.node, o, d, spans, scratch);
    Vec3 bc;
    double br = 0;
    tree.bound(bc, br);
    auto nearest = [&](const Vec3& p, double& second, const Prim*& which) {
        double best = HUGE_VAL;
        second = HUGE_VAL;
        which = nullptr;
        tree.nearest_surface(p, best, second, which);
        return best;
    };
    rt_test::check_spans(
        spans, cg.g, o, d, bc, br, false, rng, f, inside_samples, [&](const Vec3& p) { return tree.inside(p); },
        [&](const Vec3& p) {
            double second;
            const Prim* which;
            return nearest(p, second, which);
        },
        [&](const Vec3& p, const Vec3& n, const auto& fail) {
            // Outward for the combined solid, away from where operands meet or edges.
            const double h = 1e-4;
            double second;
            const Prim* which;
            nearest(p, second, which);
            if (second > 20 * h && which && which->edge_margin(p) > 20 * h) {
                if (tree.inside(p + n * h)) fail("p + h n is inside the solid");
                if (!tree.inside(p - n * h)) fail("p - h n is outside the solid");
            }
        });
}

void check_random_trees(unsigned seed, int depth, int trees, int lines_per_tree) {
    Rng rng(seed);
    Failures f;
    int inside_samples = 0, lines = 0;
    for (int k = 0; k < trees; ++k) {
        Tree tree = depth == 1 ? node(CsgType(std::array<char, 3>{'U', 'I', 'C'}[k % 3]), leaf(random_prim(rng)),
                                      leaf(random_prim(rng)))
                               : random_tree(rng, depth);
        Compiled cg(tree);
        Vec3 bc;
        double br = 0;
        tree.bound(bc, br);
        for (int j = 0; j < lines_per_tree; ++j, ++lines) {
            Vec3 o = bc + rng.unit() * (br * rng.uni(0.2, 3));
            Vec3 d = normalize(bc + rng.in_ball(br * 0.7) - o);
            check_tree_line(tree, cg, o, d, rng, f, inside_samples);
        }
    }
    CHECK_MESSAGE(f.count == 0, f.first);
    CHECK(inside_samples > lines * 3);  // the lines do cross the solids
}

}  // namespace

TEST_CASE("csg: spans of random operand pairs under U, I and C agree with point membership") {
    check_random_trees(2024, 1, 600, 6);
}

TEST_CASE("csg: spans of random nested trees (depth 2 and 3) agree with point membership") {
    SUBCASE("depth 2") { check_random_trees(2025, 2, 300, 6); }
    SUBCASE("depth 3") { check_random_trees(2026, 3, 200, 6); }
}

namespace {
bool same_end(const SpanEnd& x, const SpanEnd& y) {
    bool same_t = x.t == y.t || (std::isnan(x.t) && std::isnan(y.t));
    return same_t && x.node == y.node && x.face == y.face && x.flip == y.flip;
}
}  // namespace

// hit() and exit() take a short cut for a CSG of two primitives (no lists, and no right
// operand when the left one lies behind tmin); they must answer as the first entry
// beyond tmin (first exit beyond kDelta) of the spans from the list walk, bit for bit,
// tmin at span ends (ties) included.
TEST_CASE("csg: hit and exit of operand pairs agree with the spans' first entry and exit") {
    Rng rng(77);
    int checked = 0, hits = 0;
    for (int k = 0; k < 600; ++k) {
        Tree tree = node(CsgType(std::array<char, 3>{'U', 'I', 'C'}[k % 3]), leaf(random_prim(rng)),
                         leaf(random_prim(rng)));
        Compiled cg(tree);
        Vec3 bc;
        double br = 0;
        tree.bound(bc, br);
        for (int j = 0; j < 8; ++j) {
            Vec3 o = bc + rng.unit() * (br * rng.uni(0.2, 3));
            Vec3 d = normalize(bc + rng.in_ball(br * 0.7) - o);
            std::vector<Span> spans;
            SpanScratch scratch;
            cg.g.spans(cg.node, o, d, spans, scratch);
            std::vector<double> tmins = {0, kDelta, -br * 4, br * 4};
            for (const Span& sp : spans) tmins.insert(tmins.end(), {sp.in.t, sp.out.t, (sp.in.t + sp.out.t) / 2});
            // The operands' own ends, and just before them (where the short cut turns).
            const CsgG& c = cg.g.csgs[cg.g.nodes[cg.node].index];
            for (std::uint32_t operand : {c.left, c.right}) {
                std::vector<Span> own;
                cg.g.spans(operand, o, d, own, scratch);
                for (const Span& sp : own)
                    for (double t : {sp.in.t, sp.out.t}) tmins.insert(tmins.end(), {t, std::nextafter(t, -HUGE_VAL)});
            }
            for (double tmin : tmins) {
                const SpanEnd* want = nullptr;
                for (const Span& sp : spans)
                    if (!want && sp.in.t > tmin) want = &sp.in;
                SpanEnd got;
                bool hit = cg.g.hit(0, o, d, tmin, got, scratch);
                REQUIRE(hit == (want != nullptr));
                if (hit) CHECK(same_end(got, *want));
                ++checked;
                hits += hit;
            }
            const SpanEnd* want = nullptr;
            for (const Span& sp : spans)
                if (!want && sp.out.t > kDelta) want = &sp.out;
            SpanEnd got;
            bool left = cg.g.exit(0, o, d, got, scratch);
            REQUIRE(left == (want != nullptr));
            if (left) CHECK(same_end(got, *want));
        }
    }
    CHECK(checked > 20000);
    CHECK(hits > checked / 5);
}

TEST_CASE("csg: combine_spans of a list with itself: U and I give it back, C gives nothing") {
    Rng rng(7);
    for (int k = 0; k < 200; ++k) {
        std::vector<Span> a;
        double t = rng.uni(-5, 0);
        int n = 1 + int(rng.uni() * 4);
        for (int i = 0; i < n; ++i) {
            double t0 = t + rng.uni(0.01, 1), t1 = t0 + rng.uni(0.01, 1);
            a.push_back({{t0, 1, 0, false}, {t1, 1, 0, false}});
            t = t1;
        }
        std::vector<Span> out;
        combine_spans(CsgType::Union, a, a, out);
        REQUIRE(out.size() == a.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            CHECK(out[i].in.t == a[i].in.t);
            CHECK(out[i].out.t == a[i].out.t);
        }
        out.clear();
        combine_spans(CsgType::Intersection, a, a, out);
        CHECK(out.size() == a.size());
        out.clear();
        combine_spans(CsgType::Difference, a, a, out);
        CHECK(out.empty());
    }
}

// The one-span-a-side combination (shapes.cpp's common CSG case) is a decision tree
// written apart from the list walk; it must give the walk's spans bit for bit: the same
// surfaces on equal t (the left operand's first), empty spans dropped, and defined
// answers for infinite and NaN ends. Ends drawn from a few values, so ties are common.
TEST_CASE("csg: combine_single_spans gives combine_spans' spans, ties and non-finite ends included") {
    const double values[] = {-HUGE_VAL, -1, 0, 0.5, 1, 2, HUGE_VAL, NAN};
    Rng rng(31);
    int compared = 0, nonempty = 0;
    for (int k = 0; k < 20000; ++k) {
        auto pick = [&] { return values[int(rng.uni() * 8) % (k < 10000 ? 7 : 8)]; };
        auto span = [&](std::uint32_t node) {
            double t0 = pick(), t1 = pick();
            // Mostly ordered ends, as primitives give; sometimes any order.
            if (rng.uni() < 0.8 && t1 < t0) std::swap(t0, t1);
            return Span{{t0, node, 0, false}, {t1, node, 1, false}};
        };
        Span sa = span(1), sb = span(2);
        bool has_a = rng.uni() < 0.9, has_b = rng.uni() < 0.9;
        for (CsgType type : {CsgType::Union, CsgType::Intersection, CsgType::Difference}) {
            std::vector<Span> a, b, want, got;
            if (has_a) a.push_back(sa);
            if (has_b) b.push_back(sb);
            combine_spans(type, a, b, want);
            combine_single_spans(type, has_a ? &sa : nullptr, has_b ? &sb : nullptr, got);
            REQUIRE(got.size() == want.size());
            for (std::size_t i = 0; i < got.size(); ++i) {
                CHECK(same_end(got[i].in, want[i].in));
                CHECK(same_end(got[i].out, want[i].out));
            }
            ++compared;
            nonempty += !want.empty();
        }
    }
    CHECK(compared == 60000);
    CHECK(nonempty > 20000);
}

// Torus around the z axis (R 2, r 0.5) minus a sphere that bites one side of the ring.
// Along the x axis from x = -5 the ray enters the sphere, crosses the bitten tube, and
// leaves the sphere in the hole, outside the torus; the 2013 program stopped there
// and saw nothing. The far tube (x in [1.5, 2.5]) is untouched.
TEST_CASE("csg: a difference finds the left operand again after the right one's first exit (non-convex)") {
    Prim torus;
    torus.kind = Prim::Tor;
    torus.c = {0, 0, 0};
    torus.axis = {0, 0, 1};
    torus.R = 2;
    torus.r = 0.5;
    Prim bite;
    bite.kind = Prim::Sph;
    bite.c = {-2, 0, 0};
    bite.r = 0.8;
    Tree tree = node(CsgType::Difference, leaf(torus), leaf(bite));
    Compiled cg(tree);
    SpanScratch scratch;
    Vec3 o{-5, 0, 0}, d{1, 0, 0};
    std::vector<Span> spans;
    cg.g.spans(cg.node, o, d, spans, scratch);
    REQUIRE(spans.size() == 1);
    CHECK(spans[0].in.t == doctest::Approx(6.5).epsilon(1e-12));
    CHECK(spans[0].out.t == doctest::Approx(7.5).epsilon(1e-12));
    SpanEnd e;
    REQUIRE(cg.g.hit(0, o, d, kDelta, e, scratch));
    CHECK(e.t == doctest::Approx(6.5).epsilon(1e-12));
    Vec3 n = cg.g.normal(e.node, e.face, o + d * e.t);
    if (e.flip) n = -n;
    CHECK(length(n - Vec3{-1, 0, 0}) < 1e-9);

    // The same through the whole pipeline: the world picks it at that distance.
    Scene scene;
    scene.objects.push_back(tree.object());
    auto world = compile_world(scene);
    PickResult pr = pick(*world, Ray{o, d});
    CHECK(pr.hit);
    CHECK(pr.object == 0);
    CHECK(pr.t == doctest::Approx(6.5).epsilon(1e-12));

    // A ray just off the axis sees the bitten tube's remains only outside the bite.
    Failures f;
    int inside_samples = 0;
    Rng rng(8);
    for (int k = 0; k < 200; ++k)
        check_tree_line(tree, cg, Vec3{-5, rng.uni(-0.6, 0.6), rng.uni(-0.6, 0.6)}, normalize(Vec3{1, rng.uni(-0.1, 0.1), rng.uni(-0.1, 0.1)}),
                        rng, f, inside_samples);
    CHECK_MESSAGE(f.count == 0, f.first);
}

// Ball of radius 2 minus a shell (ball 1 minus ball 0.5): solid for |p| < 0.5 and
// 1 < |p| < 2. The 2013 program's C reported "inside" as always false, so the shell
// was never subtracted and the ray saw one chord [-2, 2].
TEST_CASE("csg: a difference used as the right operand of a difference is subtracted") {
    Prim big, mid, small;
    big.kind = mid.kind = small.kind = Prim::Sph;
    big.c = mid.c = small.c = {0.25, -0.5, 1};
    big.r = 2, mid.r = 1, small.r = 0.5;
    Tree shell = node(CsgType::Difference, leaf(mid), leaf(small));
    Tree tree = node(CsgType::Difference, leaf(big), shell);
    Compiled cg(tree);
    SpanScratch scratch;
    Vec3 d = normalize(Vec3{1, 2, -0.5});
    Vec3 o = big.c - d * 5;
    std::vector<Span> spans;
    cg.g.spans(cg.node, o, d, spans, scratch);
    REQUIRE(spans.size() == 3);
    const double want[3][2] = {{3, 4}, {4.5, 5.5}, {6, 7}};
    for (int i = 0; i < 3; ++i) {
        CHECK(spans[i].in.t == doctest::Approx(want[i][0]).epsilon(1e-12));
        CHECK(spans[i].out.t == doctest::Approx(want[i][1]).epsilon(1e-12));
    }
    // Normals face out of the remaining solid: at the inner ball's entry against d,
    // at the shell's outer sphere (leaving the solid) along d.
    auto normal_at = [&](const SpanEnd& e) {
        Vec3 n = cg.g.normal(e.node, e.face, o + d * e.t);
        return e.flip ? -n : n;
    };
    CHECK(length(normal_at(spans[0].out) - d) < 1e-9);
    CHECK(length(normal_at(spans[1].in) + d) < 1e-9);
    CHECK(length(normal_at(spans[1].out) - d) < 1e-9);
    CHECK(length(normal_at(spans[2].in) + d) < 1e-9);

    // From the centre (inside the inner ball) the ray leaves after 0.5.
    SpanEnd e;
    REQUIRE(cg.g.exit(0, big.c, d, e, scratch));
    CHECK(e.t == doctest::Approx(0.5).epsilon(1e-12));
}

// The torus as the subtracted operand: a ball of radius 3 with a ring-shaped tunnel.
TEST_CASE("csg: a torus inside a CSG, subtracted and intersected") {
    Prim ball, torus;
    ball.kind = Prim::Sph;
    ball.c = {0, 0, 0};
    ball.r = 3;
    torus.kind = Prim::Tor;
    torus.c = {0, 0, 0};
    torus.axis = {1, 2, 2};  // oblique
    torus.R = 2;
    torus.r = 0.5;
    Vec3 a = normalize(torus.axis);
    Vec3 u = normalize(cross(a, Vec3{1, 0, 0}));  // in the torus's plane
    SpanScratch scratch;
    std::vector<Span> spans;

    Compiled diff(node(CsgType::Difference, leaf(ball), leaf(torus)));
    diff.g.spans(diff.node, u * -5, u, spans, scratch);
    REQUIRE(spans.size() == 3);
    const double want_c[3][2] = {{2, 2.5}, {3.5, 6.5}, {7.5, 8}};
    for (int i = 0; i < 3; ++i) {
        CHECK(spans[i].in.t == doctest::Approx(want_c[i][0]).epsilon(1e-12));
        CHECK(spans[i].out.t == doctest::Approx(want_c[i][1]).epsilon(1e-12));
    }

    // Intersected with a slab-like cylinder around the axis: only the tubes' middles.
    Prim disc;
    disc.kind = Prim::Cyl;
    disc.e1 = a * -0.2;
    disc.e2 = a * 0.2;
    disc.r = 2.2;
    Compiled inter(node(CsgType::Intersection, leaf(torus), leaf(disc)));
    spans.clear();  // spans() appends
    inter.g.spans(inter.node, u * -5, u, spans, scratch);
    REQUIRE(spans.size() == 2);
    CHECK(spans[0].in.t == doctest::Approx(2.8).epsilon(1e-12));
    CHECK(spans[0].out.t == doctest::Approx(3.5).epsilon(1e-12));
    CHECK(spans[1].in.t == doctest::Approx(6.5).epsilon(1e-12));
    CHECK(spans[1].out.t == doctest::Approx(7.2).epsilon(1e-12));
}
