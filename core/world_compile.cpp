// compile_world(): a Scene made into a World, the shapes and BVH and the materials
// (on two threads for a big scene), then the tables, light buffers and tallies, whose
// parts World::update() (world_update.cpp) shares through world_build.h.

#include <algorithm>
#include <cmath>
#include <iterator>

#include "bvh.h"
#include "parallel.h"
#include "shade.h"
#include "shapes.h"
#include "world.h"
#include "world_build.h"

namespace rt {

namespace {

double box_distance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double e = std::max({lo[k] - p[k], 0.0, p[k] - hi[k]});
        d2 += e * e;
    }
    return d2;
}

}  // namespace

namespace detail {

// Branch and bound through the BVH. Its node boxes only prune (they are padded
// outward: their distance is a lower bound too), so the answer is the least distance
// of an object box, whatever the tree.
double distance_to_objects(const Geometry& g, const Vec3& p) {
    const Bvh& bvh = g.bvh;
    double best2 = HUGE_VAL;
    if (bvh.nodes.empty()) return HUGE_VAL;
    std::vector<std::pair<double, std::uint32_t>> todo{{0.0, 0u}};  // (distance², inner node)
    while (!todo.empty()) {
        auto [d2, ref] = todo.back();
        todo.pop_back();
        if (d2 >= best2) continue;
        const BvhNode& n = bvh.nodes[ref];
        for (int i = 0; i < 4; ++i) {
            std::uint32_t c = n.child[i];
            if (c == BvhNode::kEmpty) continue;
            if (BvhNode::is_leaf(c)) {
                std::uint32_t first = BvhNode::leaf_first(c), count = BvhNode::leaf_count(c);
                for (std::uint32_t k = 0; k < count; ++k) {
                    const Aabb& b = g.object_bounds[bvh.items[first + k]];
                    best2 = std::min(best2, box_distance2(p, b.lo, b.hi));
                }
                continue;
            }
            Vec3 lo{n.b[0][i], n.b[1][i], n.b[2][i]}, hi{n.b[3][i], n.b[4][i], n.b[5][i]};
            double cd2 = box_distance2(p, lo, hi);
            if (cd2 < best2) todo.push_back({cd2, c});
        }
    }
    return std::sqrt(best2);
}

bool has_highlight(const ShadeMaterial& m) {
    if (m.specular > 0) return true;
    if (m.file)
        for (const ShadeMaterial& f : m.file->materials)
            if (f.specular > 0) return true;
    return false;
}

bool bounded_material(const ShadeMaterial& m, double& cp) {
    if (!(m.reflection >= 0 && m.refraction >= 0 && m.scattering >= 0)) return false;
    if (m.refraction > 0 && max3(m.log_tint) > 0) return false;  // a tint above 1
    double c = max3(cabs(m.colour));
    if (!std::isfinite(c)) return false;
    // A texel is at most 1, so a texture never brightens the colour.
    if (m.scattering > 0) cp = std::max(cp, c);
    // A highlight adds at most specular times a light's strength, whatever scatters.
    if (m.specular > 0) cp = std::max(cp, (m.scattering > 0 ? c : 0.0) + m.specular);
    if (m.file) {
        for (const ShadeMaterial& f : m.file->materials)
            if (!bounded_material(f, cp)) return false;
        // Vertex colours: linear values of 8 or 16-bit channels, or floats as written.
        if (m.file->vertex_colours) return false;
    }
    return true;
}

World::Tallies::Materials tally_materials(const Chunked<ShadeMaterial>& materials, std::size_t c) {
    World::Tallies::Materials t;
    const ShadeMaterial* m = materials.chunk(c);
    const std::size_t e = materials.chunk_size(c);
    for (std::size_t k = 0; k < e && t.bounded; ++k) t.bounded = bounded_material(m[k], t.cp);
    for (std::size_t k = 0; k < e && !t.specular; ++k) t.specular = has_highlight(m[k]);
    return t;
}

Aabb tally_boxes(const Chunked<Aabb>& boxes, std::size_t c) {
    Aabb u;
    const Aabb* b = boxes.chunk(c);
    for (std::size_t k = 0, e = boxes.chunk_size(c); k < e; ++k)
        if (!b[k].empty()) u.grow(b[k]);
    return u;
}

void tally_lights(World::Tallies& t, const World& w) {
    t.light_reach.clear();
    t.light_reach.reserve(w.lights.size());
    for (const ShadeLight& l : w.lights) t.light_reach.push_back(distance_to_objects(*w.geometry, l.position));
    t.bounds = Aabb{};
    for (const Aabb& b : t.boxes) t.bounds.grow(b);
    for (const ShadeLight& l : w.lights) t.bounds.grow(l.position);
}

}  // namespace detail

namespace {

// An upper bound of the colour any ray can bring back, for the ray tree's bound
// (World::omit_weight); +inf where there is none. Every value a ray returns is a mix,
// with weights summing to 1, of direct light, glow colours, and the values of further
// rays dimmed by tints: so it is bounded by the largest direct light any surface point
// can get, or the brightest glow, provided no weight is negative and no tint brightens.
// Direct light at p is at most sum over lights of |colour| |Cp| / r^2 (rendering.md
// §3), with r at least the light's distance to the nearest surface.
double radiance_bound(const World& w) {
    const double inf = HUGE_VAL;
    const World::Tallies& t = *w.tallies;
    double cp = 0;
    for (const World::Tallies::Materials& m : t.materials) {
        if (!m.bounded) return inf;
        cp = std::max(cp, m.cp);
    }
    for (const ShadeMaterial& m : w.plane_mats)
        if (!detail::bounded_material(m, cp)) return inf;
    double glow = 0, direct = 0;
    for (std::size_t li = 0; li < w.lights.size(); ++li) {
        const ShadeLight& l = w.lights[li];
        double c = max3(cabs(l.colour));
        if (!std::isfinite(c)) return inf;
        if (l.size > 0) glow = std::max(glow, c);
        if (c == 0 || cp == 0) continue;
        double r = t.light_reach[li];
        for (const PlaneShape& pl : w.planes) r = std::min(r, std::fabs(dot(pl.n, l.position) + pl.D));
        // Hit points lie on their surface only to within rounding and the original's
        // surface tolerance.
        r -= 100 * kDelta + 1e-9 * max3(cabs(l.position));
        if (!(r > 0)) return inf;
        direct += c / (r * r);
    }
    return std::max({glow, max3(cabs(w.background)), cp * direct});
}

// The objects' shading materials (made on a thread of their own for a big scene) and
// their chunks' tallies; they do not depend on the geometry.
struct ObjectMaterials {
    Chunked<ShadeMaterial> list;
    std::vector<World::Tallies::Materials> tallies;
    std::vector<std::shared_ptr<const Texture>> textures;  // those the materials name
};

ObjectMaterials make_materials(const Scene& scene) {
    ObjectMaterials made;
    Chunked<ShadeMaterial>& out = made.list;
    const std::size_t n = scene.objects.size();
    out.reserve(n);
    constexpr unsigned kShift = Chunked<ShadeMaterial>::kShift;
    World::Tallies::Materials tally;
    for (std::size_t i = 0; i < n; ++i) {
        // Big scenes repeat a few materials, often alternating: one equal (bit for bit)
        // to either of the last two objects' in its chunk is copied, saving its three
        // logarithms and its check, which gives the same answer (and the same tally as
        // tally_materials(), which checks every one).
        // (A mesh's shading material depends on its model too.)
        const Object& o = scene.objects[i];
        const Material& m = o.material;
        const bool mesh = std::holds_alternative<Mesh>(o.shape);
        std::size_t k = mesh ? 3 : 1;
        for (; k <= 2 && k <= i && (i - k) >> kShift == i >> kShift; ++k)
            if (m.same_bits(scene.objects[i - k].material)) break;
        if (k <= 2 && k <= i && (i - k) >> kShift == i >> kShift) {
            out.push_back(out[i - k]);
        } else {
            if (m.texture_image && (made.textures.empty() || made.textures.back() != m.texture_image))
                made.textures.push_back(m.texture_image);
            out.push_back(ShadeMaterial::of(o));
            if (tally.bounded) tally.bounded = detail::bounded_material(out.back(), tally.cp);
            tally.specular |= detail::has_highlight(out.back());
        }
        if (((i + 1) >> kShift) != (i >> kShift) || i + 1 == n) {
            made.tallies.push_back(tally);
            tally = {};
        }
    }
    return made;
}

std::shared_ptr<const World> finish_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                          ObjectMaterials materials, const World* previous);

}  // namespace

std::shared_ptr<const World> compile_world(const Scene& scene, const World* previous) {
    // For a big scene the materials are made on another of the process pool's threads
    // while the shapes and the BVH are built.
    ObjectMaterials materials;
    std::shared_ptr<const Geometry> geometry;
    two_ways(scene.objects.size() >= 65536, [&](int part) {
        if (part == 1) {
            materials = make_materials(scene);
            return;
        }
        if (previous && previous->geometry && previous->geometry->object_node.size() == scene.objects.size()) {
            // The shapes compiled again are cheap to compare; only the BVH is worth keeping.
            Geometry g = build_geometry(scene, false);
            if (same_shapes(g, *previous->geometry)) {
                geometry = previous->geometry;
            } else {
                g.bvh.build(g.object_bounds);
                geometry = std::make_shared<const Geometry>(std::move(g));
            }
        } else {
            geometry = std::make_shared<const Geometry>(build_geometry(scene));
        }
    });
    return finish_world(scene, std::move(geometry), std::move(materials), previous);
}

std::shared_ptr<const World> compile_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                           const World* previous) {
    return finish_world(scene, std::move(geometry), make_materials(scene), previous);
}

namespace detail {

void keep_textures(World& w, std::vector<std::shared_ptr<const Texture>> more) {
    if (more.empty()) return;
    more.insert(more.end(), w.textures.begin(), w.textures.end());
    std::sort(more.begin(), more.end());
    more.erase(std::unique(more.begin(), more.end()), more.end());
    w.textures = std::move(more);
}

void add_planes(World& w, const Scene& scene) {
    std::vector<std::shared_ptr<const Texture>> textures;
    for (const Plane& p : scene.planes)
        for (const Material* m : {&p.material, &p.material2})
            if (m->texture_image) textures.push_back(m->texture_image);
    keep_textures(w, std::move(textures));
    for (const Plane& p : scene.planes) {
        w.planes.push_back(PlaneShape::from(p));
        w.plane_mats.push_back(ShadeMaterial::from(p.material));
        w.plane_mats.push_back(ShadeMaterial::from(p.chess ? p.material2 : p.material));
    }
}

ShadeLight shade_light(const Light& l) {
    return {l.position, l.colour, l.lamp && l.size > 0 ? l.size : 0.0, l.radius > 0 ? l.radius : 0.0};
}

void set_features(World& w, const Scene& scene) {
    w.background = scene.camera.background;
    w.area_lights = false;
    for (std::size_t c = 0; c < w.lights.chunk_count() && !w.area_lights; ++c) {
        const ShadeLight* l = w.lights.chunk(c);
        for (std::size_t k = 0, e = w.lights.chunk_size(c); k < e; ++k) w.area_lights |= l[k].radius > 0;
    }
    w.highlights = false;
    for (const World::Tallies::Materials& m : w.tallies->materials) w.highlights |= m.specular;
    for (const ShadeMaterial& m : w.plane_mats) w.highlights |= has_highlight(m);
}

void add_lights(World& w, const Scene& scene) {
    w.lights.reserve(scene.lights.size());
    for (const Light& l : scene.lights) {
        if (l.lamp && l.size > 0) w.glows.push_back(std::uint32_t(w.lights.size()));
        w.lights.push_back(shade_light(l));
    }
}

void add_glow_bvh(World& w, const World* previous) {
    w.glow_bvh = nullptr;
    if (w.glows.size() < kGlowBvhMin) return;
    bool same = previous && previous->glow_bvh && previous->glows == w.glows;
    for (std::size_t k = 0; same && k < w.glows.size(); ++k) {
        const ShadeLight &a = w.lights[w.glows[k]], &b = previous->lights[previous->glows[k]];
        same = a.position == b.position && a.size == b.size;
    }
    if (same) {
        w.glow_bvh = previous->glow_bvh;
        return;
    }
    std::vector<Aabb> boxes;
    boxes.reserve(w.glows.size());
    for (std::uint32_t i : w.glows) {
        const ShadeLight& l = w.lights[i];
        Vec3 e{l.size, l.size, l.size};
        boxes.push_back({l.position - e, l.position + e});
    }
    auto bvh = std::make_shared<Bvh>();
    bvh->build(boxes);
    w.glow_bvh = std::move(bvh);
}

}  // namespace detail

namespace {

// A light buffer around each point of `todo`, each on its own, on the process pool's
// threads (a big scene's take tens of milliseconds each; a small one's, microseconds
// on this thread).
std::vector<LightBuffer> build_light_buffers(const Chunked<Aabb>& boxes, const std::vector<Vec3>& todo,
                                             const std::vector<double>& pads, int cells_n) {
    std::vector<LightBuffer> made(todo.size());
    auto one = [&](std::size_t i) { made[i] = LightBuffer::build(boxes, todo[i], cells_n, pads[i]); };
    if (boxes.size() < 4096) {
        for (std::size_t i = 0; i < todo.size(); ++i) one(i);
    } else {
        process_pool().parallel_for(int(todo.size()), [&](int i) { one(std::size_t(i)); });
    }
    return made;
}

}  // namespace

namespace detail {

int light_buffer_cells(std::size_t objects) {
    // Cells enough that a cell holds a few of the objects it may see.
    return std::clamp(2 * int(std::ceil(std::sqrt(double(objects)))), 64, 256);
}

void add_light_buffers(World& w, const Scene& scene, const World* previous) {
    const Chunked<Aabb>& boxes = w.geometry->object_bounds;
    w.light_buffers = nullptr;
    // (By the scene's objects: a world with emptied slots has the buffers of its scene.)
    const std::size_t objects = w.object_count();
    const int cells_n = light_buffer_cells(objects);
    const bool small = objects > 0 && objects * (w.lights.size() + 1) <= kLightBufferMaxWork;
    // The buffers to make: the camera's (index 0) and the lights' (1 + light), unless
    // the previous world's serve.
    std::vector<Vec3> todo;
    std::vector<double> pads;  // each buffer's padding: a sphere light's radius
    std::shared_ptr<const LightBuffer> camera_buffer;
    if (small) {
        // Camera rays all leave from one point too: the same buffer around it serves them.
        if (previous && previous->camera_buffer && previous->geometry == w.geometry &&
            previous->camera_buffer->position == scene.camera.position)
            camera_buffer = previous->camera_buffer;
        else
            todo.push_back(scene.camera.position), pads.push_back(0);
    }
    bool lights_too = small && !w.lights.empty() &&
                      (w.lights.size() + 1) * 6 * std::size_t(cells_n) * std::size_t(cells_n) <= kLightBufferMaxCells;
    if (lights_too) {
        bool same = previous && previous->light_buffers && previous->geometry == w.geometry &&
                    previous->lights.size() == w.lights.size();
        for (std::size_t k = 0; same && k < w.lights.size(); ++k)
            same = w.lights[k].position == previous->lights[k].position &&
                   w.lights[k].radius == previous->lights[k].radius;
        if (same) {
            w.light_buffers = previous->light_buffers;
            lights_too = false;
        } else {
            for (const ShadeLight& l : w.lights) todo.push_back(l.position), pads.push_back(l.radius);
        }
    }
    if (!todo.empty()) {
        std::vector<LightBuffer> made = build_light_buffers(boxes, todo, pads, cells_n);
        std::size_t k = 0;
        if (small && !camera_buffer) camera_buffer = std::make_shared<const LightBuffer>(std::move(made[k++]));
        if (lights_too) w.light_buffers = std::make_shared<const std::vector<LightBuffer>>(
                            std::make_move_iterator(made.begin() + std::ptrdiff_t(k)), std::make_move_iterator(made.end()));
    }
    w.camera_buffer = std::move(camera_buffer);
}

void set_ray_tree_bound(World& w) {
    w.radiance_bound = radiance_bound(w);
    // Half a display step (1/255 of the unit colour) over the brightest possible return.
    // A world that cannot return any colour (nothing lit, no glow) stops at once.
    w.omit_weight = 0;
    if (w.radiance_bound == 0)
        w.omit_weight = HUGE_VAL;
    else if (std::isfinite(w.radiance_bound))
        w.omit_weight = 0.5 / 255 / w.radiance_bound;
}

}  // namespace detail

namespace {

std::shared_ptr<const World> finish_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                          ObjectMaterials materials, const World* previous) {
    auto w = std::make_shared<World>();
    w->geometry = std::move(geometry);
    w->materials = std::move(materials.list);
    detail::keep_textures(*w, std::move(materials.textures));
    detail::add_planes(*w, scene);
    detail::add_lights(*w, scene);
    detail::add_glow_bvh(*w, previous);
    detail::add_light_buffers(*w, scene, previous);
    auto tallies = std::make_shared<World::Tallies>();
    tallies->materials = std::move(materials.tallies);
    const Chunked<Aabb>& boxes = w->geometry->object_bounds;
    tallies->boxes.reserve(boxes.chunk_count());
    for (std::size_t c = 0; c < boxes.chunk_count(); ++c) tallies->boxes.push_back(detail::tally_boxes(boxes, c));
    detail::tally_lights(*tallies, *w);
    w->tallies = std::move(tallies);
    w->background = scene.camera.background;  // (before the bound, which counts it)
    detail::set_ray_tree_bound(*w);
    w->camera = scene.camera;
    detail::set_features(*w, scene);
    w->width = scene.width;
    w->height = scene.height;
    if (previous) w->options = previous->options;
    return w;
}

}  // namespace

std::shared_ptr<const World> with_camera_at(std::shared_ptr<const World> world, const Vec3& position) {
    const LightBuffer* cb = world ? world->camera_buffer.get() : nullptr;
    if (!cb || cb->position == position || world->geometry->object_bounds.size() > kQuickCameraBuffer) return world;
    auto moved = std::make_shared<World>(*world);
    const Chunked<Aabb>& boxes = world->geometry->object_bounds;
    moved->camera_buffer =
        std::make_shared<const LightBuffer>(LightBuffer::build(boxes, position, detail::light_buffer_cells(world->object_count())));
    return moved;
}

}  // namespace rt
