// Internal to core: what the scalar shading (shade.cpp) and the AVX2 packets
// (shade_avx2.cpp) share: the tracing state, the shadow rays' tests and the two
// halves of shade() that a packet runs lane by lane, and the small colour helpers.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "shapes.h"
#include "texture_map.h"
#include "world.h"

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
    if (l.size <= 0) return false;
    Vec3 co = l.position - o;
    double along = dot(co, d);
    if (!(along > 0)) return false;
    double dist2 = dot(co, co) - along * along;
    if (dist2 > l.size * l.size) return false;
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
    // The points of this camera ray's lens and sphere-light samples (sampler.h).
    PathSampler sampler;
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
    Colour cp;  // the surface's colour at p: m->colour, times its texture's texel there
};

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
// `reach`: how far from the light a blocker may be (s.r; a sphere light's, see
// objects_block_toward()).
inline bool World::cell_blocks(const ShadowRay& s, const LightBuffer& lb, const LightBuffer::Entry* e,
                               const LightBuffer::Entry* end, double reach, Colour& sh, Ctx& ctx) const {
    const Geometry& g = *geometry;
    ShadowSearch found;
    // Spheres of the prefix are tested here, as Geometry::hit() would (the same
    // operations, so the same bits), without its lookups; the rest through it.
    const std::uint32_t prefix = g.sphere_prefix;
    const SphereG* const flat = g.spheres.flat();
    SphereG* const* const table = g.spheres.table();
    for (; e != end && !(double(e->dmin) > reach); ++e) {
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
        if (!(double(a.dmin) > reach) && shadow_test(a.obj, s, found, ctx)) return true;
    unblocked(s, found, sh, ctx);
    return false;
}

// Whether an opaque object lies on the shadow ray; if none, `sh` takes the tint of the
// refractive ones on it. p1: |p|_1 of the ray's start.
inline bool World::objects_block(const ShadowRay& s, double p1, Colour& sh, Ctx& ctx) const {
    return objects_block_toward(s, p1, s.v, s.r, sh, ctx);
}

// objects_block() for a ray toward a point of a sphere light: its light buffer's boxes
// are grown by the radius, so the cell toward the centre (`toward`, from p) holds every
// object on the ray, each within `reach` (the centre's distance from p) of the centre.
inline bool World::objects_block_toward(const ShadowRay& s, double p1, const Vec3& toward, double reach, Colour& sh,
                                        Ctx& ctx) const {
    if (blocker_blocks(s, ctx)) return true;
    const LightBuffer* lb = light_buffers ? &(*light_buffers)[s.light] : nullptr;
    if (lb && lb->usable(p1, reach)) {
        const LightBuffer::Entry *e, *end;
        lb->cell_toward(toward, e, end);
        return cell_blocks(s, *lb, e, end, reach, sh, ctx);
    }
    ShadowSearch found;
    if (objects_block_bvh(s, found, ctx)) return true;
    unblocked(s, found, sh, ctx);
    return false;
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
    if (!nearest(o, d, ctx, h)) {
        out = background;
        return false;
    }
    const Vec3 p = o + d * h.t;
    s.p = p;
    if (h.kind == HitRec::Glow) {
        const ShadeLight& l = lights[h.index];
        double rho = length(l.position - p);
        if (!(rho < l.size)) return false;
        double f = (l.size - rho) / l.size;
        out = l.colour * (f * f * f * f * f);
        return false;
    }
    const ShadeMaterial* m;
    Vec3 n;
    if (h.kind == HitRec::Object) {
        m = &materials[h.index];
        n = geometry->surface_normal(h.index, h.end, p);
        s.cp = m->colour;
        if (__builtin_expect(m->texture != nullptr || m->file != nullptr, 0))
            object_look(*geometry, h.index, h.end, p, m, s.cp);
    } else {
        const PlaneShape& pl = planes[h.index];
        m = &plane_mats[2 * h.index + pl.cell(p)];
        n = pl.n;
        s.cp = m->colour;
        if (__builtin_expect(m->texture != nullptr, 0)) s.cp = plane_look(pl, *m, p);
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

namespace {
// No NaN ever reaches a pixel.
inline Colour finite_colour(Colour c) {
    if (!std::isfinite(c.x)) c.x = c.x > 0 ? 1e30 : 0;
    if (!std::isfinite(c.y)) c.y = c.y > 0 ? 1e30 : 0;
    if (!std::isfinite(c.z)) c.z = c.z > 0 ? 1e30 : 0;
    return c;
}
}  // namespace

}  // namespace rt
