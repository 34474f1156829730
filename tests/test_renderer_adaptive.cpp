// Tests for adaptive anti-aliasing (core/adaptive.h and the renderer's decision and
// refine passes): the film and every pixel's sample count are the same whatever the
// thread count, tile order or instruction set; a threshold of 0 is the uniform render;
// one sharp edge is refined exactly along it while flat regions keep one sample; the
// decisions that look only near the last changes decide as a full look would; renders
// started and cancelled in any of their passes leave the last one clean; and without
// a threshold, --samples N renders the stored reference bytes.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "adaptive.h"
#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "simd.h"
#include "test_scenes.h"
#include "test_util.h"
#include "world.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

// Edges of every kind, and flat-ish regions between them.
const std::string kScene = rt_test::mixed_scene(96, 72);

// A black ball before a grey wall lit from the eye: two smooth regions (the wall's
// light falls off slowly, far under the threshold from pixel to pixel) and one sharp
// edge, the ball's outline.
const char* kBall = R"(
thing { sphere { material { reflection 0 refraction 0 scattering 1 colour 0 0 0 } position 10 0 0 radius 3 } }
special_thing {
  plane {
    material { reflection 0 refraction 0 scattering 1 colour 0.8 0.8 0.8 }
    point 1 20 0 0  point 2 20 1 0  point 3 20 0 1  point 4 0 0 0
  }
}
light { spotlight { colour 500 500 500 position -5 0 0 } }
camera { position -5 0 0  centre 10 0 0  up 10 0 1  angle_x 60  angle_y 45 }
picture_size { x_max 96 y_max 72 }
end
)";

struct Result {
    Image film;
    std::vector<std::uint32_t> counts;
    RenderProgress progress;
};

Result render(const std::shared_ptr<const World>& world, const RenderSettings& settings, int threads) {
    rt::ThreadPool r_pool(threads + 1);
    Renderer r(r_pool);
    r.start(world, settings);
    r.wait();
    Result out;
    out.progress = r.progress();
    out.film = r.snapshot();
    int w = 0, h = 0;
    r.sample_counts(out.counts, w, h);
    REQUIRE(out.progress.done);
    return out;
}

RenderSettings adaptive(double threshold, int max_samples) {
    RenderSettings s;
    s.aa_threshold = threshold;
    s.max_samples = max_samples;
    s.coarse = false;
    return s;
}

bool same_film(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

using rt_test::IsaGuard;

}  // namespace

TEST_CASE("adaptive: film and sample counts are the same for 1, 2 and 5 threads, any tile order and both ISA paths") {
    IsaGuard guard;
    const Scene scene = parse_ok(kScene);
    RenderSettings s = adaptive(0.1, 16);
    s.tile_size = 16;
    const Result reference = render(compile_world(scene), s, 1);
    // Genuinely adaptive: many pixels keep one sample (the chess plane has edges
    // everywhere), some get every one.
    const auto ones = std::count(reference.counts.begin(), reference.counts.end(), 1u);
    const auto full = std::count(reference.counts.begin(), reference.counts.end(), 16u);
    CHECK(ones > long(reference.counts.size()) / 3);
    CHECK(full > 20);
    CHECK(reference.progress.refining == 0);
    std::uint64_t total = 0;
    for (std::uint32_t n : reference.counts) total += n;
    CHECK(reference.progress.film_samples == total);
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        if (!isa_supported(isa)) continue;
        CAPTURE(isa_name(isa));
        REQUIRE(set_isa(isa));
        const auto world = compile_world(scene);  // a BVH of this path's width
        for (int threads : {1, 2, 5})
            for (TileOrder order : {TileOrder::CentreOut, TileOrder::Scanline}) {
                CAPTURE(threads);
                CAPTURE(int(order));
                s.order = order;
                s.tile_size = threads == 5 ? 8 : 24;
                s.coarse = threads == 2;  // previews first make no difference either
                const Result got = render(world, s, threads);
                CHECK(got.counts == reference.counts);
                CHECK(same_film(got.film, reference.film));
            }
    }
}

TEST_CASE("adaptive: threshold 0 refines every pixel to max_samples, which is the uniform render") {
    const auto world = compile_world(parse_ok(kScene));
    RenderSettings uniform;
    uniform.max_samples = 5;
    uniform.coarse = false;
    const Result a = render(world, adaptive(0, 5), 2), u = render(world, uniform, 2);
    CHECK(std::all_of(a.counts.begin(), a.counts.end(), [](std::uint32_t n) { return n == 5; }));
    CHECK(same_film(a.film, u.film));
}

TEST_CASE("adaptive: one sharp edge gets more samples exactly along it, and flat regions stay at one") {
    const Scene scene = parse_ok(kBall);
    const int w = scene.width, h = scene.height;
    const Result r = render(compile_world(scene), adaptive(0.3, 16), 2);
    // Where each pixel's first sample lands, worked out from the camera alone: on the
    // ball iff its ray passes the ball's centre closer than the radius.
    const CameraBasis cam = CameraBasis::make(scene.camera, w, h, false);
    auto on_ball = [&](int x, int y) {
        const Vec3 d = normalize(cam.direction(x, y)), c = Vec3{10, 0, 0} - cam.origin;
        const double along = dot(c, d);
        return along > 0 && dot(c, c) - along * along < 9;
    };
    // Whether the first samples of the pixels within k steps of (x, y) (left, right,
    // up, down) fall on both sides.
    auto mixed = [&](int x, int y, int k) {
        for (int ny = std::max(0, y - k); ny <= std::min(h - 1, y + k); ++ny)
            for (int nx = std::max(0, x - k); nx <= std::min(w - 1, x + k); ++nx)
                if (std::abs(nx - x) + std::abs(ny - y) <= k && on_ball(nx, ny) != on_ball(x, y)) return true;
        return false;
    };
    int edge = 0, refined = 0, straddling = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::uint32_t n = r.counts[std::size_t(y) * w + x];
            const float v = r.film.rgb[3 * (std::size_t(y) * w + x)];
            CAPTURE(x);
            CAPTURE(y);
            // At the edge (a neighbour's first sample landed on the other side): refined.
            // Refined pixels lie at the edge or next to it (a neighbour refined there can
            // show that the edge reaches into this pixel too). Everything else: one sample.
            if (mixed(x, y, 1)) CHECK(n >= 6);
            if (!mixed(x, y, 2)) {
                CHECK(n == 1);
                CHECK((on_ball(x, y) ? v == 0 : v > 0.2f));  // the ball's black, the wall's grey
            }
            edge += mixed(x, y, 1);
            refined += n > 1;
            // Anti-aliased: part ball, part wall, so darker than its wall neighbours.
            float wall = 0;
            for (int ny = std::max(0, y - 1); ny <= std::min(h - 1, y + 1); ++ny)
                for (int nx = std::max(0, x - 1); nx <= std::min(w - 1, x + 1); ++nx)
                    wall = std::max(wall, r.film.rgb[3 * (std::size_t(ny) * w + nx)]);
            straddling += n > 1 && v > 0.02f && v < 0.9f * wall;
        }
    // The outline of a ball some 33 pixels across, both sides of it, and little more.
    CHECK(edge > 150);
    CHECK(refined < edge * 3 / 2);
    CHECK(straddling > 60);
}

TEST_CASE("adaptive: decisions that look only near the last changes equal decisions over every pixel") {
    // The renderer's rounds, one by one on a film of our own: first sample, then decide
    // and refine until nothing is left. At every round the decision near the changes
    // must mark exactly what a decision over the whole picture marks.
    const Scene scene = parse_ok(kScene);
    const auto world = compile_world(scene);
    const int w = scene.width, h = scene.height;
    const CameraBasis cam = CameraBasis::make(scene.camera, w, h, false);
    Film film;
    film.reset(w, h, false);
    film.squares.reset(std::size_t(w) * h);
    RayStats stats;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t idx = std::size_t(y) * w + x;
            accumulate_pixel(*world, cam, x, y, 0, 1, &film.sum[3 * idx], stats);
            film.count[idx] = 1;
        }
    const std::size_t n = std::size_t(w) * h;
    std::vector<std::uint8_t> full(n), near(n), changed(n);
    int rounds = 0;
    for (bool first = true;; first = false, ++rounds) {
        const std::size_t marked_full = decide_rows(film, 0.05, 32, nullptr, 0, h, full.data());
        // In bands, as the renderer's tasks decide them.
        std::size_t marked = 0;
        for (int y0 = 0; y0 < h; y0 += 16)
            marked += decide_rows(film, 0.05, 32, first ? nullptr : changed.data(), y0, std::min(h, y0 + 16), near.data());
        CAPTURE(rounds);
        REQUIRE(marked == marked_full);
        REQUIRE(near == full);
        if (marked == 0) break;
        std::vector<std::uint32_t> n0(static_cast<std::size_t>(w)), n1(static_cast<std::size_t>(w));
        for (int y = 0; y < h; ++y) {
            const std::size_t row = std::size_t(y) * w;
            for (int x = 0; x < w; ++x) {
                n0[x] = film.count[row + x];
                n1[x] = near[row + x] ? refine_count(n0[x], 32) : n0[x];
            }
            refine_row(*world, cam, 0, y, w, n0.data(), n1.data(), &film.sum[3 * row], &film.squares[row], stats);
            std::copy(n1.begin(), n1.end(), &film.count[row]);
        }
        changed = near;
    }
    CHECK(rounds >= 3);  // 1 -> 6 -> 12 -> 24 -> 32 and neighbours newly marked on the way
}

TEST_CASE("adaptive: without a threshold, --samples N renders the stored reference bytes") {
    // Made by the renderer before adaptive anti-aliasing existed (tests/refs/README.md).
    struct Ref {
        const char* scene;
        const char* ref;
        int w, h, samples;
    };
    for (const Ref& ref : {Ref{"showcase", "showcase-4", 160, 120, 4}, Ref{"glass", "glass-3", 120, 90, 3}}) {
        CAPTURE(ref.scene);
        std::string text;
        const std::string dir = std::string(RT_SOURCE_DIR);
        REQUIRE(read_file(dir + "/scenes/" + ref.scene + ".txt", text, Limits::max_file_size).ok());
        int rw = 0, rh = 0;
        std::vector<std::uint8_t> expected;
        REQUIRE(read_ppm(dir + "/tests/refs/samples/" + ref.ref + ".ppm", rw, rh, expected).ok());
        RenderSettings s;
        s.width = ref.w;
        s.height = ref.h;
        s.max_samples = ref.samples;
        s.samples_per_pass = ref.samples;  // as raytracer asks
        s.coarse = false;
        const Result r = render(compile_world(parse_ok(text)), s, 2);
        CHECK(r.progress.refining == -1);
        CHECK(to_rgb8(r.film) == expected);
    }
}

TEST_CASE("adaptive: renders started and cancelled in every kind of pass, while another thread reads; the last is clean") {
    const auto big = compile_world(parse_ok(kScene)), small = compile_world(parse_ok(kBall));
    rt::ThreadPool r_pool(4);
    Renderer r(r_pool);
    std::atomic<bool> stop{false}, torn{false};
    std::atomic<long> reads{0};
    std::thread reader([&] {
        std::vector<std::uint8_t> rgba;
        std::vector<std::uint32_t> counts;
        std::uint64_t version = 0;
        while (!stop.load()) {
            int w = 0, h = 0;
            r.snapshot_rgba8(rgba, w, h, version);
            r.sample_counts(counts, w, h);
            const RenderProgress p = r.progress();
            if (counts.size() != std::size_t(w) * h || p.refining > std::int64_t(p.width) * p.height) torn = true;
            ++reads;
        }
    });
    RenderSettings s = adaptive(0.05, 16);
    s.tile_size = 16;
    for (int i = 0; i < 300; ++i) {
        // Two sizes, adaptive and uniform, with and without previews, stopped early or late.
        s.aa_threshold = i % 3 == 2 ? -1 : 0.05;
        s.coarse = i % 2 == 0;
        r.start(i % 4 < 2 ? big : small, s);
        if (i % 5 == 0) r.wait_for(0.0005 * (i % 11));
        if (i % 37 == 1) r.wait();
        if (i % 3 == 1) r.cancel();
    }
    r.start(big, s = adaptive(0.05, 16));
    r.wait();
    stop = true;
    reader.join();
    CHECK(reads.load() > 0);
    CHECK_FALSE(torn.load());
    std::vector<std::uint32_t> counts;
    int w = 0, h = 0;
    r.sample_counts(counts, w, h);
    const Result fresh = render(big, s, 1);
    CHECK(r.progress().refining == 0);
    CHECK(counts == fresh.counts);
    CHECK(same_film(r.snapshot(), fresh.film));
}

TEST_CASE("raising max samples: a render goes on from the samples it has, uniform or adaptive") {
    const auto world = compile_world(parse_ok(kScene));
    RenderSettings uniform;
    uniform.coarse = true;
    const auto counts_of = [](const Renderer& r) {
        std::vector<std::uint32_t> c;
        int w = 0, h = 0;
        r.sample_counts(c, w, h);
        return c;
    };
    SUBCASE("uniform: raised once finished, or while it runs, it ends as a straight render of that many") {
        RenderSettings straight = uniform;
        straight.coarse = false;
        straight.max_samples = 6;
        const Result want = render(world, straight, 1);
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        uniform.max_samples = 2;
        r.start(world, uniform);
        r.wait();
        REQUIRE(r.progress().samples == 2);
        const double took = r.progress().elapsed;
        // A second with nothing to render: the rest itself is what is checked (not a
        // wait for anything), so it is a fixed time.
        std::this_thread::sleep_for(std::chrono::milliseconds(1000));
        CHECK(r.raise_samples(6));
        // The rest in between does not count as rendering time.
        CHECK(r.progress().elapsed < took + 0.6);
        r.wait();
        CHECK(r.progress().done);
        CHECK(r.progress().samples == 6);
        CHECK(counts_of(r) == want.counts);
        CHECK(same_film(r.snapshot(), want.film));
        CHECK_FALSE(r.raise_samples(6));  // already that many
        CHECK_FALSE(r.raise_samples(3));  // fewer: a new render's business

        // Raised before the first pass is over (paused: nothing is done until stepped).
        uniform.max_samples = 3;
        r.set_paused(true);
        r.start(world, uniform);
        r.step(3);
        CHECK(r.raise_samples(6));
        r.set_paused(false);
        r.wait();
        CHECK(counts_of(r) == want.counts);
        CHECK(same_film(r.snapshot(), want.film));
    }
    SUBCASE("adaptive: the pixels the old limit stopped go on, and the picture is the same for any thread count") {
        const RenderSettings s = adaptive(0.1, 4);
        std::vector<std::uint32_t> before, after;
        Image film;
        for (int threads : {1, 3}) {
            CAPTURE(threads);
            rt::ThreadPool r_pool(threads + 1);
            Renderer r(r_pool);
            r.start(world, s);
            r.wait();
            const std::vector<std::uint32_t> b = counts_of(r);
            REQUIRE(std::count(b.begin(), b.end(), 4u) > 20);
            REQUIRE(r.raise_samples(16));
            r.wait();
            const RenderProgress p = r.progress();
            CHECK(p.done);
            CHECK(p.refining == 0);
            const std::vector<std::uint32_t> a = counts_of(r);
            std::uint64_t total = 0;
            bool lost = false, beyond = false, over = false;
            for (std::size_t i = 0; i < a.size(); ++i) {
                total += a[i];
                lost = lost || a[i] < b[i];
                beyond = beyond || (b[i] == 4 && a[i] > 4);
                over = over || a[i] > 16;
            }
            CHECK(p.film_samples == total);
            CHECK_FALSE(lost);
            CHECK(beyond);
            CHECK_FALSE(over);
            if (threads == 1) {
                before = b, after = a, film = r.snapshot();
            } else {
                CHECK(b == before);
                CHECK(a == after);
                CHECK(same_film(r.snapshot(), film));
            }
        }
    }
    SUBCASE("adaptive, raised in its first pass: the new limit from the first decision on") {
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        r.set_paused(true);
        r.start(world, adaptive(0.1, 4));
        r.step(2);
        REQUIRE(r.raise_samples(16));
        CHECK_FALSE(r.raise_samples(12));
        r.set_paused(false);
        r.wait();
        const std::vector<std::uint32_t> a = counts_of(r);
        CHECK(r.progress().refining == 0);
        CHECK(*std::max_element(a.begin(), a.end()) == 16u);
        rt::ThreadPool fresh_pool(3);
        Renderer fresh(fresh_pool);
        fresh.start(world, adaptive(0.1, 16));
        fresh.wait();
        // Raised before any decision: the render 16 would have made.
        CHECK(counts_of(fresh) == a);
        CHECK(same_film(fresh.snapshot(), r.snapshot()));
    }
    SUBCASE("nothing to raise: no render, or one under a time limit") {
        rt::ThreadPool r_pool(2);
        Renderer r(r_pool);
        CHECK_FALSE(r.raise_samples(8));
        RenderSettings limited = uniform;
        limited.max_samples = 2;
        limited.time_limit = 100;
        r.start(world, limited);
        r.wait();
        CHECK_FALSE(r.raise_samples(8));
    }
}
