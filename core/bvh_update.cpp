// BVH refit and in-place object updates (see bvh_update.h).
#include "bvh_update.h"

#include <algorithm>
#include <cfloat>
#include <cstring>

#include "shapes.h"
#include "world_build.h"

namespace rt {

namespace {

template <class Node, int W>
void link_tree(const Chunked<Node>& nodes, const Shared<std::uint32_t>& items, std::size_t item_count,
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
void set_box(Node& n, std::uint32_t slot, const float b[6]) {
    for (int k = 0; k < 6; ++k) n.b[k][slot] = b[k];
}

// Whether a node's box in `slot` is `b` already.
template <class Node>
bool has_box(const Node& n, std::uint32_t slot, const float b[6]) {
    for (int k = 0; k < 6; ++k)
        if (!(n.b[k][slot] == b[k])) return false;
    return true;
}

// Refits one tree (4- or 8-wide) for one changed item. Only the nodes whose boxes change
// are written (and so only their chunks copied, when the tree is shared).
template <class Node, int W, class Links>
void refit_tree(Chunked<Node>& nodes, const Shared<std::uint32_t>& items, const Chunked<Aabb>& boxes,
                const Links& parent, const Links& leaf, std::uint32_t item) {
    std::uint32_t node = leaf[item].node, slot = leaf[item].slot;
    // The leaf's box as build() makes it: its items' double boxes, rounded outward once.
    std::uint32_t ref = nodes[node].child[slot];
    Aabb b;
    for (std::uint32_t k = BvhNode::leaf_first(ref), e = k + BvhNode::leaf_count(ref); k < e; ++k)
        b.grow(boxes[items[k]]);
    float fb[6];
    to_float_box(b, fb);
    if (has_box(nodes[node], slot, fb)) return;
    set_box<Node, W>(nodes.write(node), slot, fb);
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
        if (has_box(nodes[p], ps, u)) return;
        set_box<Node, W>(nodes.write(p), ps, u);
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

bool BvhLinks::refit(Bvh& bvh, const Chunked<Aabb>& boxes, const std::vector<std::uint32_t>& changed) const {
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

// Object obj's node range in g: [first, end).
void node_range(const Geometry& g, std::uint32_t obj, std::uint32_t& first, std::uint32_t& end) {
    first = g.object_node[obj];
    end = obj + 1 < g.object_node.size() ? g.object_node[obj + 1] : std::uint32_t(g.nodes.size());
}

template <class T>
bool same_record(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

ObjectRecords compare_object(const Geometry& g, std::uint32_t obj, const Geometry& one) {
    std::uint32_t first, end;
    node_range(g, obj, first, end);
    if (end - first != one.nodes.size()) return ObjectRecords::OtherStructure;
    bool same = same_record(g.object_bounds[obj], one.object_bounds[0]);
    for (std::uint32_t k = 0; k < one.nodes.size(); ++k) {
        const Node &to = g.nodes[first + k], &from = one.nodes[k];
        if (to.kind != from.kind) return ObjectRecords::OtherStructure;
        switch (to.kind) {
            case NodeKind::Sphere: same = same && same_record(g.spheres[to.index], one.spheres[from.index]); break;
            case NodeKind::Tetra: same = same && same_record(g.tetras[to.index], one.tetras[from.index]); break;
            case NodeKind::Cylinder: same = same && same_record(g.cylinders[to.index], one.cylinders[from.index]); break;
            case NodeKind::Torus: same = same && same_record(g.tori[to.index], one.tori[from.index]); break;
            case NodeKind::Box: same = same && same_record(g.boxes[to.index], one.boxes[from.index]); break;
            case NodeKind::Cone: same = same && same_record(g.cones[to.index], one.cones[from.index]); break;
            case NodeKind::Instance: {
                // (A definition built with an earlier placement is outside this one's
                // nodes: such a placement is compiled anew.)
                const InstanceG &a = g.instances[to.index], &b = one.instances[from.index];
                if (a.root < first || a.root - first != b.root) return ObjectRecords::OtherStructure;
                same = same && same_record(a.inst, b.inst);
                break;
            }
            case NodeKind::Xform: {
                const XformG &a = g.xforms[to.index], &b = one.xforms[from.index];
                if (a.child - first != b.child) return ObjectRecords::OtherStructure;
                same = same && same_record(a.inst, b.inst);
                break;
            }
            case NodeKind::Mesh: {
                // A moved, rescaled or re-read mesh is compiled anew (its instance's
                // transform and the model's tree are built together); unchanged, it stays.
                const MeshG &a = g.meshes[to.index], &b = one.meshes[from.index];
                if (!same_record(a.instance, b.instance) || a.model != b.model || a.smooth != b.smooth ||
                    a.opaque != b.opaque)
                    return ObjectRecords::OtherStructure;
                break;
            }
            case NodeKind::Csg: {
                const CsgG &a = g.csgs[to.index], &b = one.csgs[from.index];
                // Operands are numbered from the object's first node in both.
                if (a.type != b.type || a.simple != b.simple || a.left - first != b.left || a.right - first != b.right)
                    return ObjectRecords::OtherStructure;
                break;
            }
        }
    }
    return same ? ObjectRecords::Same : ObjectRecords::Moved;
}

void replace_object(Geometry& g, std::uint32_t obj, const Geometry& one) {
    std::uint32_t first, end;
    node_range(g, obj, first, end);
    for (std::uint32_t k = 0; k < one.nodes.size(); ++k) {
        const Node &to = g.nodes[first + k], &from = one.nodes[k];
        switch (to.kind) {
            case NodeKind::Sphere: g.spheres.write(to.index) = one.spheres[from.index]; break;
            case NodeKind::Tetra: g.tetras.write(to.index) = one.tetras[from.index]; break;
            case NodeKind::Cylinder: g.cylinders.write(to.index) = one.cylinders[from.index]; break;
            case NodeKind::Torus: g.tori.write(to.index) = one.tori[from.index]; break;
            case NodeKind::Box: g.boxes.write(to.index) = one.boxes[from.index]; break;
            case NodeKind::Cone: g.cones.write(to.index) = one.cones[from.index]; break;
            case NodeKind::Xform: g.xforms.write(to.index).inst = one.xforms[from.index].inst; break;
            case NodeKind::Instance: g.instances.write(to.index).inst = one.instances[from.index].inst; break;
            case NodeKind::Mesh: g.meshes.write(to.index) = one.meshes[from.index]; break;
            case NodeKind::Csg: break;  // the same structure: compare_object() said so
        }
    }
    g.object_bounds.write(obj) = one.object_bounds[0];
}

std::shared_ptr<const Geometry> move_objects(const Geometry& previous, const Scene& scene,
                                             const std::vector<std::uint32_t>& moved,
                                             std::shared_ptr<const BvhLinks> links) {
    if (previous.object_node.size() != scene.objects.size()) return nullptr;
    auto g = std::make_shared<Geometry>(previous);
    Scene one;
    for (std::uint32_t obj : moved) {
        if (obj >= scene.objects.size()) return nullptr;
        if (g->object_bounds[obj].empty()) return nullptr;  // not in the tree
        one.objects.assign(1, scene.objects[obj]);
        const Geometry alone = build_geometry(one, false);
        if (compare_object(*g, obj, alone) == ObjectRecords::OtherStructure) return nullptr;
        replace_object(*g, obj, alone);
    }
    if (!links) links = g->bvh.links;
    if (!links) links = std::make_shared<const BvhLinks>(g->bvh, g->object_bounds.size());
    if (!links->refit(g->bvh, g->object_bounds, moved)) return nullptr;
    g->bvh.links = std::move(links);
    return g;
}

std::shared_ptr<const World> update_moved_objects(const Scene& scene, const World& previous,
                                                  const std::vector<std::uint32_t>& moved,
                                                  std::shared_ptr<const BvhLinks>& links) {
    if (!previous.geometry) return nullptr;
    // Links handed in are used where they fit this tree; else the tree's own, or new ones.
    if (links && !links->fits(previous.geometry->bvh)) links = nullptr;
    std::shared_ptr<const Geometry> g = move_objects(*previous.geometry, scene, moved, links);
    if (!g) return nullptr;
    links = g->bvh.links;
    SceneDelta delta;
    delta.objects = moved;
    delta.normalize();
    return detail::update_world(previous, scene, delta, std::move(g));
}

}  // namespace rt
