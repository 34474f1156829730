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
#include "test_util.h"
#include "simd.h"
#include "test_random.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

using rt_test::IsaGuard;

std::vector<std::uint8_t> render(const Scene& scene, int w, int h, bool& wide_tree) {
    auto world = compile_world(scene);
    wide_tree = !world->geometry->bvh.nodes8.empty();
    rt::ThreadPool renderer_pool(3);
    Renderer renderer(renderer_pool);
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
        ParseResult parsed = parse_scene(text, rt_test::options_for(file.parent_path().string()));
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
// Skipped (and counted as skipped in doctest's summary) where the processor lacks
// AVX2: the kernel is never used there. ctest runs the AVX2 tests as an entry of their
// own, isa_avx2, which its log then shows as "Skipped" rather than "Passed".
TEST_CASE("isa: four spheres at once give hit()'s answer bit for bit" * doctest::skip(!isa_supported(Isa::Avx2))) {
    rt_test::Rng rng(17);
    Scene scene;
    for (int i = 0; i < 64; ++i) {
        // Radii from 1e-3 to 5 in a 10-unit box: misses, grazes, hits, origins inside.
        const Vec3 c{rng.uni(-5, 5), rng.uni(-5, 5), rng.uni(-5, 5)};
        scene.objects.emplace_back().shape.emplace<Sphere>(Sphere{c, std::exp(rng.uni(std::log(1e-3), std::log(5.0)))});
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
    MESSAGE("AVX2 ran: " << hits + misses << " sphere tests compared with hit()");
}
#endif

namespace {

Material random_material(rt_test::Rng& rng) {
    Material m;
    m.colour = {rng.uni(0.1, 1), rng.uni(0.1, 1), rng.uni(0.1, 1)};
    switch (rng.index(4)) {
    case 0:  // glass
        m.reflection = 0.1, m.refraction = 0.9, m.scattering = 0, m.refractive_index = 1.5;
        break;
    case 1:  // mirror
        m.reflection = 0.6, m.refraction = 0, m.scattering = 0.4;
        break;
    case 2:  // tinted glass that also scatters
        m.reflection = 0, m.refraction = 0.5, m.scattering = 0.5, m.refractive_index = 1.2;
        break;
    default:
        m.reflection = 0, m.refraction = 0, m.scattering = 1;
    }
    return m;
}

// Every kind of object, material and light placement that the shading paths tell apart:
// glass in front of glass, mirrors facing each other, chess planes of glass and mirror,
// lights among the objects, far away and out of the light buffers' range.
Scene random_scene(rt_test::Rng& rng, bool lamp) {
    Scene s;
    auto at = [&] { return Vec3{rng.uni(-4, 4), rng.uni(-4, 4), rng.uni(0, 3)}; };
    const int count = 6 + int(rng.index(10));
    for (int i = 0; i < count; ++i) {
        Object o;
        const Vec3 c = at();
        switch (i % 5) {
        case 0: case 1: o.shape = Sphere{c, rng.uni(0.2, 1.2)}; break;
        case 2: o.shape = Tetrahedron{{c, c + rng.unit(), c + rng.unit(), c + rng.unit() * 1.5}}; break;
        case 3: o.shape = Cylinder{c, c + rng.unit() * 2, rng.uni(0.1, 0.6)}; break;
        default: {
            Csg csg;
            csg.type = CsgType::Difference;
            Object a, b;
            a.shape = Sphere{c, 1};
            b.shape = Cylinder{c - Vec3{1.5, 0, 0}, c + Vec3{1.5, 0.2, 0.1}, 0.4};
            csg.operands = {a, b};
            o.shape = csg;
        }
        }
        o.material = random_material(rng);
        o.has_material = true;
        s.objects.push_back(o);
    }
    Plane floor;
    floor.chess = rng.index(2) == 0;
    floor.point[3] = {0, 0, 5};
    floor.material = random_material(rng);
    floor.material2 = random_material(rng);
    floor.has_material = floor.has_material2 = true;
    s.planes.push_back(floor);
    Plane wall;  // glass or mirror behind the objects
    wall.point[0] = {0, 6, 0}, wall.point[1] = {1, 6, 0}, wall.point[2] = {0, 6, 1}, wall.point[3] = {0, 0, 0};
    wall.material = random_material(rng);
    wall.has_material = true;
    s.planes.push_back(wall);
    const int lights = 1 + int(rng.index(4));
    for (int i = 0; i < lights; ++i) {
        Light l;
        l.lamp = lamp && i == 0;
        l.size = 0.5;
        l.colour = {rng.uni(10, 60), rng.uni(10, 60), rng.uni(10, 60)};
        // Above the scene, among the objects, far off, or too far for a light buffer
        // (its shadow rays then walk the BVH); the far ones bright enough to count.
        switch (i) {
        case 1: l.position = at(); break;
        case 2: l.position = {3e6, -2e6, 4e6}, l.colour = l.colour * 1e13; break;
        case 3: l.position = {2e31, -1e31, 3e31}, l.colour = l.colour * 1e63; break;
        default: l.position = {rng.uni(-8, 8), rng.uni(-8, 8), rng.uni(5, 10)};
        }
        s.lights.push_back(l);
    }
    s.camera.position = {-9, -3, 5};
    s.camera.centre = {0, 0, 1};
    s.camera.up = {0, 0, 2};
    return s;
}

}  // namespace

// Skipped where the processor lacks AVX2 (camera rays are never traced in packets
// there), as the test above.
TEST_CASE("isa: packets of four camera rays shade as single rays do, bit for bit" *
          doctest::skip(!isa_supported(Isa::Avx2))) {
    IsaGuard guard;
    REQUIRE(set_isa(Isa::Avx2));
    rt_test::Rng rng(29);
    int rays = 0, mismatches = 0, coloured = 0;
    for (int trial = 0; trial < 24; ++trial) {
        CAPTURE(trial);
        const Scene scene = random_scene(rng, trial % 6 == 5);
        World world = *compile_world(scene);
        // The original's depth, a small one and one past the packets' own depth.
        world.options.max_depth = trial % 3 == 0 ? 3 : trial % 3 == 1 ? 20 : 40;
        const Vec3 origin = scene.camera.position;
        std::vector<Vec3> dirs;
        for (int i = 0; i < 203; ++i)  // not a multiple of four: a part packet at the end
            dirs.push_back(normalize(Vec3{rng.uni(-4, 4), rng.uni(-4, 4), rng.uni(-1, 3)} - origin));
        std::vector<Colour> packed(dirs.size());
        RayStats stats;
        world.trace_units(origin, dirs.data(), dirs.size(), stats, packed.data());
        for (std::size_t i = 0; i < dirs.size(); ++i) {
            RayStats one;
            const Colour c = world.trace_unit(origin, dirs[i], one);
            mismatches += std::memcmp(&c, &packed[i], sizeof c) != 0;
            coloured += c.x + c.y + c.z > 0.05;
            ++rays;
        }
    }
    CHECK(mismatches == 0);
    // Most rays met something lit, so the comparison covered the shading.
    CHECK(coloured > rays / 2);
    MESSAGE("AVX2 ran: " << rays << " camera rays traced in packets and one by one");
}
