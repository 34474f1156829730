// The renderer's requests besides a whole film: a crop window renders the whole film's
// pixels there and nothing else; a coarse step renders the whole film's sample 0 of
// each block's corner pixel; an id pass holds what rt::pick finds along the same rays;
// a crop that goes on from loaded sums (a distributed render's tile) ends where the
// whole render does. (A tile's refine round is checked against the whole render by the
// MPI tests, tests/mpi.)
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "renderer.h"
#include "test_scenes.h"
#include "test_util.h"
#include "world.h"

using namespace rt;

namespace {

std::shared_ptr<const World> mixed_world() {
    static const std::shared_ptr<const World> world = compile_world(rt_test::parse_ok(rt_test::mixed_scene(64, 48)));
    return world;
}

Image whole(int samples) {
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings st;
    st.max_samples = samples;
    r.start(mixed_world(), st);
    r.wait();
    return r.snapshot();
}

bool same_bits(const Colour& a, const float* b) {
    const float f[3] = {float(a.x), float(a.y), float(a.z)};
    return std::memcmp(f, b, sizeof f) == 0;
}

}  // namespace

TEST_CASE("renderer: a crop renders the whole film's pixels there, sample for sample, and no other pixel") {
    const Image ref = whole(5);
    for (int threads : {1, 2}) {
        for (int tile : {8, 32}) {
            CAPTURE(threads);
            CAPTURE(tile);
            rt::ThreadPool r_pool(threads + 1);
            Renderer r(r_pool);
            RenderSettings st;
            st.max_samples = 5;
            st.tile_size = tile;
            st.crop = {7, 9, 41, 30};  // not on the tiles' grid
            r.start(mixed_world(), st);
            r.wait();
            const RenderProgress p = r.progress();
            CHECK(p.done);
            CHECK(p.samples == 5);
            CHECK(p.film_samples == std::uint64_t(34 * 21 * 5));
            std::vector<std::uint32_t> counts;
            int w = 0, h = 0;
            r.sample_counts(counts, w, h);
            REQUIRE(w == 64);
            REQUIRE(h == 48);
            int wrong = 0, outside = 0;
            const Image film = r.snapshot();
            for (int y = 0; y < 48; ++y)
                for (int x = 0; x < 64; ++x) {
                    const bool in = x >= 7 && x < 41 && y >= 9 && y < 30;
                    const std::uint32_t n = counts[std::size_t(y) * 64 + x];
                    if (!in) {
                        outside += n != 0;
                        continue;
                    }
                    wrong += n != 5 || !same_bits(ref.at(x, y), &film.rgb[3 * (std::size_t(y) * 64 + x)]);
                }
            CHECK(wrong == 0);
            CHECK(outside == 0);
            // The window read back: the same pixels and counts.
            Image part;
            std::vector<std::uint32_t> part_counts;
            r.snapshot_window({7, 9, 41, 30}, part, part_counts);
            REQUIRE(part.width == 34);
            REQUIRE(part.height == 21);
            CHECK(part_counts == std::vector<std::uint32_t>(34 * 21, 5u));
            CHECK(same_bits(ref.at(7, 9), &part.rgb[0]));
            CHECK(same_bits(ref.at(40, 29), &part.rgb[3 * (34 * 21 - 1)]));
        }
    }
}

TEST_CASE("renderer: a crop raised to more samples is the whole film's pixels at the new count") {
    const Image ref = whole(7);
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings st;
    st.max_samples = 2;
    st.crop = {3, 4, 30, 40};
    r.start(mixed_world(), st);
    r.wait();
    REQUIRE(r.raise_samples(7));
    r.wait();
    CHECK(r.progress().samples == 7);
    Image part;
    std::vector<std::uint32_t> counts;
    r.snapshot_window(st.crop, part, counts);
    int wrong = 0;
    for (int y = 4; y < 40; ++y)
        for (int x = 3; x < 30; ++x)
            wrong += !same_bits(ref.at(x, y), &part.rgb[3 * (std::size_t(y - 4) * 27 + (x - 3))]);
    CHECK(wrong == 0);
}

TEST_CASE("renderer: an empty crop, or one outside the film, is done at once with nothing rendered") {
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    RenderSettings st;
    st.max_samples = 3;
    st.crop = {70, 50, 90, 60};
    r.start(mixed_world(), st);
    REQUIRE(r.wait_for(30));
    CHECK(r.progress().done);
    CHECK(r.progress().film_samples == 0);
}

TEST_CASE("renderer: a coarse step holds the whole film's sample 0 of each block's corner pixel") {
    const Image ref = whole(1);
    for (int step : {2, 3, 7}) {
        CAPTURE(step);
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        RenderSettings st;
        st.step = step;
        st.max_samples = 4;  // (a coarse film is one sample whatever is asked)
        r.start(mixed_world(), st);
        r.wait();
        const Image film = r.snapshot();
        REQUIRE(film.width == (64 + step - 1) / step);
        REQUIRE(film.height == (48 + step - 1) / step);
        CHECK(r.progress().samples == 1);
        int wrong = 0;
        for (int y = 0; y < film.height; ++y)
            for (int x = 0; x < film.width; ++x)
                wrong += !same_bits(ref.at(x * step, y * step), &film.rgb[3 * (std::size_t(y) * film.width + x)]);
        CHECK(wrong == 0);
    }
}

TEST_CASE("renderer: an id pass holds rt::pick's answer along each pixel's first ray, in its crop only") {
    const std::shared_ptr<const World> world = mixed_world();
    const CameraBasis camera = CameraBasis::make(world->camera, 64, 48, false);
    for (int step : {1, 3}) {
        CAPTURE(step);
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        RenderSettings st;
        st.pass = RenderPass::Ids;
        st.step = step;
        // (The lower part of the picture: the objects and the floor, some sky.)
        st.crop = {6 / step, 18 / step, (58 + step - 1) / step, (46 + step - 1) / step};
        r.start(world, st);
        r.wait();
        std::vector<std::uint32_t> ids;
        int w = 0, h = 0;
        r.ids(ids, w, h);
        REQUIRE(w == (64 + step - 1) / step);
        REQUIRE(h == (48 + step - 1) / step);
        int wrong = 0, hits = 0, kinds = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool in = x >= st.crop.x0 && x < st.crop.x1 && y >= st.crop.y0 && y < st.crop.y1;
                std::uint32_t want = 0;
                if (in) {
                    const PickResult p = pick(*world, camera.ray(double(x) * step, double(y) * step));
                    want = p.object >= 0 ? std::uint32_t(p.object + 1) * 4 + 1
                           : p.plane >= 0 ? std::uint32_t(p.plane + 1) * 4 + 2
                           : p.light >= 0 ? std::uint32_t(p.light + 1) * 4 + 3
                                          : 0;
                    hits += want != 0;
                    kinds |= want ? 1 << (want % 4) : 1;
                }
                wrong += ids[std::size_t(y) * w + x] != want;
            }
        CHECK(wrong == 0);
        CHECK(hits > 0);  // something is seen there, and something is not or is another thing
        CHECK(kinds != (1 << 1));
    }
}

TEST_CASE("renderer: a crop that goes on from loaded sums ends with the whole render's sums") {
    const std::shared_ptr<const World> world = mixed_world();
    const PixelWindow tile{16, 8, 48, 40};
    const std::size_t px = std::size_t(tile.pixels());
    auto sums_of = [&](int samples) {
        rt::ThreadPool r_pool(3);
        Renderer r(r_pool);
        RenderSettings st;
        st.max_samples = samples;
        r.start(world, st);
        r.wait();
        std::vector<float> sums(3 * px);
        r.read_window(tile, sums.data());
        return sums;
    };
    const std::vector<float> two = sums_of(2), five = sums_of(5);
    REQUIRE(two != five);
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    std::vector<std::uint32_t> counts(px, 2u);
    r.load_window(64, 48, tile, two.data(), counts.data());
    RenderSettings st;
    st.crop = tile;
    st.first_sample = 2;
    st.max_samples = 5;
    st.samples_per_pass = 3;
    st.tile_size = 8;
    r.start(world, st);
    r.wait();
    CHECK(r.progress().samples == 5);
    CHECK(r.progress().passes == 1);
    CHECK(r.progress().film_samples == std::uint64_t(3 * px));
    std::vector<float> got(3 * px);
    r.read_window(tile, got.data());
    CHECK(std::memcmp(got.data(), five.data(), got.size() * sizeof(float)) == 0);
}

TEST_CASE("renderer: the tile grid covers its window once, centre first") {
    const std::vector<PixelWindow> tiles = tile_grid(100, 70, {0, 0, 100, 70}, 32, TileOrder::CentreOut);
    REQUIRE(tiles.size() == 4 * 3);
    std::vector<int> cover(100 * 70, 0);
    for (const PixelWindow& t : tiles)
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) ++cover[std::size_t(y) * 100 + x];
    CHECK(std::count(cover.begin(), cover.end(), 1) == 100 * 70);
    CHECK(tiles[0] == PixelWindow{32, 32, 64, 64});  // its centre (48, 48) is nearest (50, 35)
    // Cut to a window off the grid: the grid's tiles, cut.
    const std::vector<PixelWindow> cut = tile_grid(100, 70, {10, 5, 40, 33}, 32, TileOrder::Scanline);
    REQUIRE(cut.size() == 4);
    CHECK(cut[0] == PixelWindow{10, 5, 32, 32});
    CHECK(cut[1] == PixelWindow{32, 5, 40, 32});
    CHECK(cut[2] == PixelWindow{10, 32, 32, 33});
    CHECK(cut[3] == PixelWindow{32, 32, 40, 33});
}
