// LightBuffer::build(): the cube map of the objects a point light sees in each
// direction, for its shadow rays, or the camera sees, for its rays (world.h).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "world.h"
#include "world_build.h"

namespace rt {

namespace {
// Cells of padding on each side of an object's range in a light buffer: directions
// are computed with rounding, and a ray's points sit off its exact line by a little.
constexpr double kCellPad = 0.01;

inline double norm_inf(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// The cells of one cube face, [i0, i1] x [j0, j1], in which a light may see object `obj`.
struct CellRange {
    std::uint32_t obj;
    float dmin;
    int face, i0, i1, j0, j1;
};

// Appends the cell ranges of the box [lo, hi] (relative to the light) on the faces of
// an n x n cube map, padded by kCellPad cells on each side (tol = 2 kCellPad / n in
// face coordinates); returns the cells they cover.
std::size_t face_ranges(const Vec3& lo, const Vec3& hi, std::uint32_t obj, float dmin, int n, double tol,
                        std::vector<CellRange>& out) {
    std::size_t covered = 0;
    for (int face = 0; face < 6; ++face) {
        const int a = face / 2, bx = (a + 1) % 3, cx = (a + 2) % 3;
        // The box along the face's axis, turned so that the face looks along +a.
        double a0 = face & 1 ? -hi[a] : lo[a], a1 = face & 1 ? -lo[a] : hi[a];
        if (!(a1 > 0)) continue;
        double a0p = std::max(a0, 0.0);
        // The range of d_k / d_a over the box's part in front of the face: its
        // extremes are at corners (or unbounded where the box reaches the plane
        // of the light).
        auto range = [&](int k, double& u0, double& u1) {
            double k0 = lo[k], k1 = hi[k];
            u0 = k0 >= 0 ? k0 / a1 : (a0p > 0 ? k0 / a0p : -HUGE_VAL);
            u1 = k1 <= 0 ? k1 / a1 : (a0p > 0 ? k1 / a0p : HUGE_VAL);
        };
        double u0, u1, w0, w1;
        range(bx, u0, u1);
        range(cx, w0, w1);
        if (u0 > 1 + tol || u1 < -1 - tol || w0 > 1 + tol || w1 < -1 - tol) continue;
        auto index = [&](double u, double pad) {
            double x = (std::min(std::max(u, -2.0), 2.0) + 1) * 0.5 * n + pad;
            return std::min(std::max(int(std::floor(x)), 0), n - 1);
        };
        CellRange r{obj, dmin, face, index(u0, -kCellPad), index(u1, kCellPad), index(w0, -kCellPad),
                    index(w1, kCellPad)};
        covered += std::size_t(r.i1 - r.i0 + 1) * std::size_t(r.j1 - r.j0 + 1);
        out.push_back(r);
    }
    return covered;
}

// The least distance from the light (the origin) to the box [lo, hi]; and that, rounded
// down with room for the ray's points being off by rounding, as a float.
double origin_distance(const Vec3& lo, const Vec3& hi, float& rounded_down) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double e = std::max({lo[k], 0.0, -hi[k]});
        d2 += e * e;
    }
    double dmin = std::sqrt(d2);
    double dm = dmin * (1 - 1e-3);
    rounded_down = float(dm);
    if (double(rounded_down) > dm) rounded_down = std::nextafter(rounded_down, 0.0f);
    return dmin;
}

// A sphere light's cells list each box grown by its radius R, but a shadow ray from p
// (d from the centre c) to a point q of the sphere needs less of that growth the nearer
// the box is to p. Its point x = p + s (q - p) lies within s R of y = p + s (c - p), a
// point of the segment from p to c, which the cell toward p holds; and x in a box whose
// least distance from c is b gives b <= |x - c| <= (1 - s) d + s R, so (for b > R)
// s <= (d - b) / (d - R): y lies in the box grown by w = R (d - b) / (d - R). A cell
// that only the box grown by more than g reaches is then needed only while
// R (d - b) > g (d - R), that is for d > R (b - g) / (R - g): its entry takes that
// distance instead of b, so that the rays of nearer points stop before it. g comes from
// the box's ranges grown by a few fractions of R: a cell outside the range grown by g
// is reached only by more. Each range is cut into the rings between these ranges.
constexpr int kLevels = 8;
constexpr double kLevelFraction[kLevels] = {0, 1.0 / 32, 1.0 / 16, 1.0 / 8, 1.0 / 4, 3.0 / 8, 1.0 / 2, 3.0 / 4};

// The float below x (with room for the rounding of the rays' points), as origin_distance().
float rounded_down(double x) {
    const double dm = x * (1 - 1e-3);
    float f = float(dm);
    if (double(f) > dm) f = std::nextafter(f, 0.0f);
    return f;
}

// The distance an entry of a box b from the centre of a sphere light of radius R takes
// in the cells reached only by the box grown by more than g (b already rounded down;
// R and g with room for rounding: a larger R and a smaller g give a smaller distance).
float ring_distance(float b, double R, double g) {
    const double Rh = R * (1 + 1e-6), gl = g * (1 - 1e-6);
    return double(b) > Rh ? std::max(b, rounded_down(Rh * (double(b) - gl) / (Rh - gl))) : b;
}

// Appends the cells of range `a` outside `in` (a range within it, i0 > i1 if none) as
// up to four ranges with distance dmin.
void add_ring(const CellRange& a, const CellRange& in, float dmin, std::vector<CellRange>& out) {
    auto add = [&](int i0, int i1, int j0, int j1) {
        if (i0 <= i1 && j0 <= j1) out.push_back({a.obj, dmin, a.face, i0, i1, j0, j1});
    };
    if (in.i0 > in.i1) return add(a.i0, a.i1, a.j0, a.j1);
    add(a.i0, a.i1, a.j0, in.j0 - 1);
    add(a.i0, a.i1, in.j1 + 1, a.j1);
    add(a.i0, in.i0 - 1, in.j0, in.j1);
    add(in.i1 + 1, a.i1, in.j0, in.j1);
}

// Replaces the ranges [first, end) of `ranges`, made for the box [lo, hi] (relative to
// the light, not grown) with distance b (rounded down) from the light of radius R, by
// their rings, each with its distance.
void split_rings(std::vector<CellRange>& ranges, std::size_t first, const Vec3& lo, const Vec3& hi, float b,
                 double R, int n, double tol, std::vector<CellRange>& grown) {
    if (!(double(b) > R)) return;  // no ring would take a larger distance
    // Per face of the full ranges, the range grown by each level's fraction, made to
    // hold the level below (as they do but for rounding: a cell's level may only be
    // lower) and to lie within the full range.
    const std::size_t full = ranges.size() - first;
    CellRange level[6][kLevels];
    for (int L = 0; L < kLevels; ++L) {
        const double w = R * kLevelFraction[L];
        grown.clear();
        face_ranges(lo - Vec3{w, w, w}, hi + Vec3{w, w, w}, 0, 0.0f, n, tol, grown);
        for (std::size_t k = 0; k < full; ++k) {
            const CellRange& a = ranges[first + k];
            CellRange r = a;
            r.i0 = 1, r.i1 = 0;
            for (const CellRange& g : grown)
                if (g.face == a.face) r.i0 = g.i0, r.i1 = g.i1, r.j0 = g.j0, r.j1 = g.j1;
            if (L > 0 && level[k][L - 1].i0 <= level[k][L - 1].i1) {
                const CellRange& q = level[k][L - 1];
                if (r.i0 > r.i1) r = q;
                r.i0 = std::min(r.i0, q.i0), r.i1 = std::max(r.i1, q.i1);
                r.j0 = std::min(r.j0, q.j0), r.j1 = std::max(r.j1, q.j1);
            }
            if (r.i0 <= r.i1) {
                r.i0 = std::max(r.i0, a.i0), r.i1 = std::min(r.i1, a.i1);
                r.j0 = std::max(r.j0, a.j0), r.j1 = std::min(r.j1, a.j1);
            }
            level[k][L] = r;
        }
    }
    for (std::size_t k = 0; k < full; ++k) {
        const CellRange a = ranges[first + k];
        CellRange inner = a;
        inner.i0 = 1, inner.i1 = 0;
        for (int L = 0; L <= kLevels; ++L) {
            const CellRange& r = L < kLevels ? level[k][L] : a;
            const float dmin = L == 0 ? b : ring_distance(b, R, R * kLevelFraction[L - 1]);
            if (r.i0 <= r.i1) add_ring(r, inner, dmin, ranges), inner = r;
        }
    }
    ranges.erase(ranges.begin() + std::ptrdiff_t(first), ranges.begin() + std::ptrdiff_t(first + full));
}

// Sorts the ranges by dmin, ties in their order (which is the objects' order): a
// stable radix sort on dmin's bits, which order like the values since dmin >= 0.
void sort_nearest_first(std::vector<CellRange>& ranges) {
    const std::size_t m = ranges.size();
    // Key (dmin's bits) above the range's index, so that the digits come from the top
    // half; the index says where each range goes in the end.
    std::vector<std::uint64_t> a(m), b(m);
    for (std::size_t k = 0; k < m; ++k) {
        std::uint32_t bits;
        std::memcpy(&bits, &ranges[k].dmin, sizeof bits);
        a[k] = std::uint64_t(bits) << 32 | k;
    }
    constexpr int kDigit = 11;
    for (int shift = 32; shift < 64; shift += kDigit) {
        std::uint32_t count[1u << kDigit] = {};
        const std::uint64_t mask = (std::uint64_t(1) << kDigit) - 1;
        for (std::uint64_t x : a) ++count[x >> shift & mask];
        // A digit that all keys share leaves the order as it is.
        if (m == 0 || count[a[0] >> shift & mask] == m) continue;
        std::uint32_t sum = 0;
        for (std::uint32_t& c : count) {
            std::uint32_t here = c;
            c = sum;
            sum += here;
        }
        for (std::uint64_t x : a) b[count[x >> shift & mask]++] = x;
        a.swap(b);
    }
    std::vector<CellRange> sorted(m);
    for (std::size_t k = 0; k < m; ++k) sorted[k] = ranges[std::uint32_t(a[k])];
    ranges.swap(sorted);
}

// The buffer's cells from the ranges (a counting sort), each cell's entries nearest first
// (ties: the earlier object first).
void fill_cells(LightBuffer& lb, std::vector<CellRange>& ranges, int n) {
    const std::size_t cells = 6 * std::size_t(n) * std::size_t(n);
    auto cell = [n](const CellRange& r, int i, int j) { return (std::size_t(r.face) * n + j) * n + i; };
    // The ranges nearest first: filled in that order, every cell comes out sorted
    // (an object has one range per face, so at most one entry in a cell), with no
    // sort per cell.
    sort_nearest_first(ranges);
    // start[c]: first the count of cell c, then the end of its entries (a running sum),
    // then, filled from the back, their start.
    std::vector<std::uint32_t>& start = lb.start;
    start.assign(cells + 1, 0);
    for (const CellRange& r : ranges)
        for (int j = r.j0; j <= r.j1; ++j)
            for (int i = r.i0; i <= r.i1; ++i) ++start[cell(r, i, j)];
    std::uint32_t sum = 0;
    for (std::size_t c = 0; c < cells; ++c) start[c] = sum += start[c];
    start[cells] = sum;
    lb.entries.resize(sum);
    LightBuffer::Entry* const entries = lb.entries.data();
    for (auto r = ranges.rbegin(); r != ranges.rend(); ++r)
        for (int j = r->j0; j <= r->j1; ++j)
            for (int i = r->i0; i <= r->i1; ++i) entries[--start[cell(*r, i, j)]] = {r->obj, r->dmin};
}

}  // namespace

namespace {

template <class Boxes>
LightBuffer build_light_buffer(const Boxes& boxes, const Vec3& light, int n, double pad) {
    using Entry = LightBuffer::Entry;
    LightBuffer lb;
    lb.position = light;
    lb.position1 = LightBuffer::norm1(light);
    // Far beyond float range or not finite: the BVH copes; keep to it.
    if (!(norm_inf(light) < 1e30) || n < 1) return lb;
    const std::size_t cells = 6 * std::size_t(n) * std::size_t(n);
    const double tol = 2 * kCellPad / n;  // the padding in face coordinates
    std::vector<CellRange> ranges;
    std::vector<Entry> always;
    std::vector<CellRange> grown;  // split_rings()'s
    std::size_t total = 0, objects = 0;
    double near = HUGE_VAL;
    for (std::uint32_t obj = 0; obj < boxes.size(); ++obj) {
        const Aabb& b = boxes[obj];
        if (b.empty()) continue;  // never in the BVH: never hit
        ++objects;
        if (!(norm_inf(b.lo) < 1e30 && norm_inf(b.hi) < 1e30)) return lb;
        Vec3 lo = b.lo - light, hi = b.hi - light;
        // A sphere light's cells list the box grown by its radius, but the entry keeps
        // the box's own distance: a shadow ray from p to a point of the sphere never goes
        // farther from the centre than p is (the distance along a segment is convex, and
        // the sphere's points are nearer), so only boxes within that distance can block.
        float df_box = 0;
        const Vec3 lo_box = lo, hi_box = hi;
        if (pad > 0) {
            origin_distance(lo, hi, df_box);
            lo -= Vec3{pad, pad, pad}, hi += Vec3{pad, pad, pad};
        }
        float df;
        double dmin = origin_distance(lo, hi, df);
        if (pad > 0) df = df_box;
        double scale = std::max({norm_inf(b.lo), norm_inf(b.hi), norm_inf(light)});
        // Nearer than rounding can tell directions apart (or around the light): every
        // ray tests it.
        if (!(dmin > 1e-6 * (scale + 1))) {
            always.push_back({obj, 0.0f});
            continue;
        }
        near = std::min(near, dmin);
        std::size_t first_range = ranges.size();
        std::size_t covered = face_ranges(lo, hi, obj, df, n, tol, ranges);
        // One seen in most directions is cheaper tested by every ray than listed.
        if (covered > cells / 4) {
            ranges.resize(first_range);
            always.push_back({obj, df});
            continue;
        }
        if (pad > 0) split_rings(ranges, first_range, lo_box, hi_box, df_box, pad, n, tol, grown);
        total += covered;
        if (total > kLightBufferMaxEntries * boxes.size() + 8 * cells) return lb;
    }
    if (objects == 0) return lb;
    fill_cells(lb, ranges, n);
    lb.always = std::move(always);
    // How far a ray's points may be off its line, against the nearest listed box:
    // about 8 rounding errors of |p| + |light| + r, which must stay within the padding
    // (tol) times that box's distance, with a factor 2 to spare.
    lb.reach = near == HUGE_VAL ? HUGE_VAL : tol * near / (16 * 2.3e-16);
    lb.n = n;
    lb.half_n = 0.5 * n;
    return lb;
}

}  // namespace

LightBuffer LightBuffer::build(const std::vector<Aabb>& boxes, const Vec3& light, int n, double pad) {
    return build_light_buffer(boxes, light, n, pad);
}

LightBuffer LightBuffer::build(const Chunked<Aabb>& boxes, const Vec3& light, int n, double pad) {
    return build_light_buffer(boxes, light, n, pad);
}

}  // namespace rt
