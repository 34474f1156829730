// Bounding volume hierarchy over boxes, built with a binned surface area heuristic and
// stored as one flat array of 4-wide nodes: each node holds its (up to) four children's
// boxes in float, laid out so that one SSE instruction works on all four, and padded
// outward so that the float box test never misses what the double-precision shapes
// would hit. An 8-wide copy serves the AVX2 kernels; the walks are written once over
// the node width.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "chunked.h"
#include "math.h"
#include "simd.h"

#if RT_HAVE_AVX2_KERNELS
#include <immintrin.h>
// Compiled for AVX2 whatever the rest of the build targets; called only when the
// processor has it (simd.h). No FMA: every path rounds alike.
#define RT_TARGET_AVX2 __attribute__((target("avx2")))
#endif

namespace rt {

// b[k][i]: child i's lo x, y, z (k = 0..2) and hi x, y, z (k = 3..5). An unused slot has
// an inverted box that no ray enters.
struct alignas(16) BvhNode {
    float b[6][4];
    // Per child: an inner node's index, or kLeaf | (count - 1) << kCountShift | first
    // for a leaf holding items[first, first + count), or kEmpty.
    std::uint32_t child[4];

    static constexpr std::uint32_t kLeaf = 0x80000000u;
    static constexpr int kCountShift = 27;
    static constexpr std::uint32_t kMaxLeafCount = 16;
    static constexpr std::uint32_t kMaxItems = 1u << kCountShift;
    static constexpr std::uint32_t kEmpty = 0xffffffffu;  // an unused slot (never entered)
    static bool is_leaf(std::uint32_t ref) { return ref & kLeaf; }
    static std::uint32_t leaf_first(std::uint32_t ref) { return ref & (kMaxItems - 1); }
    static std::uint32_t leaf_count(std::uint32_t ref) { return ((ref & ~kLeaf) >> kCountShift) + 1; }
};
static_assert(sizeof(BvhNode) == 112, "BVH nodes are 112 bytes: four boxes and four child references");

// The same tree with up to eight children per node, for the AVX2 kernels: one node's
// eight boxes are tested by one pass of 8-wide instructions. Child references as in
// BvhNode.
struct alignas(32) BvhNode8 {
    float b[6][8];
    std::uint32_t child[8];
};
static_assert(sizeof(BvhNode8) == 224, "8-wide nodes are 224 bytes: eight boxes and eight child references");

namespace detail {
// For the box tests: per sign pattern of a ray's direction (bit i: axis i negative),
// the byte offsets in a node of its near x, y, z and far x, y, z rows (rows of W floats).
template <int W>
constexpr std::int32_t bvh_row(int neg, int k) {
    const int axis = k % 3;
    const bool far = k >= 3, negative = (neg >> axis & 1) != 0;
    return std::int32_t((axis + (negative != far ? 3 : 0)) * W * sizeof(float));
}
#define RT_BVH_ROWS(W, n) {bvh_row<W>(n, 0), bvh_row<W>(n, 1), bvh_row<W>(n, 2), bvh_row<W>(n, 3), bvh_row<W>(n, 4), bvh_row<W>(n, 5), 0, 0}
#define RT_BVH_TABLE(W) {RT_BVH_ROWS(W, 0), RT_BVH_ROWS(W, 1), RT_BVH_ROWS(W, 2), RT_BVH_ROWS(W, 3), \
                         RT_BVH_ROWS(W, 4), RT_BVH_ROWS(W, 5), RT_BVH_ROWS(W, 6), RT_BVH_ROWS(W, 7)}
alignas(32) inline constexpr std::int32_t kBvhRows4[8][8] = RT_BVH_TABLE(4);
alignas(32) inline constexpr std::int32_t kBvhRows8[8][8] = RT_BVH_TABLE(8);
#undef RT_BVH_TABLE
#undef RT_BVH_ROWS
}  // namespace detail

struct BvhRay {
#if defined(__SSE2__)
    // Byte offsets in a node of the near x, y, z and the far x, y, z rows.
    const std::int32_t* rows;
    // Origin, inverse direction and the slack in t for rounding the origin to float
    // (largest axis), each broadcast to four lanes.
    __m128 o4[3], inv4[3], pad4;
#else
    int near[3], far[3];  // per axis, the row of b holding the near and the far slab
    float o[3];
    float inv[3];
    float pad;
#endif

    // The ray along dir / len (len = 1 for a unit dir): its inverse is len / dir, one
    // division from an unnormalised direction and its length.
    static BvhRay make(const Vec3& origin, const Vec3& dir, double len = 1.0) {
        BvhRay r;
        // Per axis: a zero component gets a huge finite inverse instead of infinity, so
        // the slab products stay numbers (0 * inf would be NaN). Rounding the origin to
        // float moves the ray by up to |o| * 2^-24 on each axis; widening each slab by
        // that much (in t) keeps the test conservative.
#if defined(__SSE2__)
        const __m128d one = _mm_set1_pd(len), big = _mm_set1_pd(1e30), nbig = _mm_set1_pd(-1e30);
        const __m128d abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
        const __m128d rel = _mm_set1_pd(1.2e-7), tiny = _mm_set1_pd(1e-30);
        __m128d o01 = _mm_loadu_pd(&origin.x), o2 = _mm_load_sd(&origin.z);
        __m128d d01 = _mm_loadu_pd(&dir.x), d2 = _mm_load_sd(&dir.z);
        __m128d i01 = _mm_min_pd(_mm_max_pd(_mm_div_pd(one, d01), nbig), big);
        __m128d i2 = _mm_min_sd(_mm_max_sd(_mm_div_sd(one, d2), nbig), big);
        __m128d p01 = _mm_mul_pd(_mm_add_pd(_mm_mul_pd(_mm_and_pd(o01, abs_mask), rel), tiny), _mm_and_pd(i01, abs_mask));
        __m128d p2 = _mm_mul_sd(_mm_add_sd(_mm_mul_sd(_mm_and_pd(o2, abs_mask), rel), tiny), _mm_and_pd(i2, abs_mask));
        __m128d pm = _mm_max_sd(_mm_max_sd(p01, _mm_unpackhi_pd(p01, p01)), p2);
        __m128 of = _mm_movelh_ps(_mm_cvtpd_ps(o01), _mm_cvtpd_ps(o2));
        __m128 inf = _mm_movelh_ps(_mm_cvtpd_ps(i01), _mm_cvtpd_ps(i2));
        // Broadcasts by shuffles, rows from the sign bits (a table row).
        __m128 pf = _mm_cvtpd_ps(pm);
        r.pad4 = _mm_shuffle_ps(pf, pf, 0x00);
        r.o4[0] = _mm_shuffle_ps(of, of, 0x00);
        r.o4[1] = _mm_shuffle_ps(of, of, 0x55);
        r.o4[2] = _mm_shuffle_ps(of, of, 0xaa);
        r.inv4[0] = _mm_shuffle_ps(inf, inf, 0x00);
        r.inv4[1] = _mm_shuffle_ps(inf, inf, 0x55);
        r.inv4[2] = _mm_shuffle_ps(inf, inf, 0xaa);
        r.rows = detail::kBvhRows4[_mm_movemask_pd(d01) | (_mm_movemask_pd(d2) & 1) << 2];
#else
        double pad = 0;
        for (int i = 0; i < 3; ++i) {
            r.o[i] = float(origin[i]);
            double inv = std::min(std::max(len / dir[i], -1e30), 1e30);
            r.inv[i] = float(inv);
            pad = std::max(pad, (std::fabs(origin[i]) * 1.2e-7 + 1e-30) * std::fabs(inv));
            bool neg = std::signbit(dir[i]);
            r.near[i] = neg ? 3 + i : i;
            r.far[i] = neg ? i : 3 + i;
        }
        r.pad = float(pad);
#endif
        return r;
    }
};

// A node of the binary tree a build makes before it is collapsed into wide nodes, in
// preorder: an inner node's left child follows it, its right child is at `first`.
struct BvhBinNode {
    float b[6];           // lo x, y, z then hi x, y, z
    std::uint32_t first;  // leaf: first index into items; inner: right child
    std::uint32_t count;  // leaf: number of items (> 0, at most kMaxLeafCount); inner: 0
};

// Round a double box outward to float and pad it by a few float ulps of its largest
// coordinate, so that the float slab test (with the ray's origin and inverse
// direction also rounded to float) never misses a box the ray really crosses.
void to_float_box(const Aabb& b, float out[6]);

class BvhLinks;  // bvh_update.h

class Bvh {
public:
    // In chunks that copies share (chunked.h): a refitted copy of the tree holds its own
    // copies of only the chunks of the nodes it changed.
    Chunked<BvhNode> nodes;        // nodes[0] is the root (when there are items)
    Shared<std::uint32_t> items;   // item ids (indices of the boxes given to build)
    // An item taken out of the tree since its build (bvh_update.h) leaves this in its
    // place in `items`, outside every leaf: the walks over all items pass it by.
    static constexpr std::uint32_t kRemoved = 0xffffffffu;
    // The 8-wide form of the same tree (same leaves), made by build() when the AVX2
    // path is active (simd.h); empty otherwise.
    Chunked<BvhNode8> nodes8;

    // The parent links of this tree's shape, once a refit made them (bvh_update.h): a
    // refitted copy keeps its shape, so its links too. build() drops them.
    std::shared_ptr<const BvhLinks> links;

    // Items with empty boxes are left out. At most BvhNode::kMaxItems items. Built on
    // up to `threads` threads (0: the process pool's); the tree is the same for any.
    void build(const std::vector<Aabb>& boxes, int threads = 0);
    void build(const Chunked<Aabb>& boxes, int threads = 0);
    // The wide nodes of a binary tree built elsewhere (triangles.h builds its own, in
    // less memory), chosen for the least total area of their boxes (the binary tree's
    // leaves kept); `items` is left to the caller. On two threads if `threads` > 1.
    void collapse(const std::vector<BvhBinNode>& bin, int threads);

    // Walks that hand fn whole leaves instead of single items, for callers that test a
    // leaf's items together: traverse_nearest() calling fn(first, count, tmax) -> the new
    // tmax (or a negative value to stop), and occluded() calling fn(first, count) -> hit.
    template <class Fn>
    void traverse_nearest_leaves(const Vec3& origin, const Vec3& dir, double tmax, Fn&& fn) const {
        Leaves<std::remove_reference_t<Fn>> leaves{fn};
        traverse_nearest(origin, dir, tmax, leaves);
    }
    template <class Fn>
    bool occluded_leaves(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn&& fn) const {
        Leaves<std::remove_reference_t<Fn>> leaves{fn};
        return occluded(origin, dir, len, tmax, leaves);
    }

#if RT_HAVE_AVX2_KERNELS
    // The same walks on the 8-wide tree only (it must exist: !nodes8.empty()), for
    // callers compiled for AVX2 whose visitors are too (and may then be inlined).
    template <class Fn>
    RT_TARGET_AVX2 void traverse_nearest_leaves8(const Vec3& origin, const Vec3& dir, double tmax, Fn&& fn) const {
        Leaves<std::remove_reference_t<Fn>> leaves{fn};
        if (beyond_float(origin, dir)) return every_item(tmax, leaves);
        traverse8(origin, dir, tmax, leaves);
    }
    template <class Fn>
    RT_TARGET_AVX2 bool occluded_leaves8(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn&& fn) const {
        Leaves<std::remove_reference_t<Fn>> leaves{fn};
        if (beyond_float(origin, dir)) return any_item(leaves);
        return occluded8(origin, dir, len, tmax, leaves);
    }
#endif

    // Which of node's children the ray enters within [0, tmax]: a bit per child, and
    // the entry distances in t.
    static inline unsigned enter(const BvhNode& n, const BvhRay& r, float tmax, float t[4]) {
#if defined(__SSE2__)
        const __m128 ox = r.o4[0], oy = r.o4[1], oz = r.o4[2];
        const __m128 ix = r.inv4[0], iy = r.inv4[1], iz = r.inv4[2];
        auto row = [&n](std::int32_t bytes) {
            return _mm_load_ps(reinterpret_cast<const float*>(reinterpret_cast<const char*>(n.b) + bytes));
        };
        __m128 x0 = _mm_mul_ps(_mm_sub_ps(row(r.rows[0]), ox), ix);
        __m128 y0 = _mm_mul_ps(_mm_sub_ps(row(r.rows[1]), oy), iy);
        __m128 z0 = _mm_mul_ps(_mm_sub_ps(row(r.rows[2]), oz), iz);
        __m128 x1 = _mm_mul_ps(_mm_sub_ps(row(r.rows[3]), ox), ix);
        __m128 y1 = _mm_mul_ps(_mm_sub_ps(row(r.rows[4]), oy), iy);
        __m128 z1 = _mm_mul_ps(_mm_sub_ps(row(r.rows[5]), oz), iz);
        const __m128 pad = r.pad4;
        __m128 t0 = _mm_max_ps(_mm_sub_ps(_mm_max_ps(_mm_max_ps(x0, y0), z0), pad), _mm_setzero_ps());
        __m128 t1 = _mm_min_ps(_mm_add_ps(_mm_min_ps(_mm_min_ps(x1, y1), z1), pad), _mm_set1_ps(tmax));
        _mm_storeu_ps(t, t0);
        // A few ulps for the rounding of the products themselves.
        return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, _mm_mul_ps(t1, _mm_set1_ps(1.000001f)))));
#else
        unsigned mask = 0;
        for (int i = 0; i < 4; ++i) {
            float t0 = 0.f, t1 = tmax;
            for (int a = 0; a < 3; ++a) {
                float lo = (n.b[r.near[a]][i] - r.o[a]) * r.inv[a], hi = (n.b[r.far[a]][i] - r.o[a]) * r.inv[a];
                t0 = std::max(t0, lo - r.pad);
                t1 = std::min(t1, hi + r.pad);
            }
            t[i] = t0;
            if (t0 <= t1 * 1.000001f) mask |= 1u << i;
        }
        return mask;
#endif
    }

    // Visit the items whose boxes the ray may enter before tmax, nearest box first.
    // `fn(item, tmax)` returns the new tmax (smaller to prune), or a negative value to stop.
    template <class Fn>
    void traverse(const Vec3& origin, const Vec3& dir, double tmax, Fn&& fn) const {
        traverse(origin, dir, 1.0, tmax, fn);
    }
    // The same along the unit direction dir / len (dir need not be normalised).
    template <class Fn>
    void traverse(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn&& fn) const {
        if (nodes.empty()) return;
        if (beyond_float(origin, dir)) return every_item(tmax, fn);
        nearest_walk<Wide4>(BvhRay::make(origin, dir, len), tmax, fn);
    }

    // Nearest-hit queries: like traverse(), but the items may come in any order (the
    // caller keeps the nearest, ties broken by item, so the order cannot change its
    // answer). Runs the 8-wide AVX2 kernel where it is active.
    template <class Fn>
    void traverse_nearest(const Vec3& origin, const Vec3& dir, double tmax, Fn&& fn) const {
#if RT_HAVE_AVX2_KERNELS
        if (!nodes8.empty() && avx2_active() && !beyond_float(origin, dir)) {
            traverse8(origin, dir, tmax, fn);
            return;
        }
#endif
        traverse(origin, dir, 1.0, tmax, fn);
    }

    // Any-hit queries (shadow rays): visits the items whose boxes the ray may enter
    // before tmax along dir / len, in no particular order, until `fn(item)` returns
    // true; returns whether it did. Nothing is sorted and tmax never shrinks, so the
    // answer cannot depend on the order. Runs on the 8-wide tree where it is active.
    template <class Fn>
    bool occluded(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn&& fn) const {
        if (nodes.empty()) return false;
        if (beyond_float(origin, dir)) return any_item(fn);
#if RT_HAVE_AVX2_KERNELS
        if (!nodes8.empty() && avx2_active()) return occluded8(origin, dir, len, tmax, fn);
#endif
        return occluded4(origin, dir, len, tmax, fn);
    }

    std::size_t memory_bytes() const { return nodes.memory_bytes() + nodes8.memory_bytes() + items.memory_bytes(); }

private:
    // What the walks below need of a node width: its nodes, the ray in the form its box
    // test takes, and the test. The walks are written once over these.
    struct Wide4 {
        static constexpr int kWidth = 4, kStack = 256;
        using Node = BvhNode;
        using Ray = BvhRay;
        static const Chunked<Node>& tree(const Bvh& b) { return b.nodes; }
        static unsigned enter(const Node& n, const Ray& r, float tmax, float t[4]) { return Bvh::enter(n, r, tmax, t); }
    };
public:
    // The float bound a walk tests boxes against for a double tmax (a little beyond it).
    static float widen(double t) { return t == HUGE_VAL ? INFINITY : float(t * (1 + 1e-6) + 1e-6); }

#if RT_HAVE_AVX2_KERNELS
    // Which of an 8-wide node's children the ray enters within [0, tmax], with their
    // entry distances: BvhNode's test, lane for lane the same float operations. (Public
    // for the packet walks of triangles.cpp, which test each ray of a packet with it.)
    struct Wide8 {
        static constexpr int kWidth = 8, kStack = 512;
        using Node = BvhNode8;
        struct Ray {
            __m256 o[3], inv[3], pad;
            // Byte offsets in a node of the near x, y, z and the far x, y, z rows.
            const std::int32_t* rows;
        };
        static const Chunked<Node>& tree(const Bvh& b) { return b.nodes8; }
        // BvhRay::make's ray in 8-wide form, made in one pass: the same double operations
        // lane for lane (so the same floats), without the 4-wide copy in between.
        RT_TARGET_AVX2 static inline Ray ray(const Vec3& origin, const Vec3& dir, double len) {
            const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
            const __m256d o = _mm256_set_pd(0.0, origin.z, origin.y, origin.x);
            // Lane 3 divides by infinity: an inverse and a pad of 0, which leave the max alone.
            const __m256d d = _mm256_set_pd(INFINITY, dir.z, dir.y, dir.x);
            const __m256d inv = _mm256_min_pd(_mm256_max_pd(_mm256_div_pd(_mm256_set1_pd(len), d), _mm256_set1_pd(-1e30)),
                                              _mm256_set1_pd(1e30));
            const __m256d p = _mm256_mul_pd(
                _mm256_add_pd(_mm256_mul_pd(_mm256_and_pd(o, abs_mask), _mm256_set1_pd(1.2e-7)), _mm256_set1_pd(1e-30)),
                _mm256_and_pd(inv, abs_mask));
            // The largest axis's pad, taken in BvhRay::make's order.
            const __m128d p01 = _mm256_castpd256_pd128(p), p2 = _mm256_extractf128_pd(p, 1);
            const __m128d pm = _mm_max_sd(_mm_max_sd(p01, _mm_unpackhi_pd(p01, p01)), p2);
            const __m128 of = _mm256_cvtpd_ps(o), inf = _mm256_cvtpd_ps(inv);
            Ray r;
            r.o[0] = _mm256_broadcastss_ps(of);
            r.o[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(of));
            r.o[2] = _mm256_broadcastss_ps(_mm_movehl_ps(of, of));
            r.inv[0] = _mm256_broadcastss_ps(inf);
            r.inv[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(inf));
            r.inv[2] = _mm256_broadcastss_ps(_mm_movehl_ps(inf, inf));
            r.pad = _mm256_broadcastss_ps(_mm_cvtpd_ps(pm));
            r.rows = detail::kBvhRows8[_mm256_movemask_pd(d) & 7];
            return r;
        }
        RT_TARGET_AVX2 static inline __m256 row(const Node& n, std::int32_t bytes) {
            return _mm256_load_ps(reinterpret_cast<const float*>(reinterpret_cast<const char*>(n.b) + bytes));
        }
        RT_TARGET_AVX2 static inline unsigned enter(const Node& n, const Ray& r, float tmax, float t[8]) {
            __m256 x0 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[0]), r.o[0]), r.inv[0]);
            __m256 y0 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[1]), r.o[1]), r.inv[1]);
            __m256 z0 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[2]), r.o[2]), r.inv[2]);
            __m256 x1 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[3]), r.o[0]), r.inv[0]);
            __m256 y1 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[4]), r.o[1]), r.inv[1]);
            __m256 z1 = _mm256_mul_ps(_mm256_sub_ps(row(n, r.rows[5]), r.o[2]), r.inv[2]);
            __m256 t0 = _mm256_max_ps(_mm256_sub_ps(_mm256_max_ps(_mm256_max_ps(x0, y0), z0), r.pad), _mm256_setzero_ps());
            __m256 t1 = _mm256_min_ps(_mm256_add_ps(_mm256_min_ps(_mm256_min_ps(x1, y1), z1), r.pad), _mm256_set1_ps(tmax));
            _mm256_storeu_ps(t, t0);
            return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(t0, _mm256_mul_ps(t1, _mm256_set1_ps(1.000001f)), _CMP_LE_OS)));
        }
    };
#endif

private:
#if RT_HAVE_AVX2_KERNELS
    // The AVX2 entry points: the walks inlined here, where 8-wide instructions may be
    // used, so that Wide8's test is inlined into them.
    template <class Fn>
    RT_TARGET_AVX2 void traverse8(const Vec3& origin, const Vec3& dir, double tmax, Fn& fn) const {
        nearest_walk<Wide8>(Wide8::ray(origin, dir, 1.0), tmax, fn);
    }
    template <class Fn>
    RT_TARGET_AVX2 bool occluded8(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn& fn) const {
        return occluded_walk<Wide8>(Wide8::ray(origin, dir, len), widen(tmax), fn);
    }
#endif

    // (Out of line like the AVX2 one: inlined, its frame would weigh on the caller's
    // loop, which mostly takes the light buffers instead.)
    template <class Fn>
    [[gnu::noinline]] bool occluded4(const Vec3& origin, const Vec3& dir, double len, double tmax, Fn& fn) const {
        return occluded_walk<Wide4>(BvhRay::make(origin, dir, len), widen(tmax), fn);
    }

    template <class F>
    struct Leaves {
        F& fn;
    };
    // (Always inline: a caller compiled for AVX2 may then inline a visitor compiled for
    // it, which these, compiled for any processor, could not.)
    template <class F>
    [[gnu::always_inline]] bool visit_leaf(std::uint32_t ref, double& tmax, Leaves<F>& leaves) const {
        const double nt = leaves.fn(BvhNode::leaf_first(ref), BvhNode::leaf_count(ref), tmax);
        if (nt < 0) return false;
        if (nt < tmax) tmax = nt;
        return true;
    }
    template <class F>
    [[gnu::always_inline]] bool any_in_leaf(std::uint32_t ref, Leaves<F>& leaves) const {
        return leaves.fn(BvhNode::leaf_first(ref), BvhNode::leaf_count(ref));
    }

    // The items of a leaf to fn(item, tmax) in order, tmax shrinking as fn says; false
    // if fn said stop.
    template <class Fn>
    bool visit_leaf(std::uint32_t ref, double& tmax, Fn& fn) const {
        std::uint32_t first = BvhNode::leaf_first(ref), count = BvhNode::leaf_count(ref);
        for (std::uint32_t i = 0; i < count; ++i) {
            double nt = fn(items[first + i], tmax);
            if (nt < 0) return false;
            if (nt < tmax) tmax = nt;
        }
        return true;
    }

    // A ray from beyond where the float box tests hold (a coordinate of 1e30 or more,
    // or no number: a hit far out on a plane met at a grazing angle) would enter every
    // box through its infinities and NaNs, a wide node's empty slots too: such a ray
    // meets the items one by one instead (every_item, any_item).
    static bool beyond_float(const Vec3& o, const Vec3& d) {
        constexpr double kFar = 1e30;
        return !(std::fabs(o.x) < kFar && std::fabs(o.y) < kFar && std::fabs(o.z) < kFar && std::fabs(d.x) < kFar &&
                 std::fabs(d.y) < kFar && std::fabs(d.z) < kFar);
    }
    template <class Fn>
    void every_item(double tmax, Fn& fn) const {
        for (std::size_t k = 0; k < items.size(); ++k) {
            if (items[k] == kRemoved) continue;
            const double nt = fn(items[k], tmax);
            if (nt < 0) return;
            if (nt < tmax) tmax = nt;
        }
    }
    template <class F>
    void every_item(double tmax, Leaves<F>& leaves) const {
        for (std::size_t k = 0; k < items.size(); ++k) {
            if (items[k] == kRemoved) continue;
            const double nt = leaves.fn(std::uint32_t(k), 1u, tmax);
            if (nt < 0) return;
            if (nt < tmax) tmax = nt;
        }
    }
    template <class Fn>
    bool any_item(Fn& fn) const {
        for (std::size_t k = 0; k < items.size(); ++k)
            if (items[k] != kRemoved && fn(items[k])) return true;
        return false;
    }
    template <class F>
    bool any_item(Leaves<F>& leaves) const {
        for (std::size_t k = 0; k < items.size(); ++k)
            if (items[k] != kRemoved && leaves.fn(std::uint32_t(k), 1u)) return true;
        return false;
    }

    // The lowest set bit's index, cleared from mask (not 0).
    static int pop_bit(unsigned& mask) {
        int i = __builtin_ctz(mask);
        mask &= mask - 1;
        return i;
    }

    // Whether fn(item) holds for an item of a leaf (tried in order, stopping there).
    template <class Fn>
    bool any_in_leaf(std::uint32_t ref, Fn& fn) const {
        std::uint32_t first = BvhNode::leaf_first(ref), count = BvhNode::leaf_count(ref);
        for (std::uint32_t k = 0; k < count; ++k)
            if (fn(items[first + k])) return true;
        return false;
    }

    // A tree's nodes as the walks read them: an unedited tree's in one block, an edited
    // one's through its chunk table (chunked.h), either kept in registers.
    template <class W>
    struct Nodes {
        using Node = typename W::Node;
        static constexpr unsigned kShift = Chunked<Node>::kShift;
        const Node* flat;
        Node* const* table;
        explicit Nodes(const Chunked<Node>& c) : flat(c.flat()), table(c.table()) {}
        const Node& operator[](std::uint32_t ref) const {
            return flat ? flat[ref] : table[ref >> kShift][ref & Chunked<Node>::kMask];
        }
    };

    // Nearest-first walk: of the children a node's test lets through, the nearest box
    // is entered next and the others wait on a stack with their entry distance, to be
    // dropped when they come up beyond the nearest hit found so far. Children of equal
    // distance go in slot order (traverse() promises that order).
    template <class W, class Fn>
    [[gnu::always_inline]] inline void nearest_walk(const typename W::Ray& r, double tmax, Fn& fn) const {
        const Nodes<W> tree(W::tree(*this));
        float ftmax = widen(tmax);
        struct Entry {
            std::uint32_t ref;
            float t;
        };
        Entry stack[W::kStack];
        int sp = 0;
        std::uint32_t cur = 0;  // the root is an inner node
        for (;;) {
            if (BvhNode::is_leaf(cur)) {
                double before = tmax;
                if (!visit_leaf(cur, tmax, fn)) return;
                if (tmax != before) ftmax = widen(tmax);
            } else {
                const typename W::Node& n = tree[cur];
                float t[W::kWidth];
                unsigned mask = W::enter(n, r, ftmax, t);
                if (mask != 0) {
                    int i = pop_bit(mask);
                    if (mask == 0) {  // one child: nothing to sort or keep
                        cur = n.child[i];
                        continue;
                    }
                    // The children entered, nearest first (insertion by entry distance).
                    Entry hit[W::kWidth];
                    hit[0] = {n.child[i], t[i]};
                    int k = 1;
                    do {
                        i = pop_bit(mask);
                        Entry e{n.child[i], t[i]};
                        int j = k++;
                        for (; j > 0 && hit[j - 1].t > e.t; --j) hit[j] = hit[j - 1];
                        hit[j] = e;
                    } while (mask != 0);
                    for (int j = k - 1; j > 0; --j) {
                        if (sp < W::kStack) {
                            stack[sp++] = hit[j];
                        } else if (!nearest_from<W>(hit[j].ref, r, tmax, fn)) {
                            // Too deep for the stack: that subtree was searched now.
                            return;
                        } else {
                            ftmax = widen(tmax);
                        }
                    }
                    cur = hit[0].ref;
                    continue;
                }
            }
            // Pop the next subtree still in reach.
            for (;;) {
                if (sp == 0) return;
                --sp;
                if (stack[sp].t <= ftmax) break;
            }
            cur = stack[sp].ref;
        }
    }

    // Any-hit walk: children in slot order, no distances kept.
    template <class W, class Fn>
    [[gnu::always_inline]] inline bool occluded_walk(const typename W::Ray& r, float ftmax, Fn& fn) const {
        const Nodes<W> tree(W::tree(*this));
        std::uint32_t stack[W::kStack];
        int sp = 0;
        std::uint32_t cur = 0;
        for (;;) {
            const typename W::Node& n = tree[cur];
            float t[W::kWidth];
            unsigned mask = W::enter(n, r, ftmax, t);
            while (mask != 0) {
                int i = pop_bit(mask);
                std::uint32_t c = n.child[i];
                if (BvhNode::is_leaf(c)) {
                    if (any_in_leaf(c, fn)) return true;
                } else if (sp < W::kStack) {
                    stack[sp++] = c;
                } else if (occluded_from<W>(c, r, ftmax, fn)) {
                    return true;
                }
            }
            if (sp == 0) return false;
            cur = stack[--sp];
        }
    }

    // The fallbacks for pathologically deep trees: plain recursion from one child
    // reference, any-hit below an inner node, nearest from any reference.
    template <class W, class Fn>
    bool occluded_from(std::uint32_t ref, const typename W::Ray& r, float ftmax, Fn& fn) const {
        const typename W::Node& n = W::tree(*this)[ref];
        float t[W::kWidth];
        unsigned mask = W::enter(n, r, ftmax, t);
        for (int i = 0; i < W::kWidth; ++i) {
            if (!(mask >> i & 1)) continue;
            std::uint32_t c = n.child[i];
            if (BvhNode::is_leaf(c) ? any_in_leaf(c, fn) : occluded_from<W>(c, r, ftmax, fn)) return true;
        }
        return false;
    }
    template <class W, class Fn>
    bool nearest_from(std::uint32_t ref, const typename W::Ray& r, double& tmax, Fn& fn) const {
        if (BvhNode::is_leaf(ref)) return visit_leaf(ref, tmax, fn);
        const typename W::Node& n = W::tree(*this)[ref];
        float t[W::kWidth];
        unsigned mask = W::enter(n, r, widen(tmax), t);
        for (int i = 0; i < W::kWidth; ++i)
            if ((mask >> i & 1) && !nearest_from<W>(n.child[i], r, tmax, fn)) return false;
        return true;
    }
};

}  // namespace rt
