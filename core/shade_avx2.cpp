// The AVX2 path of the shading: camera rays and their mirror rays in packets of four,
// whose direct light is found together (direct4), lane by lane in the scalar code's
// order so that every pixel gets the scalar path's bits. Compiled for AVX2 function by
// function (RT_TARGET_AVX2), called only where the processor has it.

#include "shade.h"

#include <algorithm>
#include <cstdint>

namespace rt {

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
        // As in others_block(), the division only where a lane's ray may cross: most
        // rays (a point and its light on the same side) end here, and a division's
        // latency would hold up the rest.
        if (!(lanes(across) & live & ~blocked)) continue;
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
            blocked = blocker_blocks(ray, ctx) || cell_blocks(ray, *lb, e, end, ray.r, c, ctx);
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
        pp[k] = &q.p, nn[k] = &q.n, cc[k] = &q.cp;
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
            lit[k] = direct(s[k].p, s[k].n, s[k].cp, ctx);
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


}  // namespace rt
