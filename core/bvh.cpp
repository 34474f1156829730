// Binned SAH build (16 bins on the centroid bounds of each axis), falling back to a
// median split when binning cannot separate the items or the tree gets deep. The
// binary tree is then collapsed into 4-wide nodes: each node pulls up the children of
// its largest inner children until it has four. A triangle model's binary tree
// (Bvh::collapse) is collapsed by cost instead: the wide nodes chosen for the least
// total area (CollapsePlan).
#include "bvh.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <type_traits>

#include "huge_pages.h"
#include "parallel.h"

namespace rt {
namespace {

// The binary tree the SAH build makes.
using BinNode = BvhBinNode;

constexpr int kBins = 16;
constexpr std::uint32_t kMaxLeaf = 4;
static_assert(kMaxLeaf <= BvhNode::kMaxLeafCount, "leaf sizes fit the child reference");
constexpr int kMaxSahDepth = 48;
constexpr double kObjectCost = 2.0;
// Below this many items leaves may hold single objects; above it, up to kMaxLeaf, which
// keeps big scenes' trees compact (under 64 bytes per object).
constexpr std::size_t kSmallScene = 4096;
// Subtrees of at least this many items may be built on another thread.
constexpr std::uint32_t kParallelItems = 4096;

// Nodes of at least this many items are binned in two halves side by side when a
// thread is spare (the root and the first levels, before the subtrees fill the threads).
constexpr std::uint32_t kParallelBinItems = 1u << 16;
constexpr std::uint32_t kRunItems = 8192;  // nodes binned a run of items with the same bins at a time


}  // namespace

namespace {

// std::nextafter(x, -INFINITY) and (x, INFINITY) for x that is not NaN nor the infinity
// it steps towards, inline: the library call was a tenth of the BVH build's leaves.
// Floats of one sign are ordered as their bit patterns; zeros step to the smallest
// subnormal of the side they step to.
inline float float_step(float x, bool up) {
    if (x == 0) return up ? FLT_TRUE_MIN : -FLT_TRUE_MIN;
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    bits = (x > 0) == up ? bits + 1 : bits - 1;
    std::memcpy(&x, &bits, sizeof x);
    return x;
}

}  // namespace

void to_float_box(const Aabb& b, float out[6]) {
    double m = 0;
    for (int k = 0; k < 3; ++k) m = std::max({m, std::fabs(b.lo[k]), std::fabs(b.hi[k])});
    double pad = m * 1e-6 + 1e-30;
    for (int k = 0; k < 3; ++k) {
        float lo = float(b.lo[k] - pad), hi = float(b.hi[k] + pad);
        // (A NaN, or the infinity a bound would step towards, fails these comparisons.)
        if (double(lo) > b.lo[k] - pad) lo = float_step(lo, false);
        if (double(hi) < b.hi[k] + pad) hi = float_step(hi, true);
        out[k] = lo;
        out[3 + k] = hi;
    }
}

namespace {

// Per axis, the bins of one node's items: their boxes and counts. The children's
// boxes are unions of bins, and their centroid bounds are taken while partitioning, so
// no extra pass over the items finds them (min and max are exact: the unions equal
// the bounds taken item by item).
struct Bins {
#if defined(__SSE2__)
    // lo x y, lo z, hi x y, hi z: a bin grows by four SSE2 min/max, in the order
    // dmin/dmax take their operands (the same result for NaN and signed zeros).
    struct Box {
        __m128d lo01 = _mm_set1_pd(HUGE_VAL), lo2 = _mm_set1_pd(HUGE_VAL);
        __m128d hi01 = _mm_set1_pd(-HUGE_VAL), hi2 = _mm_set1_pd(-HUGE_VAL);
        Aabb aabb() const {
            Aabb b;
            _mm_storeu_pd(&b.lo.x, lo01);
            _mm_store_sd(&b.lo.z, lo2);
            _mm_storeu_pd(&b.hi.x, hi01);
            _mm_store_sd(&b.hi.z, hi2);
            return b;
        }
    };
    Box box[3][kBins];
#else
    Aabb box[3][kBins];
#endif
    std::uint32_t count[3][kBins] = {};
    // Adds the items of `o`. Only the sign of a zero bound may differ from binning all
    // items in one pass (NaN never enters a bin), and no use of the bins tells the two
    // zeros apart.
    void merge(const Bins& o) {
        for (int axis = 0; axis < 3; ++axis)
            for (int k = 0; k < kBins; ++k) {
#if defined(__SSE2__)
                Box& b = box[axis][k];
                const Box& c = o.box[axis][k];
                b.lo01 = _mm_min_pd(c.lo01, b.lo01);
                b.lo2 = _mm_min_sd(c.lo2, b.lo2);
                b.hi01 = _mm_max_pd(c.hi01, b.hi01);
                b.hi2 = _mm_max_sd(c.hi2, b.hi2);
#else
                box[axis][k].grow(o.box[axis][k]);
#endif
                count[axis][k] += o.count[axis][k];
            }
    }
    Aabb at(int axis, int k) const {
#if defined(__SSE2__)
        return box[axis][k].aabb();
#else
        return box[axis][k];
#endif
    }
};

// One item as the build moves it: its box, its centre and its index. The items of a
// node lie side by side and are partitioned in place, so every pass over a node reads
// memory in order (not through an index into a million boxes). (Recomputing the
// centre where it is needed, for a 56-byte record, cost more instructions than the
// memory traffic it saved here.)
struct Rec {
    Aabb box;
    Vec3 c;
    std::uint32_t id;
    Vec3 centre() const { return c; }
    // (&c.x)[axis]: Vec3's operator[] is a chain of branches.
    double centre(int axis) const { return (&c.x)[axis]; }
};

// The bin of centre coordinate c (NaN goes to bin 0).
inline int bin_of(double c, double lo, double scale) {
    const int k = int((c - lo) * scale);
    return k < 0 ? 0 : k > kBins - 1 ? kBins - 1 : k;
}

// The split a node's bins chose: axis -1 if none (binning could not separate them).
struct Split {
    int axis = -1;
    int bin = -1;      // the last bin on the left
    double cost = DBL_MAX;  // the children's area times count, summed
};

#if defined(__SSE2__)
// fill_bins_sse2 for big nodes. Neighbouring items mostly fall in the same three bins
// (a big scene's file lists them in order): a run of items with the same bins grows
// one box in registers, added to the three bins when the bins change, instead of a
// load, min/max and store of each bin's box for every item. Unions taken in another
// order: only the sign of a zero bound may differ (see Bins::merge).
template <bool X, bool Y, bool Z>
void fill_bins_runs(const Rec* recs, std::uint32_t begin, std::uint32_t end, const double lo[3],
                    const double scale[3], Bins& bins) {
    const __m128d lo01 = _mm_set_pd(lo[1], lo[0]), lo22 = _mm_set1_pd(lo[2]);
    const __m128d scale01 = _mm_set_pd(scale[1], scale[0]), scale22 = _mm_set1_pd(scale[2]);
    const __m128i zero = _mm_setzero_si128(), top = _mm_set1_epi16(kBins - 1);  // (as in fill_bins_sse2)
    const Rec* r = recs + begin;
    const Rec* const e = recs + end;
    auto bins_of = [&](const Rec* q) {
        const __m128i k01 = _mm_cvttpd_epi32(_mm_mul_pd(_mm_sub_pd(_mm_loadu_pd(&q->c.x), lo01), scale01));
        __m128i k22 = zero;
        if (Z) k22 = _mm_cvttpd_epi32(_mm_mul_pd(_mm_sub_pd(_mm_load1_pd(&q->c.z), lo22), scale22));
        return _mm_min_epi16(_mm_max_epi16(_mm_packs_epi32(_mm_unpacklo_epi64(k01, k22), zero), zero), top);
    };
    __m128i cur = bins_of(r);
    __m128d run_lo01 = _mm_loadu_pd(&r->box.lo.x), run_lo2 = _mm_load_sd(&r->box.lo.z);
    __m128d run_hi01 = _mm_loadu_pd(&r->box.hi.x), run_hi2 = _mm_load_sd(&r->box.hi.z);
    std::uint32_t n = 1;
    auto flush = [&] {
        auto add = [&](int axis, int kb) {
            Bins::Box& bb = bins.box[axis][kb];
            bb.lo01 = _mm_min_pd(run_lo01, bb.lo01);
            bb.lo2 = _mm_min_sd(run_lo2, bb.lo2);
            bb.hi01 = _mm_max_pd(run_hi01, bb.hi01);
            bb.hi2 = _mm_max_sd(run_hi2, bb.hi2);
            bins.count[axis][kb] += n;
        };
        if (X) add(0, _mm_extract_epi16(cur, 0));
        if (Y) add(1, _mm_extract_epi16(cur, 1));
        if (Z) add(2, _mm_extract_epi16(cur, 2));
    };
    for (++r; r != e; ++r) {
        const Aabb& box = r->box;
        const __m128d blo01 = _mm_loadu_pd(&box.lo.x), blo2 = _mm_load_sd(&box.lo.z);
        const __m128d bhi01 = _mm_loadu_pd(&box.hi.x), bhi2 = _mm_load_sd(&box.hi.z);
        const __m128i k = bins_of(r);
        if (_mm_movemask_epi8(_mm_cmpeq_epi16(k, cur)) == 0xFFFF) {
            run_lo01 = _mm_min_pd(blo01, run_lo01);
            run_lo2 = _mm_min_sd(blo2, run_lo2);
            run_hi01 = _mm_max_pd(bhi01, run_hi01);
            run_hi2 = _mm_max_sd(bhi2, run_hi2);
            ++n;
            continue;
        }
        flush();
        cur = k;
        run_lo01 = blo01, run_lo2 = blo2, run_hi01 = bhi01, run_hi2 = bhi2;
        n = 1;
    }
    flush();
}

// fill_bins for the axes that are used (X, Y, Z), known at compile time: the usual
// node bins all three, or two for flat scenes, and the checks per item and axis go.
template <bool X, bool Y, bool Z>
void fill_bins_sse2(const Rec* recs, std::uint32_t begin, std::uint32_t end, const double lo[3],
                    const double scale[3], Bins& bins) {
    if (end - begin >= kRunItems) return fill_bins_runs<X, Y, Z>(recs, begin, end, lo, scale, bins);
    // The three bin numbers at once: the same double arithmetic as bin_of, then the
    // clamp to 0..kBins-1 in 16 bits (the packing saturates; the conversion's
    // out-of-range value is negative, as in bin_of).
    const __m128d lo01 = _mm_set_pd(lo[1], lo[0]), lo22 = _mm_set1_pd(lo[2]);
    const __m128d scale01 = _mm_set_pd(scale[1], scale[0]), scale22 = _mm_set1_pd(scale[2]);
    const __m128i zero = _mm_setzero_si128(), top = _mm_set1_epi16(kBins - 1);
    for (const Rec *r = recs + begin, *e = recs + end; r != e; ++r) {
        const Aabb& box = r->box;
        const __m128d blo01 = _mm_loadu_pd(&box.lo.x), blo2 = _mm_load_sd(&box.lo.z);
        const __m128d bhi01 = _mm_loadu_pd(&box.hi.x), bhi2 = _mm_load_sd(&box.hi.z);
        const __m128i k01 = _mm_cvttpd_epi32(_mm_mul_pd(_mm_sub_pd(_mm_loadu_pd(&r->c.x), lo01), scale01));
        __m128i k22 = zero;
        if (Z) k22 = _mm_cvttpd_epi32(_mm_mul_pd(_mm_sub_pd(_mm_load1_pd(&r->c.z), lo22), scale22));
        const __m128i k = _mm_min_epi16(_mm_max_epi16(_mm_packs_epi32(_mm_unpacklo_epi64(k01, k22), zero), zero), top);
        auto add = [&](int axis, int kb) {
            Bins::Box& bb = bins.box[axis][kb];
            // dmin(acc, v) is v < acc ? v : acc, which is minpd(v, acc).
            bb.lo01 = _mm_min_pd(blo01, bb.lo01);
            bb.lo2 = _mm_min_sd(blo2, bb.lo2);
            bb.hi01 = _mm_max_pd(bhi01, bb.hi01);
            bb.hi2 = _mm_max_sd(bhi2, bb.hi2);
            ++bins.count[axis][kb];
        };
        if (X) add(0, _mm_extract_epi16(k, 0));
        if (Y) add(1, _mm_extract_epi16(k, 1));
        if (Z) add(2, _mm_extract_epi16(k, 2));
    }
}
#endif

// The bins of items [begin, end) on each axis where their centroid bounds have extent.
void fill_bins(const Rec* recs, std::uint32_t begin, std::uint32_t end, const Aabb& cb, Bins& bins) {
    Vec3 ext = cb.hi - cb.lo;
    double lo[3], scale[3];
    bool use[3];
    for (int axis = 0; axis < 3; ++axis) {
        use[axis] = ext[axis] > 0;
        lo[axis] = cb.lo[axis];
        scale[axis] = use[axis] ? kBins / ext[axis] : 0.0;
    }
#if defined(__SSE2__)
    using Fill = void (*)(const Rec*, std::uint32_t, std::uint32_t, const double*, const double*, Bins&);
    static constexpr Fill fills[8] = {fill_bins_sse2<false, false, false>, fill_bins_sse2<true, false, false>,
                                      fill_bins_sse2<false, true, false>,  fill_bins_sse2<true, true, false>,
                                      fill_bins_sse2<false, false, true>,  fill_bins_sse2<true, false, true>,
                                      fill_bins_sse2<false, true, true>,   fill_bins_sse2<true, true, true>};
    fills[int(use[0]) | int(use[1]) << 1 | int(use[2]) << 2](recs, begin, end, lo, scale, bins);
#else
    for (const Rec *r = recs + begin, *e = recs + end; r != e; ++r)
        for (int axis = 0; axis < 3; ++axis) {
            if (!use[axis]) continue;
            const int k = bin_of(r->centre(axis), lo[axis], scale[axis]);
            bins.box[axis][k].grow(r->box);
            ++bins.count[axis][k];
        }
#endif
}

// The cheapest split between bins on one axis, if cheaper than `best`.
void sweep(const Bins& bins, int axis, Split& best) {
    // Empty bins leave the running box and its area as they are: skipping them saves
    // most of the sweep in small nodes.
    double left_area[kBins];
    std::uint32_t left_n[kBins];
#if defined(__SSE2__)
    // The running box grown as Aabb::grow does (see Bins::Box), its area as Aabb::area
    // computes it, without going through an Aabb for each bin.
    Bins::Box acc;
    auto grow = [&](const Bins::Box& b) {
        acc.lo01 = _mm_min_pd(b.lo01, acc.lo01);
        acc.lo2 = _mm_min_sd(b.lo2, acc.lo2);
        acc.hi01 = _mm_max_pd(b.hi01, acc.hi01);
        acc.hi2 = _mm_max_sd(b.hi2, acc.hi2);
    };
    auto area_of = [&] {
        if ((_mm_movemask_pd(_mm_cmpgt_pd(acc.lo01, acc.hi01)) | (_mm_movemask_pd(_mm_cmpgt_sd(acc.lo2, acc.hi2)) & 1)) != 0)
            return 0.0;  // empty
        const __m128d e01 = _mm_sub_pd(acc.hi01, acc.lo01);
        const double ex = _mm_cvtsd_f64(e01), ey = _mm_cvtsd_f64(_mm_unpackhi_pd(e01, e01));
        const double ez = _mm_cvtsd_f64(_mm_sub_sd(acc.hi2, acc.lo2));
        return 2 * (ex * ey + ey * ez + ez * ex);
    };
    auto restart = [&] { acc = Bins::Box(); };
    auto add_bin = [&](int k) { grow(bins.box[axis][k]); };
#else
    Aabb acc;
    auto area_of = [&] { return acc.area(); };
    auto restart = [&] { acc = Aabb(); };
    auto add_bin = [&](int k) { acc.grow(bins.at(axis, k)); };
#endif
    double area = 0;
    std::uint32_t n = 0;
    for (int k = 0; k < kBins; ++k) {
        if (bins.count[axis][k] != 0) {
            add_bin(k);
            n += bins.count[axis][k];
            area = area_of();
        }
        left_area[k] = area;
        left_n[k] = n;
    }
    restart();
    area = 0;
    n = 0;
    for (int k = kBins - 1; k > 0; --k) {
        if (bins.count[axis][k] != 0) {
            add_bin(k);
            n += bins.count[axis][k];
            area = area_of();
        }
        if (left_n[k - 1] == 0 || n == 0) continue;
        double cost = left_area[k - 1] * left_n[k - 1] + area * n;
        if (cost < best.cost) best = {axis, k - 1, cost};
    }
}

// A node's items split in two, with each side's bounds and centroid bounds.
struct Halves {
    std::uint32_t mid;
    Aabb lb, lcb, rb, rcb;
};

struct Builder {
    Rec* recs;
    std::size_t total;  // items in the whole tree
    // Threads that may still be started for subtrees (all but the caller's).
    std::atomic<int>& spare;

    Aabb range_bounds(std::uint32_t begin, std::uint32_t end) const {
        Aabb b;
        for (std::uint32_t i = begin; i < end; ++i) b.grow(recs[i].box);
        return b;
    }
    Aabb range_centres(std::uint32_t begin, std::uint32_t end) const {
        Aabb b;
        for (std::uint32_t i = begin; i < end; ++i) b.grow(recs[i].centre());
        return b;
    }

    bool take_thread() {
        int n = spare.load(std::memory_order_relaxed);
        while (n > 0)
            if (spare.compare_exchange_weak(n, n - 1, std::memory_order_relaxed)) return true;
        return false;
    }

    // The bins of items [begin, end), big ones in two halves side by side.
    void bin_items(std::uint32_t begin, std::uint32_t end, const Aabb& cb, Bins& bins) {
        if (end - begin < kParallelBinItems || !take_thread()) return fill_bins(recs, begin, end, cb, bins);
        const std::uint32_t mid = begin + (end - begin) / 2;
        Bins upper;
        try {
            two_ways(true, [&](int part) {
                if (part == 0) fill_bins(recs, begin, mid, cb, bins);
                else fill_bins(recs, mid, end, cb, upper);
            });
        } catch (...) {
            spare.fetch_add(1, std::memory_order_relaxed);
            throw;
        }
        spare.fetch_add(1, std::memory_order_relaxed);
        bins.merge(upper);
    }

    // Moves the items of bins <= s.bin on s.axis before the others; the children's
    // bounds are unions of bins, their centroid bounds taken on the way (min and max
    // are exact: the unions equal the bounds taken item by item).
    Halves partition_bins(std::uint32_t begin, std::uint32_t end, const Aabb& cb, const Bins& bins,
                          const Split& s) {
        Halves h;
        const int axis = s.axis;
        const double lo = cb.lo[axis], scale = kBins / (cb.hi[axis] - cb.lo[axis]);
        // (std::partition applies the predicate exactly once per item.)
#if defined(__SSE2__)
        Bins::Box cbox[2];  // right, left: grown as Aabb::grow would (see Bins::Box)
        Rec* it = std::partition(recs + begin, recs + end, [&](const Rec& r) {
            const bool left = bin_of(r.centre(axis), lo, scale) <= s.bin;
            Bins::Box& a = cbox[left];
            const __m128d c01 = _mm_loadu_pd(&r.c.x), c2 = _mm_load_sd(&r.c.z);
            a.lo01 = _mm_min_pd(c01, a.lo01);
            a.lo2 = _mm_min_sd(c2, a.lo2);
            a.hi01 = _mm_max_pd(c01, a.hi01);
            a.hi2 = _mm_max_sd(c2, a.hi2);
            return left;
        });
        h.lcb = cbox[1].aabb();
        h.rcb = cbox[0].aabb();
#else
        Rec* it = std::partition(recs + begin, recs + end, [&](const Rec& r) {
            const bool left = bin_of(r.centre(axis), lo, scale) <= s.bin;
            (left ? h.lcb : h.rcb).grow(r.centre());
            return left;
        });
#endif
        h.mid = std::uint32_t(it - recs);
        for (int k = 0; k < kBins; ++k) (k <= s.bin ? h.lb : h.rb).grow(bins.at(axis, k));
        return h;
    }

    // The median split on `axis`, for items binning could not separate.
    Halves partition_median(std::uint32_t begin, std::uint32_t end, int axis) {
        Halves h;
        h.mid = begin + (end - begin) / 2;
        std::nth_element(recs + begin, recs + h.mid, recs + end,
                         [&](const Rec& a, const Rec& c) { return a.centre(axis) < c.centre(axis); });
        h.lb = range_bounds(begin, h.mid), h.lcb = range_centres(begin, h.mid);
        h.rb = range_bounds(h.mid, end), h.rcb = range_centres(h.mid, end);
        return h;
    }

    // The subtree over items [begin, end), whose bounds are b and centroid bounds cb, in
    // preorder: out[node] (already allocated, the last element) is its root, its left
    // child follows at node + 1, its right child after the left subtree. The tree does
    // not depend on which subtrees were built by other threads: those are built apart
    // and spliced in at the place the serial order gives them.
    void build(std::vector<BinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end, const Aabb& b,
               const Aabb& cb, int depth) {
        to_float_box(b, out[node].b);
        const std::uint32_t count = end - begin;
        auto make_leaf = [&] {
            out[node].first = begin;
            out[node].count = count;
        };
        if (count == 1 || (count <= kMaxLeaf && total > kSmallScene)) return make_leaf();
        // Best split over the bins of all three axes, binned in one pass over the items.
        Split s;
        Bins bins;
        if (depth < kMaxSahDepth) {
            bin_items(begin, end, cb, bins);
            Vec3 ext = cb.hi - cb.lo;
            for (int axis = 0; axis < 3; ++axis)
                if (ext[axis] > 0) sweep(bins, axis, s);
        }
        Halves h{begin, {}, {}, {}, {}};
        if (s.axis >= 0) {
            // Small leaves are allowed only when splitting would cost more: a box test
            // costs about half an object test.
            double leaf_cost = kObjectCost * b.area() * count;
            double split_cost = b.area() + kObjectCost * s.cost;
            if (count <= kMaxLeaf && !(split_cost < leaf_cost)) return make_leaf();
            h = partition_bins(begin, end, cb, bins, s);
        } else if (count <= kMaxLeaf) {
            return make_leaf();
        }
        if (h.mid == begin || h.mid == end) {
            Vec3 ext = cb.hi - cb.lo;
            int longest = ext.x > ext.y ? (ext.x > ext.z ? 0 : 2) : (ext.y > ext.z ? 1 : 2);
            h = partition_median(begin, end, s.axis >= 0 ? s.axis : longest);
        }
        out[node].count = 0;
        if (count >= kParallelItems && take_thread())
            build_apart(out, node, begin, end, h, depth + 1);
        else
            build_here(out, node, begin, end, h, depth + 1);
    }

    // Both children after node, one after the other.
    void build_here(std::vector<BinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                    const Halves& h, int depth) {
        std::uint32_t left = std::uint32_t(out.size());
        out.emplace_back();
        build(out, left, begin, h.mid, h.lb, h.lcb, depth);
        std::uint32_t right = std::uint32_t(out.size());
        out.emplace_back();
        build(out, right, h.mid, end, h.rb, h.rcb, depth);
        out[node].first = right;
    }

    // The right subtree beside the left one (on another of the pool's threads), into
    // its own array; the left one in place after node as in the serial order; then the
    // right one is copied in after it.
    void build_apart(std::vector<BinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                     const Halves& h, int depth) {
        std::vector<BinNode> right(1);
        right.reserve(2 * std::size_t(end - h.mid));
        two_ways(true, [&](int part) {
            if (part == 1) {
                build(right, 0, h.mid, end, h.rb, h.rcb, depth);
                spare.fetch_add(1, std::memory_order_relaxed);  // (a throw ends the whole build)
                return;
            }
            std::uint32_t left = std::uint32_t(out.size());
            out.emplace_back();
            build(out, left, begin, h.mid, h.lb, h.lcb, depth);
        });
        out[node].first = std::uint32_t(out.size());
        splice(out, right);
    }

    // Appends a subtree built with its root at index 0, moving its inner nodes' child
    // indices to where it now starts.
    static void splice(std::vector<BinNode>& out, const std::vector<BinNode>& sub) {
        std::uint32_t offset = std::uint32_t(out.size());
        out.insert(out.end(), sub.begin(), sub.end());
        for (std::size_t i = offset; i < out.size(); ++i)
            if (out[i].count == 0) out[i].first += offset;
    }
};

double half_area(const float b[6]) {
    double x = double(b[3]) - b[0], y = double(b[4]) - b[1], z = double(b[5]) - b[2];
    return x * y + y * z + z * x;
}

// Which binary inner nodes become W-wide nodes, chosen for the least total area of the
// wide nodes (all that a ray's walk costs beyond the leaves, which stay as they are:
// a wide node is entered about as often as its box's area says). Per binary node n
// and per number of slots k = 1..W it may take in its wide parent, plan[W n + k - 1]
// says how it fills them: 0, n itself in one slot (a leaf, or a wide node of its
// own), else l * 8 + r: its left subtree in l slots and its right one in r. Made by
// the recursion of Ylitie, Karras and Laine (HPG 2017) over fixed leaves.
template <int W>
struct CollapsePlan {
    const std::vector<BinNode>& bin;
    std::vector<std::uint8_t> plan;

    // The least cost of the subtree at n in k slots, for k = 1..W (cost[k - 1]).
    void solve(std::uint32_t n, double cost[W]) {
        std::uint8_t* p = &plan[std::size_t(W) * n];
        if (bin[n].count > 0) {
            for (int k = 0; k < W; ++k) cost[k] = 0, p[k] = 0;
            return;
        }
        // Two leaves (most of the nodes at the bottom of a triangle model's tree): what
        // the general case below gives, without its loops. Their own plans stay 0.
        const double area = half_area(bin[n].b);
        if (bin[n + 1].count > 0 && bin[bin[n].first].count > 0 && area >= 0) {
            cost[0] = area;
            p[0] = 0;
            for (int k = 2; k <= W; ++k) cost[k - 1] = 0, p[k - 1] = std::uint8_t(8 + (k - 1));
            return;
        }
        double l[W], r[W];
        solve(n + 1, l);
        solve(bin[n].first, r);
        // Split j: left in j slots, right in k - j; the best for each k.
        auto best_split = [&](int k, int& j_best) {
            j_best = 1;
            double best = DBL_MAX;
            for (int j = 1; j < k; ++j)
                if (l[j - 1] + r[k - j - 1] < best) best = l[j - 1] + r[k - j - 1], j_best = j;
            return best;
        };
        int j;
        const double inner = area + best_split(W, j);
        cost[0] = inner;
        p[0] = 0;
        for (int k = 2; k <= W; ++k) {
            int jk = 0;
            const double split = best_split(k, jk);
            // On a tie the split: one wide node fewer. At k = W the split always
            // wins (no split of fewer slots is cheaper, nor is n as a node, which
            // costs its best split of W slots and more), so p[W - 1] is the split that
            // makes n's children when n becomes a wide node.
            if (split <= cost[k - 2]) {
                cost[k - 1] = split;
                p[k - 1] = std::uint8_t(jk * 8 + (k - jk));
            } else {
                cost[k - 1] = cost[k - 2];
                p[k - 1] = p[k - 2];
            }
        }
    }

    explicit CollapsePlan(const std::vector<BinNode>& b) : bin(b), plan(std::size_t(W) * b.size()) {
        double cost[W];
        if (!b.empty()) solve(0, cost);
    }
};

template <class Node, int W>
struct Collapser {
    const std::vector<BinNode>& bin;
    Chunked<Node>& out;
    const std::uint8_t* plan = nullptr;  // CollapsePlan's, or null: the largest children opened first

    // The binary nodes the plan puts in k slots for the subtree at n.
    void expand(std::uint32_t n, int k, std::uint32_t kids[W], int& count) const {
        const std::uint8_t p = plan[std::size_t(W) * n + std::size_t(k - 1)];
        if (p == 0) {
            kids[count++] = n;
            return;
        }
        expand(n + 1, p >> 3, kids, count);
        expand(bin[n].first, p & 7, kids, count);
    }

    std::uint32_t ref(std::uint32_t i) {
        const BinNode& n = bin[i];
        if (n.count == 0) return make(i);
        return BvhNode::kLeaf | (n.count - 1) << BvhNode::kCountShift | n.first;
    }

    // The binary nodes that become the children of the W-wide node made for the binary
    // inner node i (or for a lone leaf at the root): i's children, then those of the
    // largest inner one among them, until there are W or all are leaves. Their number.
    int gather(std::uint32_t i, std::uint32_t kids[W]) const {
        int k = 0;
        if (bin[i].count > 0) {
            kids[k++] = i;
        } else if (plan) {
            // The plan's W slots for i: always a split (see CollapsePlan::solve).
            const std::uint8_t p = plan[std::size_t(W) * i + std::size_t(W - 1)];
            expand(i + 1, p >> 3, kids, k);
            expand(bin[i].first, p & 7, kids, k);
            return k;
        } else {
            kids[k++] = i + 1;
            kids[k++] = bin[i].first;
        }
        while (k < W) {
            int best = -1;
            double best_area = -1;
            for (int j = 0; j < k; ++j) {
                if (bin[kids[j]].count > 0) continue;
                double a = half_area(bin[kids[j]].b);
                if (a > best_area) best_area = a, best = j;
            }
            if (best < 0) break;
            std::uint32_t n = kids[best];
            kids[best] = n + 1;
            kids[k++] = bin[n].first;
        }
        return k;
    }

    // How many W-wide nodes make() makes for node i: room for them is taken at once, in
    // one block, with nothing to copy or give back afterwards.
    std::size_t count(std::uint32_t i) const {
        std::uint32_t kids[W];
        const int k = gather(i, kids);
        std::size_t n = 1;
        for (int j = 0; j < k; ++j)
            if (bin[kids[j]].count == 0) n += count(kids[j]);
        return n;
    }

    // A W-wide node for the binary inner node i (or for a lone leaf at the root).
    std::uint32_t make(std::uint32_t i) {
        std::uint32_t kids[W];
        const int k = gather(i, kids);
        std::uint32_t index = std::uint32_t(out.size());
        out.push_back(Node{});
        std::uint32_t refs[W];
        for (int j = 0; j < k; ++j) refs[j] = ref(kids[j]);
        Node& node = out.write(index);
        for (int j = 0; j < W; ++j) {
            for (int a = 0; a < 3; ++a) {
                node.b[a][j] = j < k ? bin[kids[j]].b[a] : FLT_MAX;
                node.b[3 + a][j] = j < k ? bin[kids[j]].b[3 + a] : -FLT_MAX;
            }
            node.child[j] = j < k ? refs[j] : BvhNode::kEmpty;
        }
        return index;
    }
};

template <class Node, int W>
void collapse_into(const std::vector<BinNode>& bin, Chunked<Node>& out, bool by_area) {
    const std::vector<std::uint8_t> plan = by_area ? CollapsePlan<W>(bin).plan : std::vector<std::uint8_t>();
    Collapser<Node, W> c{bin, out, by_area ? plan.data() : nullptr};
    out.reserve(c.count(0));
    c.make(0);
}

// The 4-wide tree and, for the AVX2 path, the 8-wide one, from the binary tree; the
// two side by side when `two_threads`. by_area: the wide nodes CollapsePlan chooses,
// else each node's largest children opened first.
void collapse(const std::vector<BinNode>& bin, Chunked<BvhNode>& nodes, Chunked<BvhNode8>& nodes8,
              bool two_threads, bool by_area) {
    const bool wide = active_isa() == Isa::Avx2;
    two_ways(two_threads && wide, [&](int part) {
        if (part == 0) {
            collapse_into<BvhNode, 4>(bin, nodes, by_area);
        } else if (wide) {
            collapse_into<BvhNode8, 8>(bin, nodes8, by_area);
        }
    });
}

}  // namespace

namespace {

template <class Boxes>
void build_tree(Bvh& bvh, const Boxes& boxes, int threads) {
    Chunked<BvhNode>& nodes = bvh.nodes;
    Chunked<BvhNode8>& nodes8 = bvh.nodes8;
    Shared<std::uint32_t>& items = bvh.items;
    bvh.links = nullptr;
    nodes.clear();
    nodes8.clear();
    items.clear();
    if (threads <= 0) threads = process_pool().size();  // (the pool two_ways runs on)
    // The boxes' records made in two halves side by side, each half's from its own
    // first slot, so that the empty boxes need not be counted first (a pass of its own
    // over them all); only when the lower half had some is the upper one moved down.
    const bool two = threads > 1 && boxes.size() >= kParallelBinItems;
    const std::size_t parts[3] = {0, boxes.size() / 2, boxes.size()};
    if (boxes.empty()) return;
    if (boxes.size() >= BvhNode::kMaxItems &&
        std::size_t(std::count_if(boxes.begin(), boxes.end(), [](const Aabb& b) { return !b.empty(); })) >=
            BvhNode::kMaxItems)
        throw std::length_error("too many objects for the BVH");
    static_assert(std::is_trivially_copyable_v<Rec>, "records are moved as bytes");
    // malloc, not a vector: its zero fill would touch every page before the real
    // values do.
    std::unique_ptr<Rec, void (*)(void*)> rec_mem(static_cast<Rec*>(std::malloc(boxes.size() * sizeof(Rec))),
                                                  std::free);
    if (!rec_mem) throw std::bad_alloc();
    Rec* recs = rec_mem.get();
    advise_huge_pages(recs, boxes.size() * sizeof(Rec));
    std::size_t kept[2] = {0, 0};
    Aabb bounds[2], centres[2];  // per half (unions as exact as one pass: see Bins::merge)
    two_ways(two, [&](int p) {
        Rec* r = recs + parts[p];
        for (std::size_t i = parts[p]; i < parts[p + 1]; ++i) {
            if (boxes[i].empty()) continue;
            *r = {boxes[i], boxes[i].centre(), std::uint32_t(i)};
            bounds[p].grow(boxes[i]);
            centres[p].grow(r++->centre());
        }
        kept[p] = std::size_t(r - (recs + parts[p]));
    });
    if (kept[0] < parts[1] && kept[1] > 0)
        std::memmove(static_cast<void*>(recs + kept[0]), recs + parts[1], kept[1] * sizeof(Rec));
    const std::size_t n = kept[0] + kept[1];
    if (n == 0) return;
    bounds[0].grow(bounds[1]);
    centres[0].grow(centres[1]);
    std::vector<BinNode> bin;
    bin.reserve(2 * n + 1);
    advise_huge_pages(bin.data(), bin.capacity() * sizeof(BinNode));
    std::atomic<int> spare{threads - 1};
    Builder b{recs, n, spare};
    bin.emplace_back();
    b.build(bin, 0, 0, std::uint32_t(n), bounds[0], centres[0], 0);
    // In two halves side by side: reading the ids strides over all the records (80 MB
    // for a million objects), far more than the 4 MB zero fill of the resize.
    items.resize(n);
    std::uint32_t* ids = &items.write(0);
    const std::size_t item_parts[3] = {0, n / 2, n};
    two_ways(two, [&](int p) {
        for (std::size_t i = item_parts[p]; i < item_parts[p + 1]; ++i) ids[i] = recs[i].id;
    });
    rec_mem.reset();
    rt::collapse(bin, nodes, nodes8, threads > 1, false);
}


}  // namespace

void Bvh::build(const std::vector<Aabb>& boxes, int threads) { build_tree(*this, boxes, threads); }
void Bvh::build(const Chunked<Aabb>& boxes, int threads) { build_tree(*this, boxes, threads); }

void Bvh::collapse(const std::vector<BvhBinNode>& bin, int threads) {
    nodes.clear();
    nodes8.clear();
    if (!bin.empty()) rt::collapse(bin, nodes, nodes8, threads > 1, true);
}

}  // namespace rt
