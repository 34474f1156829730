// TextureDirt: the film texture's unsent rows, sent within a budget a frame.
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "texture_dirt.h"

using rtview::TextureDirt;

namespace {

std::int64_t area(const std::vector<TextureDirt::Box>& bands) {
    std::int64_t n = 0;
    for (const auto& b : bands) n += std::int64_t(b[2] - b[0]) * (b[3] - b[1]);
    return n;
}

}  // namespace

TEST_CASE("a new texture is sent whole, a budget's worth of rows a frame, top to bottom") {
    TextureDirt d;
    d.reset(100, 50);
    CHECK(d.pending() == 5000);
    auto a = d.take(1000);  // ten rows
    REQUIRE(a.size() == 1);
    CHECK(a[0] == TextureDirt::Box{0, 0, 100, 10});
    auto b = d.take(1000);
    REQUIRE(b.size() == 1);
    CHECK(b[0] == TextureDirt::Box{0, 10, 100, 20});
    CHECK(d.pending() == 3000);
    int frames = 2;
    while (!d.empty()) {
        CHECK(area(d.take(1000)) == 1000);
        ++frames;
    }
    CHECK(frames == 5);
    CHECK(d.take(1000).empty());
}

TEST_CASE("a row wider than the budget is still sent, one at a time") {
    TextureDirt d;
    d.reset(300, 4);
    auto a = d.take(100);
    REQUIRE(a.size() == 1);
    CHECK(a[0] == TextureDirt::Box{0, 0, 300, 1});
}

TEST_CASE("tiles far apart in one row band are not joined into one wide rectangle") {
    TextureDirt d;
    d.reset(1000, 100);
    d.take(1000000);  // the first full upload
    REQUIRE(d.empty());
    d.add({0, 0, 32, 32});
    d.add({960, 64, 992, 96});
    CHECK(d.pending() == 2 * 32 * 32);
    auto bands = d.take(1000000);
    REQUIRE(bands.size() == 2);
    CHECK(bands[0] == TextureDirt::Box{0, 0, 32, 32});
    CHECK(bands[1] == TextureDirt::Box{960, 64, 992, 96});
    CHECK(d.empty());
}

TEST_CASE("boxes are clipped to the texture") {
    TextureDirt d;
    d.reset(10, 10);
    d.take(100);
    d.add({-5, 8, 20, 30});
    CHECK(d.pending() == 20);
    auto b = d.take(100);
    REQUIRE(b.size() == 1);
    CHECK(b[0] == TextureDirt::Box{0, 8, 10, 10});
}

TEST_CASE("random changes: every changed pixel is sent, no frame sends more than the budget and a row") {
    std::mt19937 rng(7);
    for (int round = 0; round < 40; ++round) {
        const int w = 1 + int(rng() % 90), h = 1 + int(rng() % 70);
        const std::int64_t budget = 1 + std::int64_t(rng() % 700);
        TextureDirt d;
        d.reset(w, h);
        while (!d.empty()) d.take(1 << 30);
        // What is changed and not yet sent, pixel by pixel.
        std::vector<char> dirty(std::size_t(w) * h, 0);
        for (int step = 0; step < 60; ++step) {
            for (int k = int(rng() % 3); k > 0; --k) {
                int x0 = int(rng() % (w + 10)) - 5, y0 = int(rng() % (h + 10)) - 5;
                int x1 = x0 + int(rng() % 30), y1 = y0 + int(rng() % 30);
                d.add({x0, y0, x1, y1});
                for (int y = std::max(0, y0); y < std::min(h, y1); ++y)
                    for (int x = std::max(0, x0); x < std::min(w, x1); ++x) dirty[std::size_t(y) * w + x] = 1;
            }
            const auto bands = d.take(budget);
            CHECK(area(bands) <= budget + w);
            for (const auto& b : bands) {
                REQUIRE(b[0] >= 0);
                REQUIRE(b[1] >= 0);
                REQUIRE(b[2] <= w);
                REQUIRE(b[3] <= h);
                REQUIRE(b[0] < b[2]);
                REQUIRE(b[1] < b[3]);
                for (int y = b[1]; y < b[3]; ++y)
                    for (int x = b[0]; x < b[2]; ++x) dirty[std::size_t(y) * w + x] = 0;
            }
        }
        // Enough frames with no new changes send the rest.
        for (int k = 0; k < w * h + 1 && !d.empty(); ++k)
            for (const auto& b : d.take(budget))
                for (int y = b[1]; y < b[3]; ++y)
                    for (int x = b[0]; x < b[2]; ++x) dirty[std::size_t(y) * w + x] = 0;
        CHECK(d.empty());
        int left = 0;
        for (char c : dirty) left += c;
        CHECK(left == 0);
    }
}
