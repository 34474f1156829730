// Checks of a built BVH that several tests share.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "bvh.h"

namespace rt_test {

// Whether every box of the 4-wide tree lies inside the box its parent keeps for it,
// and each leaf's items inside the leaf's box (leaf_ok(slot, box[6]): lo x y z, hi x
// y z). The count of boxes and items that do not.
template <class LeafOk>
int boxes_nested(const rt::Chunked<rt::BvhNode>& nodes, LeafOk leaf_ok) {
    struct At {
        std::uint32_t node;
        float box[6];
    };
    std::vector<At> stack{{0, {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF, HUGE_VALF, HUGE_VALF, HUGE_VALF}}};
    int bad = 0;
    while (!stack.empty()) {
        const At at = stack.back();
        stack.pop_back();
        const rt::BvhNode& n = nodes[at.node];
        for (int i = 0; i < 4; ++i) {
            const std::uint32_t c = n.child[i];
            if (c == rt::BvhNode::kEmpty) continue;
            At child{c, {n.b[0][i], n.b[1][i], n.b[2][i], n.b[3][i], n.b[4][i], n.b[5][i]}};
            for (int k = 0; k < 3; ++k)
                bad += !(child.box[k] >= at.box[k] && child.box[3 + k] <= at.box[3 + k]);
            if (!rt::BvhNode::is_leaf(c)) {
                stack.push_back(child);
                continue;
            }
            for (std::uint32_t s = rt::BvhNode::leaf_first(c); s < rt::BvhNode::leaf_first(c) + rt::BvhNode::leaf_count(c); ++s)
                bad += !leaf_ok(s, child.box);
        }
    }
    return bad;
}

}  // namespace rt_test
