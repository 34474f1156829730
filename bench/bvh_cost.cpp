// bvh_cost: the surface area cost of a scene's trees, to compare BVH builds without
// timing them. For each tree (the objects' tree, and each mesh model's once), 4- and
// 8-wide: the expected number of wide nodes a ray entering the root tests (each
// node's box area over the root's, summed over the inner nodes) and of leaf items (or
// a mesh's four-triangle blocks) it tests (each leaf's area times its items or blocks),
// and their sum with a node weighing as much as a leaf item. Also the build's time.
//
//   bvh_cost SCENE.txt
#include <chrono>
#include <cstdio>
#include <set>

#include "bench_scene.h"
#include "shapes.h"
#include "triangles.h"
#include "world.h"

namespace {

double half_area(const float lo[3], const float hi[3]) {
    const double x = double(hi[0]) - lo[0], y = double(hi[1]) - lo[1], z = double(hi[2]) - lo[2];
    return x * y + y * z + z * x;
}

template <int W, class Node>
void report(const char* what, const rt::Chunked<Node>& nodes, bool blocks) {
    if (nodes.empty()) return;
    double node_sum = 0, leaf_sum = 0;
    std::size_t inner = 0, leaves = 0, items = 0, slots = 0;
    // The root's box: the union of its children's.
    float rlo[3] = {3e38f, 3e38f, 3e38f}, rhi[3] = {-3e38f, -3e38f, -3e38f};
    for (int i = 0; i < W; ++i) {
        if (nodes[0].child[i] == rt::BvhNode::kEmpty) continue;
        for (int a = 0; a < 3; ++a) {
            rlo[a] = std::min(rlo[a], nodes[0].b[a][i]);
            rhi[a] = std::max(rhi[a], nodes[0].b[3 + a][i]);
        }
    }
    const double root = half_area(rlo, rhi);
    node_sum = 1;
    for (std::size_t n = 0; n < nodes.size(); ++n) {
        const Node& nd = nodes[n];
        ++inner;
        for (int i = 0; i < W; ++i) {
            const std::uint32_t c = nd.child[i];
            if (c == rt::BvhNode::kEmpty) continue;
            ++slots;
            const float lo[3] = {nd.b[0][i], nd.b[1][i], nd.b[2][i]}, hi[3] = {nd.b[3][i], nd.b[4][i], nd.b[5][i]};
            const double a = half_area(lo, hi) / root;
            if (rt::BvhNode::is_leaf(c)) {
                const std::uint32_t k = rt::BvhNode::leaf_count(c);
                const std::uint32_t cost = blocks ? (k + 3) / 4 : k;
                ++leaves;
                items += k;
                leaf_sum += a * cost;
            } else {
                node_sum += a;
            }
        }
    }
    std::printf("%-10s %d-wide: %zu nodes (%.2f slots used), %zu leaves (%.2f items), cost: nodes %.2f + leaves %.2f = %.2f\n",
                what, W, inner, double(slots) / double(inner), leaves, double(items) / double(leaves), node_sum, leaf_sum,
                node_sum + leaf_sum);
}

void report_bvh(const char* what, const rt::Bvh& b, bool blocks) {
    report<4>(what, b.nodes, blocks);
    report<8>(what, b.nodes8, blocks);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bvh_cost SCENE.txt\n");
        return 2;
    }
    int code = 0;
    auto scene = bench::read_scene("bvh_cost", argv[1], code);
    if (!scene) return code;
    const auto t0 = std::chrono::steady_clock::now();
    auto world = rt::compile_world(*scene);
    const auto t1 = std::chrono::steady_clock::now();
    const rt::Geometry& g = *world->geometry;
    std::printf("compile %.3f s\n", std::chrono::duration<double>(t1 - t0).count());
    report_bvh("objects", g.bvh, false);
    std::set<const rt::MeshModel*> seen;
    for (std::size_t i = 0; i < g.meshes.size(); ++i) {
        const rt::MeshModel* m = g.meshes[i].model.get();
        if (!m || !seen.insert(m).second) continue;
        const auto m0 = std::chrono::steady_clock::now();
        const rt::TriangleAccel& acc = m->accel();
        const auto m1 = std::chrono::steady_clock::now();
        std::printf("mesh %s: %zu triangles, %zu slots, accel %.3f s\n", m->path().c_str(), m->data().triangle_count(),
                    acc.ids.size(), std::chrono::duration<double>(m1 - m0).count());
        report_bvh("mesh", acc.bvh, true);
    }
    return 0;
}
