// Shading as in docs/rendering.md §2-§6: direct light with the unshadowed 0.1 term and
// coloured shadows through refractive objects, mirror reflection, refraction with the
// interior walk, and lamp glow discs. Planes are few and unbounded, so they are tested
// one by one; objects go through the BVH, and glow discs too when there are many.
// The ray tree is cut where the rays left out cannot be seen (World::omit_weight) and
// where the caller asks to stop (RayStats::stop). On the AVX2 path camera rays and their
// mirror rays go in packets of four whose direct light is found together.
#include "world.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <iterator>
#include <limits>
#include <mutex>
#include <system_error>
#include <thread>

#include "shapes.h"
#include "world_build.h"

namespace rt {
namespace {

constexpr double kInf = HUGE_VAL;

// k * C with the original's quirk: black for k <= 0.
inline Colour scale(double k, const Colour& c) { return k > 0 ? c * k : Colour{}; }

// base^e from log(base) (-inf for base 0), with the original's edge cases: x^0 = 1,
// 0^e = 0, and 0 where the power overflows.
inline double tint_pow(double log_base, double e) {
    if (e == 0 || log_base == 0) return 1;
    if (log_base == -kInf) return 0;
    double r = std::exp(e * log_base);
    return std::isfinite(r) ? r : 0;
}
// The tint of a material after a path of length s inside it.
inline Colour tint(const ShadeMaterial& m, double s) {
    return {tint_pow(m.log_tint.x, s), tint_pow(m.log_tint.y, s), tint_pow(m.log_tint.z, s)};
}

// docs/rendering.md §5, with the normal-incidence fix: straight through.
// `n` is turned to face against d (the original changes the caller's normal too).
bool refract(const Vec3& d, double eta1, double eta2, Vec3& n, Vec3& out) {
    if (dot(n, d) > 0) n = -n;
    double b = -dot(n, d);
    Vec3 t = d + n * b;
    double tl = length(t);
    double sin2 = tl * eta1 / eta2;  // |d| = 1
    if (sin2 > 1) return false;
    if (tl == 0) {
        out = d;
        return true;
    }
    out = n * -std::sqrt(1 - sin2 * sin2) + t * (sin2 / tl);
    return true;
}

inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2 * dot(d, n)); }

inline double max3(const Colour& c) { return std::max(c.x, std::max(c.y, c.z)); }
inline Colour cabs(const Colour& c) { return {std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)}; }

// From this many glow discs on, a BVH over them beats testing each one.
constexpr std::size_t kGlowBvhMin = 8;

// Lamp glow hit: the disc at the lamp's distance, if the line passes within `size`
// and the lamp is ahead (the original also hit lamps behind the origin).
inline bool glow_hit(const ShadeLight& l, const Vec3& o, const Vec3& d, double& t) {
    if (l.glow <= 0) return false;
    Vec3 co = l.position - o;
    double along = dot(co, d);
    if (!(along > 0)) return false;
    double dist2 = dot(co, co) - along * along;
    if (dist2 > l.glow * l.glow) return false;
    t = length(co);
    return true;
}

}  // namespace

namespace {
// Cells of padding on each side of an object's range in a light buffer: directions
// are computed with rounding, and a ray's points sit off its exact line by a little.
constexpr double kCellPad = 0.01;
// Light buffers are made for scenes of up to this many objects times lights (their
// build is serial and must stay well under the BVH's), and hold at most this many
// entries per object on average (and eight per cell).
constexpr std::size_t kLightBufferMaxWork = 1 << 17;
constexpr std::size_t kLightBufferMaxEntries = 64;
// And at most this many cells in all (4 bytes each): many lights over a few objects
// would otherwise take memory out of proportion to the scene.
constexpr std::size_t kLightBufferMaxCells = std::size_t(1) << 24;

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
LightBuffer build_light_buffer(const Boxes& boxes, const Vec3& light, int n) {
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
    std::size_t total = 0, objects = 0;
    double near = HUGE_VAL;
    for (std::uint32_t obj = 0; obj < boxes.size(); ++obj) {
        const Aabb& b = boxes[obj];
        if (b.empty()) continue;  // never in the BVH: never hit
        ++objects;
        if (!(norm_inf(b.lo) < 1e30 && norm_inf(b.hi) < 1e30)) return lb;
        Vec3 lo = b.lo - light, hi = b.hi - light;
        float df;
        double dmin = origin_distance(lo, hi, df);
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

LightBuffer LightBuffer::build(const std::vector<Aabb>& boxes, const Vec3& light, int n) {
    return build_light_buffer(boxes, light, n);
}

LightBuffer LightBuffer::build(const Chunked<Aabb>& boxes, const Vec3& light, int n) {
    return build_light_buffer(boxes, light, n);
}

struct World::Ctx {
    SpanScratch scratch;
    RayStats* stats = nullptr;
    // The weight that the rays left out of this camera ray's tree may still add up to,
    // and the lightest ray that is followed: a small share of that, so that the budget
    // shrinks slowly and lasts however big the tree (+inf once the caller has asked to
    // stop, which unwinds the tree at once).
    double budget = 0;
    double cutoff = 0;
    static constexpr double kShare = 1.0 / 4096;
    void leave_out(double weight) {
        budget -= weight;
        cutoff = budget * kShare;
    }
    // Per light, the last opaque object that shadowed a point (+1; 0 = none). Shadows
    // are coherent, so trying it first usually ends the search at once.
    std::vector<std::uint32_t> blocker;
    // glass_tint()'s refractive objects on a shadow ray: where it enters each.
    std::vector<std::pair<double, std::uint32_t>> glass;
};

namespace {
// Called every RayStats::kPollRays rays: has the caller asked to stop?
[[gnu::cold, gnu::noinline]] void poll(RayStats& st, double& cutoff, double& budget) {
    st.next_poll = st.rays + RayStats::kPollRays;
    const TraceStop& stop = st.stop;
    bool flagged = stop.flag && stop.flag->load(std::memory_order_relaxed);
    if (flagged || (stop.deadline != std::chrono::steady_clock::time_point::max() &&
                    (stop.now ? stop.now() : std::chrono::steady_clock::now()) >= stop.deadline)) {
        st.stopped = true;
        budget = cutoff = std::numeric_limits<double>::infinity();
    }
}
}  // namespace

struct World::HitRec {
    enum Kind { None, Object, PlaneHit, Glow } kind = None;
    double t = kInf;
    std::uint32_t index = 0;  // object, plane or light
    SpanEnd end{};            // for objects: the surface that was hit
};

// A ray's hit as shade() lights it: the point, its normal (turned toward the ray on
// refractive surfaces) and material, and the light refracted into it.
struct World::Surface {
    Vec3 p, n;
    const ShadeMaterial* m = nullptr;
    Colour refr;
};

ShadeMaterial ShadeMaterial::from(const Material& m) {
    ShadeMaterial s;
    double sum = m.reflection + m.refraction + m.scattering;
    if (sum != 0 && std::isfinite(sum)) {
        s.reflection = m.reflection / sum;
        s.refraction = m.refraction / sum;
        s.scattering = m.scattering / sum;
    } else {
        s.reflection = s.refraction = s.scattering = 0;
    }
    s.translusans = std::clamp(m.translusans, 0.0, 1.0);
    s.ior = std::max(1.0, m.refractive_index);
    s.colour = m.colour;
    Colour base = m.colour * s.translusans;
    for (int k = 0; k < 3; ++k) s.log_tint[k] = base[k] > 0 ? std::log(base[k]) : -kInf;
    return s;
}

PlaneShape PlaneShape::from(const Plane& p) {
    PlaneShape q;
    Vec3 e1 = p.point[1] - p.point[0], e2 = p.point[2] - p.point[0], e3 = p.point[3] - p.point[0];
    q.n = normalize(cross(e1, e2));
    if (dot(q.n, e3) < 0) q.n = -q.n;
    q.D = -dot(q.n, p.point[0]);
    q.p1 = p.point[0];
    q.chess = p.chess;
    double det = dot(e1, cross(e2, e3));
    // Point 4 in the plane leaves the cell decomposition singular.
    q.singular = !(std::fabs(det) > 1e-12 * length(e1) * length(e2) * length(e3));
    if (!q.singular) {
        q.inv_row[0] = cross(e2, e3) / det;
        q.inv_row[1] = cross(e3, e1) / det;
        q.inv_row[2] = cross(e1, e2) / det;
    }
    return q;
}

int PlaneShape::cell(const Vec3& p) const {
    if (!chess || singular) return 0;
    Vec3 r = p - p1;
    double a = dot(inv_row[0], r), b = dot(inv_row[1], r);
    // Far beyond any picture's resolution the parity is meaningless; keep it defined.
    if (!(std::fabs(a) < 1e15 && std::fabs(b) < 1e15)) return 0;
    // floor() by conversion: std::floor is a library call without SSE4.1.
    auto ifloor = [](double v) {
        long long i = static_cast<long long>(v);
        return i - (double(i) > v ? 1 : 0);
    };
    return int((ifloor(a) + ifloor(b)) & 1);
}

// The nearest glow disc nearer than h. (Out of line: most rays meet no glow, and
// the callers' hot loops stay small.)
void World::nearest_glow(const Vec3& o, const Vec3& d, HitRec& h) const {
    if (glow_bvh) {
        // The same disc as the loop below would find: on an exact tie the earlier lamp.
        glow_bvh->traverse(o, d, h.t, [&](std::uint32_t gi, double tmax) -> double {
            std::uint32_t i = glows[gi];
            double t;
            if (glow_hit(lights[i], o, d, t) && t > kDelta &&
                (t < tmax || (t == tmax && h.kind == HitRec::Glow && i < h.index))) {
                h.kind = HitRec::Glow;
                h.t = t;
                h.index = i;
                return t;
            }
            return tmax;
        });
        return;
    }
    for (std::uint32_t i : glows) {
        double t;
        if (glow_hit(lights[i], o, d, t) && t > kDelta && t < h.t) {
            h.kind = HitRec::Glow;
            h.t = t;
            h.index = i;
        }
    }
}

#if RT_HAVE_AVX2_KERNELS
namespace {
// nearest()'s camera-buffer loop for a scene of spheres only, on the AVX2 path: the
// cell's spheres four at a time (up to three of them past the nearest hit's reach,
// which nearest()'s rule makes harmless). Returns where the scalar loop goes on.
// (Out of line: nearest() stays as small for the other scenes.)
[[gnu::noinline]] const LightBuffer::Entry* camera_spheres(const Geometry& g, const LightBuffer::Entry* e,
                                                           const LightBuffer::Entry* end, const Vec3& o, const Vec3& d,
                                                           World::HitRec& h) {
    for (std::ptrdiff_t left; (left = end - e) >= 2 && !(double(e->dmin) > h.t);) {
        // (The lanes past the cell's end repeat its first entry, masked off.)
        const int n = left < 4 ? int(left) : 4;
        const std::uint32_t ids[4] = {e[0].obj, e[1].obj, e[n > 2 ? 2 : 0].obj, e[n > 3 ? 3 : 0].obj};
        double t[4];
        for (unsigned m = g.sphere_entries4(ids, o, d, kDelta, t) & ((1u << n) - 1); m != 0; m &= m - 1) {
            const int k = __builtin_ctz(m);
            // nearest()'s rule: the nearest, on an exact tie the earlier object.
            if (t[k] < h.t || (t[k] == h.t && h.kind == World::HitRec::Object && ids[k] < h.index)) {
                h.kind = World::HitRec::Object;
                h.t = t[k];
                h.index = ids[k];
                h.end = {t[k], ids[k], 0, false};
            }
        }
        e += n;
    }
    return e;
}
}  // namespace
#endif

bool World::nearest(const Vec3& o, const Vec3& d, Ctx& ctx, HitRec& h) const {
    const Geometry& g = *geometry;
    h.kind = HitRec::None;
    h.t = kInf;
    // Planes and glows first: their distance prunes the BVH search.
    const PlaneShape* const first_plane = planes.data();
    const std::uint32_t plane_count = std::uint32_t(planes.size());
    for (std::uint32_t i = 0; i < plane_count; ++i) {
        const PlaneShape& p = first_plane[i];
        double dn = dot(p.n, d);
        if (dn == 0) continue;
        double t = -(dot(p.n, o) + p.D) / dn;
        if (t > kDelta && t < h.t) {
            h.kind = HitRec::PlaneHit;
            h.t = t;
            h.index = i;
        }
    }
    if (!glows.empty()) nearest_glow(o, d, h);
    auto test = [&](std::uint32_t obj, double tmax) -> double {
        SpanEnd e;
        // On an exact tie the earlier object in the file wins, as in the original.
        if (g.hit_inline(obj, o, d, kDelta, e, ctx.scratch) &&
            (e.t < tmax || (e.t == tmax && h.kind == HitRec::Object && obj < h.index))) {
            h.kind = HitRec::Object;
            h.t = e.t;
            h.index = obj;
            h.end = e;
            return e.t;
        }
        return tmax;
    };
    const LightBuffer* cb = camera_buffer.get();
    if (cb && o == cb->position && cb->usable(o, 0)) {
        // A ray from the camera: only the objects seen in its direction, nearest box
        // first, until the boxes lie beyond the nearest hit. (The rule above takes the
        // nearest hit, ties to the earlier object, in whatever order they come.)
        const LightBuffer::Entry *e, *end;
        cb->cell(d, e, end);
#if RT_HAVE_AVX2_KERNELS
        if (end - e >= 2 && g.sphere_prefix == g.object_node.size() && avx2_active())
            e = camera_spheres(g, e, end, o, d, h);
#endif
        for (; e != end && !(double(e->dmin) > h.t); ++e) test(e->obj, h.t);
        for (const LightBuffer::Entry& a : cb->always) test(a.obj, h.t);
    } else {
        g.bvh.traverse_nearest(o, d, h.t, test);
    }
    return h.kind != HitRec::None;
}

// Does a lamp's glow disc lie on the segment from o along the unit dir, before limit?
// (docs/rendering.md §6: the discs block other lights.)
// (Through glow_bvh; direct() loops over a few discs itself.)
bool World::glow_blocks(const Vec3& o, const Vec3& dir, double limit) const {
    bool blocked = false;
    glow_bvh->traverse(o, dir, limit, [&](std::uint32_t gi, double tmax) -> double {
        double t;
        if (glow_hit(lights[glows[gi]], o, dir, t) && t > 0 && t < limit) {
            blocked = true;
            return -1;
        }
        return tmax;
    });
    return blocked;
}

Colour World::direct(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const {
    // Stopped: the colour is thrown away, and with thousands of lights this is the
    // costly part of unwinding a deep tree.
    if (ctx.stats->stopped) return {};
    // Two versions of the loop: a call to glow_blocks() inside it would make the
    // compiler keep its floating-point values in memory, even where it is never made.
    return glow_bvh ? direct_lights<true>(p, n, cp, ctx) : direct_lights<false>(p, n, cp, ctx);
}

// A shadow ray toward one light: it leaves p a little toward the light, along the unit
// vh, and must reach `limit` (a little short of the light) unblocked. v = light - p,
// r = |v|; `light` is the light's index.
struct World::ShadowRay {
    Vec3 o, v, vh;
    double r, limit;
    std::size_t light;
};

// The refractive objects met so far by a shadow ray: how many, and the first one.
struct World::ShadowSearch {
    std::uint32_t glass = 0, obj = 0;
    double t = 0;
};

// The shadow ray meets object `obj` at t, before its end: true if the object is opaque
// (and then the light's blocker), else it is counted in `found`.
inline bool World::met(std::uint32_t obj, double t, const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const {
    if (materials[obj].refraction == 0) {
        ctx.blocker[s.light] = obj + 1;
        return true;
    }
    if (found.glass++ == 0) found.obj = obj, found.t = t;
    return false;
}

// Whether object `obj` blocks the shadow ray (and then the light's blocker is it);
// a refractive one is counted in `found` instead.
// (kOther: not a sphere of the prefix, through Geometry::shadow_hit().)
template <bool kOther>
inline bool World::shadow_test(std::uint32_t obj, const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const {
    SpanEnd e;
    bool hit = kOther ? geometry->shadow_hit(obj, s.o, s.vh, s.limit, e, ctx.scratch)
                      : geometry->hit(obj, s.o, s.vh, 0.0, e, ctx.scratch);
    return hit && e.t < s.limit && met(obj, e.t, s, found, ctx);
}

// `sh` tinted by the refractive object `obj`, which the shadow ray enters at t: by its
// colour over the length the ray runs inside it.
inline Colour World::through_glass(std::uint32_t obj, double t, const ShadowRay& s, const Colour& sh, Ctx& ctx) const {
    const ShadeMaterial& m = materials[obj];
    const Geometry& g = *geometry;
    const Vec3 q = s.o + s.vh * t;
    double len = 0;
    if (obj < g.sphere_prefix) {
        // Geometry::exit() for a sphere, the common glass: its span's far end from q,
        // with sphere_spans()'s operations (so the same bits), if beyond kDelta.
        const SphereG& sp = g.spheres[obj];
        Vec3 oc = q - sp.c;
        double b = dot(oc, s.vh);
        double e = dot(oc, oc) - sp.r2;
        double disc = b * b - e;
        if (!(disc < 0)) {
            double out = -b + std::sqrt(disc);
            if (out > kDelta) len = out;
        }
    } else {
        SpanEnd x;
        if (g.exit(obj, q, s.vh, x, ctx.scratch)) len = x.t;
    }
    return mul(sh, tint(m, len * m.refraction));
}

// Whether an opaque plane or a glow disc lies on the shadow ray.
template <bool kGlowBvh>
inline bool World::others_block(const ShadowRay& s) const {
    for (auto it = planes.begin(); it != planes.end(); ++it) {
        const PlaneShape& pl = *it;
        double dn = dot(pl.n, s.vh), side = dot(pl.n, s.o) + pl.D;
        // t = -side / dn is positive only where the signs differ: most rays (a point
        // and its light on the same side, the ray leaving the plane) end here, before
        // the division.
        if (!((side > 0 && dn < 0) || (side < 0 && dn > 0))) continue;
        double t = -side / dn;
        if (!(t > 0 && t < s.limit)) continue;
        // A plane is a window of zero thickness: refractive ones pass light unchanged.
        if (plane_mats[2 * std::size_t(it - planes.begin()) + pl.cell(s.o + s.vh * t)].refraction == 0) return true;
    }
    if constexpr (kGlowBvh) {
        return glow_blocks(s.o, s.vh, s.limit);
    } else {
        for (std::uint32_t i : glows) {
            double t;
            if (glow_hit(lights[i], s.o, s.vh, t) && t > 0 && t < s.limit) return true;
        }
        return false;
    }
}

// Whether the opaque object that last shadowed this light here blocks the ray too.
inline bool World::blocker_blocks(const ShadowRay& s, Ctx& ctx) const {
    const std::uint32_t blocker = ctx.blocker[s.light];
    if (blocker == 0 || blocker > materials.size() || materials[blocker - 1].refraction != 0) return false;
    SpanEnd e;
    return geometry->shadow_hit(blocker - 1, s.o, s.vh, s.limit, e, ctx.scratch) && e.t < s.limit;
}

// `sh` tinted by the refractive objects that a shadow ray met (none opaque): one alone
// gives its tint; two or more need the ordered search of glass_tint(), which multiplies
// their tints in a fixed order (so that the product rounds the same on every path).
Colour World::found_tint(const ShadowRay& s, const ShadowSearch& found, const Colour& sh, Ctx& ctx) const {
    return found.glass == 1 ? through_glass(found.obj, found.t, s, sh, ctx) : glass_tint(s, sh, ctx);
}

// The end of objects_block() once no object has blocked the ray.
inline void World::unblocked(const ShadowRay& s, const ShadowSearch& found, Colour& sh, Ctx& ctx) const {
    if (found.glass > 0) sh = found_tint(s, found, sh, ctx);
    // No object blocks this light here: neighbouring points will not try one first.
    ctx.blocker[s.light] = 0;
}

// objects_block() past the blocker, for a ray whose cell of the light buffer lb holds the
// entries [e, end): only the objects the light sees in this direction, nearer than p.
// An opaque object on the way blocks the light whatever else lies there, so the objects
// may be tested in any order, stopping at the first such one.
inline bool World::cell_blocks(const ShadowRay& s, const LightBuffer& lb, const LightBuffer::Entry* e,
                               const LightBuffer::Entry* end, Colour& sh, Ctx& ctx) const {
    const Geometry& g = *geometry;
    ShadowSearch found;
    // Spheres of the prefix are tested here, as Geometry::hit() would (the same
    // operations, so the same bits), without its lookups; the rest through it.
    const std::uint32_t prefix = g.sphere_prefix;
    const SphereG* const flat = g.spheres.flat();
    SphereG* const* const table = g.spheres.table();
    for (; e != end && !(double(e->dmin) > s.r); ++e) {
        const std::uint32_t obj = e->obj;
        if (obj < prefix) {
            const SphereG& sp = flat ? flat[obj] : table[obj >> Chunked<SphereG>::kShift][obj & Chunked<SphereG>::kMask];
            Vec3 oc = s.o - sp.c;
            double b = dot(oc, s.vh);
            double disc = b * b - (dot(oc, oc) - sp.r2);
            if (disc < 0) continue;
            double t = -b - std::sqrt(disc);
            if (!(t > 0.0) || !(t < s.limit)) continue;
            if (met(obj, t, s, found, ctx)) return true;
        } else if (shadow_test<true>(obj, s, found, ctx)) {
            return true;
        }
    }
    for (const LightBuffer::Entry& a : lb.always)
        if (!(double(a.dmin) > s.r) && shadow_test(a.obj, s, found, ctx)) return true;
    unblocked(s, found, sh, ctx);
    return false;
}

// Whether an opaque object lies on the shadow ray; if none, `sh` takes the tint of the
// refractive ones on it. p1: |p|_1 of the ray's start.
inline bool World::objects_block(const ShadowRay& s, double p1, Colour& sh, Ctx& ctx) const {
    if (blocker_blocks(s, ctx)) return true;
    const LightBuffer* lb = light_buffers ? &(*light_buffers)[s.light] : nullptr;
    if (lb && lb->usable(p1, s.r)) {
        const LightBuffer::Entry *e, *end;
        lb->cell_toward(s.v, e, end);
        return cell_blocks(s, *lb, e, end, sh, ctx);
    }
    ShadowSearch found;
    if (objects_block_bvh(s, found, ctx)) return true;
    unblocked(s, found, sh, ctx);
    return false;
}

// Glow discs are tested one by one, or through their BVH if kGlowBvh.
template <bool kGlowBvh>
Colour World::direct_lights(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const {
    Colour sum;  // (returned as a copy: the caller's object would be written every turn)
    if (ctx.blocker.size() < lights.size()) ctx.blocker.resize(lights.size());
    const double p1 = LightBuffer::norm1(p);  // for the light buffers' usable()
    // Chunk by chunk of the lights (most scenes have one); each chunk's array and count
    // once: the loop's stores might otherwise be taken to change them.
    for (std::size_t c = 0, chunks = lights.chunk_count(); c < chunks; ++c) {
        const ShadeLight* const all = lights.chunk(c);
        const std::size_t first = c << Chunked<ShadeLight>::kShift, count = lights.chunk_size(c);
        for (std::size_t k = 0; k < count; ++k) {
            const std::size_t li = first + k;
            const ShadeLight& light = all[k];
            Vec3 v = light.position - p;
            double r2 = dot(v, v);
            // (Multiplying by reciprocals: a division each would sit on the critical path.)
            Colour e = r2 > 0 ? light.colour * (1 / r2) : Colour{1, 1, 1};
            sum += mul(e, cp) * 0.1;
            double vn = dot(v, n);
            if (!(vn > 0)) continue;
            double r = std::sqrt(r2), inv_r = 1 / r;
            Vec3 vh = v * inv_r;
            const ShadowRay s{p + vh * kDelta, v, vh, r, r - 10 * kDelta, li};
            ++ctx.stats->rays;
            Colour sh{1, 1, 1};
            if (objects_block(s, p1, sh, ctx) || others_block<kGlowBvh>(s)) continue;
            sum += mul(mul(e, cp), sh) * (0.9 * vn * inv_r);
        }
    }
    return Colour{sum.x, sum.y, sum.z};
}

// objects_block() where the light buffer cannot serve: through the BVH.
bool World::objects_block_bvh(const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const {
    // (The box test takes v and r: its inverse direction r / v is then one division
    // after the square root instead of two.)
    return geometry->bvh.occluded(s.o, s.v, s.r, s.limit,
                                  [&](std::uint32_t obj) { return shadow_test(obj, s, found, ctx); });
}

// `sh` times the tints of all the refractive objects on the shadow ray (none opaque),
// nearest first (on a tie, the earlier object first): an order that is the same
// whatever the BVH's shape, so that a refitted tree gives the picture of a new one.
Colour World::glass_tint(const ShadowRay& s, Colour sh, Ctx& ctx) const {
    const Geometry& g = *geometry;
    std::vector<std::pair<double, std::uint32_t>>& met = ctx.glass;
    met.clear();
    g.bvh.occluded(s.o, s.v, s.r, s.limit, [&](std::uint32_t obj) {
        SpanEnd e;
        if (g.hit(obj, s.o, s.vh, 0.0, e, ctx.scratch) && e.t < s.limit) met.push_back({e.t, obj});
        return false;
    });
    std::sort(met.begin(), met.end());
    for (const auto& [t, obj] : met) sh = through_glass(obj, t, s, sh, ctx);
    return sh;
}

Colour World::walk(const HitRec& x, const Vec3& q0, const Vec3& d1, double eta, int level, double weight,
                   Ctx& ctx) const {
    if (level >= options.max_depth) return {};
    if (__builtin_expect(weight < ctx.cutoff, 0)) {
        ctx.leave_out(weight);
        return {};
    }
    if (__builtin_expect(++ctx.stats->rays >= ctx.stats->next_poll, 0)) poll(*ctx.stats, ctx.cutoff, ctx.budget);
    const Geometry& g = *geometry;
    double s = 0;
    Vec3 n1;
    const ShadeMaterial* m;
    if (x.kind == HitRec::Object) {
        m = &materials[x.index];
        SpanEnd e;
        if (g.exit(x.index, q0, d1, e, ctx.scratch) && std::isfinite(e.t)) {
            s = e.t;
            n1 = g.surface_normal(x.index, e, q0 + d1 * s);
        } else {
            // The original would use a negative length here; treat it as 0 instead.
            n1 = g.surface_normal(x.index, x.end, q0);
        }
    } else {
        const PlaneShape& p = planes[x.index];
        m = &plane_mats[2 * x.index + p.cell(q0)];
        n1 = p.n;
    }
    Vec3 q1 = q0 + d1 * s;
    Vec3 d2;
    Colour c;
    // The segment's absorption is known before the rest of the path is followed.
    const Colour seg = tint(*m, s);
    weight *= max3(seg);
    if (refract(d1, eta, 1, n1, d2))
        c = shade(q1, d2, level + 1, weight, ctx);
    else
        c = walk(x, q1, reflect(d1, n1), eta, level + 1, weight, ctx);
    return mul(c, seg);
}

// shade() up to the point's direct light: the ray's nearest hit, its material and normal,
// and the light refracted into it (walked first, as the original does). False, with the
// ray's colour in `out`, when nothing more is needed. `weight`: how much of this ray's
// colour reaches the pixel (see World::omit_weight).
inline bool World::shade_surface(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx, Surface& s,
                                 Colour& out) const {
    out = {};
    if (depth >= options.max_depth) return false;
    if (__builtin_expect(weight < ctx.cutoff, 0)) {
        ctx.leave_out(weight);
        return false;
    }
    if (__builtin_expect(++ctx.stats->rays >= ctx.stats->next_poll, 0)) poll(*ctx.stats, ctx.cutoff, ctx.budget);
    HitRec h;
    if (!nearest(o, d, ctx, h)) return false;
    const Vec3 p = o + d * h.t;
    s.p = p;
    if (h.kind == HitRec::Glow) {
        const ShadeLight& l = lights[h.index];
        double rho = length(l.position - p);
        if (!(rho < l.glow)) return false;
        double f = (l.glow - rho) / l.glow;
        out = l.colour * (f * f * f * f * f);
        return false;
    }
    const ShadeMaterial* m;
    Vec3 n;
    if (h.kind == HitRec::Object) {
        m = &materials[h.index];
        n = geometry->surface_normal(h.index, h.end, p);
    } else {
        const PlaneShape& pl = planes[h.index];
        m = &plane_mats[2 * h.index + pl.cell(p)];
        n = pl.n;
    }
    s.m = m;
    s.refr = {};
    if (m->refraction != 0) {
        // The original refracts first, and that turns n toward the ray for the other
        // terms too (a transparent surface seen from behind is lit from the front).
        if (dot(n, d) > 0) n = -n;
        if (depth + 1 < options.max_depth && m->refraction > 0) {
            Vec3 d1;
            Vec3 nn = n;
            if (refract(d, 1, m->ior, nn, d1))
                s.refr = walk(h, p, normalize(d1), m->ior, depth + 2, weight * m->refraction, ctx);
        }
    }
    s.n = n;
    return true;
}

// A surface's colour from its direct light `lit` and the light `mirror` its mirror ray
// brings (each used only if the material scatters or reflects) and the refracted light.
inline Colour World::combine(const Surface& s, const Colour& lit, const Colour& mirror) {
    const ShadeMaterial* m = s.m;
    Colour c;
    if (m->scattering > 0) c += lit * m->scattering;
    if (m->reflection > 0) c += mirror * m->reflection;
    c += scale(m->refraction, s.refr);
    return c;
}

Colour World::shade(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx) const {
    Surface s;
    Colour out;
    if (!shade_surface(o, d, depth, weight, ctx, s, out)) return out;
    const ShadeMaterial* m = s.m;
    const Colour lit = m->scattering > 0 ? direct(s.p, s.n, m->colour, ctx) : Colour{};
    const Colour mirror =
        m->reflection > 0 ? shade(s.p, reflect(d, s.n), depth + 2, weight * m->reflection, ctx) : Colour{};
    return combine(s, lit, mirror);
}

Colour World::trace(const Vec3& origin, const Vec3& dir, int depth, RayStats& stats) const {
    return trace_from(origin, normalize(dir), depth, stats);
}

Colour World::trace_unit(const Vec3& origin, const Vec3& unit_dir, RayStats& stats) const {
    return trace_from(origin, unit_dir, 0, stats);
}

namespace {
// The tracing state of this thread's camera rays, one for all its traces (so that its
// shadow caches carry over from ray to ray).
World::Ctx& thread_ctx() {
    thread_local World::Ctx ctx;
    return ctx;
}

// No NaN ever reaches a pixel.
inline Colour finite_colour(Colour c) {
    if (!std::isfinite(c.x)) c.x = c.x > 0 ? 1e30 : 0;
    if (!std::isfinite(c.y)) c.y = c.y > 0 ? 1e30 : 0;
    if (!std::isfinite(c.z)) c.z = c.z > 0 ? 1e30 : 0;
    return c;
}
}  // namespace

Colour World::trace_from(const Vec3& origin, const Vec3& d, int depth, RayStats& stats) const {
    Ctx& ctx = thread_ctx();
    ctx.stats = &stats;
    if (stats.stopped) return {};
    ctx.budget = omit_weight;
    ctx.cutoff = omit_weight * Ctx::kShare;
    return finite_colour(shade(origin, d, depth, 1.0, ctx));
}

#if RT_HAVE_AVX2_KERNELS
namespace {
// Four lanes of doubles: one point, vector or number per ray of a packet. The helpers
// form sums and products in the scalar code's order, so that each lane has its bits.
struct V3 {
    __m256d x, y, z;
};
RT_TARGET_AVX2 inline __m256d splat(double a) { return _mm256_set1_pd(a); }
RT_TARGET_AVX2 inline __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }
RT_TARGET_AVX2 inline __m256d sub(__m256d a, __m256d b) { return _mm256_sub_pd(a, b); }
RT_TARGET_AVX2 inline __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
RT_TARGET_AVX2 inline unsigned lanes(__m256d mask) { return unsigned(_mm256_movemask_pd(mask)); }
RT_TARGET_AVX2 inline __m256d dot(const V3& a, const V3& b) { return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z)); }
// dot(n, v) with n the same in every lane.
RT_TARGET_AVX2 inline __m256d dot(const Vec3& n, const V3& v) {
    return add(add(mul(splat(n.x), v.x), mul(splat(n.y), v.y)), mul(splat(n.z), v.z));
}
RT_TARGET_AVX2 inline V3 scaled(const V3& a, __m256d s) { return {mul(a.x, s), mul(a.y, s), mul(a.z, s)}; }
// A field of each lane's Vec3, gathered into a V3.
RT_TARGET_AVX2 inline V3 gather(const Vec3* const v[4]) {
    return {_mm256_set_pd(v[3]->x, v[2]->x, v[1]->x, v[0]->x), _mm256_set_pd(v[3]->y, v[2]->y, v[1]->y, v[0]->y),
            _mm256_set_pd(v[3]->z, v[2]->z, v[1]->z, v[0]->z)};
}
// A V3's lanes as Vec3s.
struct Lanes3 {
    alignas(32) double x[4], y[4], z[4];
    RT_TARGET_AVX2 explicit Lanes3(const V3& v) {
        _mm256_store_pd(x, v.x);
        _mm256_store_pd(y, v.y);
        _mm256_store_pd(z, v.z);
    }
    Vec3 operator[](int k) const { return {x[k], y[k], z[k]}; }
};
struct Lanes1 {
    alignas(32) double a[4];
    RT_TARGET_AVX2 explicit Lanes1(__m256d v) { _mm256_store_pd(a, v); }
    double operator[](int k) const { return a[k]; }
};

// The lanes (of `live`) whose shadow ray from o along the unit vh meets an opaque plane
// before limit: others_block()'s plane loop, four rays at a time.
RT_TARGET_AVX2 unsigned planes_block4(const World& w, const V3& o, const V3& vh, __m256d limit, unsigned live) {
    const __m256d zero = _mm256_setzero_pd();
    unsigned blocked = 0;
    for (std::size_t i = 0; i < w.planes.size() && (live & ~blocked); ++i) {
        const PlaneShape& pl = w.planes[i];
        const __m256d dn = dot(pl.n, vh), side = add(dot(pl.n, o), splat(pl.D));
        const __m256d across = _mm256_or_pd(
            _mm256_and_pd(_mm256_cmp_pd(side, zero, _CMP_GT_OQ), _mm256_cmp_pd(dn, zero, _CMP_LT_OQ)),
            _mm256_and_pd(_mm256_cmp_pd(side, zero, _CMP_LT_OQ), _mm256_cmp_pd(dn, zero, _CMP_GT_OQ)));
        const __m256d t = _mm256_div_pd(_mm256_xor_pd(side, splat(-0.0)), dn);
        const __m256d within = _mm256_and_pd(_mm256_cmp_pd(t, zero, _CMP_GT_OQ), _mm256_cmp_pd(t, limit, _CMP_LT_OQ));
        unsigned m = lanes(_mm256_and_pd(across, within)) & live & ~blocked;
        if (!m) continue;
        const Lanes3 oo(o), vv(vh);
        const Lanes1 tt(t);
        for (; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            if (w.plane_mats[2 * i + pl.cell(oo[k] + vv[k] * tt[k])].refraction == 0) blocked |= 1u << k;
        }
    }
    return blocked;
}

// LightBuffer::cell_toward() for four vectors toward the light: each lane's cell, as
// the offset of its first entry's index in lb.start (the same cell, bit for bit).
RT_TARGET_AVX2 void cells_toward4(const LightBuffer& lb, const V3& v, std::int32_t cell[4]) {
    const __m256d sign = splat(-0.0), zero = _mm256_setzero_pd();
    const __m256d ax = _mm256_andnot_pd(sign, v.x), ay = _mm256_andnot_pd(sign, v.y), az = _mm256_andnot_pd(sign, v.z);
    const __m256d xm = _mm256_and_pd(_mm256_cmp_pd(ax, ay, _CMP_GE_OQ), _mm256_cmp_pd(ax, az, _CMP_GE_OQ));
    const __m256d ym = _mm256_andnot_pd(xm, _mm256_cmp_pd(ay, az, _CMP_GE_OQ));
    auto pick = [&](__m256d a, __m256d b, __m256d c) RT_TARGET_AVX2 {  // x major: a, y: b, z: c
        return _mm256_blendv_pd(_mm256_blendv_pd(c, b, ym), a, xm);
    };
    const __m256d da = pick(ax, ay, az), vb = pick(v.y, v.z, v.x), vc = pick(v.z, v.x, v.y);
    const __m256d toward = pick(_mm256_cmp_pd(v.x, zero, _CMP_GT_OQ), _mm256_cmp_pd(v.y, zero, _CMP_GT_OQ),
                                _mm256_cmp_pd(v.z, zero, _CMP_GT_OQ));
    const __m256d face = add(pick(zero, splat(2), splat(4)), _mm256_and_pd(toward, splat(1)));
    const __m256d hn = splat(lb.half_n), k = _mm256_div_pd(hn, da);
    const __m128i top = _mm_set1_epi32(lb.n - 1), n = _mm_set1_epi32(lb.n);
    // (int conversion truncates as the scalar one does; NaN and overflow give INT_MIN,
    // which the unsigned min takes to the top.)
    const __m128i i = _mm_min_epu32(_mm256_cvttpd_epi32(sub(hn, mul(vb, k))), top);
    const __m128i j = _mm_min_epu32(_mm256_cvttpd_epi32(sub(hn, mul(vc, k))), top);
    const __m128i f = _mm256_cvttpd_epi32(face);
    const __m128i c = _mm_add_epi32(_mm_mullo_epi32(_mm_add_epi32(_mm_mullo_epi32(f, n), j), n), i);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cell), c);
}
}  // namespace

// Four shadow rays toward one light (see ShadowRay), lane by lane, with |p|_1 of their
// starts.
struct World::ShadowRays4 {
    alignas(32) double ox[4], oy[4], oz[4], vx[4], vy[4], vz[4], hx[4], hy[4], hz[4], r[4], limit[4], p1[4];
    std::size_t light;
    RT_TARGET_AVX2 void store(const V3& o, const V3& v, const V3& vh, __m256d rr, __m256d lim, __m256d q1, std::size_t li) {
        _mm256_store_pd(ox, o.x), _mm256_store_pd(oy, o.y), _mm256_store_pd(oz, o.z);
        _mm256_store_pd(vx, v.x), _mm256_store_pd(vy, v.y), _mm256_store_pd(vz, v.z);
        _mm256_store_pd(hx, vh.x), _mm256_store_pd(hy, vh.y), _mm256_store_pd(hz, vh.z);
        _mm256_store_pd(r, rr), _mm256_store_pd(limit, lim), _mm256_store_pd(p1, q1);
        light = li;
    }
    ShadowRay ray(int k) const {
        return {{ox[k], oy[k], oz[k]}, {vx[k], vy[k], vz[k]}, {hx[k], hy[k], hz[k]}, r[k], limit[k], light};
    }
};

// objects_block() for the lanes `lit` of four shadow rays: those it finds blocked are
// left out of the lanes returned, the others' tints put in sh. in_cell: the lanes
// whose ray uses the light buffer lb, in the cell at start[cell[k]].
unsigned World::shadow_lanes(const ShadowRays4& q, const LightBuffer* lb, unsigned in_cell, const std::int32_t* cell,
                             unsigned lit, double (&sh)[3][4], Ctx& ctx) const {
    for (unsigned m = lit; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        bool blocked;
        Colour c{1, 1, 1};
        if ((in_cell >> k) & 1) {
            const std::uint32_t* s = lb->start.data() + cell[k];
            const LightBuffer::Entry *e = lb->entries.data() + s[0], *end = lb->entries.data() + s[1];
            // Nothing on the way and no blocker to try: cell_blocks() would find nothing.
            if (ctx.blocker[q.light] == 0 && (e == end || double(e->dmin) > q.r[k]) && lb->always.empty()) continue;
            const ShadowRay ray = q.ray(k);
            blocked = blocker_blocks(ray, ctx) || cell_blocks(ray, *lb, e, end, c, ctx);
        } else {
            blocked = objects_block(q.ray(k), q.p1[k], c, ctx);
        }
        if (blocked)
            lit &= ~(1u << k);
        else
            sh[0][k] = c.x, sh[1][k] = c.y, sh[2][k] = c.z;
    }
    return lit;
}

// direct_lights() for the lanes `live` of four surfaces (a scene without glow discs):
// each lane does its operations in its order, so gets its bits; the set-up, the planes
// and the sums are done for the four at once, the objects' tests lane by lane.
RT_TARGET_AVX2 void World::direct4(const Surface s[4], unsigned live, Colour out[4], Ctx& ctx) const {
    if (ctx.blocker.size() < lights.size()) ctx.blocker.resize(lights.size());
    const int first = __builtin_ctz(live);  // the other lanes copy it, harmlessly
    const Vec3 *pp[4], *nn[4], *cc[4];
    for (int k = 0; k < 4; ++k) {
        const Surface& q = s[(live >> k) & 1 ? k : first];
        pp[k] = &q.p, nn[k] = &q.n, cc[k] = &q.m->colour;
    }
    const V3 p = gather(pp), n = gather(nn), cp = gather(cc);
    const __m256d sign = splat(-0.0), zero = _mm256_setzero_pd(), one = splat(1.0);
    const __m256d p1 = add(add(_mm256_andnot_pd(sign, p.x), _mm256_andnot_pd(sign, p.y)), _mm256_andnot_pd(sign, p.z));
    V3 sum{zero, zero, zero};
    for (std::size_t li = 0; li < lights.size(); ++li) {
        const ShadeLight& light = lights[li];
        const V3 v{sub(splat(light.position.x), p.x), sub(splat(light.position.y), p.y),
                   sub(splat(light.position.z), p.z)};
        const __m256d r2 = dot(v, v), inv_r2 = _mm256_div_pd(one, r2);
        const __m256d positive = _mm256_cmp_pd(r2, zero, _CMP_GT_OQ);
        const V3 e{_mm256_blendv_pd(one, mul(splat(light.colour.x), inv_r2), positive),
                   _mm256_blendv_pd(one, mul(splat(light.colour.y), inv_r2), positive),
                   _mm256_blendv_pd(one, mul(splat(light.colour.z), inv_r2), positive)};
        const V3 ec{mul(e.x, cp.x), mul(e.y, cp.y), mul(e.z, cp.z)};
        sum = {add(sum.x, mul(ec.x, splat(0.1))), add(sum.y, mul(ec.y, splat(0.1))), add(sum.z, mul(ec.z, splat(0.1)))};
        const __m256d vn = dot(v, n);
        unsigned lit = lanes(_mm256_cmp_pd(vn, zero, _CMP_GT_OQ)) & live;
        if (!lit) continue;
        ctx.stats->rays += unsigned(__builtin_popcount(lit));
        const __m256d r = _mm256_sqrt_pd(r2), inv_r = _mm256_div_pd(one, r);
        const V3 vh = scaled(v, inv_r);
        const V3 o{add(p.x, mul(vh.x, splat(kDelta))), add(p.y, mul(vh.y, splat(kDelta))),
                   add(p.z, mul(vh.z, splat(kDelta)))};
        const __m256d limit = sub(r, splat(10 * kDelta));
        lit &= ~planes_block4(*this, o, vh, limit, lit);
        if (!lit) continue;
        // The objects, lane by lane, each lane's cell found for the four at once.
        ShadowRays4 rays;
        rays.store(o, v, vh, r, limit, p1, li);
        const LightBuffer* lb = light_buffers ? &(*light_buffers)[li] : nullptr;
        unsigned in_cell = 0;  // the lanes that LightBuffer::usable() lets use it
        alignas(16) std::int32_t cell[4];
        if (lb && lb->n > 0) {
            in_cell = lanes(_mm256_cmp_pd(add(add(p1, splat(lb->position1)), r), splat(lb->reach), _CMP_LE_OQ)) & lit;
            if (in_cell) cells_toward4(*lb, v, cell);
        }
        alignas(32) double shade[3][4] = {{1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 1}};
        lit = shadow_lanes(rays, lb, in_cell, cell, lit, shade, ctx);
        if (!lit) continue;
        const V3 sh{_mm256_load_pd(shade[0]), _mm256_load_pd(shade[1]), _mm256_load_pd(shade[2])};
        const V3 term = scaled({mul(ec.x, sh.x), mul(ec.y, sh.y), mul(ec.z, sh.z)}, mul(mul(splat(0.9), vn), inv_r));
        const __m256i bits = _mm256_and_si256(_mm256_set1_epi64x(lit), _mm256_set_epi64x(8, 4, 2, 1));
        const __m256d use = _mm256_castsi256_pd(_mm256_cmpgt_epi64(bits, _mm256_setzero_si256()));
        sum = {_mm256_blendv_pd(sum.x, add(sum.x, term.x), use), _mm256_blendv_pd(sum.y, add(sum.y, term.y), use),
               _mm256_blendv_pd(sum.z, add(sum.z, term.z), use)};
    }
    const Lanes3 res(sum);
    for (int k = 0; k < 4; ++k) out[k] = res[k];
}

// Four values left unset (Vec3 and Surface set theirs to zero), for the lanes of a
// packet, each set before it is read.
template <class T>
union Uninit4 {
    T v[4];
    Uninit4() {}
};

// Four rays' tree budgets (see Ctx), kept apart while their trees are traced together.
struct World::Budgets {
    double budget[4], cutoff[4];
    // Ctx takes lane k's budget (unless the trace has stopped: its budget stays spent).
    void enter(Ctx& ctx, int k) const {
        if (!ctx.stats->stopped) ctx.budget = budget[k], ctx.cutoff = cutoff[k];
    }
    void leave(const Ctx& ctx, int k) { budget[k] = ctx.budget, cutoff[k] = ctx.cutoff; }
};

// shade() for the lanes `live` of four rays at one depth, on the AVX2 path: each ray is
// shaded as shade() shades it, but the four points' direct light is found together
// (direct4), and their mirror rays go on as four rays too, down to kPacketDepth. Every
// ray spends its own tree's budget in shade()'s order (its refracted light, then its
// mirror ray's tree; the direct light spends none), so leaves out what it would alone.
void World::shade4(const Vec3 o[4], const Vec3 d[4], unsigned live, int depth, const double weight[4], Budgets& b,
                   Colour out[4], Ctx& ctx) const {
    constexpr int kPacketDepth = 8;  // deeper, a lane at a time (the stack stays small)
    Uninit4<Surface> surfaces;
    Surface* const s = surfaces.v;
    unsigned pending = 0, scatters = 0, mirrors = 0;
    for (unsigned m = live; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        b.enter(ctx, k);
        if (shade_surface(o[k], d[k], depth, weight[k], ctx, s[k], out[k])) {
            pending |= 1u << k;
            if (s[k].m->scattering > 0) scatters |= 1u << k;
            if (s[k].m->reflection > 0) mirrors |= 1u << k;
        }
        b.leave(ctx, k);
    }
    Uninit4<Colour> lits, mirrors_;
    Colour *const lit = lits.v, *const mirror = mirrors_.v;
    if (scatters && !ctx.stats->stopped) {
        if (scatters & (scatters - 1)) {
            direct4(s, scatters, lit, ctx);
        } else {  // one lane: the scalar loop costs less
            const int k = __builtin_ctz(scatters);
            lit[k] = direct(s[k].p, s[k].n, s[k].m->colour, ctx);
        }
    } else if (scatters) {
        std::fill(lit, lit + 4, Colour{});  // (thrown away: the trace has stopped)
    }
    if (mirrors) {
        Uninit4<Vec3> mos, mds;
        Vec3 *const mo = mos.v, *const md = mds.v;
        double mw[4];
        for (unsigned m = mirrors; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            mo[k] = s[k].p, md[k] = reflect(d[k], s[k].n), mw[k] = weight[k] * s[k].m->reflection;
        }
        if (depth + 2 < kPacketDepth) {
            shade4(mo, md, mirrors, depth + 2, mw, b, mirror, ctx);
        } else {
            for (unsigned m = mirrors; m; m &= m - 1) {
                const int k = __builtin_ctz(m);
                b.enter(ctx, k);
                mirror[k] = shade(mo[k], md[k], depth + 2, mw[k], ctx);
                b.leave(ctx, k);
            }
        }
    }
    for (unsigned m = pending; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        out[k] = combine(s[k], lit[k], mirror[k]);
    }
}

// trace_units() on the AVX2 path: shade4() on four camera rays at a time.
void World::trace_units4(const Vec3& origin, const Vec3* dirs, std::size_t n, Ctx& ctx, Colour* out) const {
    const Vec3 o[4] = {origin, origin, origin, origin};
    const double weight[4] = {1, 1, 1, 1};
    for (std::size_t i0 = 0; i0 < n; i0 += 4) {
        if (ctx.stats->stopped) return std::fill(out + i0, out + n, Colour{});
        const unsigned count = unsigned(std::min<std::size_t>(4, n - i0));
        // Each ray's tree starts with the whole budget, as in trace_from().
        Budgets b;
        std::fill(b.budget, b.budget + 4, omit_weight);
        std::fill(b.cutoff, b.cutoff + 4, omit_weight * Ctx::kShare);
        shade4(o, dirs + i0, (1u << count) - 1, 0, weight, b, out + i0, ctx);
        // Stopped inside these four: they and the rest are black, as in trace_units().
        if (ctx.stats->stopped) return std::fill(out + i0, out + n, Colour{});
        for (unsigned k = 0; k < count; ++k) out[i0 + k] = finite_colour(out[i0 + k]);
    }
}
#endif

void World::trace_units(const Vec3& origin, const Vec3* unit_dirs, std::size_t n, RayStats& stats, Colour* out) const {
    Ctx& ctx = thread_ctx();
    ctx.stats = &stats;
#if RT_HAVE_AVX2_KERNELS
    if (glows.empty() && avx2_active()) return trace_units4(origin, unit_dirs, n, ctx, out);
#endif
    for (std::size_t i = 0; i < n; ++i) {
        if (stats.stopped) {
            std::fill(out + i, out + n, Colour{});
            return;
        }
        // Each ray's tree starts with the whole budget, as in trace_from().
        ctx.budget = omit_weight;
        ctx.cutoff = omit_weight * Ctx::kShare;
        out[i] = finite_colour(shade(origin, unit_dirs[i], 0, 1.0, ctx));
    }
}

Colour World::trace_camera(const CameraBasis& cam, double i, double j, RayStats& stats) const {
    return trace(cam.origin, cam.direction(i, j), 0, stats);
}

Aabb World::bounds() const { return tallies ? tallies->bounds : Aabb{}; }

std::size_t World::geometry_bytes() const { return geometry->memory_bytes(); }

PickResult pick(const World& world, const Ray& ray) {
    thread_local World::Ctx ctx;
    RayStats stats;
    ctx.stats = &stats;
    World::HitRec h;
    PickResult r;
    if (!world.nearest(ray.origin, normalize(ray.dir), ctx, h)) return r;
    r.hit = true;
    r.t = h.t;
    r.point = ray.origin + normalize(ray.dir) * h.t;
    if (h.kind == World::HitRec::Object) r.object = int(h.index);
    if (h.kind == World::HitRec::PlaneHit) r.plane = int(h.index);
    if (h.kind == World::HitRec::Glow) r.light = int(h.index);
    return r;
}

namespace {

double box_distance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double e = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
        d2 += e * e;
    }
    return d2;
}

}  // namespace

namespace detail {

// Branch and bound through the BVH. Its node boxes only prune (they are padded
// outward: their distance is a lower bound too), so the answer is the least distance
// of an object box, whatever the tree.
double distance_to_objects(const Geometry& g, const Vec3& p) {
    const Bvh& bvh = g.bvh;
    double best2 = HUGE_VAL;
    if (bvh.nodes.empty()) return HUGE_VAL;
    std::vector<std::pair<double, std::uint32_t>> todo{{0.0, 0u}};  // (distance², inner node)
    while (!todo.empty()) {
        auto [d2, ref] = todo.back();
        todo.pop_back();
        if (d2 >= best2) continue;
        const BvhNode& n = bvh.nodes[ref];
        for (int i = 0; i < 4; ++i) {
            std::uint32_t c = n.child[i];
            if (c == BvhNode::kEmpty) continue;
            if (BvhNode::is_leaf(c)) {
                std::uint32_t first = BvhNode::leaf_first(c), count = BvhNode::leaf_count(c);
                for (std::uint32_t k = 0; k < count; ++k) {
                    const Aabb& b = g.object_bounds[bvh.items[first + k]];
                    best2 = std::min(best2, box_distance2(p, b.lo, b.hi));
                }
                continue;
            }
            Vec3 lo{n.b[0][i], n.b[1][i], n.b[2][i]}, hi{n.b[3][i], n.b[4][i], n.b[5][i]};
            double cd2 = box_distance2(p, lo, hi);
            if (cd2 < best2) todo.push_back({cd2, c});
        }
    }
    return std::sqrt(best2);
}

bool bounded_material(const ShadeMaterial& m, double& cp) {
    if (!(m.reflection >= 0 && m.refraction >= 0 && m.scattering >= 0)) return false;
    if (m.refraction > 0 && max3(m.log_tint) > 0) return false;  // a tint above 1
    double c = max3(cabs(m.colour));
    if (!std::isfinite(c)) return false;
    if (m.scattering > 0) cp = std::max(cp, c);
    return true;
}

World::Tallies::Materials tally_materials(const Chunked<ShadeMaterial>& materials, std::size_t c) {
    World::Tallies::Materials t;
    const ShadeMaterial* m = materials.chunk(c);
    for (std::size_t k = 0, e = materials.chunk_size(c); k < e && t.bounded; ++k) t.bounded = bounded_material(m[k], t.cp);
    return t;
}

Aabb tally_boxes(const Chunked<Aabb>& boxes, std::size_t c) {
    Aabb u;
    const Aabb* b = boxes.chunk(c);
    for (std::size_t k = 0, e = boxes.chunk_size(c); k < e; ++k)
        if (!b[k].empty()) u.grow(b[k]);
    return u;
}

void tally_lights(World::Tallies& t, const World& w) {
    t.light_reach.clear();
    t.light_reach.reserve(w.lights.size());
    for (const ShadeLight& l : w.lights) t.light_reach.push_back(distance_to_objects(*w.geometry, l.position));
    t.bounds = Aabb{};
    for (const Aabb& b : t.boxes) t.bounds.grow(b);
    for (const ShadeLight& l : w.lights) t.bounds.grow(l.position);
}

}  // namespace detail

namespace {

// An upper bound of the colour any ray can bring back, for the ray tree's bound
// (World::omit_weight); +inf where there is none. Every value a ray returns is a mix,
// with weights summing to 1, of direct light, glow colours, and the values of further
// rays dimmed by tints: so it is bounded by the largest direct light any surface point
// can get, or the brightest glow, provided no weight is negative and no tint brightens.
// Direct light at p is at most sum over lights of |colour| |Cp| / r^2 (rendering.md
// §3), with r at least the light's distance to the nearest surface.
double radiance_bound(const World& w) {
    const double inf = HUGE_VAL;
    const World::Tallies& t = *w.tallies;
    double cp = 0;
    for (const World::Tallies::Materials& m : t.materials) {
        if (!m.bounded) return inf;
        cp = std::max(cp, m.cp);
    }
    for (const ShadeMaterial& m : w.plane_mats)
        if (!detail::bounded_material(m, cp)) return inf;
    double glow = 0, direct = 0;
    for (std::size_t li = 0; li < w.lights.size(); ++li) {
        const ShadeLight& l = w.lights[li];
        double c = max3(cabs(l.colour));
        if (!std::isfinite(c)) return inf;
        if (l.glow > 0) glow = std::max(glow, c);
        if (c == 0 || cp == 0) continue;
        double r = t.light_reach[li];
        for (const PlaneShape& pl : w.planes) r = std::min(r, std::fabs(dot(pl.n, l.position) + pl.D));
        // Hit points lie on their surface only to within rounding and the original's
        // surface tolerance.
        r -= 100 * kDelta + 1e-9 * max3(cabs(l.position));
        if (!(r > 0)) return inf;
        direct += c / (r * r);
    }
    return std::max(glow, cp * direct);
}

// The objects' shading materials (made on a thread of their own for a big scene) and
// their chunks' tallies; they do not depend on the geometry.
struct ObjectMaterials {
    Chunked<ShadeMaterial> list;
    std::vector<World::Tallies::Materials> tallies;
};

ObjectMaterials make_materials(const Scene& scene) {
    ObjectMaterials made;
    Chunked<ShadeMaterial>& out = made.list;
    const std::size_t n = scene.objects.size();
    out.reserve(n);
    constexpr unsigned kShift = Chunked<ShadeMaterial>::kShift;
    World::Tallies::Materials tally;
    for (std::size_t i = 0; i < n; ++i) {
        // Big scenes repeat a few materials, often alternating: one equal (bit for bit)
        // to either of the last two objects' in its chunk is copied, saving its three
        // logarithms and its check, which gives the same answer (and the same tally as
        // tally_materials(), which checks every one).
        static_assert(sizeof(Material) == 8 * sizeof(double), "materials compare as bytes");
        const Material& m = scene.objects[i].material;
        std::size_t k = 1;
        for (; k <= 2 && k <= i && (i - k) >> kShift == i >> kShift; ++k)
            if (std::memcmp(&m, &scene.objects[i - k].material, sizeof m) == 0) break;
        if (k <= 2 && k <= i && (i - k) >> kShift == i >> kShift) {
            out.push_back(out[i - k]);
        } else {
            out.push_back(ShadeMaterial::from(m));
            if (tally.bounded) tally.bounded = detail::bounded_material(out.back(), tally.cp);
        }
        if (((i + 1) >> kShift) != (i >> kShift) || i + 1 == n) {
            made.tallies.push_back(tally);
            tally = {};
        }
    }
    return made;
}

std::shared_ptr<const World> finish_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                          ObjectMaterials materials, const World* previous);

}  // namespace

std::shared_ptr<const World> compile_world(const Scene& scene, const World* previous) {
    // For a big scene the materials are made on a thread of their own while the shapes
    // and the BVH are built.
    ObjectMaterials materials;
    std::thread materials_thread;
    std::exception_ptr materials_failed;
    if (scene.objects.size() >= 65536 && std::thread::hardware_concurrency() > 1) {
        try {
            materials_thread = std::thread([&] {
                try {
                    materials = make_materials(scene);
                } catch (...) {
                    materials_failed = std::current_exception();
                }
            });
        } catch (const std::system_error&) {
            // No thread to be had: made below.
        }
    }
    struct Join {
        std::thread& t;
        ~Join() {
            if (t.joinable()) t.join();
        }
    } join{materials_thread};
    std::shared_ptr<const Geometry> geometry;
    if (previous && previous->geometry && previous->geometry->object_node.size() == scene.objects.size()) {
        // The shapes compiled again are cheap to compare; only the BVH is worth keeping.
        Geometry g = build_geometry(scene, false);
        if (same_shapes(g, *previous->geometry)) {
            geometry = previous->geometry;
        } else {
            g.bvh.build(g.object_bounds);
            geometry = std::make_shared<const Geometry>(std::move(g));
        }
    } else {
        geometry = std::make_shared<const Geometry>(build_geometry(scene));
    }
    if (materials_thread.joinable()) {
        materials_thread.join();
        if (materials_failed) std::rethrow_exception(materials_failed);
    } else {
        materials = make_materials(scene);
    }
    return finish_world(scene, std::move(geometry), std::move(materials), previous);
}

std::shared_ptr<const World> compile_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                           const World* previous) {
    return finish_world(scene, std::move(geometry), make_materials(scene), previous);
}

namespace detail {

void add_planes(World& w, const Scene& scene) {
    for (const Plane& p : scene.planes) {
        w.planes.push_back(PlaneShape::from(p));
        w.plane_mats.push_back(ShadeMaterial::from(p.material));
        w.plane_mats.push_back(ShadeMaterial::from(p.chess ? p.material2 : p.material));
    }
}

void add_lights(World& w, const Scene& scene) {
    w.lights.reserve(scene.lights.size());
    for (const Light& l : scene.lights) {
        if (l.lamp && l.size > 0) w.glows.push_back(std::uint32_t(w.lights.size()));
        w.lights.push_back({l.position, l.colour, l.lamp && l.size > 0 ? l.size : 0.0});
    }
}

void add_glow_bvh(World& w, const World* previous) {
    w.glow_bvh = nullptr;
    if (w.glows.size() < kGlowBvhMin) return;
    bool same = previous && previous->glow_bvh && previous->glows == w.glows;
    for (std::size_t k = 0; same && k < w.glows.size(); ++k) {
        const ShadeLight &a = w.lights[w.glows[k]], &b = previous->lights[previous->glows[k]];
        same = a.position == b.position && a.glow == b.glow;
    }
    if (same) {
        w.glow_bvh = previous->glow_bvh;
        return;
    }
    std::vector<Aabb> boxes;
    boxes.reserve(w.glows.size());
    for (std::uint32_t i : w.glows) {
        const ShadeLight& l = w.lights[i];
        Vec3 e{l.glow, l.glow, l.glow};
        boxes.push_back({l.position - e, l.position + e});
    }
    auto bvh = std::make_shared<Bvh>();
    bvh->build(boxes);
    w.glow_bvh = std::move(bvh);
}

}  // namespace detail

namespace {

// A light buffer around each point of `todo`, each on its own, on as many threads as
// there are (a big scene's take tens of milliseconds each; a small one's,
// microseconds on this thread).
std::vector<LightBuffer> build_light_buffers(const Chunked<Aabb>& boxes, const std::vector<Vec3>& todo,
                                             int cells_n) {
    std::vector<LightBuffer> made(todo.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i; (i = next++) < todo.size();) made[i] = LightBuffer::build(boxes, todo[i], cells_n);
    };
    std::size_t threads = boxes.size() < 4096 ? 1 : std::min<std::size_t>(todo.size(), std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    std::exception_ptr failed;
    std::mutex failed_mutex;
    for (std::size_t t = 1; t < threads; ++t)
        pool.emplace_back([&] {
            try {
                work();
            } catch (...) {
                std::lock_guard<std::mutex> lock(failed_mutex);
                failed = std::current_exception();
            }
        });
    try {
        work();
    } catch (...) {
        for (std::thread& t : pool) t.join();
        throw;
    }
    for (std::thread& t : pool) t.join();
    if (failed) std::rethrow_exception(failed);
    return made;
}

}  // namespace

namespace detail {

void add_light_buffers(World& w, const Scene& scene, const World* previous) {
    const Chunked<Aabb>& boxes = w.geometry->object_bounds;
    w.light_buffers = nullptr;
    // Cells enough that a cell holds a few of the objects it may see.
    const int cells_n = std::clamp(2 * int(std::ceil(std::sqrt(double(boxes.size())))), 64, 256);
    const bool small = !boxes.empty() && boxes.size() * (w.lights.size() + 1) <= kLightBufferMaxWork;
    // The buffers to make: the camera's (index 0) and the lights' (1 + light), unless
    // the previous world's serve.
    std::vector<Vec3> todo;
    std::shared_ptr<const LightBuffer> camera_buffer;
    if (small) {
        // Camera rays all leave from one point too: the same buffer around it serves them.
        if (previous && previous->camera_buffer && previous->geometry == w.geometry &&
            previous->camera_buffer->position == scene.camera.position)
            camera_buffer = previous->camera_buffer;
        else
            todo.push_back(scene.camera.position);
    }
    bool lights_too = small && !w.lights.empty() &&
                      (w.lights.size() + 1) * 6 * std::size_t(cells_n) * std::size_t(cells_n) <= kLightBufferMaxCells;
    if (lights_too) {
        bool same = previous && previous->light_buffers && previous->geometry == w.geometry &&
                    previous->lights.size() == w.lights.size();
        for (std::size_t k = 0; same && k < w.lights.size(); ++k)
            same = w.lights[k].position == previous->lights[k].position;
        if (same) {
            w.light_buffers = previous->light_buffers;
            lights_too = false;
        } else {
            for (const ShadeLight& l : w.lights) todo.push_back(l.position);
        }
    }
    if (!todo.empty()) {
        std::vector<LightBuffer> made = build_light_buffers(boxes, todo, cells_n);
        std::size_t k = 0;
        if (small && !camera_buffer) camera_buffer = std::make_shared<const LightBuffer>(std::move(made[k++]));
        if (lights_too) w.light_buffers = std::make_shared<const std::vector<LightBuffer>>(
                            std::make_move_iterator(made.begin() + std::ptrdiff_t(k)), std::make_move_iterator(made.end()));
    }
    w.camera_buffer = std::move(camera_buffer);
}

void set_ray_tree_bound(World& w) {
    w.radiance_bound = radiance_bound(w);
    // Half a display step (1/255 of the unit colour) over the brightest possible return.
    // A world that cannot return any colour (nothing lit, no glow) stops at once.
    w.omit_weight = 0;
    if (w.radiance_bound == 0)
        w.omit_weight = HUGE_VAL;
    else if (std::isfinite(w.radiance_bound))
        w.omit_weight = 0.5 / 255 / w.radiance_bound;
}

}  // namespace detail

namespace {

std::shared_ptr<const World> finish_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                          ObjectMaterials materials, const World* previous) {
    auto w = std::make_shared<World>();
    w->geometry = std::move(geometry);
    w->materials = std::move(materials.list);
    detail::add_planes(*w, scene);
    detail::add_lights(*w, scene);
    detail::add_glow_bvh(*w, previous);
    detail::add_light_buffers(*w, scene, previous);
    auto tallies = std::make_shared<World::Tallies>();
    tallies->materials = std::move(materials.tallies);
    const Chunked<Aabb>& boxes = w->geometry->object_bounds;
    tallies->boxes.reserve(boxes.chunk_count());
    for (std::size_t c = 0; c < boxes.chunk_count(); ++c) tallies->boxes.push_back(detail::tally_boxes(boxes, c));
    detail::tally_lights(*tallies, *w);
    w->tallies = std::move(tallies);
    detail::set_ray_tree_bound(*w);
    w->camera = scene.camera;
    w->width = scene.width;
    w->height = scene.height;
    if (previous) w->options = previous->options;
    return w;
}

}  // namespace

}  // namespace rt
