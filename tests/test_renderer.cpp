// Tests for the progressive renderer (core/renderer.h) and the world it renders
// (core/world.h, core/camera.h): the film is bit-identical whatever the thread count,
// tile order, pass grouping or coarse previews; start/cancel can be hammered from one
// thread while another reads the film; the picture is not mirrored unless asked to
// be; and a world compiled from an edited scene reuses the geometry when it can.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "default_scene.h"
#include "image_io.h"
#include "parallel.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "test_scenes.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

const std::string kSceneA = rt_test::mixed_scene(64, 48);

// A different scene at a different size: glass cylinder, mirror tetrahedron, plain plane.
const char* kSceneB = R"(
thing {
  cylinder {
    material { reflection 0.1 refraction 0.85 scattering 0.05 translusans 0.9 refractive_index 1.3 colour 0.8 1 0.9 }
    end_1 4 -1 0.2  end_2 4 1 1.5  radius 0.7
  }
  tetrahedron {
    material { reflection 0.8 scattering 0.2 colour 1 1 1 }
    vect1 7 -2 0  vect2 8 0 0  vect3 7 2 0  vect4 7.5 0 2.5
  }
  sphere { material { colour 0.9 0.2 0.2 } position 6 2.5 0.6 radius 0.6 }
}
special_thing {
  plane { material { reflection 0.3 scattering 0.7 colour 0.6 0.7 0.9 } point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 5 }
}
light { spotlight { colour 80 80 80 position 1 3 6 } }
camera { position 0 -1 2  centre 6 0 0.5  up 6 0 1.5  angle_x 55  angle_y 45 }
picture_size { x_max 48 y_max 40 }
end
)";

Image render(const std::shared_ptr<const World>& world, const RenderSettings& settings, int threads) {
    rt::ThreadPool r_pool(threads + 1);
    Renderer r(r_pool);
    r.start(world, settings);
    r.wait();
    RenderProgress p = r.progress();
    CHECK(p.done);
    CHECK(p.samples == settings.max_samples);
    return r.snapshot();
}

bool same_film(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// Enough different pixel values that a comparison means something.
int distinct_pixels(const Image& img) {
    std::vector<float> r;
    for (std::size_t i = 0; i < img.rgb.size(); i += 3) r.push_back(img.rgb[i] + 3 * img.rgb[i + 1] + 7 * img.rgb[i + 2]);
    std::sort(r.begin(), r.end());
    return int(std::unique(r.begin(), r.end()) - r.begin());
}

}  // namespace

TEST_CASE("renderer: the film is bit-identical for 1, 2 and 4 threads and either tile order") {
    auto world = compile_world(parse_ok(kSceneA));
    RenderSettings s;
    s.max_samples = 4;
    s.tile_size = 16;
    Image reference = render(world, s, 1);
    REQUIRE(reference.width == 64);
    REQUIRE(reference.height == 48);
    CHECK(distinct_pixels(reference) > 500);
    for (int threads : {1, 2, 4}) {
        for (TileOrder order : {TileOrder::CentreOut, TileOrder::Scanline}) {
            CAPTURE(threads);
            CAPTURE(int(order));
            s.order = order;
            CHECK(same_film(render(world, s, threads), reference));
        }
    }
}

TEST_CASE("renderer: a pool of the caller alone is refused (a render runs on a worker)") {
    rt::ThreadPool caller_only(1);
    CHECK_THROWS_AS(Renderer{caller_only}, std::invalid_argument);
    rt::ThreadPool one_worker(2);
    Renderer r(one_worker);
    CHECK(r.threads() == 1);
}

TEST_CASE("renderer: renderers sharing one pool make the films they make alone, bit for bit") {
    auto world_a = compile_world(parse_ok(kSceneA));
    auto world_b = compile_world(parse_ok(kSceneB));
    RenderSettings sa, sb;
    sa.max_samples = 4;
    sa.tile_size = 16;
    sb.max_samples = 3;
    sb.aa_threshold = 0.05;
    sb.tile_size = 8;
    const Image ref_a = render(world_a, sa, 1);
    rt::ThreadPool alone_pool(2);
    Renderer alone(alone_pool);
    alone.start(world_b, sb);  // adaptive: render() would count its samples
    alone.wait();
    const Image ref_b = alone.snapshot();
    CHECK(distinct_pixels(ref_b) > 300);
    ThreadPool pool(3);
    Renderer a(pool), b(pool);
    CHECK(a.threads() == 2);
    CHECK(&a.pool() == &pool);
    for (int round = 0; round < 3; ++round) {
        a.start(world_a, sa);
        b.start(world_b, sb);
        // The pool's caller meanwhile runs loops of its own on the same threads.
        std::atomic<int> items{0};
        pool.parallel_for(1000, [&](int) { items.fetch_add(1); });
        CHECK(items.load() == 1000);
        a.wait();
        b.wait();
        CHECK(a.progress().done);
        CHECK(same_film(a.snapshot(), ref_a));
        CHECK(same_film(b.snapshot(), ref_b));
    }
    // A cancelled render leaves the pool to the other.
    a.start(world_a, sa);
    a.cancel();
    b.start(world_b, sb);
    b.wait();
    CHECK(same_film(b.snapshot(), ref_b));
}

TEST_CASE("renderer: a progressive render stopped at N samples equals a straight N-sample render") {
    auto world = compile_world(parse_ok(kSceneA));
    for (int n : {1, 3, 4}) {
        CAPTURE(n);
        RenderSettings progressive;
        progressive.max_samples = n;
        progressive.samples_per_pass = 0;  // 1, 1, 2, ... samples per pass, coarse passes first
        RenderSettings straight = progressive;
        straight.samples_per_pass = n;
        straight.coarse = false;
        straight.order = TileOrder::Scanline;
        straight.tile_size = 8;
        CHECK(same_film(render(world, progressive, 2), render(world, straight, 3)));
    }
    // One sample per pixel with and without the coarse previews first.
    RenderSettings coarse;
    coarse.max_samples = 1;
    coarse.coarse = true;
    RenderSettings plain = coarse;
    plain.coarse = false;
    CHECK(same_film(render(world, coarse, 4), render(world, plain, 1)));
}

TEST_CASE("renderer: the samples after coarse passes of any block, tile or picture size equal those without") {
    // The first sample pass takes the last coarse pass's corners from the preview: every
    // other pixel of its rows, or (previews cut short by the time limit) every 8th.
    for (const std::string& text : {kSceneA, std::string(kSceneB)}) {
        auto world = compile_world(parse_ok(text));
        for (int samples : {1, 3}) {
            for (int tile : {8, 24}) {
                for (int block : {2, 8, 16}) {
                    for (double limit : {0.0, 1e-9}) {
                        CAPTURE(samples);
                        CAPTURE(tile);
                        CAPTURE(block);
                        CAPTURE(limit);
                        RenderSettings plain;
                        plain.width = 101;
                        plain.height = 67;
                        plain.max_samples = samples;
                        plain.samples_per_pass = samples;
                        plain.tile_size = tile;
                        plain.coarse = false;
                        RenderSettings coarse = plain;
                        coarse.coarse = true;
                        coarse.coarse_block = block;
                        coarse.time_limit = limit;
                        if (limit > 0 && samples > 1) continue;  // (a time limit's first pass is one sample)
                        const Image want = render(world, plain, 1);
                        CHECK(distinct_pixels(want) > 300);
                        CHECK(same_film(render(world, coarse, 2), want));
                    }
                }
            }
        }
    }
}

TEST_CASE("renderer: coarse passes complete at block sizes 8, then 4, then 2, before the first sample") {
    auto world = compile_world(parse_ok(kSceneA));
    rt::ThreadPool r_pool(2);
    Renderer r(r_pool);
    RenderSettings s;
    s.width = 128;
    s.height = 96;
    s.max_samples = 2;
    s.coarse = true;
    // Paused from the start: nothing is traced and nothing is reported yet.
    r.set_paused(true);
    r.start(world, s);
    RenderProgress p = r.progress();
    CHECK(p.paused);
    CHECK_FALSE(p.running);
    CHECK(p.passes == 0);
    CHECK(p.coarse_level == 0);
    CHECK(p.first_coarse_time < 0);
    r.set_paused(false);
    // Every state observed while it runs fits the order 8, 4, 2, samples.
    int inconsistent = 0, observed = 0;
    std::string levels;  // distinct coarse levels in the order seen
    for (;;) {
        p = r.progress();
        ++observed;
        int want = p.passes == 0 ? 0 : p.passes == 1 ? 8 : p.passes == 2 ? 4 : 2;
        if (p.coarse_level != want || (p.passes <= 3 && p.samples != 0) || (p.passes >= 1) != (p.first_coarse_time >= 0))
            ++inconsistent;
        if (p.coarse_level != 0 && (levels.empty() || levels.back() != char('0' + p.coarse_level)))
            levels += char('0' + p.coarse_level);
        if (p.done) break;
        std::this_thread::yield();
    }
    r.wait();
    CAPTURE(levels);
    CAPTURE(observed);
    CHECK(inconsistent == 0);
    CHECK(p.coarse_level == 2);
    CHECK(p.samples == 2);
    CHECK(p.passes == 5);  // three coarse passes, then sample passes of 1 and 1
    CHECK(p.first_coarse_time >= 0);
    CHECK(p.first_coarse_time <= p.elapsed);

    s.coarse = false;
    r.start(world, s);
    r.wait();
    p = r.progress();
    CHECK(p.done);
    CHECK(p.coarse_level == 0);
    CHECK(p.first_coarse_time < 0);
    CHECK(p.passes == 2);
}

TEST_CASE("renderer: start and cancel hammered from one thread while another reads the film; the last render is clean") {
    auto world_a = compile_world(parse_ok(kSceneA));
    auto world_b = compile_world(parse_ok(kSceneB));
    RenderSettings s;
    s.max_samples = 2;
    s.tile_size = 16;
    rt::ThreadPool r_pool(5);
    Renderer r(r_pool);
    std::atomic<bool> stop{false}, torn{false};
    std::atomic<long> reads{0};
    std::thread reader([&] {
        std::vector<std::uint8_t> rgba;
        std::uint64_t version = 0;
        while (!stop.load()) {
            std::uint64_t gen = 0;
            Image img = r.snapshot(&gen);
            RenderProgress p = r.progress();
            int w = 0, h = 0;
            r.snapshot_rgba8(rgba, w, h, version);
            // A snapshot is one whole film, of one of the two sizes.
            bool sized = (img.width == 64 && img.height == 48) || (img.width == 48 && img.height == 40) || img.width == 0;
            if (!sized || img.rgb.size() != std::size_t(img.width) * img.height * 3) torn = true;
            if (p.width != 0 && !((p.width == 64 && p.height == 48) || (p.width == 48 && p.height == 40))) torn = true;
            ++reads;
        }
    });
    // Edits arrive as they do from the viewer's panels: a material change compiled
    // against the running world (sharing its BVH), alternating with another scene.
    Scene edited = parse_ok(kSceneA);
    std::shared_ptr<const World> current = world_a;
    const int rounds = 2000;
    for (int i = 0; i < rounds; ++i) {
        if (i % 2) {
            current = world_b;
        } else {
            edited.objects[0].material.colour.x = (i % 100) / 100.0;
            current = compile_world(edited, world_a.get());
        }
        r.start(current, s);
        if (i % 7 == 3) r.wait_for(0.001);
        if (i % 60 == 10) r.wait();
        if (i % 5 == 1) {
            rt_test::Watchdog dog("cancel() did not return");
            r.cancel();
        }
    }
    r.start(world_b, s);
    r.wait();
    stop = true;
    reader.join();
    CHECK(reads.load() > 0);
    CHECK_FALSE(torn.load());

    std::uint64_t gen = 0;
    Image last = r.snapshot(&gen);
    RenderProgress p = r.progress();
    CHECK(p.done);
    CHECK(p.generation == gen);
    CHECK(p.samples == 2);
    Image fresh = render(world_b, s, 1);
    CHECK(same_film(last, fresh));
}

TEST_CASE("renderer: cancel() of a long render returns and leaves the renderer reusable") {
    auto world = compile_world(parse_ok(kSceneA));
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings s;
    s.max_samples = 100000;  // would take many minutes
    r.start(world, s);
    rt_test::wait_until([&] { return r.progress().samples >= 1; }, "the first sample pass");  // under way
    {
        // (How quickly is for the benchmarks; a cancel that waited for the render to end
        // would not return for minutes.)
        rt_test::Watchdog dog("cancel() of a long render did not return");
        r.cancel();
    }
    CHECK_FALSE(r.progress().running);
    CHECK_FALSE(r.progress().done);

    s.max_samples = 1;
    r.start(world, s);
    r.wait();
    CHECK(same_film(r.snapshot(), render(world, s, 1)));
}

TEST_CASE("camera: unit_directions() gives normalize(direction()) bit for bit, pixel for pixel") {
    Camera cam;
    cam.position = {-9.8, -2.6, 6.3};
    cam.centre = {0.7, -0.2, 0.8};
    cam.up = {0.7, -0.2, 1.8};
    cam.angle_x = 61.3;
    cam.angle_y = 35.9834;
    int checked = 0;
    for (Projection proj : {Projection::Linear, Projection::Polar})
        for (bool mirror : {false, true})
            for (int width : {1, 2, 7, 1280}) {
                cam.projection = proj;
                const CameraBasis b = CameraBasis::make(cam, width, 5, mirror);
                for (int step : {1, 2, 3})
                    for (int i0 : {0, 1, width / 2}) {
                        const int count = (width - i0 + step - 1) / step;
                        std::vector<Vec3> out(std::size_t(std::max(count, 0)) + 1, Vec3{7, 7, 7});
                        b.unit_directions(i0, step, count, 3, out.data());
                        for (int k = 0; k < count; ++k) {
                            const Vec3 want = normalize(b.direction(i0 + k * step, 3));
                            CAPTURE(k);
                            REQUIRE(std::memcmp(&out[std::size_t(k)], &want, sizeof want) == 0);
                            ++checked;
                        }
                        CHECK(out[std::size_t(std::max(count, 0))] == Vec3{7, 7, 7});  // nothing past count
                    }
            }
    CHECK(checked > 10000);
}

TEST_CASE("film: zeroed arrays of every size are zero, writable to their ends, and huge ones start on 2 MB") {
    for (std::size_t n : {std::size_t(1), std::size_t(1000), std::size_t(300000), std::size_t(524288),
                          std::size_t(524289), std::size_t(3000001)}) {
        CAPTURE(n);
        ZeroedArray<float> a(n);
        REQUIRE(a.size() == n);
        const bool huge = n * sizeof(float) >= (std::size_t(2) << 20);
        if (huge) CHECK(reinterpret_cast<std::uintptr_t>(a.data()) % (std::size_t(2) << 20) == 0);
        CHECK(std::all_of(a.begin(), a.end(), [](float v) { return v == 0.0f; }));
        a[n - 1] = 2.f;
        a[0] += 1.f;
        CHECK(a[0] == (n == 1 ? 3.f : 1.f));
        CHECK(a[n - 1] == (n == 1 ? 3.f : 2.f));
        a.reset(n);  // again, from a fresh mapping: zero
        CHECK(a[0] == 0.f);
        CHECK(a[n - 1] == 0.f);
    }
}

TEST_CASE("film: an adopted array keeps the numbers' memory and bytes, and leaves the source empty") {
    for (std::size_t n : {std::size_t(1000), std::size_t(3000001)}) {  // from calloc, mapped
        CAPTURE(n);
        ZeroedArray<float> a(n);
        for (std::size_t i = 0; i < n; ++i) a[i] = float(i % 97);
        const auto* raw = reinterpret_cast<const unsigned char*>(a.data());
        std::vector<unsigned char> before(raw, raw + 3 * n);
        ZeroedArray<std::uint8_t> b(5);
        b.adopt(a, 3 * n);
        CHECK(a.empty());
        CHECK(a.data() == nullptr);
        REQUIRE(b.size() == 3 * n);
        CHECK(static_cast<const void*>(b.data()) == static_cast<const void*>(raw));
        CHECK(std::equal(before.begin(), before.end(), b.begin()));
        b[3 * n - 1] = 7;  // writable to its end
        CHECK(b[3 * n - 1] == 7);
        ZeroedArray<std::uint8_t> c;
        CHECK_THROWS_AS(c.adopt(b, 3 * n + 1), std::length_error);
        CHECK(b.size() == 3 * n);  // a refused adoption changes nothing
        c.adopt(b, 0);  // the memory goes with no elements, and is released with c
        CHECK(b.empty());
    }
}

TEST_CASE("renderer: take_rgb8 gives the bytes of to_rgb8(snapshot()) and leaves an empty film for the next render") {
    // Sizes for one, two and three parts (a part per 2^18 pixels, up to the threads),
    // rows not divisible by the parts; one sample (the bulk conversion), several
    // (pixel by pixel) and adaptive (both).
    struct Case {
        int w, h, samples;
        double aa;
    };
    for (const Case c : {Case{64, 48, 1, -1}, Case{701, 451, 1, -1}, Case{900, 700, 1, -1}, Case{701, 451, 2, -1},
                         Case{300, 200, 3, 0.02}}) {
        CAPTURE(c.w);
        CAPTURE(c.h);
        CAPTURE(c.samples);
        auto world = compile_world(parse_ok(rt_test::mixed_scene(c.w, c.h)));
        RenderSettings s;
        s.max_samples = c.samples;
        s.aa_threshold = c.aa;
        rt::ThreadPool r_pool(4);
        Renderer r(r_pool);
        for (int round = 0; round < 2; ++round) {
            r.start(world, s);
            r.wait();
            const std::vector<std::uint8_t> expected = to_rgb8(r.snapshot());
            REQUIRE(expected.size() == std::size_t(c.w) * c.h * 3);
            ZeroedArray<std::uint8_t> bytes;
            int w = 0, h = 0;
            r.take_rgb8(bytes, w, h);
            CHECK(w == c.w);
            CHECK(h == c.h);
            REQUIRE(bytes.size() == expected.size());
            CHECK(std::equal(expected.begin(), expected.end(), bytes.begin()));
            const Image after = r.snapshot();
            CHECK(after.width == 0);
            CHECK(after.rgb.empty());
            // The same picture made straight into bytes, tile by tile (or, where the
            // settings need the floats, the same way as above).
            RenderSettings direct = s;
            direct.bytes_only = true;
            direct.coarse = false;
            direct.tile_size = round == 0 ? 32 : 13;
            r.start(world, direct);
            r.wait();
            if (c.aa < 0) CHECK(r.progress().samples == c.samples);
            ZeroedArray<std::uint8_t> straight;
            r.take_rgb8(straight, w, h);
            CHECK(w == c.w);
            CHECK(h == c.h);
            REQUIRE(straight.size() == expected.size());
            CHECK(std::equal(expected.begin(), expected.end(), straight.begin()));
        }
    }
}

TEST_CASE("film: a pixel with no sample shows its block's corner colour at the last coarse level") {
    Film f;
    f.reset(10, 7);
    CHECK(f.pixel(3, 2, 2 * 10 + 3) == Colour{});  // no coarse pass yet: black
    // Corners of 4x4 blocks hold (x, y, 1); every other preview value is garbage.
    CHECK(f.preview.size() == Film::preview_size(10, 7));
    CHECK(Film::preview_size(10, 7) == 5 * 4 * 3);
    for (int y = 0; y < 7; y += 2)
        for (int x = 0; x < 10; x += 2) {
            float* p = &f.preview[f.preview_index(x, y)];
            bool corner = x % 4 == 0 && y % 4 == 0;
            p[0] = corner ? float(x) : -1.f, p[1] = corner ? float(y) : -1.f, p[2] = corner ? 1.f : -1.f;
        }
    f.preview_level = 4;
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 10; ++x) {
            CAPTURE(x);
            CAPTURE(y);
            CHECK(f.pixel(x, y, std::size_t(y) * 10 + x) == Colour{double(x / 4 * 4), double(y / 4 * 4), 1});
        }
    // A sampled pixel shows its mean instead.
    f.count[13] = 2;
    f.sum[39] = 1.f, f.sum[40] = 2.f, f.sum[41] = 3.f;
    CHECK(f.pixel(3, 1, 13) == Colour{0.5, 1, 1.5});
}

TEST_CASE("renderer: snapshot_rgba8 updated tile by tile equals a full conversion at every step") {
    auto world = compile_world(parse_ok(kSceneA));
    RenderSettings s;
    s.width = 96;
    s.height = 64;
    s.tile_size = 8;
    s.max_samples = 3;
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    std::vector<std::uint8_t> kept;  // updated in place, as the viewer does
    std::uint64_t kept_version = 0;
    int w = 0, h = 0;
    int compared = 0, partial = 0, differing = 0, steps = 0;
    // Paused and stepped one tile at a time, so that every intermediate state is seen
    // whatever the machine's load. Per render: coarse passes of 2, 6 and 24 tiles (a
    // coarse tile grows with its block: 64, 32, 16 pixels), then 3 sample passes of 96.
    r.set_paused(true);
    for (int round = 0; round < 3; ++round) {
        r.start(world, s);  // a new render over the same film size: a full update first
        for (;;) {
            RenderProgress before = r.progress();
            if (before.done) break;
            r.step(1);
            // The tile is committed when the progress moves.
            rt_test::wait_until(
                [&] {
                    const RenderProgress p = r.progress();
                    return p.done || p.passes != before.passes || p.pass_fraction != before.pass_fraction;
                },
                "the stepped tile to be committed", std::chrono::seconds(30));
            ++steps;
            std::array<int, 4> changed{};
            if (r.snapshot_rgba8(kept, w, h, kept_version, &changed)) {
                if (!(changed[0] == 0 && changed[1] == 0 && changed[2] == w && changed[3] == h)) ++partial;
                // A fresh, full conversion of the same state (nothing runs in between).
                std::vector<std::uint8_t> fresh;
                std::uint64_t fresh_version = 0;
                int fw = 0, fh = 0;
                REQUIRE(r.snapshot_rgba8(fresh, fw, fh, fresh_version));
                REQUIRE(fresh_version == kept_version);
                ++compared;
                if (fresh != kept) ++differing;
            }
        }
    }
    CAPTURE(steps);
    CAPTURE(compared);
    CAPTURE(partial);
    CHECK(steps == 3 * (2 + 6 + 24 + 3 * 96));
    CHECK(differing == 0);
    // Each state is compared once the first coarse pass is complete (its first tile
    // shows nothing yet); every sample tile is a partial update.
    CHECK(compared == steps - 3 * 1);
    CHECK(partial >= 3 * 3 * 96);
}

TEST_CASE("renderer: wait() in one thread returns when another cancels, even with every worker idle") {
    auto world = compile_world(parse_ok(kSceneA));
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings s;
    s.max_samples = 100000;
    r.set_paused(true);  // workers stay idle: no tile will ever finish
    r.start(world, s);
    std::atomic<bool> returned{false};
    std::atomic<pid_t> waiter_tid{0};
    std::thread waiter([&] {
        waiter_tid = pid_t(::gettid());
        r.wait();
        returned = true;
    });
    // The waiter asleep in wait() (it does nothing else that blocks).
    rt_test::wait_until([&] { return waiter_tid != 0 && rt_test::thread_asleep(waiter_tid); }, "the waiter to block");
    CHECK_FALSE(returned.load());  // nothing is done yet
    r.cancel();
    // A waiter that were never woken would not return: a minute is far more than it needs.
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!returned && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    CHECK(returned.load());
    r.set_paused(false);
    if (!returned) {
        // Unblock the waiter so that the test ends: a small render that finishes.
        RenderSettings small;
        small.width = small.height = 8;
        r.start(world, small);
    }
    waiter.join();
}

// Camera at the origin looking along +x with up (0, 0, 1): in a right-handed, z-up
// world the viewer's right is forward x up = (0, -1, 0). A red sphere at y = -1 must
// show on the right of the picture and a blue one at y = +1 on the left; the 2013
// program drew them the other way round (docs/rendering.md §1), which `mirror` reproduces.
TEST_CASE("renderer: the picture is not mirrored: the viewer's right is on the right, unless mirror is asked for") {
    const char* text = R"(
thing {
  sphere { material { colour 1 0 0 } position 5 -1 0 radius 0.5 }
  sphere { material { colour 0 0 1 } position 5 1 0 radius 0.5 }
}
light { spotlight { colour 30 30 30 position 0 0 0 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }
picture_size { x_max 40 y_max 30 }
end
)";
    auto world = compile_world(parse_ok(text));
    // Mean column of the pixels where one channel is lit and the other two are black.
    auto mean_column = [](const Image& img, int channel) {
        double sum = 0;
        int n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                Colour c = img.at(x, y);
                bool lit = c[channel] > 0 && c[(channel + 1) % 3] == 0 && c[(channel + 2) % 3] == 0;
                if (lit) sum += x, ++n;
            }
        REQUIRE(n > 4);
        return sum / n;
    };
    RenderSettings s;
    s.max_samples = 1;
    s.coarse = false;
    Image plain = render(world, s, 2);
    s.mirror = true;
    Image mirrored = render(world, s, 2);
    // Expected columns: 20 -+ 20 tan(atan(1/5)) / tan(30 deg) = 20 -+ 6.93.
    double red = mean_column(plain, 0), blue = mean_column(plain, 2);
    CHECK(red > 20);
    CHECK(blue < 20);
    CHECK(red == doctest::Approx(26.93).epsilon(0.05));
    CHECK(blue == doctest::Approx(13.07).epsilon(0.05));
    CHECK(mean_column(mirrored, 0) < 20);
    CHECK(mean_column(mirrored, 2) > 20);
    // Mirroring swaps columns i and W - i (the original has no half-pixel offset).
    int unequal = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 1; x < 40; ++x) unequal += plain.at(x, y) != mirrored.at(40 - x, y);
    CHECK(unequal == 0);

    // The same from the camera alone: column 0 looks toward +y (the left) unless mirrored.
    CameraBasis cam = CameraBasis::make(world->camera, 40, 30, false);
    CHECK(cam.direction(0, 15).y > 0);
    CHECK(cam.direction(39, 15).y < 0);
    CHECK(CameraBasis::make(world->camera, 40, 30, true).direction(0, 15).y < 0);
    // And pick() agrees with the picture.
    PickResult right = pick(*world, cam.ray(27, 15));
    CHECK(right.object == 0);
}

TEST_CASE("renderer: a world compiled from an edited scene shares the geometry unless a shape changed") {
    Scene a = parse_ok(kSceneA);
    auto wa = compile_world(a);
    REQUIRE(wa->geometry.get() != nullptr);

    SUBCASE("material, camera, light and plane edits share it") {
        Scene b = a;
        b.objects[1].material.colour = {0.1, 0.2, 0.3};
        b.camera.position = {-2, 0.5, 3};
        b.lights[0].colour = {10, 10, 10};
        b.planes[0].material.colour = {1, 0, 0};
        auto wb = compile_world(b, wa.get());
        CHECK(wb->geometry.get() == wa->geometry.get());
        // And renders as if compiled from scratch.
        RenderSettings s;
        s.max_samples = 1;
        s.coarse = false;
        s.width = 32;
        s.height = 24;
        CHECK(same_film(render(wb, s, 2), render(compile_world(b), s, 2)));
        CHECK_FALSE(same_film(render(wb, s, 2), render(wa, s, 2)));
    }
    SUBCASE("a radius edit does not") {
        Scene b = a;
        std::get<Sphere>(b.objects[0].shape).radius = 0.9;
        auto wb = compile_world(b, wa.get());
        CHECK(wb->geometry.get() != wa->geometry.get());
        CHECK(std::get<Sphere>(b.objects[0].shape).radius == 0.9);
        SpanEnd e;
        SpanScratch scratch;
        // The new geometry has the new radius: a ray through the centre enters 0.9 early.
        Vec3 c = std::get<Sphere>(b.objects[0].shape).position;
        REQUIRE(wb->geometry->hit(0, c + Vec3{0, 0, 5}, {0, 0, -1}, 0, e, scratch));
        CHECK(e.t == doctest::Approx(4.1));
    }
    SUBCASE("an edit inside a CSG operand does not") {
        Scene b = a;
        Csg& csg = std::get<Csg>(b.objects[3].shape);
        std::get<Cylinder>(csg.operands[1].shape).radius = 0.3;
        CHECK(compile_world(b, wa.get())->geometry.get() != wa->geometry.get());
    }
    SUBCASE("an added object does not") {
        Scene b = a;
        b.objects.push_back(b.objects[0]);
        CHECK(compile_world(b, wa.get())->geometry.get() != wa->geometry.get());
    }
}

TEST_CASE("a render thread that runs out of memory ends the render with a message, not the program") {
    auto world = compile_world(rt_test::parse_ok(rt::kDefaultScene));
    rt::ThreadPool renderer_pool(3);
    Renderer renderer(renderer_pool);
    std::atomic<int> tasks{0};
    // The third task of the render throws as a failed allocation would.
    renderer.task_hook = [&] {
        if (tasks.fetch_add(1) == 2) throw std::bad_alloc();
    };
    RenderSettings st;
    st.width = 64;
    st.height = 48;
    st.max_samples = 4;
    renderer.start(world, st);
    renderer.wait();
    RenderProgress p = renderer.progress();
    CHECK(p.done);
    CHECK(p.error == "out of memory while rendering");
    CHECK(p.samples < 4);  // stopped, not finished
    // The next render, without the failure, completes and carries no message.
    renderer.cancel();  // no worker is between taking a task and calling the hook
    renderer.task_hook = nullptr;
    renderer.start(world, st);
    renderer.wait();
    p = renderer.progress();
    CHECK(p.done);
    CHECK(p.error.empty());
    CHECK(p.samples == 4);
}
