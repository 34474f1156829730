// Snapshots: the memory and count caps, what changed between scenes, and difference
// images (a picture against itself is zero; known differences give known bytes).
#include <doctest/doctest.h>

#include <memory>

#include "renderer.h"
#include "scene_parser.h"
#include "snapshots.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

rt::Image flat(int w, int h, float v) {
    rt::Image img;
    img.width = w;
    img.height = h;
    img.rgb.assign(std::size_t(w) * h * 3, v);
    return img;
}

const std::string kScene = rtview_test::two_spheres(48, 36);

}  // namespace

TEST_CASE("the difference of a rendered picture with itself is zero") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    rt::ThreadPool renderer_pool(3);
    rt::Renderer renderer(renderer_pool);
    rtview_test::render_to_end(renderer, s, 3);
    rt::Image img = renderer.snapshot();
    REQUIRE(img.width == 48);
    double brightest = 0;
    for (float v : img.rgb) brightest = std::max(brightest, double(v));
    REQUIRE(brightest > 0.1);  // a picture, not a black film
    std::vector<std::uint8_t> rgba;
    DiffStats stats;
    REQUIRE(difference_rgba8(img, img, 1000, rgba, &stats));
    CHECK(stats.max_abs == 0);
    CHECK(stats.mean_abs == 0);
    CHECK(stats.differing == 0);
    REQUIRE(rgba.size() == 48 * 36 * 4);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        CHECK(rgba[i] == 0);
        CHECK(rgba[i + 1] == 0);
        CHECK(rgba[i + 2] == 0);
        CHECK(rgba[i + 3] == 255);
    }
}

TEST_CASE("a difference image shows |a - b| times the scale") {
    rt::Image a = flat(3, 2, 0.5f), b = flat(3, 2, 0.5f);
    b.rgb[3 * 4 + 1] = 0.25f;  // pixel (1, 1), green
    std::vector<std::uint8_t> rgba;
    DiffStats stats;
    REQUIRE(difference_rgba8(a, b, 1, rgba, &stats));
    CHECK(rgba[4 * 4 + 1] == 63);  // 255 * 0.25 = 63.75
    CHECK(rgba[4 * 4] == 0);
    CHECK(stats.max_abs == 0.25);
    CHECK(stats.differing == 1);
    CHECK(stats.mean_abs == doctest::Approx(0.25 / 18));
    REQUIRE(difference_rgba8(b, a, 2, rgba, nullptr));  // symmetric
    CHECK(rgba[4 * 4 + 1] == 127);
    CHECK_FALSE(difference_rgba8(a, flat(2, 3, 0.5f), 1, rgba));
}

TEST_CASE("the store keeps a few snapshots under its memory cap, oldest dropped first") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    const std::size_t one = [&] {
        Snapshot probe;
        probe.image = flat(100, 100, 0.5f);
        probe.scene = s;
        return probe.bytes();
    }();
    CHECK(one > 100 * 100 * 3 * sizeof(float));
    SnapshotStore store(2 * one + one / 2, 8);
    CHECK(store.add(flat(100, 100, 0.1f), 4, s, 1000)->id == 1);
    CHECK(store.add(flat(100, 100, 0.2f), 4, s, 1001)->id == 2);
    CHECK(store.add(flat(100, 100, 0.3f), 4, s, 1002)->id == 3);
    REQUIRE(store.list().size() == 2);
    CHECK(store.list()[0].id == 2);
    CHECK(store.find(1) == nullptr);
    CHECK(store.find(3)->image.rgb[0] == 0.3f);
    CHECK(store.bytes() <= store.max_bytes());
    // Too big on its own: refused, nothing dropped.
    CHECK(store.add(flat(300, 300, 0.4f), 4, s, 1003) == nullptr);
    CHECK(store.list().size() == 2);
    CHECK(store.remove(2));
    CHECK_FALSE(store.remove(2));
    CHECK(store.list().size() == 1);

    SnapshotStore few(std::size_t(1) << 30, 3);
    for (int k = 0; k < 5; ++k) few.add(flat(4, 4, 0.f), 1, s, k);
    CHECK(few.list().size() == 3);
    CHECK(few.list().front().id == 3);
}

TEST_CASE("snapshots say what changed since the one before, in the outline's numbers") {
    rt::Scene a = rtview_test::parse_ok(kScene);
    rt::Scene b = a;
    CHECK(describe_change(a, b) == "no change");
    b.camera.position.x += 1;
    b.objects[1].material.colour = {0, 1, 0};
    CHECK(describe_change(a, b) == "camera; material of object 2");
    rt::Scene c = a;
    std::get<rt::Sphere>(c.objects[0].shape).radius = 2;
    c.lights[0].colour = {2, 2, 2};
    c.planes[0].material.colour = {0, 0, 1};
    CHECK(describe_change(a, c) == "object 1; material of plane 1; light 1");
    CHECK(describe_change(a, c, 2) == "object 1; material of plane 1; 1 more");
    rt::Scene d = a;
    d.objects.push_back(d.objects[0]);
    CHECK(describe_change(a, d) == "objects 2 -> 3");

    SnapshotStore store;
    store.add(flat(2, 2, 0.f), 1, a, 0);
    const Snapshot* second = store.add(flat(2, 2, 0.f), 1, b, 0);
    CHECK(store.list().front().change.empty());
    CHECK(second->change == "camera; material of object 2");
}

TEST_CASE("nearest resampling repeats pixels") {
    rt::Image img = flat(2, 1, 0.f);
    img.rgb[3] = 1.f;  // pixel (1, 0) red
    rt::Image big = resample_nearest(img, 4, 2);
    CHECK(big.width == 4);
    CHECK(big.rgb[3 * 0] == 0.f);
    CHECK(big.rgb[3 * 1] == 0.f);
    CHECK(big.rgb[3 * 2] == 1.f);
    CHECK(big.rgb[3 * 7] == 1.f);  // (3, 1)
}
