// Triangles for tracing (see triangles.h): the watertight test in double precision
// (scalar, and four lanes at once on the AVX2 path with the same operations lane for
// lane, so the same bits), the walks and the mesh instances' transforms. The BVH
// build is in triangles_build.cpp.
//
// Watertightness: the edge function of an edge shared by two triangles is computed
// from the same two sheared corners in both, so it comes out as the other's exact
// negation, and a zero counts as inside: a ray through a shared edge or corner hits
// one of the triangles or both, never neither. Where an edge function is exactly
// zero its sign is found exactly (the products' rounding errors recovered), as the
// paper does with a second, wider evaluation.
#include "triangles.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "simd.h"

namespace rt {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- exact signs -------------------------------------------------------------------
// a * b as hi + lo exactly (Dekker's product: no FMA, the same bits everywhere).
inline void two_product(double a, double b, double& hi, double& lo) {
    auto split = [](double x, double& h, double& l) {
        const double c = 134217729.0 * x;  // 2^27 + 1
        h = c - (c - x);
        l = x - h;
    };
    hi = a * b;
    double ah, al, bh, bl;
    split(a, ah, al);
    split(b, bh, bl);
    lo = al * bl - (((hi - ah * bh) - al * bh) - ah * bl);
}
inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a, av = x - bv;
    y = (a - av) + (b - bv);
}
inline void two_diff(double a, double b, double& x, double& y) {
    x = a - b;
    const double bv = a - x, av = x + bv;
    y = (a - av) + (bv - b);
}

// The sign of a b - c d, exactly (Shewchuk's two-two difference of the products).
int exact_sign(double a, double b, double c, double d) {
    double a1, a0, b1, b0;
    two_product(a, b, a1, a0);
    two_product(c, d, b1, b0);
    double i, x0, j, z, x1, x2, x3;
    two_diff(a0, b0, i, x0);
    two_sum(a1, i, j, z);
    double k;
    two_diff(z, b1, k, x1);
    two_sum(j, k, x3, x2);
    for (double x : {x3, x2, x1, x0})
        if (x != 0) return x > 0 ? 1 : -1;
    return 0;
}

// The sheared corner of lane l: its x and y in the ray's frame, and its z (unsheared).
struct Corner {
    double x, y, z;
};
inline Corner shear(const TriRay& r, const TriBlock& b, int corner, int l) {
    const double z = double(b.v[3 * corner + r.kz][l]) - r.oz;
    return {(double(b.v[3 * corner + r.kx][l]) - r.ox) - r.sx * z, (double(b.v[3 * corner + r.ky][l]) - r.oy) - r.sy * z, z};
}

}  // namespace

TriRay TriRay::make(const Vec3& o, const Vec3& d) {
    TriRay r;
    r.o = o;
    r.d = d;
    const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    r.kz = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (d[r.kz] < 0) std::swap(r.kx, r.ky);  // keeps the triangles' winding
    r.sx = d[r.kx] / d[r.kz];
    r.sy = d[r.ky] / d[r.kz];
    r.sz = 1.0 / d[r.kz];
    r.ox = o[r.kx], r.oy = o[r.ky], r.oz = o[r.kz];
    return r;
}

double tri_intersect(const TriRay& r, const TriBlock& b, int l) {
    const Corner a = shear(r, b, 0, l), bb = shear(r, b, 1, l), c = shear(r, b, 2, l);
    const double u = c.x * bb.y - c.y * bb.x;
    const double v = a.x * c.y - a.y * c.x;
    const double w = bb.x * a.y - bb.y * a.x;
    int su = (u > 0) - (u < 0), sv = (v > 0) - (v < 0), sw = (w > 0) - (w < 0);
    if (su == 0 || sv == 0 || sw == 0) {
        su = exact_sign(c.x, bb.y, c.y, bb.x);
        sv = exact_sign(a.x, c.y, a.y, c.x);
        sw = exact_sign(bb.x, a.y, bb.y, a.x);
    }
    if ((su < 0 || sv < 0 || sw < 0) && (su > 0 || sv > 0 || sw > 0)) return kNaN;
    const double det = u + v + w;
    if (det == 0) return kNaN;
    const double t = u * (r.sz * a.z) + v * (r.sz * bb.z) + w * (r.sz * c.z);
    return t / det;
}

#if RT_HAVE_AVX2_KERNELS
namespace {
// The ray as the four-lane test takes it, made once a walk (not at every leaf): its
// values in all four lanes, and the byte offsets in a corner's rows of its kx, ky and
// kz coordinates.
struct TriLanes {
    __m256d ox, oy, oz, sx, sy, sz;
    std::size_t kx, ky, kz;
    RT_TARGET_AVX2 explicit TriLanes(const TriRay& r)
        : ox(_mm256_set1_pd(r.ox)), oy(_mm256_set1_pd(r.oy)), oz(_mm256_set1_pd(r.oz)), sx(_mm256_set1_pd(r.sx)),
          sy(_mm256_set1_pd(r.sy)), sz(_mm256_set1_pd(r.sz)), kx(sizeof(float[4]) * std::size_t(r.kx)),
          ky(sizeof(float[4]) * std::size_t(r.ky)), kz(sizeof(float[4]) * std::size_t(r.kz)) {}
};

// tri_intersect() for the four lanes of a block at once, the same operations lane for
// lane: t per lane (NaN for a miss). Lanes with an edge function of exactly zero are
// left to the scalar test (bit `exact`). False, with t not written, when the edge
// functions' signs already rule out each of the first `count` lanes (none exact):
// most blocks a walk meets, which then skip the distances and their division.
[[gnu::always_inline]] RT_TARGET_AVX2 inline bool tri_intersect4(const TriLanes& q, const TriBlock& b,
                                                                  std::uint32_t count, double t[4], unsigned& exact) {
    const __m256d ox = q.ox, oy = q.oy, oz = q.oz, sx = q.sx, sy = q.sy, sz = q.sz;
    __m256d X[3], Y[3], Z[3];
    for (int k = 0; k < 3; ++k) {
        const char* corner = reinterpret_cast<const char*>(b.v[3 * k]);
        auto row = [corner](std::size_t offset) RT_TARGET_AVX2 {
            return _mm256_cvtps_pd(_mm_load_ps(reinterpret_cast<const float*>(corner + offset)));
        };
        const __m256d z = _mm256_sub_pd(row(q.kz), oz);
        X[k] = _mm256_sub_pd(_mm256_sub_pd(row(q.kx), ox), _mm256_mul_pd(sx, z));
        Y[k] = _mm256_sub_pd(_mm256_sub_pd(row(q.ky), oy), _mm256_mul_pd(sy, z));
        Z[k] = z;
    }
    const __m256d u = _mm256_sub_pd(_mm256_mul_pd(X[2], Y[1]), _mm256_mul_pd(Y[2], X[1]));
    const __m256d v = _mm256_sub_pd(_mm256_mul_pd(X[0], Y[2]), _mm256_mul_pd(Y[0], X[2]));
    const __m256d w = _mm256_sub_pd(_mm256_mul_pd(X[1], Y[0]), _mm256_mul_pd(Y[1], X[0]));
    const __m256d zero = _mm256_setzero_pd();
    exact = unsigned(_mm256_movemask_pd(_mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_EQ_OQ),
                                                                  _mm256_cmp_pd(v, zero, _CMP_EQ_OQ)),
                                                     _mm256_cmp_pd(w, zero, _CMP_EQ_OQ))));
    const __m256d neg = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_LT_OQ), _mm256_cmp_pd(v, zero, _CMP_LT_OQ)),
                                     _mm256_cmp_pd(w, zero, _CMP_LT_OQ));
    const __m256d pos = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(u, zero, _CMP_GT_OQ), _mm256_cmp_pd(v, zero, _CMP_GT_OQ)),
                                     _mm256_cmp_pd(w, zero, _CMP_GT_OQ));
    const __m256d mixed = _mm256_and_pd(neg, pos);
    if (((~unsigned(_mm256_movemask_pd(mixed)) | exact) & ((1u << count) - 1)) == 0) return false;
    const __m256d det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    const __m256d tt = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(u, _mm256_mul_pd(sz, Z[0])),
                                                   _mm256_mul_pd(v, _mm256_mul_pd(sz, Z[1]))),
                                     _mm256_mul_pd(w, _mm256_mul_pd(sz, Z[2])));
    // A miss (mixed signs, or det 0: the division then gives inf or NaN) becomes NaN.
    const __m256d miss = _mm256_or_pd(mixed, _mm256_cmp_pd(det, zero, _CMP_EQ_OQ));
    _mm256_storeu_pd(t, _mm256_or_pd(_mm256_div_pd(tt, det), miss));
    return true;
}
}  // namespace
#endif

namespace {

// The leaf tests, from the t of each lane of the leaf's block (NaN for a miss).
// keep_nearest: the nearest; on an exact tie the lower slot, so that the order of the
// leaves (which differs between the 4- and 8-wide trees) cannot matter.
inline void keep_nearest(const double t[4], std::uint32_t first, std::uint32_t count, double tmin, TriHit& hit,
                         bool& found) {
    for (std::uint32_t l = 0; l < count; ++l) {
        const std::uint32_t slot = first + l;
        if (t[l] > tmin && (t[l] < hit.t || (found && t[l] == hit.t && slot < hit.slot))) {
            hit = {t[l], slot};
            found = true;
        }
    }
}
inline bool first_within(const double t[4], std::uint32_t count, double tmin, double tmax, double& found) {
    for (std::uint32_t l = 0; l < count; ++l)
        if (t[l] > tmin && t[l] < tmax) return found = t[l], true;
    return false;
}

// The walks' leaf visitors: Lanes::ts(r, b, count, t) gives the t of the first count
// lanes of a block.
template <class Lanes>
struct NearestLeaf {
    const TriangleAccel& a;
    const TriRay& r;
    double tmin;
    TriHit& hit;
    bool& found;
    double operator()(std::uint32_t first, std::uint32_t count, double) const {
        for (std::uint32_t j = 0; j < count; j += 4) {
            double t[4];
            const std::uint32_t c = std::min(count - j, 4u);
            Lanes::ts(r, a.blocks[(first + j) >> 2], c, t);
            keep_nearest(t, first + j, c, tmin, hit, found);
        }
        return hit.t;
    }
};

template <class Lanes>
struct AnyLeaf {
    const TriangleAccel& a;
    const TriRay& r;
    double tmin, tmax;
    double& found;
    bool operator()(std::uint32_t first, std::uint32_t count) const {
        for (std::uint32_t j = 0; j < count; j += 4) {
            double t[4];
            const std::uint32_t c = std::min(count - j, 4u);
            Lanes::ts(r, a.blocks[(first + j) >> 2], c, t);
            if (first_within(t, c, tmin, tmax, found)) return true;
        }
        return false;
    }
};

struct ScalarLanes {
    static void ts(const TriRay& r, const TriBlock& b, std::uint32_t count, double t[4]) {
        for (std::uint32_t l = 0; l < count; ++l) t[l] = tri_intersect(r, b, int(l));
    }
};

#if RT_HAVE_AVX2_KERNELS
// tri_intersect() kept out of line for the lanes the four-lane test leaves to it (rare),
// so that the flattened walks below stay small.
[[gnu::noinline]] double exact_lane(const TriRay& r, const TriBlock& b, int l) { return tri_intersect(r, b, l); }

// Four lanes at once, the same values as ScalarLanes; compiled with the 8-wide walks
// (the leaf tests then inline into them). False, t not written, when every lane
// misses.
struct Avx2Lanes {
    [[gnu::always_inline]] RT_TARGET_AVX2 static inline bool ts(const TriRay& r, const TriLanes& q, const TriBlock& b,
                                                                 std::uint32_t count, double t[4]) {
        unsigned exact;
        if (!tri_intersect4(q, b, count, t, exact)) return false;
        for (exact &= (1u << count) - 1; exact; exact &= exact - 1) {
            const int l = __builtin_ctz(exact);
            t[l] = exact_lane(r, b, l);
        }
        return true;
    }
};

// The lanes among the first `count` with lo < t and t < hi (below: t <= hi when
// `or_equal`), a bit each; NaN in none.
template <bool or_equal>
[[gnu::always_inline]] RT_TARGET_AVX2 inline unsigned lanes_within(const double t[4], std::uint32_t count, double lo,
                                                                    double hi) {
    const __m256d v = _mm256_loadu_pd(t);
    const __m256d in = _mm256_and_pd(_mm256_cmp_pd(v, _mm256_set1_pd(lo), _CMP_GT_OQ),
                                     _mm256_cmp_pd(v, _mm256_set1_pd(hi), or_equal ? _CMP_LE_OQ : _CMP_LT_OQ));
    return unsigned(_mm256_movemask_pd(in)) & ((1u << count) - 1);
}

// The same visitors compiled with the 8-wide walks, so that the four-lane test
// inlines into them, and their lanes sifted at once: keep_nearest() and
// first_within() then see only the lanes that can matter (t within reach), in order.
struct NearestLeafAvx2 : NearestLeaf<Avx2Lanes> {
    const TriLanes& q;
    RT_TARGET_AVX2 double operator()(std::uint32_t first, std::uint32_t count, double) const {
        for (std::uint32_t j = 0; j < count; j += 4) {
            double t[4];
            const std::uint32_t c = std::min(count - j, 4u);
            if (!Avx2Lanes::ts(r, q, a.blocks[(first + j) >> 2], c, t)) continue;
            // hit.t only shrinks: a lane beyond it now stays beyond it.
            for (unsigned m = lanes_within<true>(t, c, tmin, hit.t); m != 0; m &= m - 1) {
                const std::uint32_t l = std::uint32_t(__builtin_ctz(m));
                keep_nearest(t + l, first + j + l, 1, tmin, hit, found);
            }
        }
        return hit.t;
    }
};
struct AnyLeafAvx2 : AnyLeaf<Avx2Lanes> {
    const TriLanes& q;
    RT_TARGET_AVX2 bool operator()(std::uint32_t first, std::uint32_t count) const {
        for (std::uint32_t j = 0; j < count; j += 4) {
            double t[4];
            const std::uint32_t c = std::min(count - j, 4u);
            if (!Avx2Lanes::ts(r, q, a.blocks[(first + j) >> 2], c, t)) continue;
            if (const unsigned m = lanes_within<false>(t, c, tmin, tmax)) return found = t[__builtin_ctz(m)], true;
        }
        return false;
    }
};

// The 8-wide walks with the leaf visitors inlined (flatten): a call per leaf would
// spill the ray's broadcast registers around it in the walks' hottest loops.
[[gnu::flatten]] RT_TARGET_AVX2 bool nearest_avx2(const TriangleAccel& a, const TriRay& r, double tmin, TriHit& hit) {
    bool found = false;
    const TriLanes q(r);
    a.bvh.traverse_nearest_leaves8(r.o, r.d, hit.t, NearestLeafAvx2{{a, r, tmin, hit, found}, q});
    return found;
}

[[gnu::flatten]] RT_TARGET_AVX2 bool any_avx2(const TriangleAccel& a, const TriRay& r, double tmin, double tmax,
                                              double& found) {
    const TriLanes q(r);
    return a.bvh.occluded_leaves8(r.o, r.d, 1.0, tmax, AnyLeafAvx2{{a, r, tmin, tmax, found}, q});
}

// ---- packets -----------------------------------------------------------------------
// The packet walk of nearest_packet(): a stack of subtrees, each with the rays (a bit
// each) whose box tests let them into it. At an inner node every such ray takes the
// single-ray walk's box test of the eight children (BoxTest: Wide8::enter's float
// operations, lane for lane); a child is pushed with the rays that enter it, nearest
// first by the least entry distance among them. Where the rays share an origin and
// the signs of their directions, a frustum test comes first (Frustum): it bounds every
// ray's entry and exit distances from the least and greatest inverse direction per
// axis, and a child it rules out is ruled out for each ray of the packet.
using Wide8 = Bvh::Wide8;

// Wide8::enter() as vectors: the lanes' entry distances and the lanes entered.
struct BoxTest {
    __m256 t0, in;
};
[[gnu::always_inline]] RT_TARGET_AVX2 inline BoxTest box_test(const BvhNode8& n, const Wide8::Ray& r, float tmax) {
    const __m256 x0 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[0]), r.o[0]), r.inv[0]);
    const __m256 y0 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[1]), r.o[1]), r.inv[1]);
    const __m256 z0 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[2]), r.o[2]), r.inv[2]);
    const __m256 x1 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[3]), r.o[0]), r.inv[0]);
    const __m256 y1 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[4]), r.o[1]), r.inv[1]);
    const __m256 z1 = _mm256_mul_ps(_mm256_sub_ps(Wide8::row(n, r.rows[5]), r.o[2]), r.inv[2]);
    const __m256 t0 = _mm256_max_ps(_mm256_sub_ps(_mm256_max_ps(_mm256_max_ps(x0, y0), z0), r.pad), _mm256_setzero_ps());
    const __m256 t1 = _mm256_min_ps(_mm256_add_ps(_mm256_min_ps(_mm256_min_ps(x1, y1), z1), r.pad), _mm256_set1_ps(tmax));
    return {t0, _mm256_cmp_ps(t0, _mm256_mul_ps(t1, _mm256_set1_ps(1.000001f)), _CMP_LE_OS)};
}

// The packet's frustum: its rays' common origin and row offsets (the same signs), per
// axis the least and greatest inverse direction, the greatest pad. Products are
// monotonic in each factor once rounded, so (b - o) * lo and (b - o) * hi bound every
// ray's (b - o) * inv, and every later step of box_test() keeps such bounds: the lanes
// frustum_test() rules out, box_test() rules out for each ray (with tmax at least its).
struct Frustum {
    __m256 o[3], lo[3], hi[3], pad;
    const std::int32_t* rows;
};
[[gnu::always_inline]] RT_TARGET_AVX2 inline unsigned frustum_test(const BvhNode8& n, const Frustum& f, float tmax) {
    __m256 near = _mm256_setzero_ps(), far = _mm256_set1_ps(INFINITY);
    for (int a = 0; a < 3; ++a) {
        const __m256 bn = _mm256_sub_ps(Wide8::row(n, f.rows[a]), f.o[a]);
        const __m256 bf = _mm256_sub_ps(Wide8::row(n, f.rows[3 + a]), f.o[a]);
        near = _mm256_max_ps(near, _mm256_min_ps(_mm256_mul_ps(bn, f.lo[a]), _mm256_mul_ps(bn, f.hi[a])));
        far = _mm256_min_ps(far, _mm256_max_ps(_mm256_mul_ps(bf, f.lo[a]), _mm256_mul_ps(bf, f.hi[a])));
    }
    const __m256 t0 = _mm256_max_ps(_mm256_sub_ps(near, f.pad), _mm256_setzero_ps());
    const __m256 t1 = _mm256_min_ps(_mm256_add_ps(far, f.pad), _mm256_set1_ps(tmax));
    // (Not "<=" negated: a NaN bound must keep the lane.)
    return ~unsigned(_mm256_movemask_ps(_mm256_cmp_ps(t0, _mm256_mul_ps(t1, _mm256_set1_ps(1.000001f)), _CMP_GT_OQ))) &
           0xffu;
}

// The packet's frustum `f`, if its rays share an origin (bit for bit) and their signs.
[[gnu::always_inline]] RT_TARGET_AVX2 inline bool packet_frustum(const Wide8::Ray* br, const TriRay* rays, int n,
                                                                 Frustum& f) {
    bool frustum = n > 0;
    for (int i = 1; i < n && frustum; ++i)
        frustum = br[i].rows == br[0].rows && std::memcmp(&rays[i].o, &rays[0].o, sizeof(Vec3)) == 0;
    if (frustum) {
        f.rows = br[0].rows;
        f.pad = br[0].pad;
        for (int k = 0; k < 3; ++k) f.o[k] = br[0].o[k], f.lo[k] = f.hi[k] = br[0].inv[k];
        for (int i = 1; i < n; ++i) {
            f.pad = _mm256_max_ps(f.pad, br[i].pad);
            for (int k = 0; k < 3; ++k) f.lo[k] = _mm256_min_ps(f.lo[k], br[i].inv[k]), f.hi[k] = _mm256_max_ps(f.hi[k], br[i].inv[k]);
        }
    }
    return frustum;
}

// The greatest of 32 floats (32-byte aligned).
[[gnu::always_inline]] RT_TARGET_AVX2 inline float greatest32(const float* v) {
    __m256 mx = _mm256_max_ps(_mm256_load_ps(v), _mm256_load_ps(v + 8));
    mx = _mm256_max_ps(mx, _mm256_max_ps(_mm256_load_ps(v + 16), _mm256_load_ps(v + 24)));
    const __m128 h = _mm_max_ps(_mm256_castps256_ps128(mx), _mm256_extractf128_ps(mx, 1));
    const __m128 h2 = _mm_max_ps(h, _mm_movehl_ps(h, h));
    return _mm_cvtss_f32(_mm_max_ss(h2, _mm_movehdup_ps(h2)));
}

// Per child of `nd` among those `reach` allows, the rays of `rays` (a bit each) whose
// box tests enter it and their least entry distance.
[[gnu::always_inline]] RT_TARGET_AVX2 inline void children_entered(const BvhNode8& nd, const Wide8::Ray* br,
                                                                   const float* ftmax, std::uint32_t rays,
                                                                   unsigned reach, std::uint32_t* rays_in,
                                                                   float* t_in) {
    const __m256i one = _mm256_set1_epi32(1);
    const __m256 allowed = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
        _mm256_and_si256(_mm256_set1_epi32(int(reach)), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
        _mm256_setzero_si256()));
    __m256i who = _mm256_setzero_si256();  // per child, the rays entering it
    __m256 near = _mm256_set1_ps(INFINITY);  // per child, their least entry distance
    for (std::uint32_t m = rays; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const BoxTest b = box_test(nd, br[i], ftmax[i]);
        const __m256 in = _mm256_and_ps(b.in, allowed);
        who = _mm256_or_si256(who, _mm256_and_si256(_mm256_castps_si256(in), _mm256_slli_epi32(one, i)));
        near = _mm256_min_ps(near, _mm256_blendv_ps(_mm256_set1_ps(INFINITY), b.t0, in));
    }
    _mm256_store_si256(reinterpret_cast<__m256i*>(rays_in), who);
    _mm256_store_ps(t_in, near);
}

// A subtree of the nearest-hit packet walk, the rays that enter it and their least
// entry distance.
struct NearEntry {
    std::uint32_t ref, rays;
    float t;
};
constexpr int kNearStack = 1024;

// The children some ray enters pushed farthest first, so that the nearest comes up
// next; the rays of those the stack has no room for go to `overflow`.
[[gnu::always_inline]] RT_TARGET_AVX2 inline void push_nearest_last(const BvhNode8& nd, const std::uint32_t* rays_in,
                                                                    const float* t_in, NearEntry* stack, int& sp,
                                                                    std::uint32_t& overflow) {
    NearEntry kids[8];
    int k = 0;
    for (int c = 0; c < 8; ++c) {
        if (!rays_in[c]) continue;
        NearEntry x{nd.child[c], rays_in[c], t_in[c]};
        int j = k++;
        for (; j > 0 && kids[j - 1].t < x.t; --j) kids[j] = kids[j - 1];
        kids[j] = x;
    }
    for (int j = 0; j < k; ++j) {
        if (sp < kNearStack) stack[sp++] = kids[j];
        else overflow |= kids[j].rays;
    }
}

[[gnu::flatten]] RT_TARGET_AVX2 void nearest_packet_avx2(const TriangleAccel& a, const TriRay* rays, int n, double tmin,
                                                          double tmax, TriHit* hits, bool* found) {
    constexpr int P = TriangleAccel::kPacket;
    Wide8::Ray br[P];
    static_assert(P <= 32, "a packet's rays are the bits of a 32-bit mask");
    alignas(32) float ftmax[32];
    std::fill(ftmax + n, ftmax + 32, -INFINITY);  // (no ray: never the greatest)
    for (int i = 0; i < n; ++i) {
        br[i] = Wide8::ray(rays[i].o, rays[i].d, 1.0);
        hits[i] = {tmax, 0};
        found[i] = false;
        ftmax[i] = Bvh::widen(tmax);
    }
    Frustum f;
    const bool frustum = packet_frustum(br, rays, n, f);
    float packet_tmax = Bvh::widen(tmax);  // the greatest ftmax
    const BvhNode8* flat = a.bvh.nodes8.flat();
    BvhNode8* const* table = a.bvh.nodes8.table();
    auto node = [&](std::uint32_t ref) -> const BvhNode8& {
        return flat ? flat[ref] : table[ref >> Chunked<BvhNode8>::kShift][ref & Chunked<BvhNode8>::kMask];
    };
    NearEntry stack[kNearStack];
    int sp = 0;
    stack[sp++] = {0, n == 32 ? ~0u : (1u << n) - 1, 0.f};
    std::uint32_t overflow = 0;  // rays left to the single-ray walk (a stack too shallow)
    while (sp > 0) {
        const NearEntry e = stack[--sp];
        if (e.t > packet_tmax) continue;
        if (BvhNode::is_leaf(e.ref)) {
            const std::uint32_t first = BvhNode::leaf_first(e.ref), count = BvhNode::leaf_count(e.ref);
            for (std::uint32_t m = e.rays; m; m &= m - 1) {
                const int i = __builtin_ctz(m);
                if (e.t > ftmax[i]) continue;
                const TriLanes q(rays[i]);
                bool fi = found[i];
                const double before = hits[i].t;
                NearestLeafAvx2{{a, rays[i], tmin, hits[i], fi}, q}(first, count, 0.0);
                found[i] = fi;
                if (hits[i].t != before) {
                    ftmax[i] = Bvh::widen(hits[i].t);
                    packet_tmax = greatest32(ftmax);
                }
            }
            continue;
        }
        const BvhNode8& nd = node(e.ref);
        const unsigned reach = frustum ? frustum_test(nd, f, packet_tmax) : 0xffu;
        if (reach == 0) continue;
        alignas(32) std::uint32_t rays_in[8];
        alignas(32) float t_in[8];
        children_entered(nd, br, ftmax, e.rays, reach, rays_in, t_in);
        push_nearest_last(nd, rays_in, t_in, stack, sp, overflow);
    }
    // The rays a subtree was left out for: walked alone, from the nearest hit found so
    // far (a leaf seen twice changes nothing: its nearest is kept, ties to the lower slot).
    for (std::uint32_t m = overflow; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const TriLanes q(rays[i]);
        bool fi = found[i];
        a.bvh.traverse_nearest_leaves8(rays[i].o, rays[i].d, hits[i].t, NearestLeafAvx2{{a, rays[i], tmin, hits[i], fi}, q});
        found[i] = fi;
    }
}

// The any-hit packet's frustum: its rays' row offsets (the same signs) and per axis the
// least and greatest origin and inverse direction, the greatest pad. Sums and products
// rounded are monotonic in each operand, so these bound every ray's slab distances.
struct SpreadFrustum {
    __m256 olo[3], ohi[3], lo[3], hi[3], pad;
    const std::int32_t* rows;
};
// `f`, if the packet's rays share the signs of their directions.
[[gnu::always_inline]] RT_TARGET_AVX2 inline bool spread_frustum(const Wide8::Ray* br, int n, SpreadFrustum& f) {
    bool frustum = n > 0;
    for (int i = 1; i < n && frustum; ++i) frustum = br[i].rows == br[0].rows;
    f.pad = _mm256_setzero_ps();
    if (frustum) {
        f.pad = br[0].pad;
        for (int k = 0; k < 3; ++k) f.olo[k] = f.ohi[k] = br[0].o[k], f.lo[k] = f.hi[k] = br[0].inv[k];
        for (int i = 1; i < n; ++i) {
            f.pad = _mm256_max_ps(f.pad, br[i].pad);
            for (int k = 0; k < 3; ++k) {
                f.olo[k] = _mm256_min_ps(f.olo[k], br[i].o[k]), f.ohi[k] = _mm256_max_ps(f.ohi[k], br[i].o[k]);
                f.lo[k] = _mm256_min_ps(f.lo[k], br[i].inv[k]), f.hi[k] = _mm256_max_ps(f.hi[k], br[i].inv[k]);
            }
        }
    }
    f.rows = br[0].rows;
    return frustum;
}
// The children of `nd` some ray of the packet may enter within `tmax` (a bit each).
[[gnu::always_inline]] RT_TARGET_AVX2 inline unsigned spread_frustum_test(const BvhNode8& nd, const SpreadFrustum& f,
                                                                          float tmax) {
    __m256 near = _mm256_setzero_ps(), far = _mm256_set1_ps(INFINITY);
    for (int k = 0; k < 3; ++k) {
        const __m256 bn = Wide8::row(nd, f.rows[k]), bf = Wide8::row(nd, f.rows[3 + k]);
        const __m256 n0 = _mm256_sub_ps(bn, f.ohi[k]), n1 = _mm256_sub_ps(bn, f.olo[k]);
        const __m256 f0 = _mm256_sub_ps(bf, f.ohi[k]), f1 = _mm256_sub_ps(bf, f.olo[k]);
        near = _mm256_max_ps(near, _mm256_min_ps(_mm256_min_ps(_mm256_mul_ps(n0, f.lo[k]), _mm256_mul_ps(n0, f.hi[k])),
                                                 _mm256_min_ps(_mm256_mul_ps(n1, f.lo[k]), _mm256_mul_ps(n1, f.hi[k]))));
        far = _mm256_min_ps(far, _mm256_max_ps(_mm256_max_ps(_mm256_mul_ps(f0, f.lo[k]), _mm256_mul_ps(f0, f.hi[k])),
                                               _mm256_max_ps(_mm256_mul_ps(f1, f.lo[k]), _mm256_mul_ps(f1, f.hi[k]))));
    }
    const __m256 t0 = _mm256_max_ps(_mm256_sub_ps(near, f.pad), _mm256_setzero_ps());
    const __m256 t1 = _mm256_min_ps(_mm256_add_ps(far, f.pad), _mm256_set1_ps(tmax));
    return ~unsigned(_mm256_movemask_ps(_mm256_cmp_ps(t0, _mm256_mul_ps(t1, _mm256_set1_ps(1.000001f)), _CMP_GT_OQ))) & 0xffu;
}

// any() for n rays at once: a stack of subtrees with the rays still unblocked that
// enter them (per-ray box tests as in the single-ray any-hit walk, each ray with its
// own tmax), and, where the rays share the signs of their directions, a frustum test
// over the packet first: bounds of every ray's slab distances from the least and
// greatest origin and inverse direction per axis (rounded sums and products are
// monotonic in each operand). Whether a ray is blocked does not depend on the order of
// the leaves; the t of the hit found may.
[[gnu::flatten]] RT_TARGET_AVX2 void any_packet_avx2(const TriangleAccel& a, const TriRay* rays, int n, double tmin,
                                                      const double* tmax, bool* hit, double* t) {
    constexpr int P = TriangleAccel::kPacket;
    Wide8::Ray br[P];
    float ft[P];
    float packet_tmax = 0;
    for (int i = 0; i < n; ++i) {
        br[i] = Wide8::ray(rays[i].o, rays[i].d, 1.0);
        ft[i] = Bvh::widen(tmax[i]);
        packet_tmax = std::max(packet_tmax, ft[i]);
        hit[i] = false;
    }
    SpreadFrustum f;
    const bool frustum = spread_frustum(br, n, f);
    const BvhNode8* flat = a.bvh.nodes8.flat();
    BvhNode8* const* table = a.bvh.nodes8.table();
    auto node = [&](std::uint32_t ref) -> const BvhNode8& {
        return flat ? flat[ref] : table[ref >> Chunked<BvhNode8>::kShift][ref & Chunked<BvhNode8>::kMask];
    };
    struct Entry {
        std::uint32_t ref, rays;
    };
    constexpr int kStack = 1024;
    Entry stack[kStack];
    int sp = 0;
    std::uint32_t open = n == 32 ? ~0u : (1u << n) - 1;  // the rays not yet blocked
    stack[sp++] = {0, open};
    std::uint32_t overflow = 0;
    const __m256i one = _mm256_set1_epi32(1);
    while (sp > 0 && open) {
        const Entry e = stack[--sp];
        const std::uint32_t live = e.rays & open;
        if (!live) continue;
        const BvhNode8& nd = node(e.ref);
        const unsigned reach = frustum ? spread_frustum_test(nd, f, packet_tmax) : 0xffu;
        if (!reach) continue;
        unsigned leaves = 0;
        for (int c = 0; c < 8; ++c) leaves |= unsigned(BvhNode::is_leaf(nd.child[c])) << c;
        const __m256 inner = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
            _mm256_and_si256(_mm256_set1_epi32(int(reach & ~leaves)), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
            _mm256_setzero_si256()));
        __m256i who = _mm256_setzero_si256();
        for (std::uint32_t m = live; m; m &= m - 1) {
            const int i = __builtin_ctz(m);
            const BoxTest b = box_test(nd, br[i], ft[i]);
            who = _mm256_or_si256(who, _mm256_and_si256(_mm256_castps_si256(_mm256_and_ps(b.in, inner)), _mm256_slli_epi32(one, i)));
            for (unsigned lm = unsigned(_mm256_movemask_ps(b.in)) & reach & leaves; lm; lm &= lm - 1) {
                const std::uint32_t ref = nd.child[__builtin_ctz(lm)];
                const TriLanes q(rays[i]);
                if (AnyLeafAvx2{{a, rays[i], tmin, tmax[i], t[i]}, q}(BvhNode::leaf_first(ref), BvhNode::leaf_count(ref))) {
                    hit[i] = true;
                    open &= ~(1u << i);
                    break;
                }
            }
        }
        alignas(32) std::uint32_t rays_in[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(rays_in), who);
        for (int c = 0; c < 8; ++c) {
            if (!(rays_in[c] & open)) continue;
            if (sp < kStack) stack[sp++] = {nd.child[c], rays_in[c]};
            else overflow |= rays_in[c];
        }
    }
    for (std::uint32_t m = overflow & open; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        const TriLanes q(rays[i]);
        hit[i] = a.bvh.occluded_leaves8(rays[i].o, rays[i].d, 1.0, tmax[i], AnyLeafAvx2{{a, rays[i], tmin, tmax[i], t[i]}, q});
    }
}
#endif

}  // namespace

namespace {
// What prepare() keeps for one accel on this thread: the rays (their common origin and
// each direction), the bounds asked for and the answers; `next` is where the rays
// not yet asked for begin. Plain data, so that the thread's copy needs no set-up.
struct Prepared {
    const TriangleAccel* accel;
    int n, next;
    double tmin, tmax;
    Vec3 o;
    Vec3 d[TriangleAccel::kPacket];
    TriHit hit[TriangleAccel::kPacket];
    bool found[TriangleAccel::kPacket];
};
thread_local Prepared prepared[TriangleAccel::kPrepared];
thread_local int prepared_count;

bool same(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }
}  // namespace

void TriangleAccel::nearest_packet(const TriRay* rays, int n, double tmin, double tmax, TriHit* hits,
                                   bool* found) const {
#if RT_HAVE_AVX2_KERNELS
    if (n > 1 && avx2_active() && !bvh.nodes8.empty()) return nearest_packet_avx2(*this, rays, n, tmin, tmax, hits, found);
#endif
    for (int i = 0; i < n; ++i) found[i] = nearest(rays[i], tmin, tmax, hits[i]);
}

bool TriangleAccel::prepare(const TriRay* rays, int n, double tmin, double tmax, TriHit* hits, bool* found) const {
    if (n <= 0 || n > kPacket || prepared_count >= kPrepared) return false;
    for (int i = 1; i < n; ++i)
        if (!same(rays[i].o, rays[0].o)) return false;
    Prepared& p = prepared[prepared_count];
    p.accel = nullptr;  // (not yet: nearest_packet() below must walk)
    nearest_packet(rays, n, tmin, tmax, p.hit, p.found);
    if (hits) std::copy(p.hit, p.hit + n, hits), std::copy(p.found, p.found + n, found);
    p.n = n, p.next = 0, p.tmin = tmin, p.tmax = tmax, p.o = rays[0].o;
    for (int i = 0; i < n; ++i) p.d[i] = rays[i].d;
    p.accel = this;
    ++prepared_count;
    return true;
}

// What prepare_any() keeps: per ray its origin, direction and tmax, and the answer.
struct PreparedAny {
    const TriangleAccel* accel;
    int n, next;
    double tmin;
    Vec3 o[TriangleAccel::kPacket], d[TriangleAccel::kPacket];
    double tmax[TriangleAccel::kPacket], t[TriangleAccel::kPacket];
    bool hit[TriangleAccel::kPacket];
};
thread_local PreparedAny prepared_any[TriangleAccel::kPreparedAny];
thread_local int prepared_any_count;

void TriangleAccel::any_packet(const TriRay* rays, int n, double tmin, const double* tmax, bool* hit,
                               double* t) const {
#if RT_HAVE_AVX2_KERNELS
    if (n > 1 && avx2_active() && !bvh.nodes8.empty()) return any_packet_avx2(*this, rays, n, tmin, tmax, hit, t);
#endif
    for (int i = 0; i < n; ++i) hit[i] = any(rays[i], tmin, tmax[i], t[i]);
}

void TriangleAccel::prepare_any(const TriRay* rays, int n, double tmin, const double* tmax) const {
    if (n <= 0 || n > kPacket || prepared_any_count >= kPreparedAny) return;
    PreparedAny& p = prepared_any[prepared_any_count];
    p.accel = nullptr;  // (not yet: any_packet() below must walk)
    any_packet(rays, n, tmin, tmax, p.hit, p.t);
    p.n = n, p.next = 0, p.tmin = tmin;
    for (int i = 0; i < n; ++i) p.o[i] = rays[i].o, p.d[i] = rays[i].d, p.tmax[i] = tmax[i];
    p.accel = this;
    ++prepared_any_count;
}

void TriangleAccel::forget_prepared() {
    for (int k = 0; k < prepared_count; ++k) prepared[k].accel = nullptr;
    prepared_count = 0;
    for (int k = 0; k < prepared_any_count; ++k) prepared_any[k].accel = nullptr;
    prepared_any_count = 0;
}

bool TriangleAccel::nearest(const TriRay& r, double tmin, double tmax, TriHit& hit) const {
    for (int k = 0; k < prepared_count; ++k) {
        Prepared& p = prepared[k];
        if (p.accel != this || !same(r.o, p.o) || tmin != p.tmin || tmax != p.tmax) continue;
        for (int i = p.next; i < p.n; ++i)
            if (same(r.d, p.d[i])) {
                p.next = i + 1;
                hit = p.hit[i];
                return p.found[i];
            }
    }
    hit = {tmax, 0};
#if RT_HAVE_AVX2_KERNELS
    if (avx2_active() && !bvh.nodes8.empty()) return nearest_avx2(*this, r, tmin, hit);
#endif
    bool found = false;
    bvh.traverse_nearest_leaves(r.o, r.d, tmax, NearestLeaf<ScalarLanes>{*this, r, tmin, hit, found});
    return found;
}

bool TriangleAccel::any(const TriRay& r, double tmin, double tmax, double& found) const {
    for (int k = 0; k < prepared_any_count; ++k) {
        PreparedAny& p = prepared_any[k];
        if (p.accel != this || tmin != p.tmin) continue;
        for (int i = p.next; i < p.n; ++i)
            if (r.o.x == p.o[i].x && same(r.o, p.o[i]) && same(r.d, p.d[i]) && tmax == p.tmax[i]) {
                p.next = i + 1;
                if (p.hit[i]) found = p.t[i];
                return p.hit[i];
            }
    }
#if RT_HAVE_AVX2_KERNELS
    if (avx2_active() && !bvh.nodes8.empty()) return any_avx2(*this, r, tmin, tmax, found);
#endif
    return bvh.occluded_leaves(r.o, r.d, 1.0, tmax, AnyLeaf<ScalarLanes>{*this, r, tmin, tmax, found});
}

void TriangleAccel::corners(std::uint32_t slot, Vec3 c[3]) const {
    const TriBlock& b = blocks[slot >> 2];
    const std::uint32_t l = slot & 3;
    for (int k = 0; k < 3; ++k) c[k] = {b.v[3 * k][l], b.v[3 * k + 1][l], b.v[3 * k + 2][l]};
}

std::size_t TriangleAccel::memory_bytes() const {
    return bvh.memory_bytes() + blocks.capacity() * sizeof(TriBlock) + ids.capacity() * 4;
}

// ---- instances ---------------------------------------------------------------------
namespace {
// cos and sin of an angle in degrees, exact at multiples of 90.
void cos_sin(double degrees, double& c, double& s) {
    const double r = std::fmod(degrees, 360.0);
    if (r == std::floor(r) && std::fmod(r, 90.0) == 0) {
        const int q = int(r / 90) & 3;  // fmod keeps the sign: -90 is q 3
        static constexpr double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
        c = cs[q][0], s = cs[q][1];
        return;
    }
    const double a = r * (3.14159265358979323846 / 180.0);
    c = std::cos(a), s = std::sin(a);
}
}  // namespace

MeshInstance compose(const MeshInstance& a, const MeshInstance& b) {
    MeshInstance out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            out.l[i][j] = a.l[i][0] * b.l[0][j] + a.l[i][1] * b.l[1][j] + a.l[i][2] * b.l[2][j];
            out.m[i][j] = b.m[i][0] * a.m[0][j] + b.m[i][1] * a.m[1][j] + b.m[i][2] * a.m[2][j];
        }
    out.position = a.point_to_world(b.position);
    return out;
}

MeshInstance MeshInstance::make(const Vec3& position, const Vec3& scale, const Vec3& rotation) {
    double cx, sx, cy, sy, cz, sz;
    cos_sin(rotation.x, cx, sx);
    cos_sin(rotation.y, cy, sy);
    cos_sin(rotation.z, cz, sz);
    const double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
    const double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    const double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
    auto mul = [](const double a[3][3], const double b[3][3], double out[3][3]) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    };
    double zy[3][3], r[3][3];
    mul(rz, ry, zy);
    mul(zy, rx, r);
    MeshInstance in;
    in.position = position;
    const double s[3] = {scale.x, scale.y, scale.z};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            in.l[i][j] = r[i][j] * s[j];
            in.m[i][j] = r[j][i] / s[i];  // (R S)^-1 = S^-1 R^T
        }
    return in;
}

Aabb MeshInstance::world_bounds(const Aabb& b) const {
    Aabb out;
    if (b.empty()) return out;
    for (int k = 0; k < 8; ++k)
        out.grow(point_to_world({k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z}));
    double m = 0;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(out.lo[a]), std::fabs(out.hi[a])});
    const Vec3 pad = Vec3{1, 1, 1} * (m * 1e-9 + 1e-300);
    out.lo -= pad;
    out.hi += pad;
    return out;
}

}  // namespace rt
