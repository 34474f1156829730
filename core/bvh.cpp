// Binned SAH build (16 bins on the centroid bounds of each axis), falling back to a
// median split when binning cannot separate the items or the tree gets deep. The
// binary tree is then collapsed into 4-wide nodes: each node pulls up the children of
// its largest inner children until it has four.
#include "bvh.h"

#include <algorithm>
#include <cfloat>
#include <numeric>
#include <stdexcept>

namespace rt {
namespace {

// The binary tree the SAH build makes.
struct BinNode {
    float b[6];           // lo x, y, z then hi x, y, z
    std::uint32_t first;  // leaf: first index into items; inner: right child (left is this + 1)
    std::uint32_t count;  // leaf: number of items (> 0); inner: 0
};

constexpr int kBins = 16;
constexpr std::uint32_t kMaxLeaf = 4;
static_assert(kMaxLeaf <= BvhNode::kMaxLeafCount, "leaf sizes fit the child reference");
constexpr int kMaxSahDepth = 48;
constexpr double kObjectCost = 2.0;
// Below this many items leaves may hold single objects; above it, up to kMaxLeaf, which
// keeps big scenes' trees compact (under 64 bytes per object).
constexpr std::size_t kSmallScene = 4096;

// Round a double box outward to float and pad it by a few float ulps of its largest
// coordinate, so that the float slab test (with the ray's origin and inverse
// direction also rounded to float) never misses a box the ray really crosses.
void to_float_box(const Aabb& b, float out[6]) {
    double m = 0;
    for (int k = 0; k < 3; ++k) m = std::max({m, std::fabs(b.lo[k]), std::fabs(b.hi[k])});
    double pad = m * 1e-6 + 1e-30;
    for (int k = 0; k < 3; ++k) {
        float lo = float(b.lo[k] - pad), hi = float(b.hi[k] + pad);
        if (double(lo) > b.lo[k] - pad) lo = std::nextafter(lo, -INFINITY);
        if (double(hi) < b.hi[k] + pad) hi = std::nextafter(hi, INFINITY);
        out[k] = lo;
        out[3 + k] = hi;
    }
}

struct Builder {
    const std::vector<Aabb>& boxes;
    std::vector<Vec3> centres;
    std::vector<std::uint32_t>& items;
    std::vector<BinNode>& nodes;

    Aabb range_bounds(std::uint32_t begin, std::uint32_t end) const {
        Aabb b;
        for (std::uint32_t i = begin; i < end; ++i) b.grow(boxes[items[i]]);
        return b;
    }

    void emit(std::uint32_t index, const Aabb& b) {
        to_float_box(b, nodes[index].b);
    }

    void build(std::uint32_t node, std::uint32_t begin, std::uint32_t end, int depth) {
        Aabb b = range_bounds(begin, end);
        emit(node, b);
        std::uint32_t count = end - begin;
        auto make_leaf = [&] {
            nodes[node].first = begin;
            nodes[node].count = count;
        };
        if (count == 1 || (count <= kMaxLeaf && items.size() > kSmallScene)) return make_leaf();
        Aabb cb;
        for (std::uint32_t i = begin; i < end; ++i) cb.grow(centres[items[i]]);
        Vec3 ext = cb.hi - cb.lo;
        int longest = ext.x > ext.y ? (ext.x > ext.z ? 0 : 2) : (ext.y > ext.z ? 1 : 2);
        std::uint32_t mid = begin;
        // Best split over the bins of all three axes.
        double best = DBL_MAX;
        int best_axis = -1, split = -1;
        if (depth < kMaxSahDepth) {
            for (int axis = 0; axis < 3; ++axis) {
                if (!(ext[axis] > 0)) continue;
                double lo = cb.lo[axis], scale = kBins / ext[axis];
                Aabb bin_box[kBins];
                std::uint32_t bin_count[kBins] = {};
                for (std::uint32_t i = begin; i < end; ++i) {
                    int k = std::min(std::max(int((centres[items[i]][axis] - lo) * scale), 0), kBins - 1);
                    bin_box[k].grow(boxes[items[i]]);
                    ++bin_count[k];
                }
                double left_area[kBins];
                std::uint32_t left_n[kBins];
                Aabb acc;
                std::uint32_t n = 0;
                for (int k = 0; k < kBins; ++k) {
                    acc.grow(bin_box[k]);
                    n += bin_count[k];
                    left_area[k] = acc.area();
                    left_n[k] = n;
                }
                acc = Aabb();
                n = 0;
                for (int k = kBins - 1; k > 0; --k) {
                    acc.grow(bin_box[k]);
                    n += bin_count[k];
                    if (left_n[k - 1] == 0 || n == 0) continue;
                    double cost = left_area[k - 1] * left_n[k - 1] + acc.area() * n;
                    if (cost < best) best = cost, best_axis = axis, split = k - 1;
                }
            }
        }
        int axis = best_axis >= 0 ? best_axis : longest;
        if (best_axis >= 0) {
            // Small leaves are allowed only when splitting would cost more: a box test
            // costs about half an object test.
            double leaf_cost = kObjectCost * b.area() * count;
            double split_cost = b.area() + kObjectCost * best;
            if (count <= kMaxLeaf && !(split_cost < leaf_cost)) return make_leaf();
            double lo = cb.lo[axis], scale = kBins / ext[axis];
            auto it = std::partition(items.begin() + begin, items.begin() + end, [&](std::uint32_t item) {
                return std::min(std::max(int((centres[item][axis] - lo) * scale), 0), kBins - 1) <= split;
            });
            mid = std::uint32_t(it - items.begin());
        } else if (count <= kMaxLeaf) {
            return make_leaf();
        }
        if (mid == begin || mid == end) {
            mid = begin + count / 2;
            std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                             [&](std::uint32_t a, std::uint32_t c) { return centres[a][axis] < centres[c][axis]; });
        }
        std::uint32_t left = std::uint32_t(nodes.size());
        nodes.emplace_back();
        build(left, begin, mid, depth + 1);
        std::uint32_t right = std::uint32_t(nodes.size());
        nodes.emplace_back();
        build(right, mid, end, depth + 1);
        nodes[node].first = right;
        nodes[node].count = 0;
    }
};

double half_area(const float b[6]) {
    double x = double(b[3]) - b[0], y = double(b[4]) - b[1], z = double(b[5]) - b[2];
    return x * y + y * z + z * x;
}

struct Collapser {
    const std::vector<BinNode>& bin;
    std::vector<BvhNode>& out;

    std::uint32_t ref(std::uint32_t i) {
        const BinNode& n = bin[i];
        if (n.count == 0) return make(i);
        return BvhNode::kLeaf | (n.count - 1) << BvhNode::kCountShift | n.first;
    }

    // A 4-wide node for the binary inner node i (or for a lone leaf at the root).
    std::uint32_t make(std::uint32_t i) {
        std::uint32_t kids[4];
        int k = 0;
        if (bin[i].count > 0) {
            kids[k++] = i;
        } else {
            kids[k++] = i + 1;
            kids[k++] = bin[i].first;
        }
        while (k < 4) {
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
        std::uint32_t index = std::uint32_t(out.size());
        out.emplace_back();
        std::uint32_t refs[4];
        for (int j = 0; j < k; ++j) refs[j] = ref(kids[j]);
        BvhNode& node = out[index];
        for (int j = 0; j < 4; ++j) {
            for (int a = 0; a < 3; ++a) {
                node.b[a][j] = j < k ? bin[kids[j]].b[a] : FLT_MAX;
                node.b[3 + a][j] = j < k ? bin[kids[j]].b[3 + a] : -FLT_MAX;
            }
            node.child[j] = j < k ? refs[j] : BvhNode::kEmpty;
        }
        return index;
    }
};

}  // namespace

void Bvh::build(const std::vector<Aabb>& boxes) {
    nodes.clear();
    items.clear();
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].empty()) items.push_back(i);
    if (items.empty()) return;
    if (items.size() >= BvhNode::kMaxItems) throw std::length_error("too many objects for the BVH");
    std::vector<BinNode> bin;
    bin.reserve(2 * items.size() + 1);
    Builder b{boxes, {}, items, bin};
    b.centres.resize(boxes.size());
    for (std::uint32_t i : items) b.centres[i] = boxes[i].centre();
    bin.emplace_back();
    b.build(0, 0, std::uint32_t(items.size()), 0);
    nodes.reserve(bin.size() / 3 + 1);
    Collapser{bin, nodes}.make(0);
    nodes.shrink_to_fit();
}

}  // namespace rt
