// Render region: the rectangle a drag selects at several zooms, and region pixels
// equal to the full renderer's pixels at the same sample count.
#include <doctest/doctest.h>

#include <chrono>
#include <thread>

#include "readout.h"
#include "region.h"
#include "renderer.h"
#include "scene_parser.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

const char* kScene = R"(
thing { sphere { material { colour 1 0.2 0.2 } position 10 0 1 radius 1 }
        sphere { material { reflection 0.5 scattering 0.5 } position 12 2.5 1.5 radius 1.5 } }
special_thing { chess_plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 4 -3 4 colour 30 30 30 size 0.3 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
picture_size { x_max 64 y_max 48 }
end)";

bool wait_done(const RegionRenderer& rr) {
    for (int k = 0; k < 3000 && !rr.done(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return rr.done();
}

}  // namespace

TEST_CASE("a drag selects the pixels under both ends and everything between") {
    Rect area{0, 0, 640, 480};
    ImageView v;  // 64x48 fitted: 10 units a pixel
    ViewTransform t = v.transform(area, 64, 48);
    PixelRect r = region_from_drag(t, 64, 48, 105, 52, 299, 141);
    CHECK(r == PixelRect{10, 5, 30, 15});
    CHECK(region_from_drag(t, 64, 48, 299, 141, 105, 52) == r);  // dragged the other way
    CHECK(region_from_drag(t, 64, 48, -50, -50, 15, 15) == PixelRect{0, 0, 2, 2});
    CHECK(region_from_drag(t, 64, 48, 600, 400, 9999, 9999) == PixelRect{60, 40, 64, 48});
    // Zoomed to 1:1 about the centre: the picture spans 288..352 x 216..264.
    v.one_to_one(area, 64, 48, 1, 320, 240);
    t = v.transform(area, 64, 48);
    CHECK(region_from_drag(t, 64, 48, 290.5, 220.5, 299.5, 223.5) == PixelRect{2, 4, 12, 8});
    CHECK(region_from_drag(t, 64, 48, 0, 0, 100, 100).empty());  // all outside
    // In a film of twice the size the same region covers twice the pixels.
    CHECK(scale_region({10, 5, 30, 15}, 64, 48, 128, 96) == PixelRect{20, 10, 60, 30});
    CHECK(scale_region({10, 5, 30, 15}, 64, 48, 64, 48) == PixelRect{10, 5, 30, 15});
}

TEST_CASE("region pixels are the full render's pixels at the same sample count") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    rt::Renderer full(2);
    rt::RenderSettings st;
    st.max_samples = 5;
    full.start(world, st);
    full.wait();
    rt::Image ref = full.snapshot();
    REQUIRE(ref.width == 64);

    RegionRenderer rr(2);
    const PixelRect rect{7, 9, 41, 30};
    rr.start(world, s.camera, 64, 48, rect, 5);
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 5);
    RegionPicture pic;
    std::uint64_t version = 0;
    REQUIRE(rr.snapshot(pic, version));
    CHECK_FALSE(rr.snapshot(pic, version));  // nothing new since
    REQUIRE(pic.rect == rect);
    int different = 0;
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x)
            for (int c = 0; c < 3; ++c) {
                float a = pic.image.rgb[3 * (std::size_t(y - rect.y0) * rect.width() + (x - rect.x0)) + c];
                float b = ref.rgb[3 * (std::size_t(y) * ref.width + x) + c];
                different += a != b;
            }
    CHECK(different == 0);

    // Pasted into an old picture: the region's pixels change, the rest stays.
    rt::Image old;
    old.width = 64;
    old.height = 48;
    old.rgb.assign(64 * 48 * 3, -1.f);
    paste_region(pic, old);
    CHECK(old.at(7, 9).x == ref.at(7, 9).x);
    CHECK(old.at(40, 29).y == ref.at(40, 29).y);
    CHECK(old.at(6, 9).x == -1.f);
    CHECK(old.at(41, 29).x == -1.f);
    CHECK(old.at(20, 30).x == -1.f);
}

TEST_CASE("a region render can be cancelled and started again") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    RegionRenderer rr(2);
    rr.start(world, s.camera, 64, 48, {0, 0, 64, 48}, 4096);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    rr.cancel();
    CHECK_FALSE(rr.active());
    CHECK(rr.rect().empty());
    rr.start(world, s.camera, 64, 48, {1, 1, 3, 3}, 2);
    REQUIRE(wait_done(rr));
    CHECK(rr.samples() == 2);
    // A rectangle outside the picture starts nothing.
    rr.start(world, s.camera, 64, 48, {60, 40, 70, 50}, 2);
    CHECK_FALSE(rr.active());
}

TEST_CASE("the readout names what a pixel's ray hit as the outline does") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    auto world = rt::compile_world(s);
    // The picture's centre looks straight at sphere 1 (at x 9 from a camera at x 0).
    rt::PickResult hit = pick_pixel(*world, s.camera, 64, 48, 32, 24);
    REQUIRE(hit.hit);
    CHECK(outline_name(s, hit) == "object 1 (sphere)");
    CHECK(hit.t == doctest::Approx(9).epsilon(0.01));
    rt::PickResult floor = pick_pixel(*world, s.camera, 64, 48, 32, 47);
    CHECK(outline_name(s, floor) == "plane 1 (chess_plane)");
    rt::PickResult sky = pick_pixel(*world, s.camera, 64, 48, 2, 0);
    CHECK_FALSE(sky.hit);
    CHECK(outline_name(s, sky).empty());

    PixelReadout r;
    r.x = 32;
    r.y = 24;
    r.has_colour = true;
    r.linear = {0.5, 0.25, 1.75};
    r.samples = 64;
    r.hit = hit;
    r.hit_name = outline_name(s, hit);
    std::string line = format_readout(r);
    CHECK(line.find("x 32 y 24") != std::string::npos);
    CHECK(line.find("RGB 0.500 0.250 1.750") != std::string::npos);
    CHECK(line.find("64 spp") != std::string::npos);
    CHECK(line.find("object 1 (sphere) at 9") != std::string::npos);
}
