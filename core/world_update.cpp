// World::update(): a world made from another and a SceneDelta, sharing every table and
// chunk of a table the delta does not touch (see world.h). What compile_world() finds
// in passes over every object is redone here only for the chunks the delta touched
// (World::Tallies), so an edit of one object costs that object, a few chunks and the
// walk of its BVH refit, however many objects the scene holds.
#include <algorithm>
#include <cstring>
#include <utility>

#include "bvh_update.h"
#include "shapes.h"
#include "world_build.h"

namespace rt {

namespace {

using SlotPairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // (slot, object)

// Which of the objects named in `changed` moved (compiled records that differ from
// g's), and which are compiled anew into new slots (`reslotted`, by object: another
// structure, or a box that is or was empty); false if one is out of range.
bool find_moved(const Geometry& g, const Scene& scene, const SlotPairs& changed, SlotPairs& moved,
                std::vector<std::uint32_t>& reslotted) {
    Scene one;
    for (const auto& [slot, obj] : changed) {
        if (obj >= scene.objects.size() || slot >= g.object_node.size()) return false;
        one.objects.assign(1, scene.objects[obj]);
        const Geometry alone = build_geometry(one, false);
        if (alone.object_bounds[0].empty() || g.object_bounds[slot].empty()) {
            reslotted.push_back(obj);
            continue;
        }
        switch (compare_object(g, slot, alone)) {
            case ObjectRecords::OtherStructure: reslotted.push_back(obj); break;
            case ObjectRecords::Moved: moved.push_back({slot, obj}); break;
            case ObjectRecords::Same: break;
        }
    }
    return true;
}

// The objects' materials named in `changed` written where they differ; returns the
// chunks written.
std::vector<std::size_t> update_materials(World& w, const Scene& scene, const SlotPairs& changed) {
    std::vector<std::size_t> chunks;
    std::vector<std::shared_ptr<const Texture>> textures;
    for (const auto& [slot, obj] : changed) {
        const ShadeMaterial m = ShadeMaterial::of(scene.objects[obj]);
        if (scene.objects[obj].material.texture_image) textures.push_back(scene.objects[obj].material.texture_image);
        static_assert(sizeof(ShadeMaterial) == 13 * sizeof(double) + 3 * 8, "shading materials compare as bytes");
        if (std::memcmp(&m, &w.materials[slot], sizeof m) == 0) continue;
        w.materials.write(slot) = m;
        chunks.push_back(slot >> Chunked<ShadeMaterial>::kShift);
    }
    // The world keeps what it may point to (the textures it held too: other objects
    // may still name them).
    detail::keep_textures(w, std::move(textures));
    return chunks;
}

// The material of an empty slot: no weight, no colour, so that the tallies of the
// ray tree's bound and the features count nothing of it.
ShadeMaterial no_material() {
    ShadeMaterial m;
    m.scattering = 0;
    m.colour = {0, 0, 0};
    return m;
}

// The objects inserted and removed into w (a copy of `previous`) and g (a copy of its
// geometry): `slot` per object of `scene` its slot, or kNone for one inserted; the
// slots `removed` emptied and taken out of the tree, the inserted objects compiled
// into new slots and the tree, w.slots made; the objects `reslotted` (numbered as in
// `scene`) as if removed and inserted again.
// `links` are made to follow the tree. Writes the material chunks written to
// `chunks`. False when the splices do not take previous's objects to scene's.
bool splice_objects(World& w, const World& previous, Geometry& g, const Scene& scene, std::vector<std::uint32_t> slot,
                    std::vector<std::uint32_t> removed, const std::vector<std::uint32_t>& reslotted,
                    std::shared_ptr<const BvhLinks>& links, std::vector<std::size_t>& chunks) {
    constexpr std::uint32_t kNew = World::Slots::kNone;
    const std::size_t before = previous.object_count();
    // Objects compiled anew: out of their slots, into new ones.
    for (std::uint32_t i : reslotted) {
        if (slot[i] != kNew) removed.push_back(slot[i]);
        slot[i] = kNew;
    }
    // The tree follows: links of this tree, copied to change.
    if (!links) links = g.bvh.links;
    if (!links) links = std::make_shared<const BvhLinks>(g.bvh, g.object_bounds.size());
    auto follow = std::make_shared<BvhLinks>(*links);
    const ShadeMaterial none = no_material();
    for (std::uint32_t r : removed) {
        if (follow->holds(r) && !follow->remove(g.bvh, g.object_bounds, r)) return false;
        g.object_bounds.write(r) = Aabb{};
        w.materials.write(r) = none;
        chunks.push_back(r >> Chunked<ShadeMaterial>::kShift);
    }
    Scene one;
    std::vector<std::shared_ptr<const Texture>> textures;
    for (std::size_t i = 0; i < slot.size(); ++i) {
        if (slot[i] != kNew) continue;
        const Object& o = scene.objects[i];
        one.objects.assign(1, o);
        const std::uint32_t s = std::uint32_t(g.object_node.size());
        append_object(g, build_geometry(one, false));
        if (g.object_node.size() != w.materials.size() + 1) return false;
        w.materials.push_back(ShadeMaterial::of(o));
        if (o.material.texture_image) textures.push_back(o.material.texture_image);
        chunks.push_back(s >> Chunked<ShadeMaterial>::kShift);
        slot[i] = s;
        if (!g.object_bounds[s].empty() && !follow->insert(g.bvh, g.object_bounds, s)) return false;
    }
    detail::keep_textures(w, std::move(textures));
    follow->reshaped(g.bvh);
    links = follow;
    g.bvh.links = std::move(follow);
    auto slots = std::make_shared<World::Slots>();
    slots->compiled = previous.slots ? previous.slots->compiled : before;
    slots->object.assign(g.object_node.size(), World::Slots::kNone);
    for (std::size_t i = 0; i < slot.size(); ++i) slots->object[slot[i]] = std::uint32_t(i);
    slots->slot = std::move(slot);
    w.slots = std::move(slots);
    return true;
}

// The lights' table of `scene` in w: the entries named in `changed` written (all of
// them when the number of lights changed), and the list of glow discs made again.
// Returns whether anything changed.
bool update_lights(World& w, const Scene& scene, const SceneDelta& delta) {
    const std::vector<std::uint32_t>& changed = delta.lights;
    if (delta.all_lights || scene.lights.size() != w.lights.size()) {
        w.lights.clear();
        w.glows.clear();
        detail::add_lights(w, scene);
        return true;
    }
    bool any = false;
    for (std::uint32_t i : changed) {
        if (i >= scene.lights.size()) continue;
        const Light& l = scene.lights[i];
        const ShadeLight s = detail::shade_light(l);
        const ShadeLight& was = w.lights[i];
        if (was.position == s.position && was.colour == s.colour && was.size == s.size && was.radius == s.radius)
            continue;
        w.lights.write(i) = s;
        any = true;
    }
    if (!any) return false;
    w.glows.clear();
    for (std::size_t i = 0; i < w.lights.size(); ++i)
        if (w.lights[i].size > 0) w.glows.push_back(std::uint32_t(i));
    return true;
}

// The planes' table of `scene` in w, made again (planes are few: each is tested by
// every ray) if any changed.
bool update_planes(World& w, const Scene& scene, const SceneDelta& delta) {
    if (!delta.all_planes && delta.planes.empty() && scene.planes.size() * 2 == w.plane_mats.size()) return false;
    w.planes.clear();
    w.plane_mats.clear();
    detail::add_planes(w, scene);
    return true;
}

// The slot of each object number before the edit.
std::vector<std::uint32_t> slots_before(const World& previous) {
    if (previous.slots) return previous.slots->slot;
    std::vector<std::uint32_t> slot_of(previous.object_count());
    for (std::size_t i = 0; i < slot_of.size(); ++i) slot_of[i] = std::uint32_t(i);
    return slot_of;
}

// The slot map after the delta's splices (an inserted object has no slot yet); the slots
// of removed objects go to `removed`. False if a splice is out of range or the count does
// not come out as the scene's.
bool splice_slot_map(const SceneDelta& delta, const World& previous, std::size_t count,
                     std::vector<std::uint32_t>& slot_of, std::vector<std::uint32_t>& removed) {
    slot_of = slots_before(previous);
    for (const SceneDelta::Splice& s : delta.object_splices) {
        if (s.insert ? s.at > slot_of.size() : s.at >= slot_of.size()) return false;
        if (s.insert) {
            slot_of.insert(slot_of.begin() + std::ptrdiff_t(s.at), World::Slots::kNone);
        } else {
            if (slot_of[s.at] != World::Slots::kNone) removed.push_back(slot_of[s.at]);
            slot_of.erase(slot_of.begin() + std::ptrdiff_t(s.at));
        }
    }
    return slot_of.size() == count;
}

// The changed objects' materials written, and the tallies of every material chunk written
// (those in `material_chunks` already, and those this writes).
void update_material_tallies(World& w, const Scene& scene, const SlotPairs& changed,
                             std::vector<std::size_t>& material_chunks, World::Tallies& tallies) {
    const std::vector<std::size_t> written = update_materials(w, scene, changed);
    material_chunks.insert(material_chunks.end(), written.begin(), written.end());
    std::sort(material_chunks.begin(), material_chunks.end());
    material_chunks.erase(std::unique(material_chunks.begin(), material_chunks.end()), material_chunks.end());
    tallies.materials.resize(w.materials.chunk_count());
    for (std::size_t c : material_chunks) tallies.materials[c] = detail::tally_materials(w.materials, c);
}

}  // namespace

namespace detail {

std::shared_ptr<const World> update_world(const World& previous, const Scene& scene, const SceneDelta& delta,
                                          std::shared_ptr<const Geometry> moved,
                                          std::shared_ptr<const BvhLinks> links) {
    if (delta.everything || !previous.geometry || !previous.tallies) return nullptr;
    const bool spliced = !delta.object_splices.empty();
    if (spliced ? moved != nullptr : scene.objects.size() != previous.object_count()) return nullptr;
    auto w = std::make_shared<World>(previous);
    auto tallies = std::make_shared<World::Tallies>(*previous.tallies);
    // The objects changed in place, by slot (those the splices insert are new anyway).
    std::vector<std::size_t> material_chunks;
    SlotPairs changed, which;
    std::vector<std::uint32_t> reslotted, slot_of, removed;
    if (spliced && !splice_slot_map(delta, previous, scene.objects.size(), slot_of, removed)) return nullptr;
    changed.reserve(delta.objects.size());
    for (std::uint32_t i : delta.objects) {
        if (i >= scene.objects.size()) return nullptr;
        const std::uint32_t s = spliced ? slot_of[i] : previous.slot_of(i);
        if (s != World::Slots::kNone) changed.push_back({s, i});
    }
    if (!moved && !find_moved(*previous.geometry, scene, changed, which, reslotted)) return nullptr;
    std::shared_ptr<Geometry> edited;  // the geometry, once splices changed it
    if (spliced || !reslotted.empty()) {
        edited = std::make_shared<Geometry>(*previous.geometry);
        if (!spliced) slot_of = slots_before(previous);
        if (!splice_objects(*w, previous, *edited, scene, std::move(slot_of), std::move(removed), reslotted, links,
                            material_chunks))
            return nullptr;
        // (Those compiled anew have their materials made.)
        std::sort(reslotted.begin(), reslotted.end());
        std::size_t k = 0;
        for (const auto& p : changed)
            if (!std::binary_search(reslotted.begin(), reslotted.end(), p.second)) changed[k++] = p;
        changed.resize(k);
    }
    if (!moved) {
        if (!which.empty()) {
            if (!(moved = move_slots(edited ? *edited : *previous.geometry, scene, which, std::move(links))))
                return nullptr;
        } else if (edited) {
            moved = std::move(edited);
        }
    }
    const bool geometry_changed = moved != nullptr;
    if (geometry_changed) {
        w->geometry = std::move(moved);
        // The boxes' tallies of the chunks the moved objects' boxes are in.
        const Chunked<Aabb>& boxes = w->geometry->object_bounds;
        tallies->boxes.resize(boxes.chunk_count());
        for (std::size_t c = 0; c < boxes.chunk_count(); ++c)
            if (!boxes.shares_chunk(previous.geometry->object_bounds, c)) tallies->boxes[c] = tally_boxes(boxes, c);
    }
    update_material_tallies(*w, scene, changed, material_chunks, *tallies);
    const bool planes_changed = update_planes(*w, scene, delta);
    const bool lights_changed = update_lights(*w, scene, delta);
    if (lights_changed) add_glow_bvh(*w, &previous);
    if (geometry_changed || lights_changed || !(scene.camera.position == previous.camera.position))
        add_light_buffers(*w, scene, &previous);
    if (geometry_changed || lights_changed) tally_lights(*tallies, *w);
    w->tallies = std::move(tallies);
    w->background = scene.camera.background;
    if (geometry_changed || lights_changed || planes_changed || !material_chunks.empty() ||
        !(w->background == previous.background))
        set_ray_tree_bound(*w);
    w->camera = scene.camera;
    set_features(*w, scene);
    w->width = scene.width;
    w->height = scene.height;
    return w;
}

}  // namespace detail

std::shared_ptr<const World> World::update(const Scene& scene, const SceneDelta& delta,
                                           std::shared_ptr<const BvhLinks> links) const {
    return detail::update_world(*this, scene, delta, nullptr, std::move(links));
}

}  // namespace rt
