// Shading as in docs/rendering.md §2-§6: direct light with the unshadowed 0.1 term and
// coloured shadows through refractive objects, mirror reflection, refraction with the
// interior walk, and lamp glow discs. Planes are few and unbounded, so they are tested
// one by one; objects go through the BVH, and glow discs too when there are many.
// The ray tree is cut where the rays left out cannot be seen (World::omit_weight) and
// where the caller asks to stop (RayStats::stop).
#include "world.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <system_error>
#include <thread>

#include "shapes.h"

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
};

namespace {
// Called every RayStats::kPollRays rays: has the caller asked to stop?
[[gnu::cold, gnu::noinline]] void poll(RayStats& st, double& cutoff, double& budget) {
    st.next_poll = st.rays + RayStats::kPollRays;
    const TraceStop& stop = st.stop;
    bool flagged = stop.flag && stop.flag->load(std::memory_order_relaxed);
    if (flagged || (stop.deadline != std::chrono::steady_clock::time_point::max() &&
                    std::chrono::steady_clock::now() >= stop.deadline)) {
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

bool World::nearest(const Vec3& o, const Vec3& d, Ctx& ctx, HitRec& h) const {
    const Geometry& g = *geometry;
    h.kind = HitRec::None;
    h.t = kInf;
    // Planes and glows first: their distance prunes the BVH search.
    for (std::uint32_t i = 0; i < planes.size(); ++i) {
        const PlaneShape& p = planes[i];
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
    g.bvh.traverse_nearest(o, d, h.t, [&](std::uint32_t obj, double tmax) -> double {
        SpanEnd e;
        // On an exact tie the earlier object in the file wins, as in the original.
        if (g.hit(obj, o, d, kDelta, e, ctx.scratch) &&
            (e.t < tmax || (e.t == tmax && h.kind == HitRec::Object && obj < h.index))) {
            h.kind = HitRec::Object;
            h.t = e.t;
            h.index = obj;
            h.end = e;
            return e.t;
        }
        return tmax;
    });
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

// Glow discs are tested one by one, or through their BVH if kGlowBvh.
template <bool kGlowBvh>
Colour World::direct_lights(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const {
    const Geometry& g = *geometry;
    Colour sum;
    if (ctx.blocker.size() < lights.size()) ctx.blocker.resize(lights.size());
    for (const ShadeLight& light : lights) {
        Vec3 v = light.position - p;
        double r2 = dot(v, v);
        // (Multiplying by reciprocals: a division each would sit on the critical path.)
        Colour e = r2 > 0 ? light.colour * (1 / r2) : Colour{1, 1, 1};
        sum += mul(e, cp) * 0.1;
        double vn = dot(v, n);
        if (!(vn > 0)) continue;
        double r = std::sqrt(r2), inv_r = 1 / r;
        Vec3 vh = v * inv_r;
        Vec3 o = p + vh * kDelta;
        double limit = r - 10 * kDelta;
        ++ctx.stats->rays;
        std::size_t li = std::size_t(&light - lights.data());
        std::uint32_t cached = ctx.blocker[li];
        if (cached > 0 && cached <= materials.size()) {
            SpanEnd e;
            if (materials[cached - 1].refraction == 0 && g.hit(cached - 1, o, vh, 0.0, e, ctx.scratch) && e.t < limit)
                continue;
        }
        Colour sh{1, 1, 1};
        bool blocked = false;
        // (The box test takes v and r: its inverse direction r / v is then one division
        // after the square root instead of two.)
        g.bvh.traverse(o, v, r, limit, [&](std::uint32_t obj, double tmax) -> double {
            SpanEnd e;
            if (!g.hit(obj, o, vh, 0.0, e, ctx.scratch) || !(e.t < limit)) return tmax;
            const ShadeMaterial& m = materials[obj];
            if (m.refraction == 0) {
                blocked = true;
                ctx.blocker[li] = obj + 1;
                return -1;
            }
            Vec3 q = o + vh * e.t;
            SpanEnd x;
            double s = g.exit(obj, q, vh, x, ctx.scratch) ? x.t : 0.0;
            sh = mul(sh, tint(m, s * m.refraction));
            return tmax;
        });
        if (blocked) continue;
        // No object blocks this light here: neighbouring points will not try one first.
        ctx.blocker[li] = 0;
        for (std::uint32_t i = 0; i < planes.size() && !blocked; ++i) {
            const PlaneShape& pl = planes[i];
            double dn = dot(pl.n, vh);
            if (dn == 0) continue;
            double t = -(dot(pl.n, o) + pl.D) / dn;
            if (!(t > 0 && t < limit)) continue;
            const ShadeMaterial& m = plane_mats[2 * i + pl.cell(o + vh * t)];
            // A plane is a window of zero thickness: refractive ones pass light unchanged.
            if (m.refraction == 0) blocked = true;
        }
        if constexpr (kGlowBvh) {
            if (!blocked) blocked = glow_blocks(o, vh, limit);
        } else {
            for (std::uint32_t i : glows) {
                double t;
                if (!blocked && glow_hit(lights[i], o, vh, t) && t > 0 && t < limit) blocked = true;
            }
        }
        if (!blocked) sum += mul(mul(e, cp), sh) * (0.9 * vn * inv_r);
    }
    return sum;
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
            n1 = g.normal(e.node, e.face, q0 + d1 * s);
            if (e.flip) n1 = -n1;
        } else {
            // The original would use a negative length here; treat it as 0 instead.
            n1 = g.normal(x.end.node, x.end.face, q0);
            if (x.end.flip) n1 = -n1;
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

// `weight`: how much of this ray's colour reaches the pixel (see World::omit_weight).
Colour World::shade(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx) const {
    if (depth >= options.max_depth) return {};
    if (__builtin_expect(weight < ctx.cutoff, 0)) {
        ctx.leave_out(weight);
        return {};
    }
    if (__builtin_expect(++ctx.stats->rays >= ctx.stats->next_poll, 0)) poll(*ctx.stats, ctx.cutoff, ctx.budget);
    HitRec h;
    if (!nearest(o, d, ctx, h)) return {};
    Vec3 p = o + d * h.t;
    if (h.kind == HitRec::Glow) {
        const ShadeLight& l = lights[h.index];
        double rho = length(l.position - p);
        if (!(rho < l.glow)) return {};
        double f = (l.glow - rho) / l.glow;
        return l.colour * (f * f * f * f * f);
    }
    const ShadeMaterial* m;
    Vec3 n;
    if (h.kind == HitRec::Object) {
        m = &materials[h.index];
        n = geometry->normal(h.end.node, h.end.face, p);
        if (h.end.flip) n = -n;
    } else {
        const PlaneShape& pl = planes[h.index];
        m = &plane_mats[2 * h.index + pl.cell(p)];
        n = pl.n;
    }
    Colour refr;
    if (m->refraction != 0) {
        // The original refracts first, and that turns n toward the ray for the other
        // terms too (a transparent surface seen from behind is lit from the front).
        if (dot(n, d) > 0) n = -n;
        if (depth + 1 < options.max_depth && m->refraction > 0) {
            Vec3 d1;
            Vec3 nn = n;
            if (refract(d, 1, m->ior, nn, d1)) refr = walk(h, p, normalize(d1), m->ior, depth + 2, weight * m->refraction, ctx);
        }
    }
    Colour c;
    if (m->scattering > 0) c += direct(p, n, m->colour, ctx) * m->scattering;
    if (m->reflection > 0) c += shade(p, reflect(d, n), depth + 2, weight * m->reflection, ctx) * m->reflection;
    c += scale(m->refraction, refr);
    return c;
}

Colour World::trace(const Vec3& origin, const Vec3& dir, int depth, RayStats& stats) const {
    return trace_from(origin, normalize(dir), depth, stats);
}

Colour World::trace_unit(const Vec3& origin, const Vec3& unit_dir, RayStats& stats) const {
    return trace_from(origin, unit_dir, 0, stats);
}

Colour World::trace_from(const Vec3& origin, const Vec3& d, int depth, RayStats& stats) const {
    thread_local Ctx ctx;
    ctx.stats = &stats;
    if (stats.stopped) return {};
    ctx.budget = omit_weight;
    ctx.cutoff = omit_weight * Ctx::kShare;
    Colour c = shade(origin, d, depth, 1.0, ctx);
    // No NaN ever reaches a pixel.
    if (!std::isfinite(c.x)) c.x = c.x > 0 ? 1e30 : 0;
    if (!std::isfinite(c.y)) c.y = c.y > 0 ? 1e30 : 0;
    if (!std::isfinite(c.z)) c.z = c.z > 0 ? 1e30 : 0;
    return c;
}

Colour World::trace_camera(const CameraBasis& cam, double i, double j, RayStats& stats) const {
    return trace(cam.origin, cam.direction(i, j), 0, stats);
}

Aabb World::bounds() const {
    Aabb b;
    for (const Aabb& ob : geometry->object_bounds)
        if (!ob.empty()) b.grow(ob);
    for (const ShadeLight& l : lights) b.grow(l.position);
    return b;
}

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

// The distance from p to the nearest object box: a lower bound of its distance to any
// surface point of an object. Branch and bound through the BVH.
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
            // The node's float boxes are padded outward: their distance is a lower bound too.
            Vec3 lo{n.b[0][i], n.b[1][i], n.b[2][i]}, hi{n.b[3][i], n.b[4][i], n.b[5][i]};
            double cd2 = box_distance2(p, lo, hi);
            if (cd2 < best2) todo.push_back({cd2, c});
        }
    }
    return std::sqrt(best2);
}

// An upper bound of the colour any ray can bring back, for the ray tree's bound
// (World::omit_weight); +inf where there is none. Every value a ray returns is a mix,
// with weights summing to 1, of direct light, glow colours, and the values of further
// rays dimmed by tints: so it is bounded by the largest direct light any surface point
// can get, or the brightest glow, provided no weight is negative and no tint brightens.
// Direct light at p is at most sum over lights of |colour| |Cp| / r^2 (rendering.md
// §3), with r at least the light's distance to the nearest surface.
double radiance_bound(const World& w) {
    const double inf = HUGE_VAL;
    double cp = 0;
    auto usable = [&](const ShadeMaterial& m) {
        if (!(m.reflection >= 0 && m.refraction >= 0 && m.scattering >= 0)) return false;
        if (m.refraction > 0 && max3(m.log_tint) > 0) return false;  // a tint above 1
        double c = max3(cabs(m.colour));
        if (!std::isfinite(c)) return false;
        if (m.scattering > 0) cp = std::max(cp, c);
        return true;
    };
    for (const ShadeMaterial& m : w.materials)
        if (!usable(m)) return inf;
    for (const ShadeMaterial& m : w.plane_mats)
        if (!usable(m)) return inf;
    double glow = 0, direct = 0;
    for (const ShadeLight& l : w.lights) {
        double c = max3(cabs(l.colour));
        if (!std::isfinite(c)) return inf;
        if (l.glow > 0) glow = std::max(glow, c);
        if (c == 0 || cp == 0) continue;
        double r = distance_to_objects(*w.geometry, l.position);
        for (const PlaneShape& pl : w.planes) r = std::min(r, std::fabs(dot(pl.n, l.position) + pl.D));
        // Hit points lie on their surface only to within rounding and the original's
        // surface tolerance.
        r -= 100 * kDelta + 1e-9 * max3(cabs(l.position));
        if (!(r > 0)) return inf;
        direct += c / (r * r);
    }
    return std::max(glow, cp * direct);
}

}  // namespace

std::shared_ptr<const World> compile_world(const Scene& scene, const World* previous) {
    auto w = std::make_shared<World>();
    // The objects' materials do not depend on the geometry: for a big scene they are
    // made on a thread of their own while the shapes and the BVH are built.
    auto make_materials = [&] {
        w->materials.reserve(scene.objects.size());
        for (std::size_t i = 0; i < scene.objects.size(); ++i) {
            // Big scenes repeat a few materials, often alternating: one equal (bit for
            // bit) to either of the last two objects' is copied, saving its three
            // logarithms.
            static_assert(sizeof(Material) == 8 * sizeof(double), "materials compare as bytes");
            const Material& m = scene.objects[i].material;
            std::size_t k = 1;
            for (; k <= 2 && k <= i; ++k)
                if (std::memcmp(&m, &scene.objects[i - k].material, sizeof m) == 0) break;
            w->materials.push_back(k <= 2 && k <= i ? w->materials[i - k] : ShadeMaterial::from(m));
        }
    };
    std::thread materials;
    std::exception_ptr materials_failed;
    if (scene.objects.size() >= 65536 && std::thread::hardware_concurrency() > 1) {
        try {
            materials = std::thread([&] {
                try {
                    make_materials();
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
    } join{materials};
    if (previous && previous->geometry && previous->geometry->object_node.size() == scene.objects.size()) {
        // The shapes compiled again are cheap to compare; only the BVH is worth keeping.
        Geometry g = build_geometry(scene, false);
        if (same_shapes(g, *previous->geometry)) {
            w->geometry = previous->geometry;
        } else {
            g.bvh.build(g.object_bounds);
            w->geometry = std::make_shared<const Geometry>(std::move(g));
        }
    } else {
        w->geometry = std::make_shared<const Geometry>(build_geometry(scene));
    }
    if (materials.joinable()) {
        materials.join();
        if (materials_failed) std::rethrow_exception(materials_failed);
    } else {
        make_materials();
    }
    for (const Plane& p : scene.planes) {
        w->planes.push_back(PlaneShape::from(p));
        w->plane_mats.push_back(ShadeMaterial::from(p.material));
        w->plane_mats.push_back(ShadeMaterial::from(p.chess ? p.material2 : p.material));
    }
    for (const Light& l : scene.lights) {
        if (l.lamp && l.size > 0) w->glows.push_back(std::uint32_t(w->lights.size()));
        w->lights.push_back({l.position, l.colour, l.lamp && l.size > 0 ? l.size : 0.0});
    }
    if (w->glows.size() >= kGlowBvhMin) {
        bool same = previous && previous->glow_bvh && previous->glows == w->glows;
        for (std::size_t k = 0; same && k < w->glows.size(); ++k) {
            const ShadeLight &a = w->lights[w->glows[k]], &b = previous->lights[previous->glows[k]];
            same = a.position == b.position && a.glow == b.glow;
        }
        if (same) {
            w->glow_bvh = previous->glow_bvh;
        } else {
            std::vector<Aabb> boxes;
            boxes.reserve(w->glows.size());
            for (std::uint32_t i : w->glows) {
                const ShadeLight& l = w->lights[i];
                Vec3 e{l.glow, l.glow, l.glow};
                boxes.push_back({l.position - e, l.position + e});
            }
            auto bvh = std::make_shared<Bvh>();
            bvh->build(boxes);
            w->glow_bvh = std::move(bvh);
        }
    }
    w->radiance_bound = radiance_bound(*w);
    // Half a display step (1/255 of the unit colour) over the brightest possible return.
    // A world that cannot return any colour (nothing lit, no glow) stops at once.
    if (w->radiance_bound == 0)
        w->omit_weight = HUGE_VAL;
    else if (std::isfinite(w->radiance_bound))
        w->omit_weight = 0.5 / 255 / w->radiance_bound;
    w->camera = scene.camera;
    w->width = scene.width;
    w->height = scene.height;
    if (previous) w->options = previous->options;
    return w;
}

}  // namespace rt
