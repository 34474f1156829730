// The texture's bytes: the renderer's own with default display settings, exposure
// applied to the linear film otherwise, and a render region over the last picture.
#include <doctest/doctest.h>

#include <chrono>
#include <thread>

#include "film_view.h"
#include "renderer.h"
#include "scene_parser.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

const std::string kScene = rtview_test::two_spheres(64, 48);

}  // namespace

TEST_CASE("the texture shows the renderer's bytes, or the exposed film, and a region over it") {
    rt::Scene s = rtview_test::parse_ok(kScene);
    rt::ThreadPool renderer_pool(3);
    rt::Renderer renderer(renderer_pool);
    rtview_test::render_to_end(renderer, s, 3);
    rt::ZeroedArray<std::uint8_t> file;
    int fw = 0, fh = 0;
    renderer.snapshot_rgb8(file, fw, fh);
    const rt::Image film = renderer.snapshot();
    const std::size_t n = 64 * 48;

    FilmView view;
    DisplaySettings d;
    std::array<int, 4> changed{};
    REQUIRE(view.update(renderer, d, nullptr, 0, changed));
    CHECK(view.width() == 64);
    CHECK(changed == std::array<int, 4>{0, 0, 64, 48});
    int wrong = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) wrong += view.rgba()[4 * i + c] != file[3 * i + c];
    CHECK(wrong == 0);
    CHECK_FALSE(view.update(renderer, d, nullptr, 1, changed));  // nothing new

    // +1 stop: 255 * 2v truncated, from the linear film.
    d.exposure = 1;
    REQUIRE(view.update(renderer, d, nullptr, 2, changed));
    CHECK(changed == std::array<int, 4>{0, 0, 64, 48});
    wrong = 0;
    int brighter = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            double v = 255.0 * 2.0 * film.rgb[3 * i + c];
            int expect = v >= 255 ? 255 : v <= 0 ? 0 : int(v);
            wrong += view.rgba()[4 * i + c] != expect;
            brighter += view.rgba()[4 * i + c] > file[3 * i + c];
        }
    CHECK(wrong == 0);
    CHECK(brighter > int(n));  // most channels of a lit scene got brighter

    rt::Colour c;
    REQUIRE(view.linear_at(renderer, 3, 0, 10, 40, c));
    CHECK(float(c.x) == film.at(10, 40).x);
    CHECK_FALSE(view.linear_at(renderer, 3, 0, 64, 0, c));

    // A region rendered with the first sphere green: inside the rectangle it shows,
    // outside the last picture stays.
    rt::Scene green = s;
    green.objects[0].material.colour = {0.2, 1, 0.2};
    rt::ThreadPool region_pool(3);
    RegionRenderer region(region_pool);
    const PixelRect rect{20, 10, 44, 38};
    region.start(rt::compile_world(green), green.camera, 64, 48, rect, 3);
    for (int k = 0; k < 3000 && !region.done(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    REQUIRE(region.done());
    d.exposure = 0;
    REQUIRE(view.update(renderer, d, &region, 10, changed));
    rt::ThreadPool green_full_pool(3);
    rt::Renderer green_full(green_full_pool);
    rtview_test::render_to_end(green_full, green, 3);
    rt::ZeroedArray<std::uint8_t> green_file;
    green_full.snapshot_rgb8(green_file, fw, fh);
    int inside_wrong = 0, outside_wrong = 0, inside_differs = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            std::size_t i = std::size_t(y) * 64 + x;
            bool inside = x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1;
            for (int k = 0; k < 3; ++k) {
                int got = view.rgba()[4 * i + k];
                if (inside) {
                    inside_wrong += got != green_file[3 * i + k];
                    inside_differs += got != file[3 * i + k];
                } else {
                    outside_wrong += got != file[3 * i + k];
                }
            }
        }
    CHECK(inside_wrong == 0);
    CHECK(outside_wrong == 0);
    CHECK(inside_differs > 50);  // the sphere did turn green there
    CHECK(view.samples_at(30, 20, 3) == 3);
    REQUIRE(view.linear_at(renderer, 11, 1, 32, 24, c));
    CHECK(c.y > c.x);  // the green sphere's pixel, from the region
    rt::Image shown = view.linear_picture(renderer, 12);
    CHECK(shown.at(32, 24).y == float(c.y));
    CHECK(shown.at(5, 5).x == film.at(5, 5).x);

    // The region cleared: the whole last picture again.
    region.cancel();
    REQUIRE(view.update(renderer, d, &region, 20, changed));
    wrong = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) wrong += view.rgba()[4 * i + k] != file[3 * i + k];
    CHECK(wrong == 0);
}
