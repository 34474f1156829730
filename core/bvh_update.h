// Moving objects without building the BVH again: the moved objects' shapes are
// compiled anew, and the boxes of their leaves and of those leaves' ancestors are
// refitted, in a copy of the geometry that shares every chunk of its arrays but those
// (chunked.h). The tree keeps its shape, so the refit walks up a few dozen nodes per
// moved object and copies their chunks. The rest grows with the scene, if slowly: the
// copy of the geometry takes a pointer per chunk of each of its tables. The world
// around the geometry costs more where it has light buffers (objects times lights + 1
// up to 131,072): a move builds them again. World::update is the way in.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "bvh.h"
#include "scene.h"
#include "world.h"

namespace rt {

struct Geometry;

// Parent links of a BVH (both its 4-wide and 8-wide forms) and the leaf slot of each
// item: what a refit walks. They depend only on the tree's shape, which a refit keeps,
// so one set serves every refitted copy of the tree they were made from.
class BvhLinks {
public:
    BvhLinks(const Bvh& bvh, std::size_t item_count);

    // After boxes[i] changed for each i in `changed`: every box on the way from those
    // items' leaves to the root is made again (a leaf's box from its items' boxes as
    // build() makes it, an inner node's from its children's). False, with `bvh` left
    // unusable, when an item is not in the tree or its box became empty (the caller
    // builds again then). `bvh` must fit().
    bool refit(Bvh& bvh, const Chunked<Aabb>& boxes, const std::vector<std::uint32_t>& changed) const;

    // Changes of the tree's shape, these links following (a copy of the links, whose
    // tables copies share by chunks, for the changed tree; `bvh` must fit() before the
    // first and reshaped() after the last). Whether `item` is in the tree.
    bool holds(std::uint32_t item) const { return item < leaf4_.size() && leaf4_[item].node != kNone; }
    // Takes `item` out of its leaf (the leaf's last item takes its place in bvh.items,
    // the last place then holds Bvh::kRemoved; a leaf left empty becomes an empty slot)
    // and refits the boxes above it. False if it is not in the tree.
    bool remove(Bvh& bvh, const Chunked<Aabb>& boxes, std::uint32_t item);
    // Adds `item` (boxes[item], not empty) as a leaf of its own at the end of bvh.items:
    // in an empty slot of the node reached by going down toward the child whose box
    // grows least, or in a new node there with the leaf it would have entered; the
    // boxes above are refitted. False if the box is empty or the tree is full.
    bool insert(Bvh& bvh, const Chunked<Aabb>& boxes, std::uint32_t item);
    // After remove() and insert(): the sizes of the tree as it is now.
    void reshaped(const Bvh& bvh);

private:
    static constexpr std::uint32_t kNone = 0xffffffffu;
    struct Slot {
        std::uint32_t node = kNone;
        std::uint32_t slot = 0;
    };
    std::size_t nodes4_ = 0, nodes8_ = 0, items_ = 0;
    Chunked<Slot> parent4_, parent8_;  // inner node -> the slot that refers to it
    Chunked<Slot> leaf4_, leaf8_;      // item -> the slot of the leaf holding it
};

// How object obj's compiled records in g compare with `one`, the object compiled alone
// (build_geometry of a scene of it alone).
enum class ObjectRecords { Same, Moved, OtherStructure };
ObjectRecords compare_object(const Geometry& g, std::uint32_t obj, const Geometry& one);
// Writes `one`'s records and box over object obj's in g (their chunks copied first
// where shared); compare_object() must have found the same structure.
void replace_object(Geometry& g, std::uint32_t obj, const Geometry& one);
// Appends `one` (an object compiled alone) as g's object g.object_node.size(): its
// records after g's, their references to one another moved along (the sphere prefix
// grows when g is all of it and `one` a plain sphere). Not into g's BVH.
void append_object(Geometry& g, const Geometry& one);

// previous with the objects in `moved` compiled again from `scene` (each with the same
// structure: moved or otherwise reshaped) and the BVH refitted: a copy that shares all
// but the chunks those writes touched. `links` are used if given (they must fit the
// tree), else the tree's own (Bvh::links), else made; the result keeps them. Null when
// the objects cannot be updated in place (their structure changed, a box became empty,
// an object out of range): compile the scene in full then.
std::shared_ptr<const Geometry> move_objects(const Geometry& previous, const Scene& scene,
                                             const std::vector<std::uint32_t>& moved,
                                             std::shared_ptr<const BvhLinks> links = nullptr);
// The same for objects whose slots in previous (World::slots) are not their numbers in
// the scene: (slot, object) pairs.
std::shared_ptr<const Geometry> move_slots(const Geometry& previous, const Scene& scene,
                                           const std::vector<std::pair<std::uint32_t, std::uint32_t>>& moved,
                                           std::shared_ptr<const BvhLinks> links = nullptr);

}  // namespace rt
