// Packets of rays through a model's triangles (TriangleAccel::nearest_packet): every
// ray's answer must be the single-ray walk's, bit for bit (the same t, the same slot,
// found alike), and both must be brute force's over every triangle of the model (the
// watertight test on each slot, the nearest, ties to the lower slot). Camera-like
// packets (one origin, the frustum test in play), packets of scattered rays, rays
// through edges shared by two triangles, rays leaving a point on the surface, equal
// triangles at two slots (a tie), and packets made so that a frustum that left out a
// single ray's inverse direction would lose that ray's hit.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "math.h"
#include "model.h"
#include "simd.h"
#include "test_random.h"
#include "triangles.h"

namespace {

using rt::TriangleAccel;
using rt::TriHit;
using rt::TriRay;
using rt::Vec3;

// A bumpy height field over [0, n]^2 at z ~ 0: (n + 1)^2 shared vertices, two triangles
// a cell (every inner edge shared), then `copies` of its first triangles again (equal
// triangles at two slots: exact ties).
rt::MeshData terrain(int n, int copies, unsigned seed) {
    rt_test::Rng rng(seed);
    rt::MeshData m;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            const double z = 0.4 * std::sin(0.7 * x) * std::cos(0.5 * y) + rng.uni(-0.05, 0.05);
            m.positions.insert(m.positions.end(), {float(x), float(y), float(z)});
        }
    auto v = [n](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            m.triangles.insert(m.triangles.end(), {v(x, y), v(x + 1, y), v(x + 1, y + 1)});
            m.triangles.insert(m.triangles.end(), {v(x, y), v(x + 1, y + 1), v(x, y + 1)});
        }
    for (int k = 0; k < copies; ++k) m.triangles.insert(m.triangles.end(), m.triangles.begin() + 3 * k, m.triangles.begin() + 3 * k + 3);
    return m;
}

Vec3 vertex(const rt::MeshData& m, std::uint32_t i) {
    return {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
}

// Whether a slot holds a triangle (unused slots are all zero; no terrain triangle is).
bool used(const TriangleAccel& a, std::uint32_t slot) {
    for (int k = 0; k < 9; ++k)
        if (a.blocks[slot >> 2].v[k][slot & 3] != 0) return true;
    return false;
}

// Every slot's watertight test: the nearest t in (tmin, tmax), ties to the lower slot.
bool brute(const TriangleAccel& a, const TriRay& r, double tmin, double tmax, TriHit& hit) {
    bool found = false;
    hit = {tmax, 0};
    for (std::size_t b = 0; b < a.blocks.size(); ++b)
        for (int l = 0; l < 4; ++l) {
            const std::uint32_t slot = std::uint32_t(4 * b + l);
            if (slot >= a.ids.size() || !used(a, slot)) continue;
            const double t = rt::tri_intersect(r, a.blocks[b], l);
            if (t > tmin && (t < hit.t || (found && t == hit.t && slot < hit.slot))) hit = {t, slot}, found = true;
        }
    return found;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The packet against single rays and brute force; returns how many rays hit.
int check_packet(const TriangleAccel& a, const std::vector<TriRay>& rays, double tmin, double tmax) {
    const int n = int(rays.size());
    REQUIRE(n <= TriangleAccel::kPacket);
    TriHit hits[TriangleAccel::kPacket];
    bool found[TriangleAccel::kPacket];
    a.nearest_packet(rays.data(), n, tmin, tmax, hits, found);
    int hit_count = 0;
    for (int i = 0; i < n; ++i) {
        TriHit one, all;
        const bool f1 = a.nearest(rays[i], tmin, tmax, one);
        const bool fb = brute(a, rays[i], tmin, tmax, all);
        INFO("ray " << i << " of " << n << ": o " << rt_test::fmt(rays[i].o) << " d " << rt_test::fmt(rays[i].d));
        CHECK(f1 == fb);
        CHECK(found[i] == f1);
        if (found[i] && f1) {
            CHECK(same_bits(hits[i].t, one.t));
            CHECK(hits[i].slot == one.slot);
        }
        if (f1 && fb) {
            CHECK(same_bits(one.t, all.t));
            CHECK(one.slot == all.slot);
        }
        hit_count += found[i];
    }
    return hit_count;
}

// The slots of the model's triangle `id`.
std::vector<std::uint32_t> slots_of(const TriangleAccel& a, std::uint32_t id) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t s = 0; s < a.ids.size(); ++s)
        if (a.ids[s] == id && used(a, s)) out.push_back(s);
    return out;
}

// A terrain and its tree (built on one thread).
struct TerrainTree {
    rt::MeshData m;
    TriangleAccel a;
};
TerrainTree terrain_tree(int n, int copies, unsigned seed) {
    rt::MeshData m = terrain(n, copies, seed);
    TriangleAccel a = TriangleAccel::build(m, 1);
    return {std::move(m), std::move(a)};
}

}  // namespace

TEST_CASE("packets: camera-like packets through a bumpy terrain, each ray as the single walk and brute force") {
    const auto [m, a] = terrain_tree(48, 0, 7);
    rt_test::Rng rng(11);
    int hits = 0, rays_total = 0;
    for (int p = 0; p < 60; ++p) {
        // A camera above the terrain looking down at a patch; the packet is a row or a
        // small tile of its pixels (directions close together, one origin).
        const Vec3 eye{rng.uni(-10, 58), rng.uni(-10, 58), rng.uni(3, 30)};
        const Vec3 target{rng.uni(0, 48), rng.uni(0, 48), 0};
        const Vec3 fwd = normalize(target - eye), right = normalize(cross(fwd, Vec3{0, 0, 1}));
        const Vec3 up = cross(right, fwd);
        const double spread = rng.uni(0.001, 0.2);
        const int n = 1 + int(rng.index(TriangleAccel::kPacket));
        const int wide = p % 2 ? n : 8;  // a row, or tiles 8 wide
        std::vector<TriRay> rays;
        for (int i = 0; i < n; ++i) {
            const Vec3 d = normalize(fwd + right * (spread * (i % wide)) + up * (spread * (i / wide)));
            rays.push_back(TriRay::make(eye, d));
        }
        hits += check_packet(a, rays, 1e-9, HUGE_VAL);
        rays_total += n;
    }
    // Most rays meet the terrain: the walks were really compared.
    CHECK(hits > rays_total / 3);
}

TEST_CASE("packets: scattered rays (origins and directions at random), and a tmax that cuts") {
    const auto [m, a] = terrain_tree(24, 0, 3);
    rt_test::Rng rng(5);
    int hits = 0;
    for (int p = 0; p < 80; ++p) {
        const int n = 2 + int(rng.index(TriangleAccel::kPacket - 1));
        std::vector<TriRay> rays;
        for (int i = 0; i < n; ++i) {
            const Vec3 o{rng.uni(-5, 29), rng.uni(-5, 29), rng.uni(-3, 6)};
            const Vec3 t{rng.uni(0, 24), rng.uni(0, 24), rng.uni(-0.5, 0.5)};
            rays.push_back(TriRay::make(o, p % 3 ? normalize(t - o) : t - o));  // unit or not
        }
        hits += check_packet(a, rays, 0.0, p % 4 == 0 ? rng.uni(1, 10) : HUGE_VAL);
    }
    CHECK(hits > 200);
}

TEST_CASE("packets: rays through edges and corners shared by two triangles hit, as the single walk") {
    const auto [m, a] = terrain_tree(16, 0, 9);
    rt_test::Rng rng(13);
    const int n = 16;
    for (int p = 0; p < 40; ++p) {
        // One origin; each ray aims at a point of a shared edge (the diagonal of a cell,
        // shared by its two triangles, or an edge between cells), or at a vertex.
        const Vec3 eye{rng.uni(-4, 20), rng.uni(-4, 20), rng.uni(2, 12)};
        std::vector<TriRay> rays;
        for (int i = 0; i < n; ++i) {
            // (Cells off the border: their edges and corners are all shared.)
            const int cx = 1 + int(rng.index(14)), cy = 1 + int(rng.index(14));
            const std::uint32_t t0 = 2 * std::uint32_t(cy * 16 + cx);  // the cell's first triangle
            const Vec3 v0 = vertex(m, m.triangles[3 * t0]), v2 = vertex(m, m.triangles[3 * t0 + 2]);
            const Vec3 v1 = vertex(m, m.triangles[3 * t0 + 1]);
            const double f = i % 4 == 3 ? 0.0 : rng.uni(0, 1);  // every fourth: a corner
            const Vec3 aim = i % 2 ? v0 + (v2 - v0) * f : v0 + (v1 - v0) * f;
            rays.push_back(TriRay::make(eye, aim - eye));
        }
        // Every ray meets the surface (watertight: never through the crack), and the
        // terrain is a height field seen from above, so each has a nearest hit.
        CHECK(check_packet(a, rays, 0.0, HUGE_VAL) == n);
    }
}

TEST_CASE("packets: rays leaving a point on the surface, tmin 0 and a small tmin") {
    const auto [m, a] = terrain_tree(16, 0, 21);
    rt_test::Rng rng(17);
    for (int p = 0; p < 40; ++p) {
        const std::uint32_t t = std::uint32_t(rng.index(m.triangle_count()));
        const Vec3 c0 = vertex(m, m.triangles[3 * t]), c1 = vertex(m, m.triangles[3 * t + 1]),
                   c2 = vertex(m, m.triangles[3 * t + 2]);
        double u = rng.uni(), v = rng.uni();
        if (u + v > 1) u = 1 - u, v = 1 - v;
        const Vec3 o = c0 + (c1 - c0) * u + (c2 - c0) * v;
        std::vector<TriRay> rays;
        for (int i = 0; i < TriangleAccel::kPacket; ++i) {
            // Mostly low over the surface, where the neighbours and the start triangle
            // itself (t near 0) are met.
            Vec3 d = rng.unit();
            d.z *= 0.2;
            rays.push_back(TriRay::make(o, normalize(d)));
        }
        check_packet(a, rays, p % 2 ? 0.0 : 1e-9, HUGE_VAL);
    }
}

TEST_CASE("packets: equal triangles at two slots tie; the lower slot wins in packets too") {
    const auto [m, a] = terrain_tree(8, 128, 4);  // every triangle of the terrain twice
    rt_test::Rng rng(23);
    int hits = 0;
    for (int p = 0; p < 20; ++p) {
        const Vec3 eye{rng.uni(0, 8), rng.uni(0, 8), 10};
        std::vector<TriRay> rays;
        for (int i = 0; i < 24; ++i) rays.push_back(TriRay::make(eye, Vec3{rng.uni(0, 8), rng.uni(0, 8), 0} - eye));
        hits += check_packet(a, rays, 0.0, HUGE_VAL);
        // The slot found is the lower of the two slots of its triangle.
        TriHit h[TriangleAccel::kPacket];
        bool f[TriangleAccel::kPacket];
        a.nearest_packet(rays.data(), 24, 0.0, HUGE_VAL, h, f);
        for (int i = 0; i < 24; ++i) {
            if (!f[i]) continue;
            const std::uint32_t id = a.ids[h[i].slot];
            const std::uint32_t twin = id < 128 ? id + 128 : id - 128;
            for (std::uint32_t s : slots_of(a, twin)) CHECK(h[i].slot < s);
        }
    }
    CHECK(hits > 300);
}

TEST_CASE("packets: one ray that hits among rays that miss keeps its hit (the frustum takes every ray)") {
    // The packet's rays share an origin and signs, so the frustum test is in play; all
    // but one pass beside the terrain, and the one that hits is first, last or between,
    // aimed at a corner of the terrain (a box's edge: where a frustum short of that ray's
    // inverse direction would rule the boxes out). A frustum made from the first ray
    // only, or from one end of the inverse directions only, loses it.
    const auto [m, a] = terrain_tree(32, 0, 2);
    rt_test::Rng rng(29);
    const Vec3 corner = vertex(m, 0);  // (0, 0, z)
    const Vec3 far_corner = vertex(m, std::uint32_t(33 * 33 - 1));  // (32, 32, z)
    int lonely_hits = 0;
    for (int p = 0; p < 60; ++p) {
        const Vec3 eye{rng.uni(-40, -20), rng.uni(-40, -20), rng.uni(5, 20)};
        const int n = 2 + int(rng.index(TriangleAccel::kPacket - 1));
        const int lonely = p % 3 == 0 ? 0 : p % 3 == 1 ? n - 1 : int(rng.index(std::size_t(n)));
        const Vec3 aim = p % 2 ? corner + Vec3{1e-4, 1e-4, 0} : far_corner - Vec3{1e-4, 1e-4, 0};
        std::vector<TriRay> rays;
        for (int i = 0; i < n; ++i) {
            // The others: toward points beyond the terrain's near corner, off to one side
            // (x < 0 or y < 0), each with the same signs as the lonely ray's direction.
            const Vec3 miss = corner + Vec3{-rng.uni(0.5, 3), rng.uni(-3, -0.5), -rng.uni(0, 1)};
            rays.push_back(TriRay::make(eye, (i == lonely ? aim : miss) - eye));
        }
        for (const TriRay& r : rays)
            for (int k = 0; k < 3; ++k) REQUIRE(std::signbit(r.d[k]) == std::signbit(rays[0].d[k]));
        TriHit h[TriangleAccel::kPacket];
        bool f[TriangleAccel::kPacket];
        a.nearest_packet(rays.data(), n, 0.0, HUGE_VAL, h, f);
        TriHit one;
        const bool f1 = a.nearest(rays[std::size_t(lonely)], 0.0, HUGE_VAL, one);
        REQUIRE(f1);  // (aimed just inside a corner of the terrain)
        CHECK(f[lonely]);
        lonely_hits += f[lonely];
        check_packet(a, rays, 0.0, HUGE_VAL);
    }
    CHECK(lonely_hits == 60);
}

TEST_CASE("packets: prepared answers are taken for exactly the rays prepared, and forgotten") {
    const auto [m, a] = terrain_tree(16, 0, 31);
    rt_test::Rng rng(37);
    const Vec3 eye{8, -6, 9};
    std::vector<TriRay> rays;
    for (int i = 0; i < 20; ++i) rays.push_back(TriRay::make(eye, normalize(Vec3{rng.uni(0, 16), rng.uni(0, 16), 0} - eye)));
    TriHit expect[20];
    bool fe[20];
    for (int i = 0; i < 20; ++i) fe[i] = a.nearest(rays[i], 1e-9, HUGE_VAL, expect[i]);
    a.prepare(rays.data(), 20, 1e-9, HUGE_VAL);
    // Asked in order with some skipped, then with another tmin (not prepared: walked).
    for (int i = 0; i < 20; i += 1 + i % 3) {
        TriHit h;
        CHECK(a.nearest(rays[i], 1e-9, HUGE_VAL, h) == fe[i]);
        CHECK(same_bits(h.t, expect[i].t));
        CHECK(h.slot == expect[i].slot);
    }
    TriHit h;
    const bool f0 = a.nearest(rays[0], 0.5, HUGE_VAL, h);
    TriHit h0;
    CHECK(f0 == a.nearest(rays[0], 0.5, HUGE_VAL, h0));
    CHECK(same_bits(h.t, h0.t));
    TriangleAccel::forget_prepared();
    CHECK(a.nearest(rays[19], 1e-9, HUGE_VAL, h) == fe[19]);
    CHECK(same_bits(h.t, expect[19].t));
}

namespace {
// Whether any slot's watertight test puts a triangle on the segment tmin < t < tmax.
bool brute_any(const TriangleAccel& a, const TriRay& r, double tmin, double tmax) {
    for (std::size_t b = 0; b < a.blocks.size(); ++b)
        for (int l = 0; l < 4; ++l) {
            const std::uint32_t slot = std::uint32_t(4 * b + l);
            if (slot >= a.ids.size() || !used(a, slot)) continue;
            const double t = rt::tri_intersect(r, a.blocks[b], l);
            if (t > tmin && t < tmax) return true;
        }
    return false;
}

// any_packet() against any() and brute force, ray by ray; returns how many are blocked.
int check_any_packet(const TriangleAccel& a, const std::vector<TriRay>& rays, const std::vector<double>& tmax) {
    const int n = int(rays.size());
    bool hit[TriangleAccel::kPacket];
    double t[TriangleAccel::kPacket];
    a.any_packet(rays.data(), n, 0.0, tmax.data(), hit, t);
    int blocked = 0;
    for (int i = 0; i < n; ++i) {
        double t1 = -1;
        const bool one = a.any(rays[i], 0.0, tmax[i], t1);
        INFO("ray " << i << " of " << n << ": o " << rt_test::fmt(rays[i].o) << " d " << rt_test::fmt(rays[i].d));
        CHECK(hit[i] == one);
        CHECK(one == brute_any(a, rays[i], 0.0, tmax[i]));
        if (hit[i]) {
            // A triangle really lies there (not necessarily the one any() met first).
            CHECK(t[i] > 0.0);
            CHECK(t[i] < tmax[i]);
        }
        blocked += hit[i];
    }
    return blocked;
}
}  // namespace

TEST_CASE("packets: shadow-like packets (points of the surface toward one light) blocked as any() says") {
    const auto [m, a] = terrain_tree(24, 0, 41);
    rt_test::Rng rng(43);
    int blocked = 0, total = 0;
    for (int p = 0; p < 60; ++p) {
        // A light low over the terrain (long shadows), the packet's points on a patch of
        // it: each ray from a point just off the surface to just short of the light.
        const Vec3 light{rng.uni(-20, 44), rng.uni(-20, 44), rng.uni(0.5, 4)};
        const double cx = rng.uni(2, 22), cy = rng.uni(2, 22), size = rng.uni(0.2, 4);
        const int n = 1 + int(rng.index(TriangleAccel::kPacket));
        std::vector<TriRay> rays;
        std::vector<double> tmax;
        for (int i = 0; i < n; ++i) {
            // The surface point under (x, y): the terrain's first hit from above.
            const TriRay down = TriRay::make(Vec3{cx + rng.uni(0, size), cy + rng.uni(0, size), 10}, Vec3{0, 0, -1});
            TriHit h;
            if (!a.nearest(down, 0.0, HUGE_VAL, h)) continue;
            const Vec3 q = down.o + down.d * h.t;
            const Vec3 v = light - q;
            const double r = length(v);
            const Vec3 vh = v / r;
            rays.push_back(TriRay::make(q + vh * 1.5e-5, vh));
            tmax.push_back(r - 1.5e-4);
        }
        if (rays.empty()) continue;
        blocked += check_any_packet(a, rays, tmax);
        total += int(rays.size());
    }
    // Both answers were met often: the walks were really compared.
    CHECK(blocked > total / 10);
    CHECK(blocked < total * 9 / 10);
}

TEST_CASE("packets: any_packet on scattered rays, rays through shared edges, and prepared answers") {
    const auto [m, a] = terrain_tree(16, 0, 47);
    rt_test::Rng rng(53);
    for (int p = 0; p < 60; ++p) {
        const int n = 2 + int(rng.index(TriangleAccel::kPacket - 1));
        std::vector<TriRay> rays;
        std::vector<double> tmax;
        for (int i = 0; i < n; ++i) {
            const Vec3 o{rng.uni(-4, 20), rng.uni(-4, 20), rng.uni(-2, 6)};
            Vec3 aim{rng.uni(0, 16), rng.uni(0, 16), rng.uni(-0.5, 0.5)};
            if (i % 3 == 0) {  // a point of a shared edge (a cell's diagonal) inside the terrain
                const int cx = 1 + int(rng.index(14)), cy = 1 + int(rng.index(14));
                const std::uint32_t t0 = 2 * std::uint32_t(cy * 16 + cx);
                const Vec3 v0 = vertex(m, m.triangles[3 * t0]), v2 = vertex(m, m.triangles[3 * t0 + 2]);
                aim = v0 + (v2 - v0) * rng.uni(0, 1);
            }
            rays.push_back(TriRay::make(o, aim - o));
            tmax.push_back(p % 2 ? 1.0 : rng.uni(0.2, 1.5));  // the aim at t = 1: before, on or past it
        }
        check_any_packet(a, rays, tmax);
        // Prepared: any() takes the packet's answers for those very rays, in order.
        bool hit[TriangleAccel::kPacket];
        double t[TriangleAccel::kPacket];
        a.any_packet(rays.data(), n, 0.0, tmax.data(), hit, t);
        a.prepare_any(rays.data(), n, 0.0, tmax.data());
        for (int i = 0; i < n; i += 2) {
            double ti = -1;
            CHECK(a.any(rays[i], 0.0, tmax[i], ti) == hit[i]);
            if (hit[i]) CHECK(same_bits(ti, t[i]));
        }
        TriangleAccel::forget_prepared();
    }
}
