// The AVX2 path of the shading: camera rays and their mirror rays in packets of four,
// whose direct light is found together (direct4), lane by lane in the scalar code's
// order so that every pixel gets the scalar path's bits. Compiled for AVX2 function by
// function (RT_TARGET_AVX2), called only where the processor has it.

#include "shade.h"

#include <algorithm>
#include <cstdint>

#include "triangles.h"

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

// The sampler's integer steps (sampler.h) on eight 32-bit lanes: the same integers.
using I8 = __m256i;
RT_TARGET_AVX2 inline I8 reverse_bits8(I8 v) {
    const I8 nibble = _mm256_setr_epi8(0x0, 0x8, 0x4, 0xC, 0x2, 0xA, 0x6, 0xE, 0x1, 0x9, 0x5, 0xD, 0x3, 0xB, 0x7, 0xF,
                                       0x0, 0x8, 0x4, 0xC, 0x2, 0xA, 0x6, 0xE, 0x1, 0x9, 0x5, 0xD, 0x3, 0xB, 0x7, 0xF);
    const I8 low = _mm256_set1_epi8(0x0F);
    const I8 lo = _mm256_and_si256(v, low), hi = _mm256_and_si256(_mm256_srli_epi16(v, 4), low);
    // Each byte's bits reversed (its nibbles, each reversed, swapped), then the bytes.
    const I8 r = _mm256_or_si256(_mm256_slli_epi16(_mm256_shuffle_epi8(nibble, lo), 4), _mm256_shuffle_epi8(nibble, hi));
    return _mm256_shuffle_epi8(r, _mm256_setr_epi8(3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7,
                                                   6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12));
}
RT_TARGET_AVX2 inline I8 times(I8 x, std::uint32_t c) { return _mm256_mullo_epi32(x, _mm256_set1_epi32(int(c))); }
RT_TARGET_AVX2 inline I8 nested_scramble8(I8 x, I8 seed) {
    const I8 odd = _mm256_or_si256(_mm256_srli_epi32(seed, 16), _mm256_set1_epi32(1));
    return _mm256_mullo_epi32(_mm256_add_epi32(x, seed), odd);
}
RT_TARGET_AVX2 inline I8 hash8(I8 x) {
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
    x = times(x, 0x7feb352du);
    x = _mm256_xor_si256(x, _mm256_srli_epi32(x, 15));
    x = times(x, 0x846ca68bu);
    return _mm256_xor_si256(x, _mm256_srli_epi32(x, 16));
}
RT_TARGET_AVX2 inline I8 sobol1_reversed8(I8 i) {
    auto step = [&](int shift, std::uint32_t mask) RT_TARGET_AVX2 {
        i = _mm256_xor_si256(i, _mm256_and_si256(_mm256_srli_epi32(i, shift), _mm256_set1_epi32(int(mask))));
    };
    step(1, 0x55555555u), step(2, 0x33333333u), step(4, 0x0F0F0F0Fu), step(8, 0x00FF00FFu), step(16, 0x0000FFFFu);
    return i;
}
// sampling::fraction() of four lanes.
RT_TARGET_AVX2 inline __m256d fraction4(__m128i v) {
    const __m256d signed_ = _mm256_cvtepi32_pd(_mm_xor_si128(v, _mm_set1_epi32(int(0x80000000u))));
    return mul(add(signed_, splat(2147483648.0)), splat(1.0 / 4294967296.0));
}

// The points of the next few sphere lights for the samplers of four lanes: each lane's
// next dimensions, in the lights' order, as PathSampler::next() draws them (the same
// points). Drawn four lights at a time, two lights to a vector: the chains of
// multiplications of a light's four points are long, and overlap this way.
struct LightSamples4 {
    static constexpr int kMax = 4;
    __m256d u[kMax], v[kMax];
    int count = 0, used = 0;
    // Draws for the sphere lights from `first` on, up to kMax of them, for the lanes
    // `live` (the others' points are made up).
    RT_TARGET_AVX2 void draw(const Chunked<ShadeLight>& lights, std::size_t first, PathSampler (&s)[4], unsigned live) {
        count = used = 0;
        for (std::size_t j = first; j < lights.size() && count < kMax; ++j) count += lights[j].radius > 0;
        // The lanes' keys built in registers (stored lane by lane and loaded whole, they
        // would wait for the stores).
        auto lanes4 = [&](auto field) RT_TARGET_AVX2 {
            return _mm_setr_epi32(int(field(s[0])), int(field(s[1])), int(field(s[2])), int(field(s[3])));
        };
        const __m128i pixel = lanes4([](const PathSampler& p) { return p.pixel(); });
        const __m128i dim = _mm_mullo_epi32(lanes4([](const PathSampler& p) { return p.dimension(); }),
                                            _mm_set1_epi32(int(PathSampler::kGolden)));
        const __m128i rindex = lanes4([](const PathSampler& p) { return p.reversed_index(); });
        for (unsigned m = live; m; m &= m - 1) s[__builtin_ctz(m)].skip(std::uint32_t(count));
        const I8 index = _mm256_set_m128i(rindex, rindex);
        auto key = [&](int j) RT_TARGET_AVX2 {  // pixel ^ (dimension + j) kGolden
            return _mm_xor_si128(pixel, _mm_add_epi32(dim, _mm_set1_epi32(int(std::uint32_t(j) * PathSampler::kGolden))));
        };
        for (int pair = 0; pair < count; pair += 2) {
            const I8 seed = hash8(_mm256_set_m128i(key(pair + 1), key(pair)));
            const I8 i = reverse_bits8(nested_scramble8(index, seed));
            const I8 su = _mm256_xor_si256(seed, _mm256_set1_epi32(int(PathSampler::kSeedU)));
            const I8 sv = _mm256_xor_si256(seed, _mm256_set1_epi32(int(PathSampler::kSeedV)));
            const I8 uu = reverse_bits8(nested_scramble8(i, su));
            const I8 vv = reverse_bits8(nested_scramble8(sobol1_reversed8(i), sv));
            u[pair] = fraction4(_mm256_castsi256_si128(uu)), v[pair] = fraction4(_mm256_castsi256_si128(vv));
            u[pair + 1] = fraction4(_mm256_extracti128_si256(uu, 1)), v[pair + 1] = fraction4(_mm256_extracti128_si256(vv, 1));
        }
    }
};

// sampling::cos_sin_turn() for four angles: the same operations, so the same bits.
RT_TARGET_AVX2 void cos_sin_turn4(__m256d v, __m256d& c, __m256d& s) {
    const __m256d q = _mm256_round_pd(mul(v, splat(4)), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
    const __m256d x = mul(sub(v, mul(q, splat(0.25))), splat(sampling::kTwoPi)), x2 = mul(x, x);
    __m256d ps = splat(sampling::kTurnSin[6]), pc = splat(sampling::kTurnCos[7]);
    for (int i = 5; i >= 0; --i) ps = add(splat(sampling::kTurnSin[i]), mul(x2, ps));
    for (int i = 6; i >= 0; --i) pc = add(splat(sampling::kTurnCos[i]), mul(x2, pc));
    const __m256d sx = mul(x, ps);
    // The quarter turn's number, 0-3, in each lane's 64 bits.
    const __m256i quarter =
        _mm256_and_si256(_mm256_cvtepi32_epi64(_mm256_cvttpd_epi32(q)), _mm256_set1_epi64x(3));
    auto is = [&](long long k) RT_TARGET_AVX2 {
        return _mm256_castsi256_pd(_mm256_cmpeq_epi64(quarter, _mm256_set1_epi64x(k)));
    };
    const __m256d odd = _mm256_or_pd(is(1), is(3)), sign = splat(-0.0);
    c = _mm256_xor_pd(_mm256_blendv_pd(pc, sx, odd), _mm256_and_pd(sign, _mm256_or_pd(is(1), is(2))));
    s = _mm256_xor_pd(_mm256_blendv_pd(sx, pc, odd), _mm256_and_pd(sign, _mm256_or_pd(is(2), is(3))));
}

// shade.cpp's below_horizon() for four points (a mask).
RT_TARGET_AVX2 inline __m256d below_horizon4(const V3& vc, const V3& n, __m256d d, double radius) {
    return _mm256_cmp_pd(dot(vc, n), sub(splat(-radius), mul(splat(1e-9), d)), _CMP_LT_OQ);
}

// shade.cpp's toward_sphere() for four points, vc from each to the light's centre
// (r2 = |vc|^2): the same operations, so the same bits. The cone's sampling only where a
// lane of `live` lies outside the sphere.
struct SphereRay4 {
    V3 vh, v;
    __m256d r, inv_r2, reach;
};
RT_TARGET_AVX2 SphereRay4 toward_sphere4(const V3& vc, __m256d r2, double radius, __m256d u, __m256d v,
                                         const V3& n, unsigned live) {
    const __m256d one = splat(1.0), zero = _mm256_setzero_pd(), minus = splat(-0.0);
    SphereRay4 q;
    const __m256d d = _mm256_sqrt_pd(r2);
    const __m256d sign = _mm256_or_pd(_mm256_and_pd(vc.z, minus), one);  // copysign(1, vc.z)
    const __m256d y = add(mul(sign, d), vc.z), inv = _mm256_div_pd(one, mul(r2, y));
    q.inv_r2 = mul(y, inv);
    const __m256d inv_d = mul(d, q.inv_r2);
    const V3 w = scaled(vc, inv_d);
    const __m256d outside = _mm256_cmp_pd(d, splat(radius), _CMP_GT_OQ);
    q.vh = w, q.v = vc, q.r = d, q.reach = d;
    // (Where every lane is inside, or its sphere below its horizon, no direction of the
    // cone is lit: w is as dark.)
    if (!(lanes(_mm256_andnot_pd(below_horizon4(vc, n, d, radius), outside)) & live)) return q;
    const __m256d rr = splat(radius * radius);
    const __m256d one_minus = sub(one, mul(_mm256_sqrt_pd(_mm256_max_pd(sub(r2, rr), zero)), inv_d));
    const __m256d x = mul(u, one_minus);
    const __m256d cos_t = sub(one, x), sin_t2 = mul(x, sub(splat(2.0), x));
    const __m256d sin_t = _mm256_sqrt_pd(sin_t2);
    __m256d cos_phi, sin_phi;
    cos_sin_turn4(v, cos_phi, sin_phi);
    const __m256d a = mul(_mm256_xor_pd(d, minus), mul(r2, inv)), b = mul(mul(w.x, w.y), a);
    const V3 t1{add(one, mul(mul(mul(sign, w.x), w.x), a)), mul(sign, b), mul(_mm256_xor_pd(sign, minus), w.x)};
    const V3 t2{b, add(sign, mul(mul(w.y, w.y), a)), _mm256_xor_pd(w.y, minus)};
    const __m256d sc = mul(sin_t, cos_phi), ss = mul(sin_t, sin_phi);
    const V3 dir{add(add(mul(w.x, cos_t), mul(t1.x, sc)), mul(t2.x, ss)),
                 add(add(mul(w.y, cos_t), mul(t1.y, sc)), mul(t2.y, ss)),
                 add(add(mul(w.z, cos_t), mul(t1.z, sc)), mul(t2.z, ss))};
    const __m256d t = sub(mul(d, cos_t), _mm256_sqrt_pd(_mm256_max_pd(sub(rr, mul(r2, sin_t2)), zero)));
    const V3 dt = scaled(dir, t);
    auto pick = [&](__m256d in, __m256d out) RT_TARGET_AVX2 { return _mm256_blendv_pd(in, out, outside); };
    q.vh = {pick(w.x, dir.x), pick(w.y, dir.y), pick(w.z, dir.z)};
    q.v = {pick(vc.x, dt.x), pick(vc.y, dt.y), pick(vc.z, dt.z)};
    q.r = pick(d, t);
    return q;
}

// A light's strength at four points: its colour times 1 / r2, or 1 where r2 is not
// positive (the lanes not `positive`), as direct_sampled() finds it.
RT_TARGET_AVX2 inline V3 strength4(const Colour& c, __m256d inv_r2, __m256d positive) {
    const __m256d one = splat(1.0);
    return {_mm256_blendv_pd(one, mul(splat(c.x), inv_r2), positive),
            _mm256_blendv_pd(one, mul(splat(c.y), inv_r2), positive),
            _mm256_blendv_pd(one, mul(splat(c.z), inv_r2), positive)};
}

// direct_sampled()'s highlights for the lanes `lit` (normals n, materials m, seen
// along d) that a light of strength e reaches along vh, tinted sh: lane by lane, its
// operations.
RT_TARGET_AVX2 void highlights4(const Vec3* const n[4], const ShadeMaterial* const m[4], const Vec3 d[4], const V3& e,
                                const V3& vh, const double (&sh)[3][4], unsigned lit, Colour highlight[4]) {
    const Lanes3 ee(e), hh(vh);
    for (; lit; lit &= lit - 1) {
        const int k = __builtin_ctz(lit);
        const Vec3 h = hh[k] - d[k];
        const double hl = length(h);
        const double nh = hl > 0 ? dot(*n[k], h) / hl : 0;
        if (nh > 0)
            highlight[k] += mul(ee[k], Colour{sh[0][k], sh[1][k], sh[2][k]}) * (m[k]->specular * std::pow(nh, m[k]->shininess));
    }
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
// starts, and how far from the light's centre (toward: from the start) a blocker may
// lie: objects_block_toward()'s reach, the ray's length r for a point light.
struct World::ShadowRays4 {
    alignas(32) double ox[4], oy[4], oz[4], vx[4], vy[4], vz[4], hx[4], hy[4], hz[4], r[4], limit[4], p1[4];
    alignas(32) double reach[4], tx[4], ty[4], tz[4];
    std::size_t light;
    RT_TARGET_AVX2 void store(const V3& o, const V3& v, const V3& vh, __m256d rr, __m256d lim, __m256d q1, std::size_t li) {
        _mm256_store_pd(ox, o.x), _mm256_store_pd(oy, o.y), _mm256_store_pd(oz, o.z);
        _mm256_store_pd(vx, v.x), _mm256_store_pd(vy, v.y), _mm256_store_pd(vz, v.z);
        _mm256_store_pd(hx, vh.x), _mm256_store_pd(hy, vh.y), _mm256_store_pd(hz, vh.z);
        _mm256_store_pd(r, rr), _mm256_store_pd(limit, lim), _mm256_store_pd(p1, q1);
        light = li;
    }
    RT_TARGET_AVX2 void store_toward(const V3& t, __m256d far) {
        _mm256_store_pd(tx, t.x), _mm256_store_pd(ty, t.y), _mm256_store_pd(tz, t.z), _mm256_store_pd(reach, far);
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
            if (ctx.blocker[q.light] == 0 && (e == end || double(e->dmin) > q.reach[k]) && lb->always.empty()) continue;
            const ShadowRay ray = q.ray(k);
            blocked = blocker_blocks(ray, ctx) || cell_blocks(ray, *lb, e, end, q.reach[k], c, ctx);
        } else {
            blocked = objects_block_toward(q.ray(k), q.p1[k], {q.tx[k], q.ty[k], q.tz[k]}, q.reach[k], c, ctx);
        }
        if (blocked)
            lit &= ~(1u << k);
        else
            sh[0][k] = c.x, sh[1][k] = c.y, sh[2][k] = c.z;
    }
    return lit;
}

// The lanes (of `live`) whose shadow ray a glow disc blocks: others_block()'s glow
// part, lane by lane.
unsigned World::glows_block4(const ShadowRays4& q, unsigned live) const {
    unsigned blocked = 0;
    for (unsigned m = live; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        const Vec3 o{q.ox[k], q.oy[k], q.oz[k]}, vh{q.hx[k], q.hy[k], q.hz[k]};
        bool hit = false;
        if (glow_bvh) {
            hit = glow_blocks(o, vh, q.limit[k]);
        } else {
            for (std::uint32_t i : glows) {
                double t;
                if (glow_hit(lights[i], o, vh, t) && t > 0 && t < q.limit[k]) {
                    hit = true;
                    break;
                }
            }
        }
        if (hit) blocked |= 1u << k;
    }
    return blocked;
}

// Four rays' tree budgets (see Ctx), kept apart while their trees are traced together,
// and their paths' samplers.
struct World::Budgets {
    double budget[4], cutoff[4];
    PathSampler sampler[4];
    // Ctx takes lane k's budget (unless the trace has stopped: its budget stays spent)
    // and sampler.
    void enter(Ctx& ctx, int k) const {
        if (!ctx.stats->stopped) ctx.budget = budget[k], ctx.cutoff = cutoff[k];
        ctx.sampler = sampler[k];
    }
    void leave(const Ctx& ctx, int k) { budget[k] = ctx.budget, cutoff[k] = ctx.cutoff, sampler[k] = ctx.sampler; }
};

// direct_sampled() (direct() where no light is a sphere and no lane has a highlight)
// for the lanes `live` of four surfaces seen along d:
// each lane does its operations in its order, so gets its bits; the set-up, the sphere
// lights' points, the planes and the sums are done for the four at once, the objects'
// tests lane by lane. A lane's highlight is added to highlight[k].
RT_TARGET_AVX2 void World::direct4(const Surface s[4], const Vec3 d[4], unsigned live, Colour out[4],
                                   Colour highlight[4], Budgets& b, Ctx& ctx) const {
    if (ctx.blocker.size() < lights.size()) ctx.blocker.resize(lights.size());
    const int first = __builtin_ctz(live);  // the other lanes copy it, harmlessly
    const Vec3 *pp[4], *nn[4], *cc[4];
    const ShadeMaterial* mats[4];
    unsigned shiny = 0;  // the lanes with a highlight
    for (int k = 0; k < 4; ++k) {
        const Surface& q = s[(live >> k) & 1 ? k : first];
        pp[k] = &q.p, nn[k] = &q.n, cc[k] = &q.cp, mats[k] = q.m;
        if ((live >> k) & 1 && q.m->specular > 0) shiny |= 1u << k;
    }
    const V3 p = gather(pp), n = gather(nn), cp = gather(cc);
    const __m256d sign = splat(-0.0), zero = _mm256_setzero_pd(), one = splat(1.0);
    const __m256d p1 = add(add(_mm256_andnot_pd(sign, p.x), _mm256_andnot_pd(sign, p.y)), _mm256_andnot_pd(sign, p.z));
    V3 sum{zero, zero, zero};
    LightSamples4 drawn;
    for (std::size_t li = 0; li < lights.size(); ++li) {
        const ShadeLight& light = lights[li];
        const V3 vc{sub(splat(light.position.x), p.x), sub(splat(light.position.y), p.y),
                    sub(splat(light.position.z), p.z)};
        const __m256d r2 = dot(vc, vc), positive = _mm256_cmp_pd(r2, zero, _CMP_GT_OQ);
        // The ray toward the light's centre, or toward this sample's point of a sphere
        // light (from outside it), whose blockers lie within `reach` of the centre.
        const bool sphere = light.radius > 0;
        SphereRay4 q;
        if (sphere) {
            if (drawn.used == drawn.count) drawn.draw(lights, li, b.sampler, live);
            q = toward_sphere4(vc, r2, light.radius, drawn.u[drawn.used], drawn.v[drawn.used], n, live);
            ++drawn.used;
        } else {
            q.inv_r2 = _mm256_div_pd(one, r2);
        }
        const V3 e = strength4(light.colour, q.inv_r2, positive);
        const V3 ec{mul(e.x, cp.x), mul(e.y, cp.y), mul(e.z, cp.z)};
        sum = {add(sum.x, mul(ec.x, splat(0.1))), add(sum.y, mul(ec.y, splat(0.1))), add(sum.z, mul(ec.z, splat(0.1)))};
        const __m256d vn = dot(sphere ? q.vh : vc, n);
        unsigned lit = lanes(_mm256_cmp_pd(vn, zero, _CMP_GT_OQ)) & live;
        if (!lit) continue;
        ctx.stats->rays += unsigned(__builtin_popcount(lit));
        __m256d cos_w;  // 0.9 times the cosine toward the light's point
        if (sphere) {
            cos_w = mul(splat(0.9), vn);
        } else {
            q.v = vc, q.r = _mm256_sqrt_pd(r2);
            const __m256d inv_r = _mm256_div_pd(one, q.r);
            q.vh = scaled(vc, inv_r), q.reach = q.r, cos_w = mul(mul(splat(0.9), vn), inv_r);
        }
        const V3 &v = q.v, &vh = q.vh;
        const __m256d &r = q.r, &reach = q.reach;
        const V3 o{add(p.x, mul(vh.x, splat(kDelta))), add(p.y, mul(vh.y, splat(kDelta))),
                   add(p.z, mul(vh.z, splat(kDelta)))};
        const __m256d limit = sub(r, splat(10 * kDelta));
        lit &= ~planes_block4(*this, o, vh, limit, lit);
        if (!lit) continue;
        // The objects, lane by lane, each lane's cell found for the four at once.
        ShadowRays4 rays;
        rays.store(o, v, vh, r, limit, p1, li);
        rays.store_toward(vc, reach);
        if (!glows.empty() && !(lit &= ~glows_block4(rays, lit))) continue;
        const LightBuffer* lb = light_buffers ? &(*light_buffers)[li] : nullptr;
        unsigned in_cell = 0;  // the lanes that LightBuffer::usable() lets use it
        alignas(16) std::int32_t cell[4];
        if (lb && lb->n > 0) {
            in_cell = lanes(_mm256_cmp_pd(add(add(p1, splat(lb->position1)), reach), splat(lb->reach), _CMP_LE_OQ)) & lit;
            if (in_cell) cells_toward4(*lb, vc, cell);
        }
        alignas(32) double shade[3][4] = {{1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 1}};
        lit = shadow_lanes(rays, lb, in_cell, cell, lit, shade, ctx);
        if (!lit) continue;
        const V3 sh{_mm256_load_pd(shade[0]), _mm256_load_pd(shade[1]), _mm256_load_pd(shade[2])};
        const V3 term = scaled({mul(ec.x, sh.x), mul(ec.y, sh.y), mul(ec.z, sh.z)}, cos_w);
        const __m256i bits = _mm256_and_si256(_mm256_set1_epi64x(lit), _mm256_set_epi64x(8, 4, 2, 1));
        const __m256d use = _mm256_castsi256_pd(_mm256_cmpgt_epi64(bits, _mm256_setzero_si256()));
        sum = {_mm256_blendv_pd(sum.x, add(sum.x, term.x), use), _mm256_blendv_pd(sum.y, add(sum.y, term.y), use),
               _mm256_blendv_pd(sum.z, add(sum.z, term.z), use)};
        if (lit & shiny) highlights4(nn, mats, d, e, vh, shade, lit & shiny, highlight);
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
    // scatters: the lanes whose direct light is found; fresh: those that shade() shades
    // with the New: terms (direct_sampled(), and a highlight added).
    unsigned pending = 0, scatters = 0, mirrors = 0, fresh = 0;
    for (unsigned m = live; m; m &= m - 1) {
        const int k = __builtin_ctz(m);
        b.enter(ctx, k);
        if (shade_surface(o[k], d[k], depth, weight[k], ctx, s[k], out[k])) {
            pending |= 1u << k;
            const bool shiny = s[k].m->specular > 0;
            if (area_lights || shiny) fresh |= 1u << k;
            if (s[k].m->scattering > 0 || shiny) scatters |= 1u << k;
            if (s[k].m->reflection > 0) mirrors |= 1u << k;
        }
        b.leave(ctx, k);
    }
    Uninit4<Colour> lits, mirrors_;
    Colour *const lit = lits.v, *const mirror = mirrors_.v;
    Colour highlight[4];
    if (scatters && !ctx.stats->stopped) {
        if (scatters & (scatters - 1)) {
            direct4(s, d, scatters, lit, highlight, b, ctx);
        } else {  // one lane: the scalar loop costs less
            const int k = __builtin_ctz(scatters);
            if ((fresh >> k) & 1) {
                b.enter(ctx, k);
                lit[k] = direct_sampled(s[k].p, s[k].n, d[k], *s[k].m, s[k].cp, highlight[k], ctx);
                b.leave(ctx, k);
            } else {
                lit[k] = direct(s[k].p, s[k].n, s[k].cp, ctx);
            }
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
        if ((fresh >> k) & 1) out[k] = out[k] + highlight[k];
    }
}

namespace {
// The nearest plane of each of the n rays from `o` along d[i] (its index, -1 for none,
// and its distance), as World::nearest() finds it; none where the world has glows (a
// disc might be nearer, and then no guess is made for the plane).
void nearest_planes(const World& w, const Vec3& o, const Vec3* d, int n, double* plane_t, int* plane) {
    for (int i = 0; i < n; ++i) {
        plane_t[i] = HUGE_VAL, plane[i] = -1;
        if (!w.glows.empty()) continue;
        for (std::size_t k = 0; k < w.planes.size(); ++k) {
            const PlaneShape& pl = w.planes[k];
            const double dn = dot(pl.n, d[i]);
            if (dn == 0) continue;
            const double t = -(dot(pl.n, o) + pl.D) / dn;
            if (t > kDelta && t < plane_t[i]) plane_t[i] = t, plane[i] = int(k);
        }
    }
}

// A sphere around the mesh in world space (its centre and squared radius, a little
// more), from the boxes of its 8-wide tree's root.
void mesh_sphere(const MeshG& m, Vec3& centre, double& reach2) {
    const BvhNode8& root = m.accel->bvh.nodes8[0];
    Aabb box;
    for (int c = 0; c < 8; ++c) {
        if (root.child[c] == BvhNode::kEmpty) continue;
        box.grow(Vec3{root.b[0][c], root.b[1][c], root.b[2][c]});
        box.grow(Vec3{root.b[3][c], root.b[4][c], root.b[5][c]});
    }
    const Aabb wb = m.instance.world_bounds(box);
    centre = (wb.lo + wb.hi) * 0.5;
    reach2 = length2(wb.hi - centre) * 1.01 + 1e-9;
}

// Camera rays from one origin meet a scene's few meshes as packets: before the next
// TriangleAccel::kPacket rays of a row are shaded, each mesh's nearest triangle for
// each of them is found by one packet walk (TriangleAccel::prepare), with the very
// operands mesh_hit() will ask with (the ray in the mesh's space, tmin kDelta), and
// mesh_hit() then takes the answers kept. A ray that does not ask (its cell of the
// camera buffer lacks the mesh, a plane is nearer) leaves its answer unused.
//
// The shadow rays of those hits toward each point light, likewise, for an opaque mesh:
// where a ray's nearest hit is on the mesh (its triangle's normal turned toward the
// ray) or on a nearer plane, and that faces the light, its shadow ray is made as
// direct4() will make it (p = o + d t, v = light - p, r = |v|, the start p + kDelta v / r
// and the limit r - 10 kDelta: the same operations, so the same bits), and if it passes
// near the mesh, the answers of all of them are found as one packet
// (TriangleAccel::prepare_any). A guess that differs from the ray direct4() makes
// (another object nearer, a smooth normal on the other side) is never asked for and
// costs only its walk.
void prepare_meshes(const World& w, const Vec3& o, const Vec3* d, int n) {
    TriangleAccel::forget_prepared();
    const Geometry& g = *w.geometry;
    if (g.meshes.empty() || g.meshes.size() > std::size_t(TriangleAccel::kPrepared)) return;
    constexpr int P = TriangleAccel::kPacket;
    double plane_t[P];
    int plane[P];
    nearest_planes(w, o, d, n, plane_t, plane);
    TriRay r[P];
    TriHit hits[P];
    bool found[P];
    Vec3 p[P], n_out[P];
    bool point[P];
    double limit[P];
    for (const MeshG& m : g.meshes) {
        if (!m.accel) continue;
        const Vec3 om = m.instance.point_to_model(o);
        for (int i = 0; i < n; ++i) r[i] = TriRay::make(om, m.instance.to_model(d[i]));
        // (Shadow packets only on the 8-wide tree: a model read while the SSE2 path was
        // chosen has none, and its shadow rays are walked alone.)
        if (!m.accel->prepare(r, n, kDelta, HUGE_VAL, hits, found) || !m.opaque || m.accel->bvh.nodes8.empty()) continue;
        // The point each ray's shading will light, where it can be told: the mesh's
        // triangle (its normal turned toward the ray) or, nearer, a plane.
        for (int i = 0; i < n; ++i) {
            point[i] = false;
            if (plane[i] >= 0 && (!found[i] || plane_t[i] <= hits[i].t)) {
                const PlaneShape& pl = w.planes[std::size_t(plane[i])];
                if (w.plane_mats[2 * std::size_t(plane[i])].refraction != 0 ||
                    w.plane_mats[2 * std::size_t(plane[i]) + 1].refraction != 0)
                    continue;
                p[i] = o + d[i] * plane_t[i];
                n_out[i] = pl.n;
                point[i] = true;
            } else if (found[i]) {
                p[i] = o + d[i] * hits[i].t;
                Vec3 c[3];
                m.accel->corners(hits[i].slot, c);
                n_out[i] = m.instance.normal_to_world(cross(c[1] - c[0], c[2] - c[0]));
                if (dot(n_out[i], d[i]) > 0) n_out[i] = -n_out[i];
                point[i] = true;
            }
        }
        // A sphere around the mesh, for the shadow rays from elsewhere that cannot reach
        // it at all: left out here, they are only walked alone later.
        Vec3 centre;
        double reach2;
        mesh_sphere(m, centre, reach2);
        for (std::size_t li = 0; li < w.lights.size(); ++li) {
            const ShadeLight& l = w.lights[li];
            if (l.radius > 0) continue;
            int k = 0;
            for (int i = 0; i < n; ++i) {
                if (!point[i]) continue;
                const Vec3 v{l.position.x - p[i].x, l.position.y - p[i].y, l.position.z - p[i].z};
                if (!(dot(v, n_out[i]) > 0)) continue;
                const Vec3 c = centre - p[i];
                const double vv = dot(v, v), cv = dot(c, v);
                const double d2 = cv <= 0 ? length2(c) : cv >= vv ? length2(centre - l.position) : length2(c) - cv * cv / vv;
                if (d2 > reach2) continue;
                const double rr = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z), inv = 1.0 / rr;
                const Vec3 vh{v.x * inv, v.y * inv, v.z * inv};
                const Vec3 so{p[i].x + vh.x * kDelta, p[i].y + vh.y * kDelta, p[i].z + vh.z * kDelta};
                r[k] = TriRay::make(m.instance.point_to_model(so), m.instance.to_model(vh));
                limit[k++] = rr - 10 * kDelta;
            }
            if (k > 1) m.accel->prepare_any(r, k, 0.0, limit);
        }
    }
}
// Drops the kept answers however trace_units4() ends: no later walk may take them.
struct Prepared {
    ~Prepared() { TriangleAccel::forget_prepared(); }
};
}  // namespace

// trace_units() on the AVX2 path: shade4() on four camera rays at a time. With keys,
// trace_samples(): each ray takes its sample's sampler and its point of the lens.
void World::trace_units4(const CameraBasis& cam, const Vec3* dirs, const PixelSample* keys, std::size_t n, Ctx& ctx,
                         Colour* out) const {
    Vec3 o[4] = {cam.origin, cam.origin, cam.origin, cam.origin};
    Vec3 lens_dirs[4];
    const double weight[4] = {1, 1, 1, 1};
    const Geometry& g = *geometry;
    // Packets where the rays share the camera's origin (no lens) and the scene has meshes.
    const bool packets = !(keys && cam.lens > 0) && !g.meshes.empty();
    const Prepared forget;
    int row_y = keys && n > 0 ? keys[0].y : 0;  // the samplers' row and its hash
    std::uint32_t row = PathSampler::row_hash(row_y);
    for (std::size_t i0 = 0; i0 < n; i0 += 4) {
        if (ctx.stats->stopped) return std::fill(out + i0, out + n, Colour{});
        if (packets && i0 % TriangleAccel::kPacket == 0)
            prepare_meshes(*this, cam.origin, dirs + i0, int(std::min<std::size_t>(TriangleAccel::kPacket, n - i0)));
        const unsigned count = unsigned(std::min<std::size_t>(4, n - i0));
        // Each ray's tree starts with the whole budget, as in trace_from().
        Budgets b;
        std::fill(b.budget, b.budget + 4, omit_weight);
        std::fill(b.cutoff, b.cutoff + 4, omit_weight * Ctx::kShare);
        const Vec3* d = dirs + i0;
        if (keys) {
            for (unsigned k = 0; k < count; ++k) {
                if (keys[i0 + k].y != row_y) row_y = keys[i0 + k].y, row = PathSampler::row_hash(row_y);
                b.sampler[k] = PathSampler(keys[i0 + k], row);
                lens_dirs[k] = d[k];
                if (cam.lens > 0) {
                    double u, v;
                    b.sampler[k].next(u, v);
                    const Ray r = cam.lens_ray(d[k], u, v);
                    o[k] = r.origin, lens_dirs[k] = r.dir;
                }
            }
            d = lens_dirs;
        }
        shade4(o, d, (1u << count) - 1, 0, weight, b, out + i0, ctx);
        // Stopped inside these four: they and the rest are black, as in trace_units().
        if (ctx.stats->stopped) return std::fill(out + i0, out + n, Colour{});
        for (unsigned k = 0; k < count; ++k) out[i0 + k] = finite_colour(out[i0 + k]);
    }
}
#endif


}  // namespace rt
