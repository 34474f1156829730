// Triangles for tracing (see triangles.h): the BVH build over float boxes, the
// watertight test in double precision (scalar, and four lanes at once on the AVX2
// path with the same operations lane for lane, so the same bits), and the walks.
//
// Watertightness: the edge function of an edge shared by two triangles is computed
// from the same two sheared corners in both, so it comes out as the other's exact
// negation, and a zero counts as inside: a ray through a shared edge or corner hits
// one of the triangles or both, never neither. Where an edge function is exactly
// zero its sign is found exactly (the products' rounding errors recovered), as the
// paper does with a second, wider evaluation.
#include "triangles.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <stdexcept>
#include <thread>

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
// tri_intersect() for the four lanes of a block at once, the same operations lane for
// lane: t per lane (NaN for a miss). Lanes with an edge function of exactly zero are
// left to the scalar test (bit `exact`).
RT_TARGET_AVX2 void tri_intersect4(const TriRay& r, const TriBlock& b, double t[4], unsigned& exact) {
    const __m256d ox = _mm256_set1_pd(r.ox), oy = _mm256_set1_pd(r.oy), oz = _mm256_set1_pd(r.oz);
    const __m256d sx = _mm256_set1_pd(r.sx), sy = _mm256_set1_pd(r.sy), sz = _mm256_set1_pd(r.sz);
    __m256d X[3], Y[3], Z[3];
    for (int k = 0; k < 3; ++k) {
        const __m256d z = _mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(b.v[3 * k + r.kz])), oz);
        X[k] = _mm256_sub_pd(_mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(b.v[3 * k + r.kx])), ox), _mm256_mul_pd(sx, z));
        Y[k] = _mm256_sub_pd(_mm256_sub_pd(_mm256_cvtps_pd(_mm_load_ps(b.v[3 * k + r.ky])), oy), _mm256_mul_pd(sy, z));
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
    const __m256d det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    const __m256d tt = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(u, _mm256_mul_pd(sz, Z[0])),
                                                   _mm256_mul_pd(v, _mm256_mul_pd(sz, Z[1]))),
                                     _mm256_mul_pd(w, _mm256_mul_pd(sz, Z[2])));
    // A miss (mixed signs, or det 0: the division then gives inf or NaN) becomes NaN.
    const __m256d miss = _mm256_or_pd(_mm256_and_pd(neg, pos), _mm256_cmp_pd(det, zero, _CMP_EQ_OQ));
    _mm256_storeu_pd(t, _mm256_or_pd(_mm256_div_pd(tt, det), miss));
}
}  // namespace
#endif

namespace {

// The t of each lane of a leaf's block (count lanes), NaN for a miss: four at once
// where AVX2 is active, the same values either way.
inline void leaf_ts(const TriRay& r, const TriBlock& b, std::uint32_t count, double t[4]) {
#if RT_HAVE_AVX2_KERNELS
    if (avx2_active()) {
        unsigned exact;
        tri_intersect4(r, b, t, exact);
        for (exact &= (1u << count) - 1; exact; exact &= exact - 1) {
            const int l = __builtin_ctz(exact);
            t[l] = tri_intersect(r, b, l);
        }
        return;
    }
#endif
    for (std::uint32_t l = 0; l < count; ++l) t[l] = tri_intersect(r, b, int(l));
}

}  // namespace

bool TriangleAccel::nearest(const TriRay& r, double tmin, double tmax, TriHit& hit) const {
    bool found = false;
    hit = {tmax, 0};
    bvh.traverse_nearest_leaves(r.o, r.d, tmax, [&](std::uint32_t first, std::uint32_t count, double) -> double {
        double t[4];
        leaf_ts(r, blocks[first >> 2], count, t);
        for (std::uint32_t l = 0; l < count; ++l) {
            // The nearest; on an exact tie the lower slot, so that the order of the
            // leaves (which differs between the 4- and 8-wide trees) cannot matter.
            const std::uint32_t slot = first + l;
            if (t[l] > tmin && (t[l] < hit.t || (found && t[l] == hit.t && slot < hit.slot))) {
                hit = {t[l], slot};
                found = true;
            }
        }
        return hit.t;
    });
    return found;
}

bool TriangleAccel::any(const TriRay& r, double tmin, double tmax, double& found) const {
    return bvh.occluded_leaves(r.o, r.d, 1.0, tmax, [&](std::uint32_t first, std::uint32_t count) {
        double t[4];
        leaf_ts(r, blocks[first >> 2], count, t);
        for (std::uint32_t l = 0; l < count; ++l)
            if (t[l] > tmin && t[l] < tmax) return found = t[l], true;
        return false;
    });
}

void TriangleAccel::corners(std::uint32_t slot, Vec3 c[3]) const {
    const TriBlock& b = blocks[slot >> 2];
    const std::uint32_t l = slot & 3;
    for (int k = 0; k < 3; ++k) c[k] = {b.v[3 * k][l], b.v[3 * k + 1][l], b.v[3 * k + 2][l]};
}

std::size_t TriangleAccel::memory_bytes() const {
    return bvh.memory_bytes() + blocks.capacity() * sizeof(TriBlock) + ids.capacity() * 4;
}

// ---- the build ---------------------------------------------------------------------
namespace {

constexpr int kBins = 16;
constexpr std::uint32_t kLeaf = 4;  // triangles in a leaf: one block
constexpr int kMaxSahDepth = 64;
constexpr std::uint32_t kParallelItems = 16384;

// A triangle as the build moves it: its box and index (28 bytes, against 80 for the
// objects' build: a 10M-triangle model must build within a few hundred MB). Centres
// are taken as lo + hi (twice the centre) where they are needed.
struct TRec {
    float lo[3], hi[3];
    std::uint32_t id;
    float c(int a) const { return lo[a] + hi[a]; }
};

struct FBox {
    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    void grow(const float l[3], const float h[3]) {
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], l[a]), hi[a] = std::max(hi[a], h[a]);
    }
    void grow(const FBox& b) { grow(b.lo, b.hi); }
    void grow_point(const float p[3]) { grow(p, p); }
    double area() const {
        if (lo[0] > hi[0]) return 0;
        const double x = double(hi[0]) - lo[0], y = double(hi[1]) - lo[1], z = double(hi[2]) - lo[2];
        return x * y + y * z + z * x;
    }
};

struct TriBuilder {
    TRec* recs;
    std::atomic<int>& spare;

    bool take_thread() {
        int n = spare.load(std::memory_order_relaxed);
        while (n > 0)
            if (spare.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) return true;
        return false;
    }

    static void set_box(BvhBinNode& n, const FBox& b) {
        Aabb a;
        a.lo = {b.lo[0], b.lo[1], b.lo[2]};
        a.hi = {b.hi[0], b.hi[1], b.hi[2]};
        to_float_box(a, n.b);
    }

    // The cheapest binned SAH split: axis and last bin on the left; false if none.
    bool sah(std::uint32_t begin, std::uint32_t end, const FBox& cb, int& axis, int& bin, float scale[3]) {
        FBox box[3][kBins];
        std::uint32_t count[3][kBins] = {};
        for (int a = 0; a < 3; ++a) {
            const float ext = cb.hi[a] - cb.lo[a];
            scale[a] = ext > 0 ? kBins / ext : 0.0f;
        }
        for (std::uint32_t i = begin; i < end; ++i) {
            const TRec& r = recs[i];
            for (int a = 0; a < 3; ++a) {
                const int k = std::min(kBins - 1, std::max(0, int((r.c(a) - cb.lo[a]) * scale[a])));
                box[a][k].grow(r.lo, r.hi);
                ++count[a][k];
            }
        }
        double best = DBL_MAX;
        axis = -1;
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0) continue;
            double left_area[kBins];
            std::uint32_t left_n[kBins];
            FBox acc;
            std::uint32_t n = 0;
            for (int k = 0; k < kBins; ++k) {
                acc.grow(box[a][k]);
                n += count[a][k];
                left_area[k] = acc.area();
                left_n[k] = n;
            }
            acc = FBox();
            n = 0;
            for (int k = kBins - 1; k > 0; --k) {
                acc.grow(box[a][k]);
                n += count[a][k];
                if (left_n[k - 1] == 0 || n == 0) continue;
                const double cost = left_area[k - 1] * left_n[k - 1] + acc.area() * n;
                if (cost < best) best = cost, axis = a, bin = k - 1;
            }
        }
        return axis >= 0;
    }

    // The node's items split in two: by the SAH where it separates them, else at the
    // median of the widest centre axis (or simply in half when all centres coincide).
    std::uint32_t split(std::uint32_t begin, std::uint32_t end, const FBox& cb, int depth) {
        int axis = -1, bin = 0;
        float scale[3];
        if (depth < kMaxSahDepth && sah(begin, end, cb, axis, bin, scale)) {
            const float lo = cb.lo[axis], s = scale[axis];
            TRec* mid = std::partition(recs + begin, recs + end, [&](const TRec& r) {
                return std::min(kBins - 1, std::max(0, int((r.c(axis) - lo) * s))) <= bin;
            });
            const std::uint32_t m = std::uint32_t(mid - recs);
            if (m != begin && m != end) return m;
        }
        axis = 0;
        for (int a = 1; a < 3; ++a)
            if (cb.hi[a] - cb.lo[a] > cb.hi[axis] - cb.lo[axis]) axis = a;
        const std::uint32_t m = begin + (end - begin) / 2;
        if (cb.hi[axis] > cb.lo[axis])
            std::nth_element(recs + begin, recs + m, recs + end,
                             [axis](const TRec& a, const TRec& b) { return a.c(axis) < b.c(axis); });
        return m;
    }

    void bounds(std::uint32_t begin, std::uint32_t end, FBox& b, FBox& cb) const {
        for (std::uint32_t i = begin; i < end; ++i) {
            const TRec& r = recs[i];
            b.grow(r.lo, r.hi);
            const float c[3] = {r.c(0), r.c(1), r.c(2)};
            cb.grow_point(c);
        }
    }

    // The subtree over [begin, end) with its root at out[node], in preorder (see
    // BvhBinNode); the same tree whichever subtrees other threads build.
    void build(std::vector<BvhBinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end, int depth) {
        FBox b, cb;
        bounds(begin, end, b, cb);
        set_box(out[node], b);
        if (end - begin <= kLeaf) {
            out[node].first = begin;
            out[node].count = end - begin;
            return;
        }
        const std::uint32_t mid = split(begin, end, cb, depth);
        out[node].count = 0;
        if (end - begin >= kParallelItems && take_thread()) {
            std::vector<BvhBinNode> right(1);
            std::exception_ptr failed;
            std::thread t([&] {
                try {
                    build(right, 0, mid, end, depth + 1);
                } catch (...) {
                    failed = std::current_exception();
                }
                spare.fetch_add(1, std::memory_order_relaxed);
            });
            try {
                const std::uint32_t left = std::uint32_t(out.size());
                out.emplace_back();
                build(out, left, begin, mid, depth + 1);
            } catch (...) {
                t.join();
                throw;
            }
            t.join();
            if (failed) std::rethrow_exception(failed);
            const std::uint32_t offset = std::uint32_t(out.size());
            out[node].first = offset;
            out.insert(out.end(), right.begin(), right.end());
            for (std::size_t i = offset; i < out.size(); ++i)
                if (out[i].count == 0) out[i].first += offset;
            return;
        }
        const std::uint32_t left = std::uint32_t(out.size());
        out.emplace_back();
        build(out, left, begin, mid, depth + 1);
        const std::uint32_t right = std::uint32_t(out.size());
        out.emplace_back();
        build(out, right, mid, end, depth + 1);
        out[node].first = right;
    }
};

}  // namespace

TriangleAccel TriangleAccel::build(const MeshData& m, int threads) {
    TriangleAccel acc;
    const std::size_t n = m.triangle_count();
    if (n == 0) return acc;
    if (n > ModelLimits::max_triangles) throw std::length_error("too many triangles for the BVH");
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    std::unique_ptr<TRec, void (*)(void*)> mem(static_cast<TRec*>(std::malloc(n * sizeof(TRec))), std::free);
    if (!mem) throw std::bad_alloc();
    TRec* recs = mem.get();
    const float* p = m.positions.data();
    for (std::size_t t = 0; t < n; ++t) {
        const std::uint32_t* v = &m.triangles[3 * t];
        TRec& r = recs[t];
        for (int a = 0; a < 3; ++a) {
            const float x = p[3 * v[0] + a], y = p[3 * v[1] + a], z = p[3 * v[2] + a];
            r.lo[a] = std::min({x, y, z});
            r.hi[a] = std::max({x, y, z});
        }
        r.id = std::uint32_t(t);
    }
    std::vector<BvhBinNode> bin(1);
    bin.reserve(n / 2 + 16);
    std::atomic<int> spare{threads - 1};
    TriBuilder{recs, spare}.build(bin, 0, 0, std::uint32_t(n), 0);
    // Each leaf's triangles into a block of their own, in the leaves' order.
    std::size_t leaves = 0;
    for (const BvhBinNode& b : bin) leaves += b.count > 0;
    acc.blocks.resize(leaves);
    acc.ids.assign(4 * leaves, 0);
    std::size_t block = 0;
    for (BvhBinNode& b : bin) {
        if (b.count == 0) continue;
        TriBlock& tb = acc.blocks[block];
        std::memset(&tb, 0, sizeof tb);
        for (std::uint32_t l = 0; l < b.count; ++l) {
            const std::uint32_t id = recs[b.first + l].id;
            acc.ids[4 * block + l] = id;
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) tb.v[3 * k + a][l] = p[3 * m.triangles[3 * std::size_t(id) + k] + a];
        }
        b.first = std::uint32_t(4 * block++);
    }
    mem.reset();
    acc.bvh.collapse(bin, threads);
    return acc;
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
