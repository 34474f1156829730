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
#endif

}  // namespace

bool TriangleAccel::nearest(const TriRay& r, double tmin, double tmax, TriHit& hit) const {
    hit = {tmax, 0};
#if RT_HAVE_AVX2_KERNELS
    if (avx2_active() && !bvh.nodes8.empty()) return nearest_avx2(*this, r, tmin, hit);
#endif
    bool found = false;
    bvh.traverse_nearest_leaves(r.o, r.d, tmax, NearestLeaf<ScalarLanes>{*this, r, tmin, hit, found});
    return found;
}

bool TriangleAccel::any(const TriRay& r, double tmin, double tmax, double& found) const {
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
