// The instruction-set paths (core/simd.h): each one the processor runs, forced in turn,
// renders every example scene and every benchmark scene to the same bytes. The paths
// differ in how many boxes one instruction tests and in the tree's width, never in a
// pixel; the 8-wide tree must really be in use when AVX2 is forced, or this test would
// compare a path with itself.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "simd.h"
#include "test_random.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

struct IsaGuard {
    Isa saved = active_isa();
    ~IsaGuard() { set_isa(saved); }
};

std::vector<std::uint8_t> render(const Scene& scene, int w, int h, bool& wide_tree) {
    auto world = compile_world(scene);
    wide_tree = !world->geometry->bvh.nodes8.empty();
    Renderer renderer(2);
    RenderSettings settings;
    settings.width = w;
    settings.height = h;
    settings.coarse = false;
    renderer.start(world, settings);
    renderer.wait();
    return to_rgb8(renderer.snapshot());
}

}  // namespace

TEST_CASE("isa: every available path renders the example and benchmark scenes to the same bytes") {
    IsaGuard guard;
    std::vector<Isa> paths;
    for (Isa isa : {Isa::Sse2, Isa::Avx2})
        if (isa_supported(isa)) paths.push_back(isa);
    REQUIRE(!paths.empty());
    if (paths.size() == 1) MESSAGE("only " << isa_name(paths[0]) << " runs here: nothing to compare it with");

    std::vector<fs::path> files;
    for (const char* dir : {"scenes", "bench/scenes"})
        for (const auto& e : fs::directory_iterator(fs::path(RT_SOURCE_DIR) / dir))
            if (e.path().extension() == ".txt") files.push_back(e.path());
    CHECK(files.size() >= 19);
    int compared = 0;
    for (const fs::path& file : files) {
        CAPTURE(file.string());
        std::string text;
        REQUIRE(read_file(file.string(), text, Limits::max_file_size).ok());
        ParseResult parsed = parse_scene(text);
        REQUIRE(parsed.ok());
        // An eighth of the size in each direction: enough rays for every kind of hit.
        int w = std::max(8, parsed.scene.width / 8), h = std::max(8, parsed.scene.height / 8);
        std::vector<std::uint8_t> first;
        for (Isa isa : paths) {
            CAPTURE(isa_name(isa));
            REQUIRE(set_isa(isa));
            bool wide = false;
            std::vector<std::uint8_t> got = render(parsed.scene, w, h, wide);
            CHECK(wide == (isa == Isa::Avx2));
            REQUIRE(got.size() == std::size_t(w) * h * 3);
            if (first.empty()) {
                first = got;
            } else {
                CHECK(got == first);
                ++compared;
            }
        }
    }
    if (paths.size() > 1) CHECK(compared == int(files.size() * (paths.size() - 1)));
}

TEST_CASE("isa: a path the processor lacks cannot be forced, and SSE2 always can") {
    IsaGuard guard;
    CHECK(isa_supported(Isa::Sse2));
    CHECK(set_isa(Isa::Sse2));
    CHECK(active_isa() == Isa::Sse2);
    if (isa_supported(Isa::Avx2)) {
        CHECK(set_isa(Isa::Avx2));
        CHECK(active_isa() == Isa::Avx2);
    } else {
        CHECK(!set_isa(Isa::Avx2));
        CHECK(active_isa() == Isa::Sse2);
    }
}

#if RT_HAVE_AVX2_KERNELS
TEST_CASE("isa: four spheres at once give hit()'s answer bit for bit") {
    if (!isa_supported(Isa::Avx2)) {
        MESSAGE("no AVX2 here: the four-sphere kernel is never used");
        return;
    }
    rt_test::Rng rng(17);
    Scene scene;
    for (int i = 0; i < 64; ++i) {
        Object o;
        // Radii from 1e-3 to 5 in a 10-unit box: misses, grazes, hits, origins inside.
        o.shape = Sphere{{rng.uni(-5, 5), rng.uni(-5, 5), rng.uni(-5, 5)}, std::exp(rng.uni(std::log(1e-3), std::log(5.0)))};
        scene.objects.push_back(o);
    }
    Geometry g = build_geometry(scene, false);
    REQUIRE(g.sphere_prefix == 64);
    SpanScratch scratch;
    int hits = 0, misses = 0, mismatches = 0;
    for (int ray = 0; ray < 4000; ++ray) {
        Vec3 o{rng.uni(-8, 8), rng.uni(-8, 8), rng.uni(-8, 8)};
        std::uint32_t ids[4];
        for (std::uint32_t& id : ids) id = std::uint32_t(rng.index(64));
        // Aimed at a sphere's edge now and then, so that the discriminant is near 0.
        const SphereG& aim = g.spheres[ids[0]];
        Vec3 target = ray % 3 == 0 ? aim.c + rng.unit() * aim.r : aim.c;
        Vec3 d = normalize(target - o);
        double tmin = ray % 2 ? kDelta : 0.0;
        double t[4];
        unsigned mask = g.sphere_entries4(ids, o, d, tmin, t);
        for (int k = 0; k < 4; ++k) {
            SpanEnd e{};
            bool hit = g.hit(ids[k], o, d, tmin, e, scratch);
            bool same = hit == bool(mask >> k & 1) && (!hit || (std::memcmp(&e.t, &t[k], sizeof(double)) == 0 && e.node == ids[k]));
            mismatches += !same;
            (hit ? hits : misses) += 1;
        }
    }
    CHECK(mismatches == 0);
    // Both outcomes were tried often enough to mean something.
    CHECK(hits > 1000);
    CHECK(misses > 1000);
}
#endif
