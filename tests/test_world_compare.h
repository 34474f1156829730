// Two compiled worlds compared the way World::update promises them equal (core/world.h):
// every table bit for bit (the BVH's shape aside), and the same pictures (the films
// byte for byte, and the colours of a grid of camera rays, on each instruction-set
// path the processor runs). Shared by the core's and the viewer's tests.
#pragma once

#include <doctest/doctest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "renderer.h"
#include "shapes.h"
#include "simd.h"
#include "world.h"

namespace rt_test {

using namespace rt;

// (Empty tables may have no storage at all: memcmp must not see their null pointers.)
inline bool same_bytes(const void* a, const void* b, std::size_t n) { return n == 0 || std::memcmp(a, b, n) == 0; }

inline bool same_buffer(const LightBuffer* a, const LightBuffer* b) {
    if (!a || !b) return a == b;
    auto entries = [](const std::vector<LightBuffer::Entry>& x, const std::vector<LightBuffer::Entry>& y) {
        if (x.size() != y.size()) return false;
        for (std::size_t k = 0; k < x.size(); ++k)
            if (x[k].obj != y[k].obj || !same_bytes(&x[k].dmin, &y[k].dmin, sizeof(float))) return false;
        return true;
    };
    return a->position == b->position && a->n == b->n && same_bytes(&a->reach, &b->reach, sizeof(double)) &&
           a->start == b->start && entries(a->entries, b->entries) && entries(a->always, b->always);
}

// Every table of `got` equals `want`'s, bit for bit (the BVH aside: only its shape may
// differ). Where either took inserted or removed objects (World::slots), per object
// through the slots: their materials and boxes, and the light buffers' sizes (their
// entries name slots).
inline void check_same_world(const World& got, const World& want) {
    const bool slotted = got.slots || want.slots;
    if (!slotted) {
        CHECK(same_shapes(*got.geometry, *want.geometry));
        CHECK(same_bits(got.materials, want.materials));
    } else {
        REQUIRE(got.object_count() == want.object_count());
        for (std::size_t i = 0; i < got.object_count(); ++i) {
            CAPTURE(i);
            const std::uint32_t a = got.slot_of(i), b = want.slot_of(i);
            CHECK(same_bytes(&got.materials[a], &want.materials[b], sizeof(ShadeMaterial)));
            CHECK(same_bytes(&got.geometry->object_bounds[a], &want.geometry->object_bounds[b], sizeof(Aabb)));
        }
    }
    REQUIRE(got.planes.size() == want.planes.size());
    for (std::size_t k = 0; k < got.planes.size(); ++k) {
        const PlaneShape &a = got.planes[k], &b = want.planes[k];
        CHECK((a.n == b.n && same_bytes(&a.D, &b.D, sizeof(double)) && a.p1 == b.p1 && a.chess == b.chess &&
               a.singular == b.singular && a.inv_row[0] == b.inv_row[0] && a.inv_row[1] == b.inv_row[1] &&
               a.inv_row[2] == b.inv_row[2]));
    }
    CHECK(same_bytes(got.plane_mats.data(), want.plane_mats.data(), got.plane_mats.size() * sizeof(ShadeMaterial)));
    CHECK(same_bits(got.lights, want.lights));
    CHECK(got.glows == want.glows);
    REQUIRE(bool(got.glow_bvh) == bool(want.glow_bvh));
    if (got.glow_bvh) CHECK((same_bits(got.glow_bvh->nodes, want.glow_bvh->nodes) && same_bits(got.glow_bvh->items, want.glow_bvh->items)));
    REQUIRE(bool(got.camera_buffer) == bool(want.camera_buffer));
    if (!slotted) CHECK(same_buffer(got.camera_buffer.get(), want.camera_buffer.get()));
    REQUIRE(bool(got.light_buffers) == bool(want.light_buffers));
    if (got.light_buffers && slotted) {
        CHECK(got.light_buffers->size() == want.light_buffers->size());
    } else if (got.light_buffers) {
        REQUIRE(got.light_buffers->size() == want.light_buffers->size());
        for (std::size_t k = 0; k < got.light_buffers->size(); ++k)
            CHECK(same_buffer(&(*got.light_buffers)[k], &(*want.light_buffers)[k]));
    }
    CHECK(same_bytes(&got.radiance_bound, &want.radiance_bound, sizeof(double)));
    CHECK(same_bytes(&got.omit_weight, &want.omit_weight, sizeof(double)));
    const Aabb a = got.bounds(), b = want.bounds();
    CHECK((a.lo == b.lo && a.hi == b.hi));
    CHECK(got.camera == want.camera);
    CHECK((got.width == want.width && got.height == want.height));
}

// The world's whole picture at `samples` per pixel, on two threads.
inline Image render(const std::shared_ptr<const World>& world, int samples = 2) {
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings st;
    st.width = world->width;
    st.height = world->height;
    st.max_samples = samples;
    st.coarse = false;
    r.start(world, st);
    r.wait();
    return r.snapshot();
}

// The colours (doubles, before any rounding to the film's floats) of a grid of camera
// rays, one at a time and four at a time.
inline std::vector<Colour> trace_grid(const World& w) {
    const CameraBasis cam = CameraBasis::make(w.camera, 2 * w.width, 2 * w.height, false);
    std::vector<Colour> out;
    std::vector<Vec3> dirs;
    RayStats stats;
    for (int j = 0; j < 2 * w.height; ++j)
        for (int i = 0; i < 2 * w.width; ++i) {
            out.push_back(w.trace_camera(cam, i + 0.5, j + 0.5, stats));
            dirs.push_back(normalize(cam.direction(i + 0.5, j + 0.5)));
        }
    std::vector<Colour> rows(dirs.size());
    w.trace_units(cam.origin, dirs.data(), dirs.size(), stats, rows.data());
    out.insert(out.end(), rows.begin(), rows.end());
    return out;
}

// The two worlds' films, and their colours of a grid of rays, on each instruction-set
// path this processor runs.
inline void check_same_pictures(const std::shared_ptr<const World>& got, const std::shared_ptr<const World>& want) {
    const Isa saved = active_isa();
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        if (!set_isa(isa)) continue;
        CAPTURE(int(isa));
        const Image a = render(got), b = render(want);
        REQUIRE(a.rgb.size() == b.rgb.size());
        CHECK(same_bytes(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)));
        const std::vector<Colour> x = trace_grid(*got), y = trace_grid(*want);
        CHECK(same_bytes(x.data(), y.data(), x.size() * sizeof(Colour)));
    }
    set_isa(saved);
}

}  // namespace rt_test
