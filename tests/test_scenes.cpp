// End to end: every scene in scenes/ renders to its stored reference in tests/refs/
// (made by tests/refs/make-refs.sh at a quarter of the scene's size and checked by
// eye). Small tolerances allow for floating-point differences between builds.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"

using namespace rt;
namespace fs = std::filesystem;

TEST_CASE("every example scene renders like its stored reference") {
    fs::path scenes = fs::path(RT_SOURCE_DIR) / "scenes";
    fs::path refs = fs::path(RT_SOURCE_DIR) / "tests" / "refs";
    rt::ThreadPool renderer_pool(3);
    Renderer renderer(renderer_pool);
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(scenes)) {
        if (entry.path().extension() != ".txt") continue;
        std::string name = entry.path().stem().string();
        CAPTURE(name);
        std::string text;
        REQUIRE(read_file(entry.path().string(), text, Limits::max_file_size).ok());
        ParseOptions options;
        options.base_dir = scenes.string();
        ParseResult parsed = parse_scene(text, options);
        REQUIRE(parsed.ok());

        int w = 0, h = 0;
        std::vector<std::uint8_t> ref;
        std::string err = read_ppm((refs / (name + ".ppm")).string(), w, h, ref).message();
        REQUIRE_MESSAGE(err.empty(), "no reference for " << name << ": run tests/refs/make-refs.sh");
        CHECK(w == parsed.scene.width / 4);
        CHECK(h == parsed.scene.height / 4);

        RenderSettings settings;
        settings.width = w;
        settings.height = h;
        settings.coarse = false;
        renderer.start(compile_world(parsed.scene), settings);
        renderer.wait();
        std::vector<std::uint8_t> got = to_rgb8(renderer.snapshot());
        REQUIRE(got.size() == ref.size());

        double total = 0;
        std::size_t off = 0;
        for (std::size_t i = 0; i < got.size(); ++i) {
            int d = std::abs(int(got[i]) - int(ref[i]));
            total += d;
            off += d > 3;
        }
        double mean = total / double(got.size());
        CHECK(mean < 0.5);
        CHECK(double(off) / double(got.size()) < 0.005);
        // Guard against a reference that is itself black or uniform.
        std::size_t distinct = 0;
        for (std::size_t i = 3; i < ref.size(); i += 3) distinct += ref[i] != ref[0];
        CHECK(distinct > ref.size() / 30);
        ++checked;
    }
    CHECK(checked >= 15);
}
