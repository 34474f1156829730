// The parts of making a World that compile_world() (world_compile.cpp) and World::update()
// (world_update.cpp) share: the tables of planes and lights, the glow BVH, the light
// buffers, and the tallies behind World::bounds() and the ray tree's bound. Internal
// to core.
#pragma once

#include <memory>
#include <vector>

#include "shapes.h"
#include "world.h"

namespace rt {

struct World::Tallies {
    // Per chunk of the objects' materials: whether all of them keep radiance_bound's
    // premises, and the largest colour channel of those that scatter.
    struct Materials {
        bool bounded = true;
        double cp = 0;
        bool specular = false;  // some material of the chunk has a highlight (New: specular)
    };
    std::vector<Materials> materials;
    // Per chunk of geometry->object_bounds: the union of its boxes that are not empty.
    std::vector<Aabb> boxes;
    // Per light: the distance from it to the nearest object's box.
    std::vector<double> light_reach;
    Aabb bounds;  // all the objects' boxes and the lights' positions (World::bounds)
};

// Light buffers are made for scenes of up to this many objects times lights (their
// build is serial and must stay well under the BVH's), and hold at most this many
// entries per object on average (and eight per cell).
constexpr std::size_t kLightBufferMaxWork = 1 << 17;
constexpr std::size_t kLightBufferMaxEntries = 64;
// And at most this many cells in all (4 bytes each): many lights over a few objects
// would otherwise take memory out of proportion to the scene.
constexpr std::size_t kLightBufferMaxCells = std::size_t(1) << 24;

namespace detail {

// Cells per face side of a scene's light buffers, for its number of objects.
int light_buffer_cells(std::size_t objects);

// Whether material m keeps radiance_bound's premises (no negative weight, no tint above
// 1, a finite colour); cp grows to its colour's largest channel if it scatters.
bool bounded_material(const ShadeMaterial& m, double& cp);
// Whether a material (or its model file's) has a highlight (New: specular).
bool has_highlight(const ShadeMaterial& m);
// Chunk c of the materials' tally.
World::Tallies::Materials tally_materials(const Chunked<ShadeMaterial>& materials, std::size_t c);
// The union of the boxes of chunk c that are not empty.
Aabb tally_boxes(const Chunked<Aabb>& boxes, std::size_t c);
// The distance from p to the nearest object box (a lower bound of its distance to any
// object): the same value whatever the BVH's shape.
double distance_to_objects(const Geometry& g, const Vec3& p);
// Tallies::light_reach and Tallies::bounds from the rest of the tallies and w's lights.
void tally_lights(World::Tallies& t, const World& w);
// w.radiance_bound and w.omit_weight from w's tables and tallies.
void set_ray_tree_bound(World& w);

// The planes' and lights' tables of `scene` in w (which holds none yet), and which
// lights have glow discs.
void add_planes(World& w, const Scene& scene);
// Adds `more` to w.textures (each texture once).
void keep_textures(World& w, std::vector<std::shared_ptr<const Texture>> more);
void add_lights(World& w, const Scene& scene);
// A light as the tracer uses it.
ShadeLight shade_light(const Light& l);
// World::background, area_lights and highlights from the scene and w's tables (after
// its tallies are made).
void set_features(World& w, const Scene& scene);
// The BVH of many glow discs: the previous world's if its discs are the same.
void add_glow_bvh(World& w, const World* previous);
// The camera's light buffer and the lights', or the previous world's where they serve.
void add_light_buffers(World& w, const Scene& scene, const World* previous);

// World::update(), with the geometry of the moved objects made already (`moved`), or
// made here from what delta.objects names (`moved` null; with `links` as World::update).
std::shared_ptr<const World> update_world(const World& previous, const Scene& scene, const SceneDelta& delta,
                                          std::shared_ptr<const Geometry> moved,
                                          std::shared_ptr<const BvhLinks> links = nullptr);

}  // namespace detail

}  // namespace rt
