// The BVH build over a model's triangles (see triangles.h): binned SAH on float boxes,
// 32 bytes a triangle (the objects' build takes 80: a 10M-triangle model must build in
// a few hundred MB), four floats at a time, into the binary tree that Bvh::collapse()
// turns into the same wide nodes as the scene's objects. Each node's children's boxes
// are unions of bins and their centre bounds come from the partition, so a node costs
// one binning pass and one partition pass over its triangles. Subtrees (and the
// binning of big nodes) go to another thread while one is spare; each is built apart
// and spliced in where the serial order puts it, so the tree is the same for any
// number of threads.
#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <system_error>
#include <thread>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "pages.h"
#include "parallel.h"
#include "triangles.h"

namespace rt {

namespace {

constexpr int kBins = 16;
constexpr std::uint32_t kLeaf = 4;     // triangles in a block; a leaf always when no more
constexpr std::uint32_t kMaxLeaf = 8;  // triangles in a leaf at most: two blocks
constexpr double kNodeCost = 1.0;      // a node's test, in blocks' tests
constexpr int kMaxSahDepth = 64;
constexpr std::uint32_t kParallelItems = 16384;     // subtrees built on another thread
constexpr std::uint32_t kParallelBinItems = 1u << 16;  // nodes binned in two halves
constexpr std::uint32_t kSmallNode = 32;  // nodes binned in their used bins only
constexpr std::uint32_t kRunBins = 8192;  // nodes binned a run of one bin at a time (smaller: shorter runs)

// Four floats: one SSE2 register, or plain floats where there is none.
#if defined(__SSE2__)
struct F4 {
    __m128 v;
    static F4 load(const float* p) { return {_mm_load_ps(p)}; }
    static F4 all(float x) { return {_mm_set1_ps(x)}; }
    void store(float* p) const { _mm_store_ps(p, v); }
    friend F4 min(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
    friend F4 max(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
    friend F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
    friend F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
    friend F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
    // Truncated to int, lane by lane.
    void truncate(std::int32_t out[4]) const { _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(v)); }
};
#else
struct F4 {
    float v[4];
    static F4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
    static F4 all(float x) { return {{x, x, x, x}}; }
    void store(float* p) const { std::memcpy(p, v, sizeof v); }
    template <class Op>
    static F4 each(F4 a, F4 b, Op op) {
        return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
    }
    friend F4 min(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x < y ? x : y; }); }
    friend F4 max(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x > y ? x : y; }); }
    friend F4 operator+(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x + y; }); }
    friend F4 operator-(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x - y; }); }
    friend F4 operator*(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x * y; }); }
    void truncate(std::int32_t out[4]) const {
        for (int k = 0; k < 4; ++k) out[k] = std::int32_t(v[k]);
    }
};
#endif

// A triangle as the build moves it: its box, with its index in the fourth lanes (low
// and high 16 bits as small whole floats, so that no lane ever holds a denormal or a
// NaN for the arithmetic to trip on). Centres are taken as lo + hi (twice the centre).
struct alignas(16) TRec {
    float lo[4], hi[4];
    std::uint32_t id() const { return std::uint32_t(lo[3]) | std::uint32_t(hi[3]) << 16; }
};

struct Box {
    F4 lo = F4::all(FLT_MAX), hi = F4::all(-FLT_MAX);
    void grow(F4 l, F4 h) { lo = min(lo, l), hi = max(hi, h); }
    void grow(const Box& b) { grow(b.lo, b.hi); }
    // Half the surface area (lanes 0-2); 0 when empty.
    double area() const {
        alignas(16) float l[4], h[4];
        lo.store(l), hi.store(h);
        if (l[0] > h[0]) return 0;
        const double x = double(h[0]) - l[0], y = double(h[1]) - l[1], z = double(h[2]) - l[2];
        return x * y + y * z + z * x;
    }
};
// (Its name outside this file's namespace, where rt::Box, the scene's box, is seen too.)
using BuildBox = Box;

struct Bins {
    Box box[3][kBins];
    std::uint32_t count[3][kBins] = {};
    void merge(const Bins& o) {
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < kBins; ++k) box[a][k].grow(o.box[a][k]), count[a][k] += o.count[a][k];
    }
};

// Which bins a centre falls in, per axis: the same float operations everywhere (the
// binning and the partition must agree).
struct Binner {
    F4 lo, scale;
    Binner(const Box& centres) {
        alignas(16) float l[4], h[4], s[4];
        centres.lo.store(l), centres.hi.store(h);
        // An extent so thin that kBins over it overflows gets one bin: an infinite
        // scale would make 0 * inf = NaN of the centre at `lo`, and a NaN bin number.
        for (int a = 0; a < 4; ++a) {
            s[a] = a < 3 && h[a] > l[a] ? float(kBins) / (h[a] - l[a]) : 0.0f;
            if (!std::isfinite(s[a])) s[a] = 0.0f;
        }
        lo = centres.lo;
        scale = F4::load(s);
    }
    void bins(F4 centre, std::int32_t k[4]) const {
        min(max((centre - lo) * scale, F4::all(0)), F4::all(float(kBins - 1))).truncate(k);
    }
};

void fill_bins(const TRec* recs, std::uint32_t begin, std::uint32_t end, const Binner& binner, Bins& bins) {
    alignas(16) std::int32_t k[4];
    // Neighbouring triangles mostly share their bins: each axis's current bin grows in
    // registers and goes to memory only when the bin changes, not with a load and a
    // store of its box for every triangle (the 10M-triangle build: 9 % faster). Unions
    // taken in another order are the same boxes, up to the sign of a zero, which
    // neither the areas nor the nodes' padded float boxes see: the tree is the same.
    if (end - begin >= kRunBins) {
        const TRec* r = recs + begin;
        const TRec* const e = recs + end;
        Box run[3];
        std::int32_t cur[3];
        std::uint32_t n[3] = {0, 0, 0};
        {
            const F4 lo = F4::load(r->lo), hi = F4::load(r->hi);
            binner.bins(lo + hi, k);
            for (int a = 0; a < 3; ++a) run[a].lo = lo, run[a].hi = hi, cur[a] = k[a], n[a] = 1;
        }
        for (++r; r != e; ++r) {
            const F4 lo = F4::load(r->lo), hi = F4::load(r->hi);
            binner.bins(lo + hi, k);
            for (int a = 0; a < 3; ++a) {
                if (k[a] == cur[a]) {
                    run[a].grow(lo, hi);
                    ++n[a];
                    continue;
                }
                bins.box[a][cur[a]].grow(run[a]);
                bins.count[a][cur[a]] += n[a];
                run[a].lo = lo, run[a].hi = hi, cur[a] = k[a], n[a] = 1;
            }
        }
        for (int a = 0; a < 3; ++a) {
            bins.box[a][cur[a]].grow(run[a]);
            bins.count[a][cur[a]] += n[a];
        }
        return;
    }
    for (const TRec *r = recs + begin, *e = recs + end; r != e; ++r) {
        const F4 lo = F4::load(r->lo), hi = F4::load(r->hi);
        binner.bins(lo + hi, k);
        for (int a = 0; a < 3; ++a) {
            bins.box[a][k[a]].grow(lo, hi);
            ++bins.count[a][k[a]];
        }
    }
}

struct Split {
    int axis = -1, bin = 0;
    double cost = DBL_MAX;
};

// A side's cost counts the blocks its triangles will fill, not the triangles: a leaf
// tests four at once, so splits that leave whole blocks are preferred.
inline double blocks(std::uint32_t n) { return double((n + kLeaf - 1) / kLeaf); }

// The cheapest split between bins on one axis, if cheaper than `best`.
void sweep(const Bins& bins, int axis, Split& best) {
    double left_area[kBins];
    std::uint32_t left_n[kBins];
    Box acc;
    std::uint32_t n = 0;
    for (int k = 0; k < kBins; ++k) {
        acc.grow(bins.box[axis][k]);
        n += bins.count[axis][k];
        left_area[k] = acc.area();
        left_n[k] = n;
    }
    acc = Box();
    n = 0;
    for (int k = kBins - 1; k > 0; --k) {
        acc.grow(bins.box[axis][k]);
        n += bins.count[axis][k];
        if (left_n[k - 1] == 0 || n == 0) continue;
        const double cost = left_area[k - 1] * blocks(left_n[k - 1]) + acc.area() * blocks(n);
        if (cost < best.cost) best = {axis, k - 1, cost};
    }
}

// The bins of a small node: only those its triangles fall in are filled (a bin's
// box is its first triangle's box, then grown: the values an empty box grown by the
// same triangles in the same order has), and `used` marks them per axis.
struct SmallBins {
    Box box[3][kBins];
    std::uint32_t count[3][kBins];
    unsigned used[3] = {0, 0, 0};
    void add(const TRec& r, const Binner& binner) {
        alignas(16) std::int32_t k[4];
        const F4 lo = F4::load(r.lo), hi = F4::load(r.hi);
        binner.bins(lo + hi, k);
        for (int a = 0; a < 3; ++a) {
            const unsigned bit = 1u << k[a];
            if (used[a] & bit) {
                box[a][k[a]].grow(lo, hi);
                ++count[a][k[a]];
            } else {
                used[a] |= bit;
                box[a][k[a]].lo = lo, box[a][k[a]].hi = hi;
                count[a][k[a]] = 1;
            }
        }
    }
};

// sweep() over a small node's bins: the full sweep's candidates between two empty
// bins repeat the cost of the candidate above them (empty bins change neither side),
// and only the first of equal costs is taken, so only the splits just below each used
// bin but the lowest are costed, with the same unions in the same order.
void sweep(const SmallBins& bins, int axis, Split& best) {
    const unsigned used = bins.used[axis];
    if ((used & (used - 1)) == 0) return;  // one bin: no split
    double left_area[kBins];
    std::uint32_t left_n[kBins];
    Box acc;
    std::uint32_t n = 0;
    for (unsigned m = used; m != 0; m &= m - 1) {
        const int k = __builtin_ctz(m);
        acc.grow(bins.box[axis][k]);
        n += bins.count[axis][k];
        left_area[k] = acc.area();
        left_n[k] = n;
    }
    acc = Box();
    n = 0;
    // From the highest used bin down: the split below bin k (left: the used bins under
    // k, whose union is the one at the next used bin below).
    for (unsigned m = used; (m & (m - 1)) != 0;) {
        const int k = 31 - __builtin_clz(m);
        m &= ~(1u << k);
        acc.grow(bins.box[axis][k]);
        n += bins.count[axis][k];
        const int below = 31 - __builtin_clz(m);
        const double cost = left_area[below] * blocks(left_n[below]) + acc.area() * blocks(n);
        if (cost < best.cost) best = {axis, k - 1, cost};
    }
}

// A node's triangles split in two, with each side's box and centre box.
struct Halves {
    std::uint32_t mid;
    Box lb, lcb, rb, rcb;
    double cost = DBL_MAX;  // the SAH split's (blocks times half areas); DBL_MAX for a median split
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
    void give_thread() { spare.fetch_add(1, std::memory_order_relaxed); }

    void bounds(std::uint32_t begin, std::uint32_t end, Box& b, Box& cb) const {
        for (std::uint32_t i = begin; i < end; ++i) {
            const F4 lo = F4::load(recs[i].lo), hi = F4::load(recs[i].hi);
            b.grow(lo, hi);
            const F4 c = lo + hi;
            cb.grow(c, c);
        }
    }

    void bin(std::uint32_t begin, std::uint32_t end, const Binner& binner, Bins& bins) {
        if (end - begin < kParallelBinItems || !take_thread()) return fill_bins(recs, begin, end, binner, bins);
        const std::uint32_t mid = begin + (end - begin) / 2;
        Bins upper;
        struct Give {
            TriBuilder& b;
            ~Give() { b.give_thread(); }
        } give{*this};
        two_ways(true, [&](int part) { fill_bins(recs, part ? mid : begin, part ? end : mid, binner, part ? upper : bins); });
        bins.merge(upper);
    }

    // By the binned SAH where it separates the triangles; else at the median of the
    // widest centre axis (or in half, when all centres coincide).
    Halves split(std::uint32_t begin, std::uint32_t end, const Box& cb, int depth) {
        if (depth < kMaxSahDepth) {
            const Binner binner(cb);
            Split s;
            Halves h;
            if (end - begin <= kSmallNode) {
                SmallBins bins;
                for (std::uint32_t i = begin; i < end; ++i) bins.add(recs[i], binner);
                for (int a = 0; a < 3; ++a) sweep(bins, a, s);
                if (s.axis >= 0 && sah_halves(begin, end, binner, s, bins.box[s.axis], bins.used[s.axis], h)) return h;
            } else {
                Bins bins;
                bin(begin, end, binner, bins);
                for (int a = 0; a < 3; ++a) sweep(bins, a, s);
                if (s.axis >= 0 && sah_halves(begin, end, binner, s, bins.box[s.axis], 0xFFFFu, h)) return h;
            }
        }
        return median_halves(begin, end, cb);
    }

    // The triangles partitioned at the split `s` found with `binner`, each side's box
    // the union of its bins (those in `used`, in order). False if one side is empty.
    bool sah_halves(std::uint32_t begin, std::uint32_t end, const Binner& binner, const Split& s, const Box* boxes,
                    unsigned used, Halves& h) {
        const int axis = s.axis;
        // The bin on `axis` as Binner::bins() finds it: the same float operations.
        alignas(16) float lo[4], scale[4];
        binner.lo.store(lo), binner.scale.store(scale);
        const float l = lo[axis], sc = scale[axis];
        TRec* mid = std::partition(recs + begin, recs + end, [&](const TRec& r) {
            const F4 c = F4::load(r.lo) + F4::load(r.hi);
            const float x = std::min(std::max((r.lo[axis] + r.hi[axis] - l) * sc, 0.0f), float(kBins - 1));
            const bool left = std::int32_t(x) <= s.bin;
            (left ? h.lcb : h.rcb).grow(c, c);
            return left;
        });
        h.mid = std::uint32_t(mid - recs);
        for (int b = 0; b < kBins; ++b)
            if (used >> b & 1) (b <= s.bin ? h.lb : h.rb).grow(boxes[b]);
        h.cost = s.cost;
        return h.mid != begin && h.mid != end;
    }

    // At the median of the widest centre axis (or in half, when all centres coincide).
    Halves median_halves(std::uint32_t begin, std::uint32_t end, const Box& cb) {
        Halves h;
        alignas(16) float l[4], hh[4];
        cb.lo.store(l), cb.hi.store(hh);
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (hh[a] - l[a] > hh[axis] - l[axis]) axis = a;
        h.mid = begin + (end - begin) / 2;
        if (hh[axis] > l[axis])
            std::nth_element(recs + begin, recs + h.mid, recs + end, [axis](const TRec& a, const TRec& b) {
                return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis];
            });
        bounds(begin, h.mid, h.lb, h.lcb);
        bounds(h.mid, end, h.rb, h.rcb);
        return h;
    }

    static void set_box(BvhBinNode& n, const Box& b) {
        alignas(16) float l[4], h[4];
        b.lo.store(l), b.hi.store(h);
        Aabb a;
        a.lo = {l[0], l[1], l[2]};
        a.hi = {h[0], h[1], h[2]};
        to_float_box(a, n.b);
    }

    // The subtree over [begin, end), whose box is b and centre box cb, with its root
    // at out[node], in preorder (see BvhBinNode).
    void build(std::vector<BvhBinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end, const Box& b,
               const Box& cb, int depth) {
        set_box(out[node], b);
        if (end - begin <= kLeaf) {
            out[node].first = begin;
            out[node].count = end - begin;
            return;
        }
        const Halves h = split(begin, end, cb, depth);
        // Two blocks in one leaf where the SAH finds that cheaper than a node over two
        // leaves (a node's test costing about a block's).
        if (end - begin <= kMaxLeaf && h.cost >= b.area() * (blocks(end - begin) - kNodeCost)) {
            out[node].first = begin;
            out[node].count = end - begin;
            return;
        }
        out[node].count = 0;
        if (end - begin >= kParallelItems && take_thread()) return build_apart(out, node, begin, end, h, depth + 1);
        const std::uint32_t left = std::uint32_t(out.size());
        out.emplace_back();
        build(out, left, begin, h.mid, h.lb, h.lcb, depth + 1);
        const std::uint32_t right = std::uint32_t(out.size());
        out.emplace_back();
        build(out, right, h.mid, end, h.rb, h.rcb, depth + 1);
        out[node].first = right;
    }

    // The right subtree beside the left one (on another of the pool's threads), into
    // its own array, then copied in after the left one (built in place).
    void build_apart(std::vector<BvhBinNode>& out, std::uint32_t node, std::uint32_t begin, std::uint32_t end,
                     const Halves& h, int depth) {
        std::vector<BvhBinNode> right(1);
        right.reserve((end - h.mid) / 2 + 16);
        two_ways(true, [&](int part) {
            if (part == 1) {
                build(right, 0, h.mid, end, h.rb, h.rcb, depth);
                give_thread();  // (a throw ends the whole build)
                return;
            }
            const std::uint32_t left = std::uint32_t(out.size());
            out.emplace_back();
            build(out, left, begin, h.mid, h.lb, h.lcb, depth);
        });
        const std::uint32_t offset = std::uint32_t(out.size());
        out[node].first = offset;
        out.insert(out.end(), right.begin(), right.end());
        for (std::size_t i = offset; i < out.size(); ++i)
            if (out[i].count == 0) out[i].first += offset;
    }
};

// The leaves' triangles in the leaves' order, four slots to a block and one or two
// blocks to a leaf (unused slots 0),
// and the leaves then naming their slots: all the blocks need of the records, which can
// go before the blocks are made.
void number_slots(TriangleAccel& acc, std::vector<BvhBinNode>& bin, const TRec* recs) {
    std::size_t slots = 0;
    for (const BvhBinNode& b : bin) slots += 4 * std::size_t(blocks(b.count));
    if (slots >= BvhNode::kMaxItems) throw std::length_error("too many triangles for the BVH");
    acc.ids.assign(slots, 0);
    std::uint32_t slot = 0;
    for (BvhBinNode& b : bin) {
        if (b.count == 0) continue;
        for (std::uint32_t l = 0; l < b.count; ++l) acc.ids[slot + l] = recs[b.first + l].id();
        b.first = slot;
        slot += 4 * std::uint32_t(blocks(b.count));
    }
}

// Each leaf's triangles into blocks of its own (one or two), from the slots' triangles.
void fill_blocks(TriangleAccel& acc, const BvhBinNode* begin, const BvhBinNode* end, const MeshData& m) {
    const float* p = m.positions.data();
    for (const BvhBinNode* n = begin; n != end; ++n) {
        const BvhBinNode& b = *n;
        if (b.count == 0) continue;
        for (std::uint32_t l = 0; l < b.count; ++l) {
            TriBlock& tb = acc.blocks[(b.first + l) / 4];
            const std::uint32_t id = acc.ids[b.first + l];
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) tb.v[3 * k + a][l & 3] = p[3 * m.triangles[3 * std::size_t(id) + k] + a];
        }
    }
}

// All the leaves' blocks (zero in unused lanes): the leaves of each half of the tree
// on a thread of their own.
void fill_blocks(TriangleAccel& acc, const std::vector<BvhBinNode>& bin, const MeshData& m, bool two_threads) {
    acc.blocks.resize(acc.ids.size() / 4);
    two_ways(two_threads, [&](int part) {
        const std::size_t half = bin.size() / 2;
        fill_blocks(acc, bin.data() + (part ? half : 0), bin.data() + (part ? bin.size() : half), m);
    });
}

// The records of triangles [begin, end).
void make_records(const MeshData& m, TRec* recs, std::size_t begin, std::size_t end) {
    const float* p = m.positions.data();
    for (std::size_t t = begin; t < end; ++t) {
        const std::uint32_t* v = &m.triangles[3 * t];
        TRec& r = recs[t];
        for (int a = 0; a < 3; ++a) {
            const float x = p[3 * v[0] + a], y = p[3 * v[1] + a], z = p[3 * v[2] + a];
            r.lo[a] = std::min({x, y, z});
            r.hi[a] = std::max({x, y, z});
        }
        r.lo[3] = float(t & 0xffff);
        r.hi[3] = float(t >> 16);
    }
}

}  // namespace

TriangleAccel TriangleAccel::build(const MeshData& m, int threads) {
    TriangleAccel acc;
    const std::size_t n = m.triangle_count();
    if (n == 0) return acc;
    if (n > ModelLimits::max_triangles) throw std::length_error("too many triangles for the BVH");
    if (threads <= 0) threads = process_pool().size();  // (the pool two_ways runs on)
    // Pages of their own, given back before the blocks are made (pages.h).
    PageBuffer mem(n * sizeof(TRec));
    TRec* recs = reinterpret_cast<TRec*>(mem.data());
    std::atomic<int> spare{threads - 1};
    TriBuilder builder{recs, spare};
    // The records and their bounds, a half on each of two threads (the bounds' union
    // is the same either way).
    BuildBox b, cb, half_b, half_cb;
    const std::size_t mid = n / 2;
    two_ways(threads > 1 && n >= kParallelItems, [&](int part) {
        const std::size_t begin = part ? mid : 0, end = part ? n : mid;
        make_records(m, recs, begin, end);
        builder.bounds(std::uint32_t(begin), std::uint32_t(end), part ? half_b : b, part ? half_cb : cb);
    });
    b.grow(half_b);
    cb.grow(half_cb);
    // Room for the tree the build usually makes (leaves of three or four triangles and
    // as many inner nodes), so that it seldom moves; the pages not used cost nothing.
    std::vector<BvhBinNode> bin(1);
    bin.reserve(n * 2 / 3 + 16);
    builder.build(bin, 0, 0, std::uint32_t(n), b, cb, 0);
    number_slots(acc, bin, recs);
    mem.reset();
    fill_blocks(acc, bin, m, threads > 1 && n >= kParallelItems);
    acc.bvh.collapse(bin, threads);
    return acc;
}

}  // namespace rt
