// Scene text <-> Scene agreement: layout scanning, in-place patches, the fallback,
// carrying edits into drafts, line/column helpers.
#include <doctest/doctest.h>

#include <random>

#include "default_scene.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "viewer_test_util.h"

using namespace rtview;
using rtview_test::parse_ok;

namespace {

// The format spec's example (every feature), with comments in awkward places.
const char* const kExample = R"(// demo scene
thing {
  sphere {                         // glass ball
    material { reflection 0.1 refraction 0.8 scattering 0.1
               translusans 0.9 refractive_index 1.5 colour 0.9 0.95 1 }
    position 6 1.5 0.8
    radius 0.8
  }
  tetrahedron {
    material { reflection 0.3 scattering 0.7 colour 1 0.3 0.2 }
    vect1 5 -2 0  vect2 6 -1 0  vect3 6.5 -2.5 0  vect4 5.8 -1.8 1.6
  }
  cylinder { material { colour 0.3 0.4 1 } end_1 8 0 0 end_2 8 0 2 radius 0.5 }
  torus {
    material { reflection 0.4 scattering 0.6 colour 1 0.8 0.2 }
    position 4.5 0 0.25  direction 0 0 1  major 0.6  minor 0.2
  }
  constructive_solid_geometry {    // a lens with two bites taken out }
    type C
    left { constructive_solid_geometry { type I
             left { sphere { position 7 -0.3 2.2 radius 0.8 } }
             right { sphere { position 7 0.5 2.2 radius 0.8 } } } }
    right { constructive_solid_geometry { type U
             left { sphere { position 6.5 0.1 2.6 radius 0.3 } }
             right { sphere { position 6.5 0.1 1.8 radius 0.3 } } } }
    material { reflection 0.2 scattering 0.8 colour 0.3 1 0.4 }
  }
}
special_thing {
  chess_plane {
    material 1 { reflection 0.3 scattering 0.7 colour 1 1 1 }
    material 2 { colour 0.1 0.1 0.1 }
    point 1 0.5 0.5 0  point 2 1.5 0.5 0  point 3 0.5 1.5 0  point 4 0 0 1
  }
  plane { material { colour 0.6 0.7 0.9 }
          point 1 20 0 0  point 2 20 1 0  point 3 20 0 1  point 4 0 0 0 }
}
light {
  lamp { colour 60 60 50 position 2 3 5 size 0.3 }
  spotlight { colour 40 40 60 position 0 -4 3 }
}
camera { position 0 0 2 centre 6 0 1 }
camera { up 6 0 2 projection x angle_x 60 angle_y 45 }
picture_size { x_max 320 y_max 240 }
end
text after end is ignored { even unbalanced
)";

}  // namespace

TEST_CASE("the layout scan finds the same items the parser does") {
    for (const char* text : {kExample, rt::kDefaultScene}) {
        rt::Scene s = parse_ok(text);
        SceneLayout l = scan_layout(text);
        REQUIRE(l.ok);
        CHECK(l.objects.size() == s.objects.size());
        CHECK(l.planes.size() == s.planes.size());
        CHECK(l.lights.size() == s.lights.size());
        CHECK(!l.cameras.empty());
    }
    SceneLayout l = scan_layout(kExample);
    std::string ex = kExample;
    CHECK(ex.substr(l.objects[2].begin, 8) == "cylinder");
    CHECK(ex[l.objects[2].end - 1] == '}');
    CHECK(l.cameras.size() == 2);
    CHECK(ex.substr(l.append_at, 3) == "end");
}

TEST_CASE("the layout scan uses the parser's token rules") {
    // Glued braces, a brace inside a comment, `//` inside a token (not a comment).
    std::string t = "thing{sphere{position 1 2 3 radius 1}// } not a brace\n}\nlight { lamp { position a//b } }";
    SceneLayout l = scan_layout(t);
    REQUIRE(l.ok);
    REQUIRE(l.objects.size() == 1);
    CHECK(t.substr(l.objects[0].begin, l.objects[0].end - l.objects[0].begin) == "sphere{position 1 2 3 radius 1}");
    CHECK(l.lights.size() == 1);
    CHECK_FALSE(scan_layout("thing { sphere { radius 1 }").ok);  // unbalanced
}

TEST_CASE("a material edit rewrites only that object and keeps the comments") {
    std::string text = kExample;
    rt::Scene from = parse_ok(text);
    rt::Scene to = from;
    to.objects[1].material.reflection = 0.75;
    auto out = patch_scene_text(text, from, to);
    REQUIRE(out.has_value());
    CHECK(parse_ok(*out) == to);
    CHECK(out->find("// glass ball") != std::string::npos);
    CHECK(out->find("// a lens with two bites taken out }") != std::string::npos);
    CHECK(out->find("text after end is ignored { even unbalanced") != std::string::npos);
    // The untouched glass sphere keeps its original two-line material.
    CHECK(out->find("translusans 0.9 refractive_index 1.5 colour 0.9 0.95 1 }") != std::string::npos);
}

TEST_CASE("a camera edit becomes one complete block in place of the last camera section") {
    std::string text = kExample;
    rt::Scene from = parse_ok(text);
    rt::Scene to = from;
    to.camera.position = {-3, 1, 4};
    to.camera.angle_x = 70;
    auto out = patch_scene_text(text, from, to);
    REQUIRE(out.has_value());
    rt::Scene back = parse_ok(*out);
    CHECK(back == to);
    CHECK(back.width == 320);  // picture size survives (the first camera set x_max too)
    CHECK(out->find("camera { position 0 0 2 centre 6 0 1 }") != std::string::npos);
}

TEST_CASE("writing panel edits back round-trips for random edits") {
    std::mt19937 rng(7);
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    for (const char* base : {kExample, rt::kDefaultScene}) {
        std::string text = base;
        rt::Scene cur = parse_ok(text);
        for (int step = 0; step < 60; ++step) {
            rt::Scene next = cur;
            switch (step % 4) {
                case 0: {
                    auto& m = next.objects[std::size_t(rng() % next.objects.size())];
                    m.material.reflection = u(0, 1);
                    m.material.colour = {u(0, 1), u(0, 1), u(0, 1)};
                    m.has_material = true;
                    break;
                }
                case 1: {
                    auto& l = next.lights[std::size_t(rng() % next.lights.size())];
                    l.position = {u(-9, 9), u(-9, 9), u(0, 9)};
                    l.colour = {u(0, 200), u(0, 200), u(0, 200)};
                    break;
                }
                case 2:
                    next.camera.position = {u(-9, 0), u(-3, 3), u(0, 5)};
                    next.camera.angle_y = u(10, 90);
                    break;
                case 3: {
                    auto& p = next.planes[0];
                    p.material2.colour = {u(0, 1), u(0, 1), u(0, 1)};
                    p.has_material2 = p.chess;
                    p.material.scattering = u(0, 2);
                    p.has_material = true;
                    break;
                }
            }
            std::string out = sync_scene_text(text, cur, next);
            CHECK(parse_ok(out) == next);
            CHECK(patch_scene_text(text, cur, next).has_value());  // never needed the fallback
            // The same edit named by its items gives the same text.
            ItemIndices at;
            rt::Scene values;
            for (std::size_t i = 0; i < next.objects.size(); ++i)
                if (!(cur.objects[i] == next.objects[i])) at.objects.push_back(i), values.objects.push_back(next.objects[i]);
            for (std::size_t i = 0; i < next.planes.size(); ++i)
                if (!(cur.planes[i] == next.planes[i])) at.planes.push_back(i), values.planes.push_back(next.planes[i]);
            for (std::size_t i = 0; i < next.lights.size(); ++i)
                if (!(cur.lights[i] == next.lights[i])) at.lights.push_back(i), values.lights.push_back(next.lights[i]);
            at.camera = !(cur.camera == next.camera);
            values.camera = next.camera;
            CHECK(patch_scene_items(text, cur, at, values) == out);
            text = out;
            cur = next;
        }
    }
}

TEST_CASE("an edit named by its items refuses indices out of range and values that do not read back") {
    const std::string text = kExample;
    const rt::Scene cur = parse_ok(text);
    ItemIndices at;
    rt::Scene values;
    at.objects = {cur.objects.size()};
    values.objects = {cur.objects[0]};
    CHECK_FALSE(patch_scene_items(text, cur, at, values));
    at.objects = {0};
    CHECK_FALSE(patch_scene_items(text, cur, at, rt::Scene{}));  // one index, no value
    std::get<rt::Sphere>(values.objects[0].shape).position.x = 1e300;  // beyond the format's numbers
    CHECK_FALSE(patch_scene_items(text, cur, at, values));
    values.objects[0] = cur.objects[0];
    CHECK(patch_scene_items(text, cur, at, values) == text);  // nothing changed
}

TEST_CASE("sync falls back to the writer when the items changed in number") {
    std::string text = rt::kDefaultScene;
    rt::Scene from = parse_ok(text);
    rt::Scene to = from;
    to.objects.pop_back();
    CHECK_FALSE(patch_scene_text(text, from, to).has_value());
    CHECK(parse_ok(sync_scene_text(text, from, to)) == to);
}

TEST_CASE("an edit is carried into a draft only for the items it changed") {
    rt::Scene base = parse_ok(rt::kDefaultScene);
    rt::Scene draft = base;
    draft.objects[0].material.colour = {1, 0, 0};  // the user's own draft change
    rt::Scene edited = base;
    edited.objects[1].material.reflection = 0.9;  // the panel edit
    edited.camera.angle_y = 50;
    bool complete = false;
    rt::Scene r = carry_edit(draft, base, edited, &complete);
    CHECK(complete);
    CHECK(r.objects[0].material.colour == rt::Vec3{1, 0, 0});
    CHECK(r.objects[1].material.reflection == 0.9);
    CHECK(r.camera.angle_y == 50);
    draft.objects.pop_back();  // the draft removed an object: object edits cannot be placed
    carry_edit(draft, base, edited, &complete);
    CHECK_FALSE(complete);
}

TEST_CASE("line and column convert to offsets and back") {
    std::string t = "ab\ncde\n\nf";
    CHECK(offset_of(t, 1, 1) == 0);
    CHECK(offset_of(t, 2, 3) == 5);
    CHECK(offset_of(t, 2, 99) == 6);  // clamped to the end of the line
    CHECK(offset_of(t, 4, 1) == 8);
    CHECK(offset_of(t, 9, 1) == t.size());
    // Every offset from its line and column, counted here.
    int line = 1, col = 1;
    for (std::size_t off = 0; off <= t.size(); ++off) {
        CHECK(offset_of(t, line, col) == off);
        if (off < t.size() && t[off] == '\n') ++line, col = 1;
        else ++col;
    }
}

TEST_CASE("diagnostic positions point at the offending token") {
    std::string t = "thing {\n  sphere { positio 1 2 3 }\n}\n";
    rt::ParseResult r = rt::parse_scene(t);
    REQUIRE_FALSE(r.ok());
    const rt::Diagnostic& d = r.diagnostics.front();
    CHECK(t.substr(offset_of(t, d.line, d.col), 7) == "positio");
}

TEST_CASE("scene text or not: NUL bytes and much that is not UTF-8 are refused, a few foreign bytes pass") {
    CHECK(not_scene_text(rt::kDefaultScene).empty());
    CHECK(not_scene_text("").empty());
    // UTF-8 of every length, at the text's end too.
    CHECK(not_scene_text("// \xc3\xa6\xc3\xb8\xc3\xa5 \xe2\x82\xac \xf0\x9f\x98\x80\nend\n\xe2\x82\xac").empty());
    CHECK(not_scene_text(std::string("end\n\0", 5)) == "not a scene text: a NUL byte at byte 5 (a binary file?)");
    // A comment in Latin-1 ("blå kule"): a few bytes, well under 1 %.
    std::string latin = "// bl\xe5 kule\n" + std::string(rt::kDefaultScene);
    CHECK(not_scene_text(latin).empty());
    // kMaxForeignBytes of them in a short text still pass; one more is refused.
    std::string few = "// " + std::string(kMaxForeignBytes, '\xe5') + "\nend\n";
    CHECK(not_scene_text(few).empty());
    few.insert(3, "\xff");
    CHECK(not_scene_text(few) == "not a scene text: 17 of its 25 bytes are not UTF-8 text, the first at byte 4 (a binary file?)");
    // Overlong forms, surrogates, lone continuation and truncated sequences are foreign.
    std::string bad;
    for (int i = 0; i < 5; ++i) bad += "\xc0\xaf \xed\xa0\x80 \x80 \xe2\x82";
    CHECK_FALSE(not_scene_text(bad).empty());
}
