// BVH refit and in-place object updates (see bvh_update.h).
#include "bvh_update.h"

#include <algorithm>
#include <cfloat>

#include "shapes.h"

namespace rt {

namespace {

template <class Node, int W>
void link_tree(const std::vector<Node>& nodes, std::vector<std::uint32_t> const& items, std::size_t item_count,
               std::vector<std::uint32_t>& parent_node, std::vector<std::uint32_t>& parent_slot,
               std::vector<std::uint32_t>& leaf_node, std::vector<std::uint32_t>& leaf_slot) {
    parent_node.assign(nodes.size(), 0xffffffffu);
    parent_slot.assign(nodes.size(), 0);
    leaf_node.assign(item_count, 0xffffffffu);
    leaf_slot.assign(item_count, 0);
    for (std::uint32_t n = 0; n < nodes.size(); ++n)
        for (int i = 0; i < W; ++i) {
            std::uint32_t c = nodes[n].child[i];
            if (c == BvhNode::kEmpty) continue;
            if (BvhNode::is_leaf(c)) {
                std::uint32_t first = BvhNode::leaf_first(c), count = BvhNode::leaf_count(c);
                for (std::uint32_t k = first; k < first + count; ++k) {
                    leaf_node[items[k]] = n;
                    leaf_slot[items[k]] = std::uint32_t(i);
                }
            } else {
                parent_node[c] = n;
                parent_slot[c] = std::uint32_t(i);
            }
        }
}

template <class Node, int W>
bool set_box(Node& n, std::uint32_t slot, const float b[6]) {
    bool same = true;
    for (int k = 0; k < 6; ++k) {
        same = same && n.b[k][slot] == b[k];
        n.b[k][slot] = b[k];
    }
    return !same;
}

// Refits one tree (4- or 8-wide) for one changed item.
template <class Node, int W, class Links>
void refit_tree(std::vector<Node>& nodes, const std::vector<std::uint32_t>& items, const std::vector<Aabb>& boxes,
                const Links& parent, const Links& leaf, std::uint32_t item) {
    std::uint32_t node = leaf[item].node, slot = leaf[item].slot;
    // The leaf's box as build() makes it: its items' double boxes, rounded outward once.
    std::uint32_t ref = nodes[node].child[slot];
    Aabb b;
    for (std::uint32_t k = BvhNode::leaf_first(ref), e = k + BvhNode::leaf_count(ref); k < e; ++k)
        b.grow(boxes[items[k]]);
    float fb[6];
    to_float_box(b, fb);
    if (!set_box<Node, W>(nodes[node], slot, fb)) return;
    // Up the tree: each box the union of its node's (already conservative) child boxes.
    // A box that comes out as it was ends the walk: nothing above it changes either.
    while (parent[node].node != 0xffffffffu) {
        const Node& n = nodes[node];
        float u[6] = {FLT_MAX, FLT_MAX, FLT_MAX, -FLT_MAX, -FLT_MAX, -FLT_MAX};
        for (int i = 0; i < W; ++i) {
            if (n.child[i] == BvhNode::kEmpty) continue;
            for (int k = 0; k < 3; ++k) {
                u[k] = std::min(u[k], n.b[k][i]);
                u[3 + k] = std::max(u[3 + k], n.b[3 + k][i]);
            }
        }
        std::uint32_t p = parent[node].node, ps = parent[node].slot;
        if (!set_box<Node, W>(nodes[p], ps, u)) return;
        node = p;
    }
}

}  // namespace

namespace {

// A fingerprint of a tree's shape: its leaves' items and every child reference. A
// refit keeps it; a build of other boxes (or in another order) almost surely not.
std::uint64_t shape_hash(const Bvh& bvh) {
    std::uint64_t h = 1469598103934665603ull;
    auto add = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
    for (std::uint32_t i : bvh.items) add(i);
    for (const BvhNode& n : bvh.nodes)
        for (std::uint32_t c : n.child) add(c);
    add(bvh.nodes8.size());
    return h;
}

}  // namespace

BvhLinks::BvhLinks(const Bvh& bvh, std::size_t item_count)
    : nodes4_(bvh.nodes.size()), nodes8_(bvh.nodes8.size()), items_(bvh.items.size()), shape_(shape_hash(bvh)) {
    std::vector<std::uint32_t> pn, ps, ln, ls;
    auto pack = [&](std::vector<Slot>& parent, std::vector<Slot>& leaf) {
        parent.resize(pn.size());
        for (std::size_t i = 0; i < pn.size(); ++i) parent[i] = {pn[i], ps[i]};
        leaf.resize(ln.size());
        for (std::size_t i = 0; i < ln.size(); ++i) leaf[i] = {ln[i], ls[i]};
    };
    link_tree<BvhNode, 4>(bvh.nodes, bvh.items, item_count, pn, ps, ln, ls);
    pack(parent4_, leaf4_);
    if (!bvh.nodes8.empty()) {
        link_tree<BvhNode8, 8>(bvh.nodes8, bvh.items, item_count, pn, ps, ln, ls);
        pack(parent8_, leaf8_);
    }
}

bool BvhLinks::fits(const Bvh& bvh) const {
    return bvh.nodes.size() == nodes4_ && bvh.nodes8.size() == nodes8_ && bvh.items.size() == items_ &&
           shape_hash(bvh) == shape_;
}

bool BvhLinks::refit(Bvh& bvh, const std::vector<Aabb>& boxes, const std::vector<std::uint32_t>& changed) const {
    // (Sizes only: the caller has checked fits(), and the walk below stays inside the
    // arrays whatever the tree.)
    if (bvh.nodes.size() != nodes4_ || bvh.nodes8.size() != nodes8_ || bvh.items.size() != items_) return false;
    for (std::uint32_t item : changed) {
        if (item >= leaf4_.size() || leaf4_[item].node == kNone || item >= boxes.size() || boxes[item].empty())
            return false;
        refit_tree<BvhNode, 4>(bvh.nodes, bvh.items, boxes, parent4_, leaf4_, item);
        if (!bvh.nodes8.empty()) refit_tree<BvhNode8, 8>(bvh.nodes8, bvh.items, boxes, parent8_, leaf8_, item);
    }
    return true;
}

namespace {

// Copies object `obj`'s compiled records from `one` (the object compiled alone) into
// g, node for node. False if the two differ in structure.
bool replace_object(Geometry& g, std::uint32_t obj, const Geometry& one) {
    std::uint32_t first = g.object_node[obj];
    std::uint32_t end = obj + 1 < g.object_node.size() ? g.object_node[obj + 1] : std::uint32_t(g.nodes.size());
    if (end - first != one.nodes.size()) return false;
    for (std::uint32_t k = 0; k < one.nodes.size(); ++k) {
        const Node &to = g.nodes[first + k], &from = one.nodes[k];
        if (to.kind != from.kind) return false;
        switch (to.kind) {
            case NodeKind::Sphere: g.spheres[to.index] = one.spheres[from.index]; break;
            case NodeKind::Tetra: g.tetras[to.index] = one.tetras[from.index]; break;
            case NodeKind::Cylinder: g.cylinders[to.index] = one.cylinders[from.index]; break;
            case NodeKind::Torus: g.tori[to.index] = one.tori[from.index]; break;
            case NodeKind::Mesh: g.meshes[to.index] = one.meshes[from.index]; break;
            case NodeKind::Csg: {
                const CsgG &a = g.csgs[to.index], &b = one.csgs[from.index];
                // Operands are numbered from the object's first node in both.
                if (a.type != b.type || a.simple != b.simple || a.left - first != b.left || a.right - first != b.right)
                    return false;
                break;
            }
        }
    }
    g.object_bounds[obj] = one.object_bounds[0];
    return true;
}

}  // namespace

std::shared_ptr<const World> update_moved_objects(const Scene& scene, const World& previous,
                                                  const std::vector<std::uint32_t>& moved,
                                                  std::shared_ptr<const BvhLinks>& links) {
    if (!previous.geometry || previous.geometry->object_node.size() != scene.objects.size()) return nullptr;
    auto g = std::make_shared<Geometry>(*previous.geometry);
    Scene one;
    for (std::uint32_t obj : moved) {
        if (obj >= scene.objects.size()) return nullptr;
        if (g->object_bounds[obj].empty()) return nullptr;  // not in the tree
        one.objects.assign(1, scene.objects[obj]);
        if (!replace_object(*g, obj, build_geometry(one, false))) return nullptr;
    }
    if (!links || !links->fits(g->bvh)) links = std::make_shared<const BvhLinks>(g->bvh, g->object_bounds.size());
    if (!links->refit(g->bvh, g->object_bounds, moved)) return nullptr;
    return compile_world(scene, std::move(g), &previous);
}

}  // namespace rt
