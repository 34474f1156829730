// Reading a big file in pieces on several threads (ParseOptions::threads) must give
// exactly what reading it in one go gives: the scene, every item's line and column,
// and every diagnostic. Checked on generated scenes, valid and mutated, with pieces
// forced on small texts; and the progress callback and its cancel.
#include <doctest/doctest.h>

#include <string>
#include <thread>
#include <vector>

#include "scene_parser.h"
#include "test_random.h"

using namespace rt;
using rt_test::Rng;

namespace {

const char* const kItems[] = {
    "sphere { position 1 2 3 radius 0.5 }",
    "sphere {\n  material { scattering 1 colour 0.25 0.25 0.55 }\n  position -4.5 -3.5 0.4\n  radius 0.4\n}",
    "sphere { material { reflection 0.5 scattering 0.5 colour 0.9 0.9 0.9 } position 1e2 2 3 radius 1 }",
    "tetrahedron { vect1 0 0 0 vect2 1 0 0 vect3 0 1 0 vect4 0 0 1 }",
    "cylinder { end_1 0 0 0 end_2 0 0 2 radius 0.3 material { colour 1 0 0 } }",
    "torus { position 0 0 1 direction 0 0 1 major 2 minor 0.5 }",
    "constructive_solid_geometry { type I left { sphere { radius 2 } } right {\n"
    "  constructive_solid_geometry { type U left { sphere { } } right { torus { } } } } }",
    // with a warning, and with errors: a helper must leave these to the main reading
    "sphere { material { reflection 0 refraction 0 scattering 0 } }",
    "sphere { radius -1 }",
    "sphere { position 1 2 }",
    "cube { size 1 }",
    "cylinder { end_1 1 1 1 end_2 1 1 1 }",
    "constructive_solid_geometry { type X left { sphere { } } right { sphere { } } }",
    "sphere { colour 1 2 3 }",
    // comments and odd spacing
    "// a comment } sphere {\nsphere{position 0 0 0}",
    "sphere\r\n{\r\n radius 2\r\n}",
    "\tsphere {radius 3}// tail",
};
constexpr std::size_t kValidItems = 7;

const char* const kOther[] = {
    "special_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 } }",
    "light { lamp { position 1 2 3 colour 1 1 1 size 0.5 } spotlight { position 0 0 5 } }",
    "camera { position 0 0 10 centre 0 0 0 up 0 1 10 angle_x 60 angle_y 45 }",
    "picture_size { x_max 64 y_max 48 }",
};

const char* const kNoise[] = {"}", "{", "thing", "sphere", "sphere {", "// x\n", "\n", "1e400", "light", " ",
                              "radius", "end", "\r", "left {", "constructive_solid_geometry {"};

std::string make_scene(Rng& rng, bool valid_only) {
    std::string s = rng.uni() < 0.2 ? "\xEF\xBB\xBF" : "";
    const int sections = 1 + int(rng.index(3));
    for (int k = 0; k < sections; ++k) {
        s += "thing {\n";
        const std::size_t n = 1 + rng.index(40);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t pick = valid_only ? rng.index(kValidItems) : rng.index(std::size(kItems));
            s += rng.uni() < 0.5 ? "\t" : "  ";
            s += kItems[pick];
            s += rng.uni() < 0.1 ? " " : "\n";
        }
        s += "}\n";
        if (rng.uni() < 0.5) s += std::string(kOther[rng.index(2)]) + "\n";
    }
    s += kOther[2];
    s += "\n";
    s += kOther[3];
    s += "\nend\n";
    return s;
}

// A few random edits: deleted or repeated spans, inserted noise, changed bytes.
void mutate(Rng& rng, std::string& s) {
    const int edits = 1 + int(rng.index(4));
    for (int e = 0; e < edits && !s.empty(); ++e) {
        const std::size_t at = rng.index(s.size());
        const std::size_t len = std::min(s.size() - at, 1 + rng.index(30));
        switch (rng.index(4)) {
            case 0: s.erase(at, len); break;
            case 1: s.insert(at, s.substr(at, len)); break;
            case 2: s.insert(at, kNoise[rng.index(std::size(kNoise))]); break;
            default: s[at] = char(rng.index(256)); break;
        }
    }
}

void same_locs(const Object& a, const Object& b) {
    REQUIRE(a.loc.line == b.loc.line);
    REQUIRE(a.loc.col == b.loc.col);
    if (const auto* ca = std::get_if<Csg>(&a.shape)) {
        const auto& cb = std::get<Csg>(b.shape);
        REQUIRE(ca->operands.size() == cb.operands.size());
        for (std::size_t i = 0; i < ca->operands.size(); ++i) same_locs(ca->operands[i], cb.operands[i]);
    }
}

// Everything a ParseResult says, compared field by field.
void same_result(const ParseResult& a, const ParseResult& b) {
    REQUIRE(a.diagnostics.size() == b.diagnostics.size());
    for (std::size_t i = 0; i < a.diagnostics.size(); ++i) {
        const Diagnostic &x = a.diagnostics[i], &y = b.diagnostics[i];
        REQUIRE(x.message == y.message);
        REQUIRE(x.line == y.line);
        REQUIRE(x.col == y.col);
        REQUIRE(x.severity == y.severity);
    }
    REQUIRE(a.ok() == b.ok());
    REQUIRE(a.scene == b.scene);
    REQUIRE(a.scene.objects.size() == b.scene.objects.size());
    for (std::size_t i = 0; i < a.scene.objects.size(); ++i) same_locs(a.scene.objects[i], b.scene.objects[i]);
    for (std::size_t i = 0; i < a.scene.planes.size(); ++i) {
        REQUIRE(a.scene.planes[i].loc.line == b.scene.planes[i].loc.line);
        REQUIRE(a.scene.planes[i].loc.col == b.scene.planes[i].loc.col);
    }
    for (std::size_t i = 0; i < a.scene.lights.size(); ++i) {
        REQUIRE(a.scene.lights[i].loc.line == b.scene.lights[i].loc.line);
        REQUIRE(a.scene.lights[i].loc.col == b.scene.lights[i].loc.col);
    }
    REQUIRE(a.scene.camera_loc.line == b.scene.camera_loc.line);
    REQUIRE(a.scene.camera_loc.col == b.scene.camera_loc.col);
}

ParseResult in_one_go(const std::string& text, int max_errors = 20) {
    ParseOptions o;
    o.threads = 1;
    o.max_errors = max_errors;
    return parse_scene(text, o);
}

ParseResult in_pieces(const std::string& text, int threads, int max_errors = 20, std::size_t chunk = 4096) {
    ParseOptions o;
    o.threads = threads;
    o.min_piece_bytes = 1;
    o.chunk_objects = chunk;
    o.max_errors = max_errors;
    return parse_scene(text, o);
}

}  // namespace

TEST_CASE("pieces: valid scenes read in pieces equal the one-go reading, and pieces are used") {
    Rng rng(17);
    std::size_t ahead = 0, objects = 0;
    for (int round = 0; round < 150; ++round) {
        const std::string text = make_scene(rng, true);
        const ParseResult one = in_one_go(text);
        REQUIRE(one.ok());
        CHECK(one.objects_read_ahead == 0);
        for (int threads : {2, 3, 5}) {
            // Helpers hand their objects over one by one, a few at a time, or at their end.
            const ParseResult many = in_pieces(text, threads, 20, threads == 2 ? 1 : threads == 3 ? 3 : 4096);
            same_result(one, many);
            ahead += many.objects_read_ahead;
            objects += many.scene.objects.size();
        }
    }
    // Some objects came from helpers. (How many depends on timing: on texts this small
    // the main reading often reaches a piece before a thread of the pool has begun it,
    // and then reads it itself; the big file's test below counts them.)
    CHECK(ahead > 0);
    CHECK(ahead < objects);
}

TEST_CASE("pieces: scenes with errors, warnings and random edits give the same result and diagnostics") {
    Rng rng(1717);
    std::size_t ahead = 0, with_errors = 0;
    for (int round = 0; round < 1500; ++round) {
        std::string text = make_scene(rng, false);
        if (round % 4 != 0) mutate(rng, text);
        const int max_errors = round % 3 == 0 ? 1 : 20;
        const ParseResult one = in_one_go(text, max_errors);
        with_errors += !one.ok();
        const ParseResult many = in_pieces(text, 2 + round % 4, max_errors, 1 + round % 5);
        INFO("round ", round, "\n", text);
        same_result(one, many);
        ahead += many.objects_read_ahead;
    }
    CHECK(with_errors > 500);
    CHECK(ahead > 0);  // (how many: see the test above)
}

TEST_CASE("pieces: a big generated file takes its pieces with the default size") {
    std::string text = "thing {\n";
    for (int i = 0; i < 120000; ++i)
        text += "\tsphere {\n\t\tmaterial { scattering 1 colour 0.25 0.25 0.55 }\n\t\tposition " + std::to_string(i) +
                " 0.5 0.4\n\t\tradius 0.4\n\t}\n";
    text += "}\ncamera { position 0 0 10 centre 0 0 0 up 0 1 10 angle_x 60 angle_y 45 }\n"
            "picture_size { x_max 64 y_max 48 }\nend\n";
    REQUIRE(text.size() > (std::size_t(8) << 20));
    ParseOptions o;
    o.threads = 2;
    const ParseResult many = parse_scene(text, o);
    CHECK(many.objects_read_ahead > 40000);
    same_result(in_one_go(text), many);
    // The last object's line: 5 lines per sphere after the `thing {` line.
    CHECK(many.scene.objects.back().loc.line == 2 + 5 * 119999);
    CHECK(std::get<Sphere>(many.scene.objects.back().shape).position.x == 119999);
}

// A big file cut short anywhere (as a file still being written, or truncated, is read):
// the pieces stop where the text does, the helpers' chunks taken so far stay exactly
// those the one-go reading makes, and the diagnostic at the end is the same.
TEST_CASE("pieces: a big file cut at any point gives the one-go reading's result and message") {
    std::string text = "thing {\n";
    for (int i = 0; i < 6000; ++i)
        text += "\tsphere {\n\t\tmaterial { scattering 1 colour 0.25 0.25 0.55 }\n\t\tposition " + std::to_string(i) +
                " 0.5 0.4\n\t\tradius 0.4\n\t}\n";
    text += "}\ncamera { position 0 0 10 centre 0 0 0 up 0 1 10 angle_x 60 angle_y 45 }\n"
            "picture_size { x_max 64 y_max 48 }\nend\n";
    Rng rng(4242);
    std::size_t ahead = 0;
    for (int round = 0; round < 40; ++round) {
        const std::string cut = text.substr(0, round == 0 ? text.size() : rng.index(text.size()));
        const ParseResult one = in_one_go(cut);
        INFO("cut at ", cut.size());
        if (round == 0) CHECK(one.ok());
        for (int threads : {2, 4}) {
            const ParseResult many = in_pieces(cut, threads, 20, 1 + std::size_t(round % 3) * 50);
            same_result(one, many);
            ahead += many.objects_read_ahead;
        }
        if (!one.ok()) {
            // The one message of a file cut inside its thing section (or after it).
            REQUIRE(!one.diagnostics.empty());
            const std::string& m = one.diagnostics.back().message;
            CHECK((m.find("unexpected end of file") == 0 || m.find("missing") != std::string::npos ||
                   m.find("the scene has no") == 0));
        }
    }
    CHECK(ahead > 0);
}

TEST_CASE("progress: bytes rise to the text's size, objects to their count; false cancels soon") {
    std::string text = "thing {\n";
    for (int i = 0; i < 60000; ++i) text += "sphere { position " + std::to_string(i) + " 0 0 radius 0.5 }\n";
    text += "}\ncamera { position 0 0 10 centre 0 0 0 up 0 1 10 angle_x 60 angle_y 45 }\n"
            "picture_size { x_max 64 y_max 48 }\nend\n";
    for (int threads : {1, 2}) {
        CAPTURE(threads);
        std::vector<std::pair<std::size_t, std::size_t>> calls;
        ParseOptions o;
        o.threads = threads;
        o.min_piece_bytes = 1 << 20;
        bool elsewhere = false;  // called on another thread than the parse's caller
        const auto me = std::this_thread::get_id();
        o.progress = [&](std::size_t bytes, std::size_t objects) {
            calls.emplace_back(bytes, objects);
            elsewhere |= std::this_thread::get_id() != me;
            return true;
        };
        const ParseResult r = parse_scene(text, o);
        REQUIRE(r.ok());
        CHECK_FALSE(elsewhere);
        REQUIRE(calls.size() >= 2);
        for (std::size_t i = 1; i < calls.size(); ++i) CHECK(calls[i].first >= calls[i - 1].first);
        CHECK(calls.back().first <= text.size());
        CHECK(calls.back().second <= r.scene.objects.size());
        CHECK(calls.back().first > text.size() / 2);

        // The first false ends the parse: no call after it.
        int after_false = 0;
        bool said_false = false;
        o.progress = [&](std::size_t bytes, std::size_t) {
            after_false += said_false;
            said_false = bytes >= (std::size_t(1) << 20);
            return !said_false;
        };
        const ParseResult c = parse_scene(text, o);
        CHECK(c.cancelled);
        CHECK_FALSE(c.ok());
        CHECK(said_false);
        CHECK(after_false == 0);
        CHECK(c.scene.objects.size() < 60000);
    }
}
