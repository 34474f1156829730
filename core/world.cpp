// Shading as in rendering.md §2-§6: direct light with the unshadowed 0.1 term and
// coloured shadows through refractive objects, mirror reflection, refraction with the
// interior walk, and lamp glow discs. Planes and glows are few and unbounded, so they
// are tested one by one; everything else goes through the BVH.
#include "world.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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

// rendering.md §5, with the normal-incidence fix: straight through.
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
    // Per light, the last opaque object that shadowed a point (+1; 0 = none). Shadows
    // are coherent, so trying it first usually ends the search at once.
    std::vector<std::uint32_t> blocker;
};

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
    for (std::uint32_t i : glows) {
        double t;
        if (glow_hit(lights[i], o, d, t) && t > kDelta && t < h.t) {
            h.kind = HitRec::Glow;
            h.t = t;
            h.index = i;
        }
    }
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

Colour World::direct(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const {
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
        for (std::uint32_t i : glows) {
            double t;
            if (!blocked && glow_hit(lights[i], o, vh, t) && t > 0 && t < limit) blocked = true;
        }
        if (!blocked) sum += mul(mul(e, cp), sh) * (0.9 * vn * inv_r);
    }
    return sum;
}

Colour World::walk(const HitRec& x, const Vec3& q0, const Vec3& d1, double eta, int level, Ctx& ctx) const {
    if (level >= options.max_depth) return {};
    ++ctx.stats->rays;
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
    if (refract(d1, eta, 1, n1, d2))
        c = shade(q1, d2, level + 1, ctx);
    else
        c = walk(x, q1, reflect(d1, n1), eta, level + 1, ctx);
    return mul(c, tint(*m, s));
}

Colour World::shade(const Vec3& o, const Vec3& d, int depth, Ctx& ctx) const {
    if (depth >= options.max_depth) return {};
    ++ctx.stats->rays;
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
            if (refract(d, 1, m->ior, nn, d1)) refr = walk(h, p, normalize(d1), m->ior, depth + 2, ctx);
        }
    }
    Colour c;
    if (m->scattering > 0) c += direct(p, n, m->colour, ctx) * m->scattering;
    if (m->reflection > 0) c += shade(p, reflect(d, n), depth + 2, ctx) * m->reflection;
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
    Colour c = shade(origin, d, depth, ctx);
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

std::shared_ptr<const World> compile_world(const Scene& scene, const World* previous) {
    auto w = std::make_shared<World>();
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
    w->materials.reserve(scene.objects.size());
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        // Big scenes repeat a few materials, often alternating: one equal (bit for bit)
        // to either of the last two objects' is copied, saving its three logarithms.
        static_assert(sizeof(Material) == 8 * sizeof(double), "materials compare as bytes");
        const Material& m = scene.objects[i].material;
        std::size_t k = 1;
        for (; k <= 2 && k <= i; ++k)
            if (std::memcmp(&m, &scene.objects[i - k].material, sizeof m) == 0) break;
        w->materials.push_back(k <= 2 && k <= i ? w->materials[i - k] : ShadeMaterial::from(m));
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
    w->camera = scene.camera;
    w->width = scene.width;
    w->height = scene.height;
    if (previous) w->options = previous->options;
    return w;
}

}  // namespace rt
