// BVH refit and in-place object updates (see bvh_update.h).
#include "bvh_update.h"

#include <algorithm>
#include <cfloat>
#include <cstring>
#include <type_traits>

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

template <class Node, int W, class Links>
void refit_up(Chunked<Node>& nodes, const Links& parent, std::uint32_t node);

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
    refit_up<Node, W>(nodes, parent, node);
}

// Up the tree from `node`: each box the union of its node's (already conservative)
// child boxes. A box that comes out as it was ends the walk: nothing above it changes.
template <class Node, int W, class Links>
void refit_up(Chunked<Node>& nodes, const Links& parent, std::uint32_t node) {
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

BvhLinks::BvhLinks(const Bvh& bvh, std::size_t item_count)
    : nodes4_(bvh.nodes.size()), nodes8_(bvh.nodes8.size()), items_(bvh.items.size()) {
    std::vector<std::uint32_t> pn, ps, ln, ls;
    auto pack = [&](Chunked<Slot>& parent, Chunked<Slot>& leaf) {
        parent.reserve(pn.size());
        for (std::size_t i = 0; i < pn.size(); ++i) parent.push_back({pn[i], ps[i]});
        leaf.reserve(ln.size());
        for (std::size_t i = 0; i < ln.size(); ++i) leaf.push_back({ln[i], ls[i]});
    };
    link_tree<BvhNode, 4>(bvh.nodes, bvh.items, item_count, pn, ps, ln, ls);
    pack(parent4_, leaf4_);
    if (!bvh.nodes8.empty()) {
        link_tree<BvhNode8, 8>(bvh.nodes8, bvh.items, item_count, pn, ps, ln, ls);
        pack(parent8_, leaf8_);
    }
}

bool BvhLinks::refit(Bvh& bvh, const Chunked<Aabb>& boxes, const std::vector<std::uint32_t>& changed) const {
    // (Sizes only: the caller hands in links of this tree or of one it was refitted
    // from, and the walk below stays inside the arrays whatever the tree.)
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

template <class Node, int W>
Node empty_node() {
    Node n;
    for (int i = 0; i < W; ++i) {
        for (int k = 0; k < 3; ++k) n.b[k][i] = FLT_MAX, n.b[3 + k][i] = -FLT_MAX;
        n.child[i] = BvhNode::kEmpty;
    }
    return n;
}

std::uint32_t leaf_ref(std::uint32_t first, std::uint32_t count) {
    return BvhNode::kLeaf | (count - 1) << BvhNode::kCountShift | first;
}

// One tree's part of BvhLinks::remove(): the leaf that held items [first, first +
// count) holds one fewer (or none), its box and those above made again.
template <class Node, int W, class Links>
void remove_from_tree(Chunked<Node>& nodes, const Shared<std::uint32_t>& items, const Chunked<Aabb>& boxes,
                      const Links& parent, std::uint32_t node, std::uint32_t slot, std::uint32_t first,
                      std::uint32_t count) {
    Node& n = nodes.write(node);
    if (count == 1) {
        n.child[slot] = BvhNode::kEmpty;
        const float none[6] = {FLT_MAX, FLT_MAX, FLT_MAX, -FLT_MAX, -FLT_MAX, -FLT_MAX};
        set_box<Node, W>(n, slot, none);
    } else {
        n.child[slot] = leaf_ref(first, count - 1);
        Aabb b;
        for (std::uint32_t k = first; k < first + count - 1; ++k) b.grow(boxes[items[k]]);
        float fb[6];
        to_float_box(b, fb);
        set_box<Node, W>(n, slot, fb);
    }
    refit_up<Node, W>(nodes, parent, node);
}

// The surface area of a float box, half of it (for comparisons).
double half_area(const float b[6]) {
    const double x = double(b[3]) - b[0], y = double(b[4]) - b[1], z = double(b[5]) - b[2];
    return x * y + y * z + z * x;
}

// One tree's part of BvhLinks::insert(): the leaf `ref` (box fb) of `item` placed.
template <class Node, int W, class Links>
void insert_into_tree(Chunked<Node>& nodes, const Shared<std::uint32_t>& items, Links& parent, Links& leaf,
                      std::uint32_t item, std::uint32_t ref, const float fb[6]) {
    using Slot = std::decay_t<decltype(leaf[0])>;
    if (nodes.empty()) {
        nodes.push_back(empty_node<Node, W>());
        parent.push_back(Slot{});
    }
    std::uint32_t node = 0;
    for (;;) {
        const Node& n = nodes[node];
        int free = -1;
        for (int i = 0; i < W && free < 0; ++i)
            if (n.child[i] == BvhNode::kEmpty) free = i;
        if (free >= 0) {
            Node& w = nodes.write(node);
            w.child[free] = ref;
            set_box<Node, W>(w, std::uint32_t(free), fb);
            leaf.write(item) = {node, std::uint32_t(free)};
            refit_up<Node, W>(nodes, parent, node);
            return;
        }
        // The child whose box grows least (then the smallest).
        int best = 0;
        double best_growth = HUGE_VAL, best_area = HUGE_VAL;
        for (int i = 0; i < W; ++i) {
            float b[6], u[6];
            for (int k = 0; k < 6; ++k) b[k] = n.b[k][i];
            for (int k = 0; k < 3; ++k) u[k] = std::min(b[k], fb[k]), u[3 + k] = std::max(b[3 + k], fb[3 + k]);
            const double area = half_area(b), growth = half_area(u) - area;
            if (growth < best_growth || (growth == best_growth && area < best_area))
                best = i, best_growth = growth, best_area = area;
        }
        const std::uint32_t c = n.child[best];
        if (!BvhNode::is_leaf(c)) {
            node = c;
            continue;
        }
        // A new node in that leaf's place: the leaf and the new one.
        Node m = empty_node<Node, W>();
        m.child[0] = c;
        for (int k = 0; k < 6; ++k) m.b[k][0] = n.b[k][best];
        m.child[1] = ref;
        set_box<Node, W>(m, 1, fb);
        const std::uint32_t mi = std::uint32_t(nodes.size());
        nodes.push_back(m);
        parent.push_back(Slot{node, std::uint32_t(best)});
        for (std::uint32_t k = BvhNode::leaf_first(c), e = k + BvhNode::leaf_count(c); k < e; ++k)
            leaf.write(items[k]) = {mi, 0};
        leaf.write(item) = {mi, 1};
        nodes.write(node).child[best] = mi;
        refit_up<Node, W>(nodes, parent, mi);
        return;
    }
}

}  // namespace

bool BvhLinks::remove(Bvh& bvh, const Chunked<Aabb>& boxes, std::uint32_t item) {
    if (!holds(item)) return false;
    const Slot at = leaf4_[item];
    const std::uint32_t ref = bvh.nodes[at.node].child[at.slot];
    const std::uint32_t first = BvhNode::leaf_first(ref), count = BvhNode::leaf_count(ref);
    // The leaf's last item in the removed one's place, the last place freed.
    std::uint32_t k = first;
    while (k < first + count && bvh.items[k] != item) ++k;
    if (k == first + count) return false;
    const std::uint32_t last = first + count - 1;
    if (k != last) bvh.items.write(k) = bvh.items[last];
    bvh.items.write(last) = Bvh::kRemoved;
    remove_from_tree<BvhNode, 4>(bvh.nodes, bvh.items, boxes, parent4_, at.node, at.slot, first, count);
    if (!bvh.nodes8.empty() && item < leaf8_.size() && leaf8_[item].node != kNone) {
        const Slot at8 = leaf8_[item];
        remove_from_tree<BvhNode8, 8>(bvh.nodes8, bvh.items, boxes, parent8_, at8.node, at8.slot, first, count);
        leaf8_.write(item) = Slot{};
    }
    leaf4_.write(item) = Slot{};
    return true;
}

bool BvhLinks::insert(Bvh& bvh, const Chunked<Aabb>& boxes, std::uint32_t item) {
    if (item >= boxes.size() || boxes[item].empty() || holds(item) || bvh.items.size() + 1 >= BvhNode::kMaxItems)
        return false;
    float fb[6];
    to_float_box(boxes[item], fb);
    const std::uint32_t ref = leaf_ref(std::uint32_t(bvh.items.size()), 1);
    bvh.items.push_back(item);
    if (leaf4_.size() <= item) leaf4_.resize(item + 1);
    insert_into_tree<BvhNode, 4>(bvh.nodes, bvh.items, parent4_, leaf4_, item, ref, fb);
    // (An 8-wide tree is kept where the build made one: an empty scene's has none.)
    if (!bvh.nodes8.empty()) {
        if (leaf8_.size() <= item) leaf8_.resize(item + 1);
        insert_into_tree<BvhNode8, 8>(bvh.nodes8, bvh.items, parent8_, leaf8_, item, ref, fb);
    }
    return true;
}

void BvhLinks::reshaped(const Bvh& bvh) {
    nodes4_ = bvh.nodes.size();
    nodes8_ = bvh.nodes8.size();
    items_ = bvh.items.size();
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

void append_object(Geometry& g, const Geometry& one) {
    const std::uint32_t node0 = std::uint32_t(g.nodes.size());
    const bool prefix = g.sphere_prefix == g.object_node.size() && g.nodes.size() == g.object_node.size() &&
                        g.spheres.size() == g.object_node.size() && one.sphere_prefix == 1;
    for (std::size_t k = 0; k < one.nodes.size(); ++k) {
        Node n = one.nodes[k];
        switch (n.kind) {
            case NodeKind::Sphere: n.index += std::uint32_t(g.spheres.size()); break;
            case NodeKind::Tetra: n.index += std::uint32_t(g.tetras.size()); break;
            case NodeKind::Cylinder: n.index += std::uint32_t(g.cylinders.size()); break;
            case NodeKind::Torus: n.index += std::uint32_t(g.tori.size()); break;
            case NodeKind::Box: n.index += std::uint32_t(g.boxes.size()); break;
            case NodeKind::Cone: n.index += std::uint32_t(g.cones.size()); break;
            case NodeKind::Xform: n.index += std::uint32_t(g.xforms.size()); break;
            case NodeKind::Instance: n.index += std::uint32_t(g.instances.size()); break;
            case NodeKind::Mesh: n.index += std::uint32_t(g.meshes.size()); break;
            case NodeKind::Csg: n.index += std::uint32_t(g.csgs.size()); break;
        }
        g.nodes.push_back(n);
    }
    for (const SphereG& r : one.spheres) g.spheres.push_back(r);
    for (const TetraG& r : one.tetras) g.tetras.push_back(r);
    for (const CylinderG& r : one.cylinders) g.cylinders.push_back(r);
    for (const TorusG& r : one.tori) g.tori.push_back(r);
    for (const BoxG& r : one.boxes) g.boxes.push_back(r);
    for (const ConeG& r : one.cones) g.cones.push_back(r);
    for (XformG r : one.xforms) {
        r.child += node0;
        g.xforms.push_back(r);
    }
    for (InstanceG r : one.instances) {
        r.root += node0;
        g.instances.push_back(r);
    }
    for (const MeshG& r : one.meshes) g.meshes.push_back(r);
    for (CsgG r : one.csgs) {
        r.left += node0;
        r.right += node0;
        g.csgs.push_back(r);
    }
    g.object_node.push_back(one.object_node[0] + node0);
    g.object_bounds.push_back(one.object_bounds[0]);
    if (prefix) ++g.sphere_prefix;
}

std::shared_ptr<const Geometry> move_slots(const Geometry& previous, const Scene& scene,
                                           const std::vector<std::pair<std::uint32_t, std::uint32_t>>& moved,
                                           std::shared_ptr<const BvhLinks> links) {
    auto g = std::make_shared<Geometry>(previous);
    Scene one;
    std::vector<std::uint32_t> slots;
    slots.reserve(moved.size());
    for (const auto& [slot, obj] : moved) {
        if (obj >= scene.objects.size() || slot >= g->object_bounds.size()) return nullptr;
        if (g->object_bounds[slot].empty()) return nullptr;  // not in the tree
        one.objects.assign(1, scene.objects[obj]);
        const Geometry alone = build_geometry(one, false);
        if (compare_object(*g, slot, alone) == ObjectRecords::OtherStructure) return nullptr;
        replace_object(*g, slot, alone);
        slots.push_back(slot);
    }
    if (!links) links = g->bvh.links;
    if (!links) links = std::make_shared<const BvhLinks>(g->bvh, g->object_bounds.size());
    if (!links->refit(g->bvh, g->object_bounds, slots)) return nullptr;
    g->bvh.links = std::move(links);
    return g;
}

std::shared_ptr<const Geometry> move_objects(const Geometry& previous, const Scene& scene,
                                             const std::vector<std::uint32_t>& moved,
                                             std::shared_ptr<const BvhLinks> links) {
    if (previous.object_node.size() != scene.objects.size()) return nullptr;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    pairs.reserve(moved.size());
    for (std::uint32_t obj : moved) pairs.emplace_back(obj, obj);
    return move_slots(previous, scene, pairs, std::move(links));
}

}  // namespace rt
