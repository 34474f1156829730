// Structural edits as text replacements: each kind applied to the text parses to the
// scene with the edit made on the Scene directly; the inverse restores the text byte
// for byte; lamp -> spotlight -> lamp keeps the size; comments elsewhere survive. And
// moves: every kind of item moved as the move tool does it, against numbers by hand.
#include <doctest/doctest.h>

#include <cmath>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "document.h"
#include "move_handle.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

// Every kind of item, comments in awkward places, items sharing lines, no final newline.
const std::string kScene = std::string(rtview_test::kDemoScene) + "after end { unbalanced";

// Only the camera: every section has to be created.
const char* const kEmpty = "camera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 60 angle_y 45 }\n"
                           "picture_size { x_max 32 y_max 24 }\nend\n";

using rtview_test::applied;
using rtview_test::parse_ok;

// Applies the edit, checks the parse against `expected`, and that the inverse
// restores the original text exactly.
std::string check_edit(const std::string& text, const SceneEdit& e, const rt::Scene& expected) {
    std::string t = text;
    TextReplacement back = e.replacement.apply(t);
    INFO("edited text:\n" << t);
    rt::Scene got = parse_ok(t);
    CHECK(got == expected);
    std::string undone = t;
    TextReplacement again = back.apply(undone);
    CHECK(undone == text);
    // And redo (the inverse of the inverse) gives the edited text again.
    again.apply(undone);
    CHECK(undone == t);
    return t;
}

double dist(rt::Vec3 a, rt::Vec3 b) { return rt::length(a - b); }

}  // namespace

TEST_CASE("scene edits: a CSG operand moves alone, and the move handle sits on it") {
    const rt::Scene s = parse_ok(kScene);
    const SceneItem lens{SceneItem::Kind::Object, 4};
    const auto& before = std::get<rt::Csg>(s.objects[4].shape);
    rt::Object o = s.objects[4];
    REQUIRE(translate_operand(o, {0}, {0, 1, 0}));
    const auto& after = std::get<rt::Csg>(o.shape);
    CHECK(std::get<rt::Sphere>(after.operands[0].shape).position == rt::Vec3{7, 0.7, 2.2});
    CHECK(after.operands[1] == before.operands[1]);
    CHECK(o.material == s.objects[4].material);
    // An empty path is the whole object; a path to nothing moves nothing.
    rt::Object whole = s.objects[4];
    REQUIRE(translate_operand(whole, {}, {0, 1, 0}));
    CHECK(std::get<rt::Sphere>(std::get<rt::Csg>(whole.shape).operands[1].shape).position == rt::Vec3{7, 1.5, 2.2});
    CHECK_FALSE(translate_operand(o, {2}, {1, 0, 0}));
    CHECK_FALSE(translate_operand(o, {0, 0}, {1, 0, 0}));
    CHECK(std::get<rt::Sphere>(after.operands[0].shape).position == rt::Vec3{7, 0.7, 2.2});

    CHECK(item_anchor(s, lens, {0}) == rt::Vec3{7, -0.3, 2.2});
    CHECK(item_anchor(s, lens, {1}) == rt::Vec3{7, 0.5, 2.2});
    CHECK_FALSE(item_anchor(s, lens, {0, 1}));
    CHECK_FALSE(item_anchor(s, {SceneItem::Kind::Light, 0}, {0}));
}

TEST_CASE("scene edits: delete each object, plane and light") {
    const std::string text = kScene;
    const rt::Scene s = parse_ok(text);
    REQUIRE(s.objects.size() == 5);
    for (int i = 0; i < 5; ++i) {
        CAPTURE(i);
        auto e = delete_item(text, s, {SceneItem::Kind::Object, i});
        REQUIRE(e);
        rt::Scene want = s;
        want.objects.erase(want.objects.begin() + i);
        std::string t = check_edit(text, *e, want);
        CHECK(t.find("// demo scene") == 0);
        CHECK(t.find("after end { unbalanced") != std::string::npos);
        CHECK(e->select.index == std::min(i, 3));
    }
    for (int i = 0; i < 2; ++i) {
        auto e = delete_item(text, s, {SceneItem::Kind::Plane, i});
        REQUIRE(e);
        rt::Scene want = s;
        want.planes.erase(want.planes.begin() + i);
        check_edit(text, *e, want);
        e = delete_item(text, s, {SceneItem::Kind::Light, i});
        REQUIRE(e);
        want = s;
        want.lights.erase(want.lights.begin() + i);
        std::string t = check_edit(text, *e, want);
        // A block alone on its line goes with its line and its trailing comment.
        if (i == 0) CHECK(t.find("// warm") == std::string::npos);
    }
    // The whole line went: no blank line where the glass ball was.
    auto e = delete_item(text, s, {SceneItem::Kind::Object, 0});
    std::string t = applied(e->replacement, text);
    CHECK(t.find("thing {\n  tetrahedron {") != std::string::npos);
    CHECK_FALSE(delete_item(text, s, {SceneItem::Kind::Object, 5}));
    CHECK_FALSE(delete_item(text, s, {SceneItem::Kind::Light, -1}));
}

TEST_CASE("scene edits: deleting a CSG operand leaves the other, with the CSG's material") {
    const std::string text = kScene;
    const rt::Scene s = parse_ok(text);
    const auto& lens = std::get<rt::Csg>(s.objects[4].shape);
    for (int side = 0; side < 2; ++side) {
        CAPTURE(side);
        auto e = delete_operand(text, s, 4, {side});
        REQUIRE(e);
        rt::Scene want = s;
        want.objects[4] = lens.operands[std::size_t(1 - side)];
        want.objects[4].material = s.objects[4].material;
        want.objects[4].has_material = true;
        std::string t = check_edit(text, *e, want);
        CHECK(e->select.index == 4);
        CHECK(t.find("constructive_solid_geometry") == std::string::npos);
        CHECK(t.find("// demo scene") == 0);  // the rest of the text as it was
    }
    // Nested: deleting an operand of the inner CSG leaves the outer one, the inner
    // CSG's place taken by its other operand.
    rt::Scene nested = s;
    rt::Object inner = s.objects[4];
    rt::Object outer;
    outer.shape = rt::Csg{rt::CsgType::Union, {inner, s.objects[0]}};
    outer.material = s.objects[1].material;
    outer.has_material = true;
    nested.objects[4] = outer;
    const std::string ntext = rt::write_scene(nested);
    const rt::Scene ns = parse_ok(ntext);
    REQUIRE(ns == nested);
    auto e = delete_operand(ntext, ns, 4, {0, 1});
    REQUIRE(e);
    rt::Scene want = ns;
    std::get<rt::Csg>(want.objects[4].shape).operands[0] = lens.operands[0];  // its own material, not rendered
    check_edit(ntext, *e, want);
    // Paths to nothing, and no path at all (the object itself: delete_item's).
    CHECK_FALSE(delete_operand(text, s, 4, {}));
    CHECK_FALSE(delete_operand(text, s, 4, {2}));
    CHECK_FALSE(delete_operand(text, s, 4, {0, 1}));
    CHECK_FALSE(delete_operand(text, s, 0, {0}));
    CHECK_FALSE(delete_operand(text, s, 9, {0}));
}

TEST_CASE("scene edits: duplicate copies the block verbatim, or moved by an offset") {
    const std::string text = kScene;
    const rt::Scene s = parse_ok(text);
    for (int i = 0; i < 5; ++i) {
        CAPTURE(i);
        auto e = duplicate_item(text, s, {SceneItem::Kind::Object, i});
        REQUIRE(e);
        rt::Scene want = s;
        want.objects.insert(want.objects.begin() + i + 1, s.objects[std::size_t(i)]);
        check_edit(text, *e, want);
        CHECK(e->select.index == i + 1);

        e = duplicate_item(text, s, {SceneItem::Kind::Object, i}, {1, 0, -0.5});
        REQUIRE(e);
        rt::Object moved = s.objects[std::size_t(i)];
        translate(moved, {1, 0, -0.5});
        want = s;
        want.objects.insert(want.objects.begin() + i + 1, moved);
        check_edit(text, *e, want);
    }
    // A moved sphere really is moved (translate checked against numbers by hand).
    rt::Object sp = s.objects[0];
    translate(sp, {1, 0, -0.5});
    CHECK(std::get<rt::Sphere>(sp.shape).position == rt::Vec3{7, 1.5, 0.3});  // not 0.30000000000000004
    rt::Light li;
    li.position = {2.07, 0, 0};
    translate(li, {-2.5, 0, 0});
    CHECK(li.position.x == -0.43);
    rt::Object csg = s.objects[4];
    translate(csg, {1, 0, 0});
    CHECK(std::get<rt::Sphere>(std::get<rt::Csg>(csg.shape).operands[1].shape).position == rt::Vec3{8, 0.5, 2.2});

    auto e = duplicate_item(text, s, {SceneItem::Kind::Plane, 0});
    REQUIRE(e);
    rt::Scene want = s;
    want.planes.insert(want.planes.begin() + 1, s.planes[0]);
    check_edit(text, *e, want);
    e = duplicate_item(text, s, {SceneItem::Kind::Light, 1}, {0, 0, 1});
    REQUIRE(e);
    want = s;
    rt::Light l = s.lights[1];
    l.position = {0, -4, 4};
    want.lights.push_back(l);
    check_edit(text, *e, want);
}

TEST_CASE("scene edits: add every kind at a point, sized from the scene, also into a scene without sections") {
    for (const std::string& src : {kScene, std::string(kEmpty)}) {
        const std::string text = src;
        const rt::Scene s = parse_ok(text);
        const double extent = scene_extent(s);
        const rt::Vec3 p{3, 0.5, 0};
        for (NewItem k : kNewItems) {
            CAPTURE(new_item_name(k));
            CHECK(new_item_kind(new_item_name(k)) == k);
            auto e = add_item(text, s, k, {p, {0, 0, 1}});
            REQUIRE(e);
            std::string t = applied(e->replacement, text);
            INFO(t);
            rt::Scene got = parse_ok(t);
            rt::Scene want = s;
            // Everything else is unchanged; the new item is last of its kind.
            if (k == NewItem::Plane || k == NewItem::ChessPlane) {
                REQUIRE(got.planes.size() == s.planes.size() + 1);
                const rt::Plane& pl = got.planes.back();
                CHECK(pl.chess == (k == NewItem::ChessPlane));
                CHECK(dist(pl.point[0], p) < 1e-9);
                // Upright on the surface z = 0 (not lying in it, where it would not be
                // seen), lit on the side of the scene's camera.
                const rt::Vec3 n = rt::normalize(rt::cross(pl.point[1] - pl.point[0], pl.point[2] - pl.point[0]));
                CHECK(n.z == doctest::Approx(0).epsilon(1e-3));
                CHECK(pl.point[2].z > 0);
                CHECK(rt::dot(pl.point[3] - pl.point[0], n) * rt::dot(s.camera.position - p, n) > 0);
                rt::Vec3 level = s.camera.position - p;
                level.z = 0;
                CHECK(std::fabs(rt::dot(rt::normalize(level), n)) == doctest::Approx(1).epsilon(1e-3));
                want.planes.push_back(pl);
                CHECK(e->select.kind == SceneItem::Kind::Plane);
                CHECK(e->select.index == int(s.planes.size()));
            } else if (k == NewItem::Lamp || k == NewItem::Spotlight) {
                REQUIRE(got.lights.size() == s.lights.size() + 1);
                const rt::Light& l = got.lights.back();
                CHECK(l.lamp == (k == NewItem::Lamp));
                CHECK(l.position.z > 0);  // above the surface
                CHECK(dist({l.position.x, l.position.y, 0}, p) < 1e-9);
                if (!s.lights.empty()) {
                    // As bright at the clicked point as the last light is there (1/r^2),
                    // to three digits: not a copy of a far light's colour.
                    const rt::Light& last = s.lights.back();
                    const double k = rt::length2(l.position - p) / rt::length2(last.position - p);
                    CHECK(l.colour.x == doctest::Approx(last.colour.x * k).epsilon(0.006));
                    CHECK(l.colour.y == doctest::Approx(last.colour.y * k).epsilon(0.006));
                    CHECK(l.colour.z == doctest::Approx(last.colour.z * k).epsilon(0.006));
                }
                want.lights.push_back(l);
            } else {
                REQUIRE(got.objects.size() == s.objects.size() + 1);
                const rt::Object& o = got.objects.back();
                CHECK_FALSE(o.has_material);
                if (k == NewItem::Sphere) {
                    auto sp = std::get<rt::Sphere>(o.shape);
                    // Resting on the surface at p: centre one radius above it. As big
                    // as the scene's objects (radii 0.5 to 0.8 here), or a twentieth
                    // of a scene without any (10 across: 0.5).
                    CHECK(sp.radius >= 0.25);
                    CHECK(sp.radius <= 1.6);
                    if (s.objects.empty()) CHECK(sp.radius == doctest::Approx(0.05 * extent));
                    CHECK(dist(sp.position, p + rt::Vec3{0, 0, sp.radius}) < 1e-9);
                } else if (k == NewItem::Cylinder) {
                    auto c = std::get<rt::Cylinder>(o.shape);
                    CHECK(dist(c.end1, p) < 1e-9);
                    CHECK(c.end2.z > 0);
                } else if (k == NewItem::Tetrahedron) {
                    auto tt = std::get<rt::Tetrahedron>(o.shape);
                    for (int v = 0; v < 3; ++v) CHECK(tt.v[v].z == doctest::Approx(0));
                    CHECK(tt.v[3].z > 0);
                } else if (k == NewItem::Box) {
                    // A cube standing on the surface, centred over the point.
                    auto b = std::get<rt::Box>(o.shape);
                    const rt::Vec3 side = b.corner2 - b.corner1;
                    CHECK(side.x > 0);
                    CHECK(side.x == doctest::Approx(side.y));
                    CHECK(side.x == doctest::Approx(side.z));
                    CHECK(b.corner1.z == doctest::Approx(0));
                    CHECK(dist((b.corner1 + b.corner2) * 0.5, p + rt::Vec3{0, 0, side.z / 2}) < 1e-9);
                } else if (k == NewItem::Cone) {
                    // Its base on the surface at the point, its tip straight above.
                    auto c = std::get<rt::Cone>(o.shape);
                    CHECK(dist(c.end1, p) < 1e-9);
                    CHECK(dist({c.end2.x, c.end2.y, 0}, p) < 1e-9);
                    CHECK(c.end2.z > 0);
                    CHECK(c.radius1 > 0);
                    CHECK(c.radius2 == 0);
                } else {
                    auto to = std::get<rt::Torus>(o.shape);
                    CHECK(to.direction == rt::Vec3{0, 0, 1});
                    CHECK(to.major > to.minor);
                }
                want.objects.push_back(o);
            }
            CHECK(got == want);
            check_edit(text, *e, want);
            if (src == kScene) CHECK(t.find("after end { unbalanced") != std::string::npos);
        }
    }
    // A plane faces the given viewer, whatever the scene camera; looking straight down
    // on the surface it still stands upright.
    const rt::Scene s = parse_ok(kEmpty);
    for (rt::Vec3 toward : {rt::Vec3{0, 5, 1}, rt::Vec3{0, 0, 7}}) {
        CAPTURE(toward);
        auto e = add_item(kEmpty, s, NewItem::Plane, {{3, 0.5, 0}, {0, 0, 1}, toward});
        REQUIRE(e);
        const rt::Plane pl = parse_ok(applied(e->replacement, kEmpty)).planes.back();
        const rt::Vec3 n = rt::normalize(rt::cross(pl.point[1] - pl.point[0], pl.point[2] - pl.point[0]));
        CHECK(n.z == doctest::Approx(0).epsilon(1e-3));
        CHECK(rt::dot(pl.point[3] - pl.point[0], toward) >= 0);
        if (toward.y > 0) CHECK(std::fabs(n.y) == doctest::Approx(1));
    }
    // Sizes follow the scene: the same scene ten times larger gets items ten times larger.
    const std::string small = kEmpty;
    std::string big = "camera { position 0 0 0 centre 100 0 0 up 100 0 1 angle_x 60 angle_y 45 }\n"
                      "picture_size { x_max 32 y_max 24 }\nend\n";
    auto es = add_item(small, parse_ok(small), NewItem::Sphere, {{5, 0, 0}});
    auto eb = add_item(big, parse_ok(big), NewItem::Sphere, {{50, 0, 0}});
    REQUIRE(es);
    REQUIRE(eb);
    double rs = std::get<rt::Sphere>(parse_ok(applied(es->replacement, small)).objects[0].shape).radius;
    double rb = std::get<rt::Sphere>(parse_ok(applied(eb->replacement, big)).objects[0].shape).radius;
    CHECK(rb == doctest::Approx(10 * rs));
}

TEST_CASE("scene edits: a CSG of two top-level objects replaces both, left then right") {
    const std::string text = kScene;
    const rt::Scene s = parse_ok(text);
    for (auto [a, b] : {std::pair{0, 1}, std::pair{3, 2}, std::pair{4, 0}, std::pair{1, 4}}) {
        CAPTURE(a);
        CAPTURE(b);
        auto e = make_csg(text, s, a, b, rt::CsgType::Difference);
        REQUIRE(e);
        rt::Object o;
        rt::Csg c;
        c.type = rt::CsgType::Difference;
        c.operands = {s.objects[std::size_t(a)], s.objects[std::size_t(b)]};
        o.shape = c;
        o.material = s.objects[std::size_t(a)].material;
        o.has_material = s.objects[std::size_t(a)].has_material;
        rt::Scene want = s;
        want.objects[std::size_t(a)] = o;
        want.objects.erase(want.objects.begin() + b);
        check_edit(text, *e, want);
        CHECK(e->select.index == (b < a ? a - 1 : a));
    }
    CHECK_FALSE(make_csg(text, s, 1, 1, rt::CsgType::Union));
    CHECK_FALSE(make_csg(text, s, 0, 9, rt::CsgType::Union));
}

TEST_CASE("scene edits: lamp -> spotlight -> lamp keeps the size; a spotlight without one gets a scaled size") {
    const std::string text = kScene;
    const rt::Scene s = parse_ok(text);
    REQUIRE(s.lights[0].lamp);
    REQUIRE(s.lights[0].size == 0.3);
    auto e = switch_light_kind(text, s, 0);
    REQUIRE(e);
    rt::Scene want = s;
    want.lights[0].lamp = false;
    want.lights[0].size = 1;  // what the parser gives a spotlight
    std::string t1 = check_edit(text, *e, want);
    CHECK(t1.find("// warm") != std::string::npos);  // outside the block: kept

    rt::Scene s1 = parse_ok(t1);
    auto e2 = switch_light_kind(t1, s1, 0);
    REQUIRE(e2);
    std::string t2 = check_edit(t1, *e2, s);  // the original lights, size 0.3 included

    // A spotlight that never was a lamp.
    auto e3 = switch_light_kind(text, s, 1);
    REQUIRE(e3);
    rt::Scene got = parse_ok(applied(e3->replacement, text));
    CHECK(got.lights[1].lamp);
    CHECK(got.lights[1].size > 0);
    CHECK(got.lights[1].size < scene_extent(s));
    CHECK(got.lights[1].position == s.lights[1].position);
    CHECK(got.lights[1].colour == s.lights[1].colour);
    CHECK_FALSE(switch_light_kind(text, s, 2));
}

TEST_CASE("scene edits: nothing when the text does not match the scene") {
    const std::string text = kScene;
    rt::Scene s = parse_ok(text);
    s.objects.pop_back();
    CHECK_FALSE(delete_item(text, s, {SceneItem::Kind::Object, 0}));
    CHECK_FALSE(add_item("thing { sphere {", s, NewItem::Sphere, {{0, 0, 0}}));
    CHECK_FALSE(add_item(text, parse_ok(text), NewItem::Sphere, {{NAN, 0, 0}}));
}

TEST_CASE("scene edits through the document: one undo step each, undo and redo restore the text byte for byte") {
    const std::string text = kScene;
    Document doc;
    doc.load_text(text, "", "demo");
    const rt::Scene s = parse_ok(text);
    REQUIRE(doc.scene() == s);
    std::vector<std::string> texts{text};
    std::vector<rt::Scene> scenes{s};
    auto step = [&](std::optional<SceneEdit> e) {
        REQUIRE(e);
        const std::size_t depth = doc.undo_depth();
        REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
        CHECK(doc.undo_depth() == depth + 1);
        texts.push_back(std::as_const(doc).editor_text());
        CHECK(texts.back() == applied(e->replacement, texts[texts.size() - 2]));
        scenes.push_back(parse_ok(texts.back()));
        CHECK(doc.scene() == scenes.back());
        CHECK_FALSE(doc.editor_dirty());
    };
    step(add_item(texts.back(), doc.scene(), NewItem::Sphere, {{1, 2, 0}, {0, 0, 1}}));
    step(duplicate_item(texts.back(), doc.scene(), {SceneItem::Kind::Object, 5}, {0.5, 0, 0}));
    step(delete_item(texts.back(), doc.scene(), {SceneItem::Kind::Object, 0}));
    step(switch_light_kind(texts.back(), doc.scene(), 0));
    step(make_csg(texts.back(), doc.scene(), 0, 1, rt::CsgType::Union));
    step(switch_light_kind(texts.back(), doc.scene(), 0));
    CHECK(doc.scene().lights[0].size == 0.3);
    for (std::size_t k = texts.size() - 1; k > 0; --k) {
        REQUIRE(doc.undo());
        CHECK(std::as_const(doc).editor_text() == texts[k - 1]);
        CHECK(doc.scene() == scenes[k - 1]);
    }
    for (std::size_t k = 1; k < texts.size(); ++k) {
        REQUIRE(doc.redo());
        CHECK(std::as_const(doc).editor_text() == texts[k]);
        CHECK(doc.scene() == scenes[k]);
    }
    // Not over an unapplied draft, and not when the result would not parse.
    CHECK_FALSE(doc.replace_text(0, 0, "thing { sphere {"));
    CHECK(std::as_const(doc).editor_text() == texts.back());
    doc.typing_text() += "\n// typed";
    doc.note_typed();
    auto e = delete_item(texts.back(), doc.scene(), {SceneItem::Kind::Object, 0});
    REQUIRE(e);
    CHECK_FALSE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
}

TEST_CASE("scene edits through the document after typing: the typing stays a step of its own") {
    const std::string text = kScene;
    Document doc;
    doc.load_text(text, "", "demo");
    doc.typing_text().insert(0, "// typed\n");
    doc.note_typed();
    REQUIRE(doc.apply_text());
    const std::string typed = std::as_const(doc).editor_text();
    auto e = add_item(typed, doc.scene(), NewItem::Torus, {{0, 0, 0}});
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK(doc.scene().objects.size() == 6);
    REQUIRE(doc.undo());
    CHECK(std::as_const(doc).editor_text() == typed);
    while (doc.undo()) {
    }
    CHECK(std::as_const(doc).editor_text() == text);
    CHECK(doc.scene() == parse_ok(text));
}

// Found by the edit fuzzer: with a light 1e15 away the scene's extent is 1e15, and
// rounding to a thousandth of it put a new torus's direction at 0 0 0 (a text that does
// not parse) and every new item at the origin.
TEST_CASE("scene edits: an item added to a scene with a far light is where it was put, and parses") {
    const std::string text = "thing { sphere { position 5 0 1 radius 1 } }\n"
                             "light { spotlight { position 0 0 1e15 colour 1 1 1 } }\n"
                             "camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 32 y_max 24 }\nend\n";
    const rt::Scene s = parse_ok(text);
    REQUIRE(scene_extent(s) > 1e14);
    const Placement at{{5, 0, 2}, {0, 0, 1}, {-1, 0, 0}};
    for (NewItem k : {NewItem::Sphere, NewItem::Cylinder, NewItem::Tetrahedron, NewItem::Torus, NewItem::Box,
                      NewItem::Cone, NewItem::Plane, NewItem::ChessPlane, NewItem::Lamp}) {
        CAPTURE(new_item_name(k));
        const auto e = add_item(text, s, k, at);
        REQUIRE(e);
        const rt::Scene got = parse_ok(applied(e->replacement, text));
        if (got.objects.size() == 2)
            if (const auto* t = std::get_if<rt::Torus>(&got.objects[1].shape)) CHECK(t->direction == rt::Vec3{0, 0, 1});
        const auto where = item_anchor(got, e->select, {});
        REQUIRE(where);
        // Near the point it was put at (within a few of the scene's object sizes).
        CHECK(dist(*where, at.point) < 5);
    }
}

// Found by the edit fuzzer: a copy moved by an offset is rounded to 12 significant
// digits, which far out can merge the corners of a tiny shape; the edit is then not
// offered (it would not parse).
TEST_CASE("scene edits: no duplicate whose rounding would flatten a tiny tetrahedron") {
    const std::string text = "thing { tetrahedron { vect1 1000000 0 0 vect2 1000000.0000001 0 0 "
                             "vect3 1000000 0.0000001 0 vect4 1000000 0 0.0000001 } }\n"
                             "camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 32 y_max 24 }\nend\n";
    const rt::Scene s = parse_ok(text);
    CHECK(duplicate_item(text, s, {SceneItem::Kind::Object, 0}));  // verbatim: fine
    CHECK_FALSE(duplicate_item(text, s, {SceneItem::Kind::Object, 0}, {1, 0, 0}));
}

namespace {

// Every kind of item on a line of its own, CSG operands of every kind (a CSG among
// them), and the same moved by kMove, written out by hand: the oracle does not call
// translate().
const char* const kMoveScene[] = {
    "// every kind of item, each on its own line",
    "thing {",
    "  sphere { position 1 2 3 radius 0.5 }",
    "  cylinder { end_1 1 0 0 end_2 1 0 2 radius 0.25 }",
    "  tetrahedron { vect1 0 0 0 vect2 1 0 0 vect3 0 1 0 vect4 0 0 1 }",
    "  torus { position 4 5 6 direction 0 1 1 major 1 minor 0.25 }",
    "  constructive_solid_geometry { type U left { cylinder { end_1 0 0 0 end_2 0 0 1 radius 0.5 } } right { "
    "constructive_solid_geometry { type I left { tetrahedron { vect1 0 0 0 vect2 2 0 0 vect3 0 2 0 vect4 0 0 2 } } "
    "right { torus { position 1 1 1 direction 1 0 0 major 2 minor 0.5 } } } } }",
    "  constructive_solid_geometry { type C left { sphere { position 0 0 0 radius 1 } } right { sphere { position 0.5 0 "
    "0 radius 1 } } material { colour 1 0 0 } }",
    "}",
    "special_thing {",
    "  plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 }",
    "  chess_plane { material 2 { colour 0 0 0 } point 1 0 0 -1 point 2 1 0 -1 point 3 0 1 -1 point 4 0 0 5 }",
    "}",
    "light {",
    "  lamp { colour 10 10 10 position 1 2 3 size 0.5 }",
    "  spotlight { colour 5 5 5 position -1 -2 -3 }",
    "}",
    "camera { position -10 0 2 centre 0 0 0 up 0 0 3 angle_x 60 angle_y 45 }",
    "picture_size { x_max 32 y_max 24 }",
    "end",
};
const rt::Vec3 kMove{1.5, -2, 0.25};  // exact in binary: the sums are exact too

struct MovedItem {
    const char* what;
    SceneItem item;
    int line;           // its line in kMoveScene
    const char* moved;  // that line with every point moved by kMove
};
const MovedItem kMovedItems[] = {
    {"sphere", {SceneItem::Kind::Object, 0}, 2, "  sphere { position 2.5 0 3.25 radius 0.5 }"},
    {"cylinder", {SceneItem::Kind::Object, 1}, 3, "  cylinder { end_1 2.5 -2 0.25 end_2 2.5 -2 2.25 radius 0.25 }"},
    {"tetrahedron", {SceneItem::Kind::Object, 2}, 4,
     "  tetrahedron { vect1 1.5 -2 0.25 vect2 2.5 -2 0.25 vect3 1.5 -1 0.25 vect4 1.5 -2 1.25 }"},
    {"torus (its direction stays)", {SceneItem::Kind::Object, 3}, 5,
     "  torus { position 5.5 3 6.25 direction 0 1 1 major 1 minor 0.25 }"},
    {"CSG of a cylinder and a CSG of a tetrahedron and a torus", {SceneItem::Kind::Object, 4}, 6,
     "  constructive_solid_geometry { type U left { cylinder { end_1 1.5 -2 0.25 end_2 1.5 -2 1.25 radius 0.5 } } "
     "right { constructive_solid_geometry { type I left { tetrahedron { vect1 1.5 -2 0.25 vect2 3.5 -2 0.25 vect3 "
     "1.5 0 0.25 vect4 1.5 -2 2.25 } } right { torus { position 2.5 -1 1.25 direction 1 0 0 major 2 minor 0.5 } } } "
     "} }"},
    {"CSG of two spheres", {SceneItem::Kind::Object, 5}, 7,
     "  constructive_solid_geometry { type C left { sphere { position 1.5 -2 0.25 radius 1 } } right { sphere { "
     "position 2 -2 0.25 radius 1 } } material { colour 1 0 0 } }"},
    {"plane", {SceneItem::Kind::Plane, 0}, 10,
     "  plane { point 1 1.5 -2 0.25 point 2 2.5 -2 0.25 point 3 1.5 -1 0.25 point 4 1.5 -2 1.25 }"},
    {"chess plane", {SceneItem::Kind::Plane, 1}, 11,
     "  chess_plane { material 2 { colour 0 0 0 } point 1 1.5 -2 -0.75 point 2 2.5 -2 -0.75 point 3 1.5 -1 -0.75 "
     "point 4 1.5 -2 5.25 }"},
    {"lamp", {SceneItem::Kind::Light, 0}, 14, "  lamp { colour 10 10 10 position 2.5 0 3.25 size 0.5 }"},
    {"spotlight", {SceneItem::Kind::Light, 1}, 15, "  spotlight { colour 5 5 5 position 0.5 -4 -2.75 }"},
};

std::string lines_text(const std::vector<std::string>& lines) {
    std::string t;
    for (const std::string& l : lines) t += l + "\n";
    return t;
}

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

// A drag of the move tool (ui/move_tool.cpp MoveTool::apply): every frame the item
// becomes what it was when the drag began, moved by the drag so far; the release
// commits. Two frames, halfway and all the way.
void drag_item(Document& doc, SceneItem item, rt::Vec3 d) {
    const std::size_t i = std::size_t(item.index);
    const rt::Scene start = doc.scene();
    for (rt::Vec3 so_far : {d * 0.5, d}) {
        switch (item.kind) {
            case SceneItem::Kind::Object: {
                rt::Object& o = doc.edit_object(i);
                o = start.objects[i];
                translate(o, so_far);
                break;
            }
            case SceneItem::Kind::Plane: {
                rt::Plane& p = doc.edit_plane(i);
                p = start.planes[i];
                translate(p, so_far);
                break;
            }
            case SceneItem::Kind::Light: {
                rt::Light& l = doc.edit_light(i);
                l = start.lights[i];
                translate(l, so_far);
                break;
            }
        }
    }
    doc.commit();
}

}  // namespace

TEST_CASE("scene edits: moving each kind of item moves every point of it in the text, and nothing else") {
    const std::vector<std::string> lines(std::begin(kMoveScene), std::end(kMoveScene));
    const std::string text = lines_text(lines);
    const rt::Scene s = parse_ok(text);
    REQUIRE(s.objects.size() == 6);
    REQUIRE(s.planes.size() == 2);
    REQUIRE(s.lights.size() == 2);
    for (const MovedItem& m : kMovedItems) {
        CAPTURE(m.what);
        std::vector<std::string> want_lines = lines;
        REQUIRE(lines[std::size_t(m.line)].find(std::string(m.moved).substr(0, 8)) == 0);
        want_lines[std::size_t(m.line)] = m.moved;
        const rt::Scene want = parse_ok(lines_text(want_lines));
        REQUIRE_FALSE(want == s);

        // Moved with the move tool, through the document.
        Document doc;
        doc.load_text(text, "", "moves");
        drag_item(doc, m.item, kMove);
        const std::string moved = std::as_const(doc).editor_text();
        INFO("text after the move:\n" << moved);
        const rt::Scene got = parse_ok(moved);
        // Each item compared on its own, so that a failure names the one that differs.
        for (std::size_t k = 0; k < want.objects.size(); ++k) {
            CAPTURE(k);
            CHECK(got.objects[k] == want.objects[k]);
        }
        for (std::size_t k = 0; k < want.planes.size(); ++k) {
            CAPTURE(k);
            CHECK(got.planes[k] == want.planes[k]);
        }
        for (std::size_t k = 0; k < want.lights.size(); ++k) {
            CAPTURE(k);
            CHECK(got.lights[k] == want.lights[k]);
        }
        CHECK(got == want);
        CHECK(doc.scene() == got);
        // The text changed on the item's own line only.
        const std::vector<std::string> got_lines = split_lines(moved);
        REQUIRE(got_lines.size() == lines.size());
        for (std::size_t k = 0; k < lines.size(); ++k)
            if (k != std::size_t(m.line)) CHECK(got_lines[k] == lines[k]);
        // One undo step takes it back to the original bytes.
        REQUIRE(doc.undo());
        CHECK(std::as_const(doc).editor_text() == text);

        // Duplicated with an offset (Edit > Duplicate moved aside): the copy is the
        // item moved.
        auto e = duplicate_item(text, s, m.item, kMove);
        REQUIRE(e);
        const rt::Scene dup = parse_ok(applied(e->replacement, text));
        const std::size_t at = std::size_t(m.item.index) + 1;
        switch (m.item.kind) {
            case SceneItem::Kind::Object: CHECK(dup.objects.at(at) == want.objects[at - 1]); break;
            case SceneItem::Kind::Plane: CHECK(dup.planes.at(at) == want.planes[at - 1]); break;
            case SceneItem::Kind::Light: CHECK(dup.lights.at(at) == want.lights[at - 1]); break;
        }
    }
}

TEST_CASE("scene edits: the menu's Add finds a clear spot; added objects keep the scene's size") {
    // A unit sphere on the floor z = 0 at the origin, seen from -x.
    const std::string text = "thing { sphere { position 0 0 1 radius 1 } }\n"
                             "camera { position -10 0 2 centre 0 0 1 up 0 0 2 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 32 y_max 24 }\nend\n";
    const rt::Scene s = parse_ok(text);
    const rt::Vec3 up{0, 0, 1};
    // On the sphere's front (where the picture's centre looks), on the floor right in
    // front of it, then beside it: the first clear one is beside.
    const std::vector<Placement> candidates = {
        {{-1, 0, 1}, {-1, 0, 0}}, {{-1.5, 0, 0}, up}, {{0, 2.4, 0}, up}, {{0, 3.6, 0}, up}, {{0, 6, 0}, up}};
    const std::optional<std::size_t> k = first_clear(s, candidates);
    REQUIRE(k);
    // The new unit sphere at (0, 3.6, 1) stands 2.6 from the box at y <= 1: more than
    // 1.5 sizes. At (0, 2.4, 1) only 1.4: too near.
    CHECK(*k == 3);
    // Nothing clear: none.
    CHECK_FALSE(first_clear(s, {candidates[0], candidates[1]}));
    // In the air (no normal): the point is the object's middle.
    CHECK(first_clear(s, {{{0, 0, 3.6}}}) == std::optional<std::size_t>(0));
    CHECK_FALSE(first_clear(s, {{{0, 0, 3.4}}}));
    // Seen whole: the first clear one `seen` accepts; accepting none, the first clear one.
    auto beyond = [](const rt::Vec3& middle, double) { return middle.y > 5; };
    CHECK(first_clear(s, candidates, beyond) == std::optional<std::size_t>(4));
    CHECK(first_clear(s, candidates, [](const rt::Vec3&, double) { return false; }) == std::optional<std::size_t>(3));

    // Added one after another, objects keep the first one's size (a bigger torus box
    // does not make the next object bigger), and no coordinate is written -0.
    std::string t = text;
    rt::Scene cur = s;
    double y = 3;
    for (NewItem kind : {NewItem::Torus, NewItem::Sphere, NewItem::Cylinder, NewItem::Sphere}) {
        CAPTURE(new_item_name(kind));
        // (The normal as picks measure it: a hair off the axis.)
        auto e = add_item(t, cur, kind, {{0, y, 0}, {-1e-9, -1e-9, 1}, {-1, 0, 0}});
        REQUIRE(e);
        t = applied(e->replacement, t);
        cur = parse_ok(t);
        CHECK(typical_object_size(cur) == doctest::Approx(1));
        y += 3;
    }
    CHECK(std::get<rt::Sphere>(cur.objects.back().shape).radius == 1);
    CHECK(t.find("-0 ") == std::string::npos);
    CHECK(t.find("direction 0 0 1") != std::string::npos);
}
