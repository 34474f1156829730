// Shading as in docs/rendering.md §2-§6: direct light with the unshadowed 0.1 term and
// coloured shadows through refractive objects, mirror reflection, refraction with the
// interior walk, and lamp glow discs. Planes are few and unbounded, so they are tested
// one by one; objects go through the BVH, and glow discs too when there are many.
// The ray tree is cut where the rays left out cannot be seen (World::omit_weight) and
// where the caller asks to stop (RayStats::stop). On the AVX2 path camera rays and their
// mirror rays go in packets of four whose direct light is found together.

#include "shade.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bvh.h"
#include "shapes.h"

namespace rt {

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

// `sh` tinted by the refractive objects that a shadow ray met (none opaque): one alone
// gives its tint; two or more need the ordered search of glass_tint(), which multiplies
// their tints in a fixed order (so that the product rounds the same on every path).
Colour World::found_tint(const ShadowRay& s, const ShadowSearch& found, const Colour& sh, Ctx& ctx) const {
    return found.glass == 1 ? through_glass(found.obj, found.t, s, sh, ctx) : glass_tint(s, sh, ctx);
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

namespace {
// The ray toward a sphere light of radius R whose centre is vc from p (r2 = |vc|^2 > 0):
// the light's 1 / r2 for its strength, and the unit vector vh and the length r of the
// shadow ray. From outside (d = |vc| > R) the sample (u, v) picks a direction uniformly
// in the cone the sphere fills, and the ray ends where that direction enters the
// sphere; from inside, it goes to the centre. Either way no point of the ray is farther
// from the centre than p (the distance along a segment is convex): blockers lie within
// d of it. One division and four square roots (one from inside): the division's
// 1 / (r2 y), y = d (sign + w_z) (w = vc / d), gives both 1 / r2 = y / (r2 y) and the
// frame's 1 / (sign + w_z) = d r2 / (r2 y); cos(theta_max) is sqrt(r2 - R^2) / d, whose
// cancellation in 1 - cos(theta_max) errs by at most 2^-53 / (R / d)^2 of the cone's
// width (1e-12 at R / d = 0.01); the direction is a unit vector by construction and the
// entry distance is the ray's length, so the ray takes no normalising division or
// square root of its own. (Each step as shade_avx2.cpp's toward_sphere4() takes it,
// for the same bits; a light below the horizon is dark there whether sampled or not.)
struct SphereRay {
    Vec3 vh, v;
    double r, inv_r2, d;
    bool outside;
};
// Whether the whole sphere light lies below the horizon of a surface with unit normal n
// (as every Surface's is), d from its centre (with room for rounding): then no direction
// toward it is lit.
bool below_horizon(const Vec3& vc, const Vec3& n, double d, double radius) { return dot(vc, n) < -radius - 1e-9 * d; }

// The sample's point is taken from `sampler` (only its dimension where it is not used:
// from inside, or below the horizon of the surface with normal n).
SphereRay toward_sphere(const Vec3& vc, double r2, double radius, const Vec3& n, PathSampler& sampler) {
    SphereRay q;
    q.d = std::sqrt(r2);
    const double sign = std::copysign(1.0, vc.z), y = sign * q.d + vc.z, inv = 1 / (r2 * y);
    q.inv_r2 = y * inv;
    const double inv_d = q.d * q.inv_r2;
    const Vec3 w = vc * inv_d;
    q.outside = q.d > radius;
    if (!q.outside || below_horizon(vc, n, q.d, radius)) {
        sampler.skip(1);  // the dimensions stay in step
        q.vh = w, q.v = vc, q.r = q.d;
        return q;
    }
    double u, v;
    sampler.next(u, v);
    const double rr = radius * radius;
    const double one_minus = 1 - std::sqrt(std::max(0.0, r2 - rr)) * inv_d;  // 1 - cos(theta_max)
    const double x = u * one_minus;                                           // 1 - cos(theta)
    const double cos_t = 1 - x, sin_t2 = x * (2 - x);
    const double sin_t = std::sqrt(sin_t2);
    double cos_phi, sin_phi;
    sampling::cos_sin_turn(v, cos_phi, sin_phi);
    // An orthonormal frame around w (Duff et al. 2017), a = -1 / (sign + w_z).
    const double a = -q.d * (r2 * inv), b = w.x * w.y * a;
    const Vec3 t1{1 + sign * w.x * w.x * a, sign * b, -sign * w.x};
    const Vec3 t2{b, sign + w.y * w.y * a, -w.y};
    const double sc = sin_t * cos_phi, ss = sin_t * sin_phi;
    q.vh = {w.x * cos_t + t1.x * sc + t2.x * ss, w.y * cos_t + t1.y * sc + t2.y * ss,
            w.z * cos_t + t1.z * sc + t2.z * ss};
    // Where the ray p + t vh enters the sphere (it does: vh lies in the cone).
    q.r = q.d * cos_t - std::sqrt(std::max(0.0, rr - r2 * sin_t2));
    q.v = q.vh * q.r;
    return q;
}
}  // namespace

Colour World::direct_sampled(const Vec3& p, const Vec3& n, const Vec3& d, const ShadeMaterial& m, const Colour& cp,
                             Colour& highlight, Ctx& ctx) const {
    Colour sum;
    if (ctx.stats->stopped) return sum;
    if (ctx.blocker.size() < lights.size()) ctx.blocker.resize(lights.size());
    const double p1 = LightBuffer::norm1(p);
    for (std::size_t li = 0; li < lights.size(); ++li) {
        const ShadeLight& light = lights[li];
        // The 2013 terms (docs/rendering.md §3) at the light's centre: its strength, the
        // unshadowed tenth; then the shadow ray and the cosine toward the light's point
        // that this sample takes (the centre for a point light, or from inside one).
        const Vec3 vc = light.position - p;
        const double rc2 = dot(vc, vc);
        Vec3 v = vc, vh;
        double r, cos_w, reach;  // cos_w: 0.9 times the cosine toward the point
        Colour e;
        if (light.radius > 0) {
            const SphereRay q = toward_sphere(vc, rc2, light.radius, n, ctx.sampler);
            e = rc2 > 0 ? light.colour * q.inv_r2 : Colour{1, 1, 1};
            sum += mul(e, cp) * 0.1;
            const double vn = dot(q.vh, n);
            if (!(vn > 0)) continue;
            v = q.v, vh = q.vh, r = q.r, cos_w = 0.9 * vn;
            reach = q.d;  // blockers lie within this of the centre (toward_sphere())
        } else {
            e = rc2 > 0 ? light.colour * (1 / rc2) : Colour{1, 1, 1};
            sum += mul(e, cp) * 0.1;
            const double vn = dot(v, n);
            if (!(vn > 0)) continue;
            r = length(v);
            const double inv_r = 1 / r;
            vh = v * inv_r, cos_w = 0.9 * vn * inv_r, reach = r;
        }
        const ShadowRay s{p + vh * kDelta, v, vh, r, r - 10 * kDelta, li};
        ++ctx.stats->rays;
        Colour sh{1, 1, 1};
        const bool blocked = light.radius > 0 ? objects_block_toward(s, p1, vc, reach, sh, ctx)
                                              : objects_block(s, p1, sh, ctx);
        if (blocked || (glow_bvh ? others_block<true>(s) : others_block<false>(s))) continue;
        sum += mul(mul(e, cp), sh) * cos_w;
        if (m.specular > 0) {
            // Blinn-Phong: the normal against the half vector of the light and the eye.
            const Vec3 h = vh - d;
            const double hl = length(h);
            const double nh = hl > 0 ? dot(n, h) / hl : 0;
            if (nh > 0) highlight += mul(e, sh) * (m.specular * std::pow(nh, m.shininess));
        }
    }
    return sum;
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

Colour World::shade(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx) const {
    Surface s;
    Colour out;
    if (!shade_surface(o, d, depth, weight, ctx, s, out)) return out;
    const ShadeMaterial* m = s.m;
    if (__builtin_expect(area_lights || m->specular > 0, 0)) {
        // The New: terms: sphere lights sampled, highlights.
        Colour highlight;
        const Colour lit =
            m->scattering > 0 || m->specular > 0 ? direct_sampled(s.p, s.n, d, *m, s.cp, highlight, ctx) : Colour{};
        const Colour mirror =
            m->reflection > 0 ? shade(s.p, reflect(d, s.n), depth + 2, weight * m->reflection, ctx) : Colour{};
        return combine(s, lit, mirror) + highlight;
    }
    const Colour lit = m->scattering > 0 ? direct(s.p, s.n, s.cp, ctx) : Colour{};
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

}  // namespace

Colour World::trace_from(const Vec3& origin, const Vec3& d, int depth, RayStats& stats) const {
    Ctx& ctx = thread_ctx();
    ctx.stats = &stats;
    if (stats.stopped) return {};
    ctx.budget = omit_weight;
    ctx.cutoff = omit_weight * Ctx::kShare;
    ctx.sampler = PathSampler();  // (a ray of no pixel sample: the same points every time)
    return finite_colour(shade(origin, d, depth, 1.0, ctx));
}

void World::trace_units(const Vec3& origin, const Vec3* unit_dirs, std::size_t n, RayStats& stats, Colour* out) const {
    CameraBasis cam;
    cam.origin = origin;
    trace_rays(cam, unit_dirs, nullptr, n, stats, out);
}

void World::trace_samples(const CameraBasis& cam, const Vec3* unit_dirs, const PixelSample* keys, std::size_t n,
                          RayStats& stats, Colour* out) const {
    trace_rays(cam, unit_dirs, sampled(cam) ? keys : nullptr, n, stats, out);
}

// Camera rays from cam.origin along unit_dirs, each with its sample's sampler and point
// of the lens where keys are given, else the same points for every ray.
void World::trace_rays(const CameraBasis& cam, const Vec3* unit_dirs, const PixelSample* keys, std::size_t n,
                       RayStats& stats, Colour* out) const {
    Ctx& ctx = thread_ctx();
    ctx.stats = &stats;
#if RT_HAVE_AVX2_KERNELS
    if (avx2_active()) return trace_units4(cam, unit_dirs, keys, n, ctx, out);
#endif
    for (std::size_t i = 0; i < n; ++i) {
        if (stats.stopped) {
            std::fill(out + i, out + n, Colour{});
            return;
        }
        // Each ray's tree starts with the whole budget, as in trace_from().
        ctx.budget = omit_weight;
        ctx.cutoff = omit_weight * Ctx::kShare;
        ctx.sampler = keys ? PathSampler(keys[i]) : PathSampler();
        Vec3 o = cam.origin, d = unit_dirs[i];
        if (keys && cam.lens > 0) {
            double u, v;
            ctx.sampler.next(u, v);
            const Ray r = cam.lens_ray(d, u, v);
            o = r.origin, d = r.dir;
        }
        out[i] = finite_colour(shade(o, d, 0, 1.0, ctx));
    }
}

Colour World::trace_camera(const CameraBasis& cam, double i, double j, RayStats& stats) const {
    return trace(cam.origin, cam.direction(i, j), 0, stats);
}

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
    if (h.kind == World::HitRec::Object) r.object = world.object_of(h.index);
    if (h.kind == World::HitRec::PlaneHit) r.plane = int(h.index);
    if (h.kind == World::HitRec::Glow) r.light = int(h.index);
    return r;
}

}  // namespace rt
