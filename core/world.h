// A scene compiled for tracing: flat primitive arrays, a BVH, normalised materials.
// A world is immutable once made; an edit makes a new one (World::update) that shares
// every table and chunk of table the edit did not touch with the world it came from.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

#include "camera.h"
#include "chunked.h"
#include "math.h"
#include "sampler.h"
#include "scene.h"
#include "scene_delta.h"

namespace rt {

struct Geometry;  // primitives + BVH (shapes.h, bvh.h)
class Bvh;

struct ModelShading;

// Material as the tracer uses it: weights normalised to sum 1 (or all 0).
struct ShadeMaterial {
    double reflection = 0, refraction = 0, scattering = 1;
    double translusans = 0, ior = 1;
    Colour colour{0.5, 0.5, 0.5};
    // log(colour * translusans) per channel (-inf where that is 0): light crossing a
    // length s of the material keeps exp(s * log_tint) of itself.
    Colour log_tint;
    // New: the lights' highlight (Blinn-Phong), added on top of the terms above.
    double specular = 0, shininess = 50;
    // New: the image multiplied into `colour` (null: none, the 2013 look; the scene's
    // Material holds it, and World::textures keeps it alive) and the scene units per
    // repeat of the mappings that have no scale of their own.
    const Texture* texture = nullptr;
    double texture_scale = 1;
    // New: a mesh drawn with its model file's own materials or vertex colours (no
    // material block overrides them): what the file gives, made once per model.
    const ModelShading* file = nullptr;
    static ShadeMaterial from(const Material& m);
    // The material of object `o` as shading uses it (a mesh's with its file's).
    static ShadeMaterial of(const Object& o);
};

// A model file's materials as shading uses them (MeshModel::shading()): per entry of
// MeshData::materials, and whether its vertices' colours colour it.
struct ModelShading {
    std::vector<ShadeMaterial> materials;
    bool vertex_colours = false;
};

// An infinite plane, two-sided for hits, one-sided for shading (normal toward point 4).
struct PlaneShape {
    Vec3 n;
    double D = 0;  // n.x + D = 0 on the plane
    Vec3 p1;
    bool chess = false;
    bool singular = true;  // point 4 in the plane: every cell is material 1
    Vec3 inv_row[3];       // cell coordinates of p - p1
    // New: texture coordinates of p - p1 in scene units: along point 1 -> 2 and, in
    // the plane, along point 1 -> 3 (the axes as they are, not made square).
    Vec3 uv_row[2];
    static PlaneShape from(const Plane& p);
    // 0 for material 1, 1 for material 2.
    int cell(const Vec3& p) const;
};

struct ShadeLight {
    Vec3 position;
    Colour colour;
    double size = 0;  // the lamp's glow-sphere radius (its `size`); 0 = none (a spotlight)
    double radius = 0;  // New: a sphere light of this radius (soft shadows); 0 = a point
};

// The objects a point light sees in each direction, for its shadow rays (a "light
// buffer"): the six faces of a cube around the light, each cut into n x n cells, and
// per cell the objects whose boxes may lie in its directions, with the boxes' least
// distance from the light. A shadow ray tests only its cell's objects nearer than
// its own end: most cells are empty or hold a few, and no tree is walked. Every
// bound is padded outward, so an object a ray can hit is always among them.
struct LightBuffer {
    struct Entry {
        std::uint32_t obj;
        float dmin;  // no point of the object's box is nearer the light than this
    };
    Vec3 position;
    double position1 = 0;               // norm1(position)
    int n = 0;                          // cells per face side; 0: no buffer (use the BVH)
    double reach = 0;                   // use it only while |p|_1 + |light|_1 + r <= reach
    double half_n = 0;                  // n / 2
    std::vector<std::uint32_t> start;   // per cell, its first entry; 6 n n + 1 of them
    std::vector<Entry> entries;
    std::vector<Entry> always;          // objects around or next to the light: every ray's
    // pad > 0: every box grown by it (a sphere light of that radius: a shadow ray from
    // any point of it to p meets only objects of the cell toward p, within its reach).
    static LightBuffer build(const std::vector<Aabb>& boxes, const Vec3& light, int n, double pad = 0);
    static LightBuffer build(const Chunked<Aabb>& boxes, const Vec3& light, int n, double pad = 0);
    // Whether a shadow ray from p (r from the light) may use the buffer: the rounding
    // of its points stays within the cells' padding.
    bool usable(const Vec3& p, double r) const { return usable(norm1(p), r); }
    // The same with p1 = norm1(p), for callers that ask for many lights at one point.
    bool usable(double p1, double r) const { return n > 0 && p1 + position1 + r <= reach; }
    static double norm1(const Vec3& a) { return std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z); }
    // The entries of the cell holding direction d (from the light, not zero).
    void cell(const Vec3& d, const Entry*& first, const Entry*& last) const {
        const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
        // The major axis and the two others in cyclic order, as build() takes them.
        double da, db, dc;
        int face;
        if (ax >= ay && ax >= az) {
            da = ax, db = d.y, dc = d.z, face = d.x < 0;
        } else if (ay >= az) {
            da = ay, db = d.z, dc = d.x, face = 2 + (d.y < 0);
        } else {
            da = az, db = d.x, dc = d.y, face = 4 + (d.z < 0);
        }
        // |db|, |dc| <= da, so db k + hn rounds to no less than -3e-16 hn: its
        // truncation is never negative, and only the top needs a clamp (db = da).
        const double k = half_n / da;
        const unsigned top = unsigned(n - 1);
        unsigned i = std::min(unsigned(int(db * k + half_n)), top);
        unsigned j = std::min(unsigned(int(dc * k + half_n)), top);
        const std::uint32_t* c = start.data() + (std::size_t(face) * n + j) * n + i;
        first = entries.data() + c[0];
        last = entries.data() + c[1];
    }
    // cell(-v) for v toward the light, without negating v: the same cell, bit for bit
    // (-v.x < 0 exactly where v.x > 0, and (-b) k + h rounds as h - b k).
    void cell_toward(const Vec3& v, const Entry*& first, const Entry*& last) const {
        const double ax = std::fabs(v.x), ay = std::fabs(v.y), az = std::fabs(v.z);
        double da, vb, vc;
        int face;
        if (ax >= ay && ax >= az) {
            da = ax, vb = v.y, vc = v.z, face = v.x > 0;
        } else if (ay >= az) {
            da = ay, vb = v.z, vc = v.x, face = 2 + (v.y > 0);
        } else {
            da = az, vb = v.x, vc = v.y, face = 4 + (v.z > 0);
        }
        const double k = half_n / da;
        const unsigned top = unsigned(n - 1);
        unsigned i = std::min(unsigned(int(half_n - vb * k)), top);
        unsigned j = std::min(unsigned(int(half_n - vc * k)), top);
        const std::uint32_t* c = start.data() + (std::size_t(face) * n + j) * n + i;
        first = entries.data() + c[0];
        last = entries.data() + c[1];
    }
};

struct TraceOptions {
    int max_depth = 20;  // the original's recursion limit
};

// When to give up tracing: another thread's flag, a deadline, or both (default never).
struct TraceStop {
    const std::atomic<bool>* flag = nullptr;
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
    // The clock the deadline is read on (null: steady_clock::now), read once a poll
    // while a deadline is set. For tests, whose clock advances by the poll instead of
    // by what a loaded machine makes of a second.
    std::chrono::steady_clock::time_point (*now)() = nullptr;
};

// What one thread's run of traces counts, and how it is stopped. A ray tree can take
// minutes (glass among mirrors at a high depth limit), so the tracer polls `stop` every
// kPollRays rays from inside the tree, not only between traces.
struct RayStats {
    static constexpr std::uint64_t kPollRays = 4096;  // about a millisecond of tracing
    std::uint64_t rays = 0;  // camera + reflected + refracted + shadow rays
    TraceStop stop;          // set by the caller
    // Set by the tracer once it has given up: the colours it returned since are
    // meaningless, and every later trace with these stats returns at once.
    bool stopped = false;
    std::uint64_t next_poll = 0;  // the ray count at which `stop` is polled next
};

struct PickResult;
struct Ray;
class BvhLinks;  // bvh_update.h

class World {
public:
    std::shared_ptr<const Geometry> geometry;
    Chunked<ShadeMaterial> materials;       // per top-level object
    std::vector<PlaneShape> planes;
    std::vector<ShadeMaterial> plane_mats;  // 2 per plane (material 1, material 2)
    Chunked<ShadeLight> lights;
    std::vector<std::uint32_t> glows;       // indices of the lights with a glow disc
    Camera camera;
    int width = 1, height = 1;
    TraceOptions options;
    // The ray tree's bound. A ray's weight is the share of its colour that reaches the
    // pixel: the product of the reflection and refraction weights and tints on its way
    // from the camera. The rays left out of a camera ray's tree weigh less than this in
    // all, so that all they could bring back (at most radiance_bound each) is less than
    // half a display step: no pixel changes by more than that. The lightest rays are
    // left out first, each for a small share of what remains, so the bound holds in a
    // tree of any size. 0: follow every ray.
    double omit_weight = 0;
    double radiance_bound = HUGE_VAL;
    // Glow discs of many lamps in a BVH of their own (null when a loop over them is
    // cheaper): a ray then tests the few discs near it, not every lamp.
    std::shared_ptr<const Bvh> glow_bvh;
    // New: every texture the materials above point to (a model's own are kept by its
    // model, which the geometry holds).
    std::vector<std::shared_ptr<const Texture>> textures;
    // Per light (same index), its light buffer; null or n == 0: shadow rays walk the BVH.
    std::shared_ptr<const std::vector<LightBuffer>> light_buffers;
    // The same around the camera's position, for the rays that leave from it; null if none.
    std::shared_ptr<const LightBuffer> camera_buffer;
    // New: the colour of rays that meet nothing (the camera's `background`), and what
    // the scene uses of the realism keys: sphere lights, highlights. Sphere lights and a
    // lens need each ray's pixel sample (trace_samples).
    Colour background;
    bool area_lights = false, highlights = false;
    // Whether camera rays through `cam` need their pixel samples (trace_samples).
    bool sampled(const CameraBasis& cam) const { return area_lights || cam.lens > 0; }

    // Colour seen along the original's camera ray through pixel (i, j).
    Colour trace_camera(const CameraBasis& cam, double i, double j, RayStats& stats) const;
    Colour trace(const Vec3& origin, const Vec3& dir, int depth, RayStats& stats) const;
    // A camera ray whose direction is already normalize(cam.direction(i, j)): the
    // same colour as trace_camera(cam, i, j), for callers that make many directions
    // in one go (their square roots and divisions then overlap).
    Colour trace_unit(const Vec3& origin, const Vec3& unit_dir, RayStats& stats) const;
    // trace_unit() for each of n unit directions from one origin, into out[0, n): the
    // same colours, for callers that trace a row in one go (the per-ray set-up is done
    // once). Once `stats` has stopped, the remaining colours are black.
    void trace_units(const Vec3& origin, const Vec3* unit_dirs, std::size_t n, RayStats& stats, Colour* out) const;
    // The camera rays of n pixel samples, unit_dirs[k] being the pinhole direction of
    // keys[k]: through a point of the lens and with points on the sphere lights chosen
    // by the sample (sampler.h), so that a sample's colour depends on nothing else.
    // Where sampled(cam) is false, trace_units(cam.origin, ...) (keys are not read).
    void trace_samples(const CameraBasis& cam, const Vec3* unit_dirs, const PixelSample* keys, std::size_t n,
                       RayStats& stats, Colour* out) const;
    // Bounds of all bounded objects (and lamps); empty if there are none. Kept up to
    // date by compile_world() and update(): no pass over the objects.
    Aabb bounds() const;

    // The world of `scene`, which is this world's scene changed as `delta` says: the
    // entries of the items it names are made again and everything else is shared with
    // this world; moved objects have their boxes refitted into the BVH (bvh_update.h).
    // Objects inserted or removed (delta.object_splices) take new slots of the tables
    // and leave theirs empty (World::slots): the tree loses a removed object's item
    // and gains a leaf for an inserted one, without a build; so does an object whose
    // structure changed (or whose box is or was empty). The same world, entry for
    // entry and so picture for picture, as compile_world() makes of `scene`, but for
    // the BVH's shape and the slots' order. Null when it cannot be done that way
    // (delta.everything, lists that do not add up): compile_world() then. `links`, if given, are this
    // world's tree's parent links made elsewhere (BvhLinks of geometry->bvh, say on
    // another thread while nothing moved): a first move then does not make them. They
    // must have been made from this world's tree or from one it was refitted from.
    std::shared_ptr<const World> update(const Scene& scene, const SceneDelta& delta,
                                        std::shared_ptr<const BvhLinks> links = nullptr) const;

    // The objects' places in the tables (geometry, materials, the BVH's items, the light
    // buffers) once update() inserted or removed some: a slot per object of the scene
    // compiled last and per object inserted since, a removed object's slot left empty
    // (no box, out of the tree, a material that adds nothing). Null: slot i is object i.
    struct Slots {
        static constexpr std::uint32_t kNone = 0xffffffffu;
        std::vector<std::uint32_t> slot;    // per object of the scene, its slot
        std::vector<std::uint32_t> object;  // per slot, its object, or kNone
        std::size_t compiled = 0;           // slots made by the compile (the rest inserted)
    };
    std::shared_ptr<const Slots> slots;
    // The scene's number of objects.
    std::size_t object_count() const { return slots ? slots->slot.size() : materials.size(); }
    // Object i's slot (i < object_count()).
    std::uint32_t slot_of(std::size_t i) const { return slots ? slots->slot[i] : std::uint32_t(i); }
    // The object in slot s, or -1 for an empty slot.
    int object_of(std::uint32_t s) const {
        if (!slots) return int(s);
        return s < slots->object.size() && slots->object[s] != Slots::kNone ? int(slots->object[s]) : -1;
    }
    // Objects inserted and removed since the compile: slots the tree holds apart from
    // its build (0 for a compiled world).
    std::size_t spliced() const {
        return slots ? 2 * slots->object.size() - slots->compiled - slots->slot.size() : 0;
    }

    // What compile_world() finds in passes over every object and update() keeps up to
    // date chunk by chunk (per chunk of the object tables): the bounds, the materials'
    // share of the ray tree's bound, and each light's distance to the nearest object.
    struct Tallies;
    std::shared_ptr<const Tallies> tallies;

    struct Ctx;
    struct HitRec;

private:
    Colour trace_from(const Vec3& origin, const Vec3& unit_dir, int depth, RayStats& stats) const;
    void trace_rays(const CameraBasis& cam, const Vec3* unit_dirs, const PixelSample* keys, std::size_t n,
                    RayStats& stats, Colour* out) const;
    bool nearest(const Vec3& o, const Vec3& d, Ctx& ctx, HitRec& h) const;
    Colour shade(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx) const;
    // shade() in two halves around the direct light, so that packets can share them.
    struct Surface;
    [[gnu::always_inline]] bool shade_surface(const Vec3& o, const Vec3& d, int depth, double weight, Ctx& ctx,
                                              Surface& s, Colour& out) const;
    static Colour combine(const Surface& s, const Colour& lit, const Colour& mirror);
    // The AVX2 path traces camera rays four at a time: shade4() shades them as shade()
    // does one, with the four points' direct light found together (direct4), lane by
    // lane the same operations, so the same bits.
    struct Budgets;
    struct ShadowRays4;
    void trace_units4(const CameraBasis& cam, const Vec3* dirs, const PixelSample* keys, std::size_t n, Ctx& ctx,
                      Colour* out) const;
    void shade4(const Vec3 o[4], const Vec3 d[4], unsigned live, int depth, const double weight[4], Budgets& b,
                Colour out[4], Ctx& ctx) const;
    void direct4(const Surface s[4], const Vec3 d[4], unsigned live, Colour out[4], Colour highlight[4], Budgets& b,
                 Ctx& ctx) const;
    unsigned glows_block4(const ShadowRays4& q, unsigned live) const;
    unsigned shadow_lanes(const ShadowRays4& q, const LightBuffer* lb, unsigned in_cell, const std::int32_t* cell,
                          unsigned lit, double (&sh)[3][4], Ctx& ctx) const;
    Colour direct(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const;
    // direct() with the New: terms: sphere lights sampled, and the highlight (seen along
    // d) added to `highlight`.
    Colour direct_sampled(const Vec3& p, const Vec3& n, const Vec3& d, const ShadeMaterial& m, const Colour& cp,
                          Colour& highlight, Ctx& ctx) const;
    template <bool kGlowBvh>
    Colour direct_lights(const Vec3& p, const Vec3& n, const Colour& cp, Ctx& ctx) const;
    struct ShadowRay;
    struct ShadowSearch;
    template <bool kOther = false>
    bool shadow_test(std::uint32_t obj, const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const;
    bool met(std::uint32_t obj, double t, const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const;
    [[gnu::always_inline]] bool objects_block(const ShadowRay& s, double p1, Colour& sh, Ctx& ctx) const;
    bool blocker_blocks(const ShadowRay& s, Ctx& ctx) const;
    [[gnu::always_inline]] bool objects_block_toward(const ShadowRay& s, double p1, const Vec3& toward, double reach,
                                                     Colour& sh, Ctx& ctx) const;
    [[gnu::always_inline]] bool cell_blocks(const ShadowRay& s, const LightBuffer& lb, const LightBuffer::Entry* e,
                                            const LightBuffer::Entry* end, double reach, Colour& sh, Ctx& ctx) const;
    [[gnu::always_inline]] void unblocked(const ShadowRay& s, const ShadowSearch& found, Colour& sh, Ctx& ctx) const;
    [[gnu::noinline]] Colour found_tint(const ShadowRay& s, const ShadowSearch& found, const Colour& sh,
                                        Ctx& ctx) const;
    [[gnu::noinline]] bool objects_block_bvh(const ShadowRay& s, ShadowSearch& found, Ctx& ctx) const;
    [[gnu::noinline]] Colour glass_tint(const ShadowRay& s, Colour sh, Ctx& ctx) const;
    Colour through_glass(std::uint32_t obj, double t, const ShadowRay& s, const Colour& sh, Ctx& ctx) const;
    template <bool kGlowBvh>
    [[gnu::always_inline]] bool others_block(const ShadowRay& s) const;
    Colour walk(const HitRec& x, const Vec3& q0, const Vec3& d1, double eta, int level, double weight,
                Ctx& ctx) const;
    [[gnu::noinline]] void nearest_glow(const Vec3& o, const Vec3& d, HitRec& h) const;
    [[gnu::noinline]] bool glow_blocks(const Vec3& o, const Vec3& dir, double limit) const;
    friend PickResult pick(const World& world, const Ray& ray);

};

// Compile a valid scene. If `previous` has the same geometry, its BVH is reused.
std::shared_ptr<const World> compile_world(const Scene& scene, const World* previous = nullptr);
// The same with the scene's geometry already compiled (moved objects: bvh_update.h).
std::shared_ptr<const World> compile_world(const Scene& scene, std::shared_ptr<const Geometry> geometry,
                                           const World* previous);

// Scenes of up to this many objects get a camera buffer made for a view away from the
// scene's camera (with_camera_at): its build then takes well under what it saves.
constexpr std::size_t kQuickCameraBuffer = 512;
// `world` with its camera buffer (World::camera_buffer) around `position`, for rays
// from a view that moved away from the scene's camera: the same colours, the camera
// rays through the buffer instead of the BVH. Shares every table with `world`; is
// `world` itself when that already has a buffer there, or has none (a big scene), or
// has more than kQuickCameraBuffer objects.
std::shared_ptr<const World> with_camera_at(std::shared_ptr<const World> world, const Vec3& position);

// What lies under a camera ray: the nearest object or plane.
struct PickResult {
    bool hit = false;
    int object = -1;  // index into Scene::objects
    int plane = -1;   // index into Scene::planes
    int light = -1;   // index into Scene::lights (a lamp's glow)
    double t = 0;
    Vec3 point;
};
PickResult pick(const World& world, const Ray& ray);

}  // namespace rt
