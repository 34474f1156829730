// World::update(): a world made from another and a SceneDelta, sharing every table and
// chunk of a table the delta does not touch (see world.h). What compile_world() finds
// in passes over every object is redone here only for the chunks the delta touched
// (World::Tallies), so an edit of one object costs that object, a few chunks and the
// walk of its BVH refit, however many objects the scene holds.
#include <cstring>

#include "bvh_update.h"
#include "shapes.h"
#include "world_build.h"

namespace rt {

namespace {

// Which of the objects named in `changed` moved (compiled records that differ from
// g's); false if one cannot be updated in place (out of range, other structure).
bool find_moved(const Geometry& g, const Scene& scene, const std::vector<std::uint32_t>& changed,
                std::vector<std::uint32_t>& moved) {
    Scene one;
    for (std::uint32_t i : changed) {
        if (i >= scene.objects.size() || i >= g.object_node.size()) return false;
        one.objects.assign(1, scene.objects[i]);
        switch (compare_object(g, i, build_geometry(one, false))) {
            case ObjectRecords::OtherStructure: return false;
            case ObjectRecords::Moved: moved.push_back(i); break;
            case ObjectRecords::Same: break;
        }
    }
    return true;
}

// The objects' materials named in `changed` written where they differ; returns the
// chunks written.
std::vector<std::size_t> update_materials(World& w, const Scene& scene, const std::vector<std::uint32_t>& changed) {
    std::vector<std::size_t> chunks;
    std::vector<std::shared_ptr<const Texture>> textures;
    for (std::uint32_t i : changed) {
        const ShadeMaterial m = ShadeMaterial::of(scene.objects[i]);
        if (scene.objects[i].material.texture_image) textures.push_back(scene.objects[i].material.texture_image);
        static_assert(sizeof(ShadeMaterial) == 13 * sizeof(double) + 3 * 8, "shading materials compare as bytes");
        if (std::memcmp(&m, &w.materials[i], sizeof m) == 0) continue;
        w.materials.write(i) = m;
        const std::size_t c = i >> Chunked<ShadeMaterial>::kShift;
        if (chunks.empty() || chunks.back() != c) chunks.push_back(c);
    }
    // The world keeps what it may point to (the textures it held too: other objects
    // may still name them).
    detail::keep_textures(w, std::move(textures));
    return chunks;
}

// The lights' table of `scene` in w: the entries named in `changed` written (all of
// them when the number of lights changed), and the list of glow discs made again.
// Returns whether anything changed.
bool update_lights(World& w, const Scene& scene, const std::vector<std::uint32_t>& changed) {
    if (scene.lights.size() != w.lights.size()) {
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
        if (was.position == s.position && was.colour == s.colour && was.glow == s.glow && was.radius == s.radius)
            continue;
        w.lights.write(i) = s;
        any = true;
    }
    if (!any) return false;
    w.glows.clear();
    for (std::size_t i = 0; i < w.lights.size(); ++i)
        if (w.lights[i].glow > 0) w.glows.push_back(std::uint32_t(i));
    return true;
}

// The planes' table of `scene` in w, made again (planes are few: each is tested by
// every ray) if any changed.
bool update_planes(World& w, const Scene& scene, const SceneDelta& delta) {
    if (delta.planes.empty() && scene.planes.size() * 2 == w.plane_mats.size()) return false;
    w.planes.clear();
    w.plane_mats.clear();
    detail::add_planes(w, scene);
    return true;
}

}  // namespace

namespace detail {

std::shared_ptr<const World> update_world(const World& previous, const Scene& scene, const SceneDelta& delta,
                                          std::shared_ptr<const Geometry> moved,
                                          std::shared_ptr<const BvhLinks> links) {
    if (delta.everything || !previous.geometry || !previous.tallies || scene.objects.size() != previous.materials.size())
        return nullptr;
    auto w = std::make_shared<World>(previous);
    auto tallies = std::make_shared<World::Tallies>(*previous.tallies);
    if (!moved) {
        std::vector<std::uint32_t> which;
        if (!find_moved(*previous.geometry, scene, delta.objects, which)) return nullptr;
        if (!which.empty() && !(moved = move_objects(*previous.geometry, scene, which, std::move(links)))) return nullptr;
    }
    const bool geometry_changed = moved != nullptr;
    if (geometry_changed) {
        w->geometry = std::move(moved);
        // The boxes' tallies of the chunks the moved objects' boxes are in.
        const Chunked<Aabb>& boxes = w->geometry->object_bounds;
        for (std::size_t c = 0; c < boxes.chunk_count(); ++c)
            if (!boxes.shares_chunk(previous.geometry->object_bounds, c)) tallies->boxes[c] = tally_boxes(boxes, c);
    }
    const std::vector<std::size_t> material_chunks = update_materials(*w, scene, delta.objects);
    for (std::size_t c : material_chunks) tallies->materials[c] = tally_materials(w->materials, c);
    const bool planes_changed = update_planes(*w, scene, delta);
    const bool lights_changed = update_lights(*w, scene, delta.lights);
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
