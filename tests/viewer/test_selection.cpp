// Several things selected at once: Shift+click's rules for the set, a move of all of
// them as one undo step (numbers by hand), delete and duplicate of all as one text
// replacement (against the scene edited directly), the box select against a pick of
// every pixel, the joint outline against the single-item outline, and the selection
// that undo and redo give back.
#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "document.h"
#include "selection.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

using rtview_test::applied;
using rtview_test::parse_ok;

const SceneItem kObj0{SceneItem::Kind::Object, 0}, kObj2{SceneItem::Kind::Object, 2}, kObj3{SceneItem::Kind::Object, 3};
const SceneItem kLight0{SceneItem::Kind::Light, 0}, kLight1{SceneItem::Kind::Light, 1};
const SceneItem kPlane1{SceneItem::Kind::Plane, 1};

rt::Vec3 sphere_at(const rt::Scene& s, std::size_t i) { return std::get<rt::Sphere>(s.objects[i].shape).position; }
rt::Vec3 torus_at(const rt::Scene& s, std::size_t i) { return std::get<rt::Torus>(s.objects[i].shape).position; }

// Unit segments of an outline, as a set (runs may be joined differently).
std::set<std::tuple<int, int, int, int>> unit_segments(const std::vector<Edge>& edges) {
    std::set<std::tuple<int, int, int, int>> out;
    for (const Edge& e : edges) {
        if (e.x0 == e.x1)
            for (int y = std::min(e.y0, e.y1); y < std::max(e.y0, e.y1); ++y) out.insert({e.x0, y, e.x0, y + 1});
        else
            for (int x = std::min(e.x0, e.x1); x < std::max(e.x0, e.x1); ++x) out.insert({x, e.y0, x + 1, e.y0});
    }
    return out;
}

}  // namespace

TEST_CASE("selection: Shift+click adds and takes out, the last added is the one the panels edit") {
    Selection s;
    toggle(s, kObj0);  // from nothing: one thing, alone
    CHECK(s.one == ItemRef{kObj0, {}});
    CHECK(s.many.empty());
    toggle(s, kLight1);
    CHECK(s.many == std::vector<SceneItem>{kObj0, kLight1});
    CHECK(s.one == ItemRef{kLight1, {}});
    toggle(s, kObj2);
    CHECK(selected_items(s).size() == 3);
    CHECK(is_selected(s, kObj2));
    CHECK(!is_selected(s, kObj3));
    CHECK(selection_summary(s) == "3 things selected: 2 objects, 1 light");
    toggle(s, kObj2);  // taken out: the one before it is the last again
    CHECK(s.many == std::vector<SceneItem>{kObj0, kLight1});
    CHECK(s.one == ItemRef{kLight1, {}});
    toggle(s, kLight1);  // one left: it alone
    CHECK(s.many.empty());
    CHECK(s.one == ItemRef{kObj0, {}});
    toggle(s, kObj0);
    CHECK(s.one.none());
    CHECK(selected_items(s).empty());
    // A CSG operand selected alone: Shift+click on another object adds its whole object.
    select_one(s, ItemRef{kObj3, {0}});
    toggle(s, kObj0);
    CHECK(s.many == std::vector<SceneItem>{kObj3, kObj0});
    select_one(s, ItemRef{kPlane1, {}});
    CHECK(s.many.empty());
    CHECK(s.one == ItemRef{kPlane1, {}});
}

TEST_CASE("selection: a box adds what it saw once each; items the scene lost leave") {
    Selection s;
    select_one(s, {kObj2, {}});
    add_all(s, {kObj0, kObj2, kLight0, kObj0});
    CHECK(s.many == std::vector<SceneItem>{kObj2, kObj0, kLight0});
    CHECK(s.one == ItemRef{kLight0, {}});
    add_all(s, {});
    CHECK(s.many.size() == 3);
    // A scene of 1 object and no lights (an undo took the rest away).
    rt::Scene small;
    small.objects.resize(1);
    keep_existing(s, small);
    CHECK(s.many.empty());
    CHECK(s.one == ItemRef{kObj0, {}});
    keep_existing(s, rt::Scene{});
    CHECK(s.one.none());
}

TEST_CASE("selection: the group's handle sits at the centre of the box round their anchors") {
    const rt::Scene s = parse_ok(rtview_test::kDemoScene);
    // The glass sphere at 6 1.5 0.8 and the lamp at 2 3 5.
    const std::optional<rt::Vec3> c = group_anchor(s, {kObj0, kLight0});
    REQUIRE(c);
    CHECK(*c == rt::Vec3{4, 2.25, 2.9});
    CHECK(!group_anchor(s, {}));
}

TEST_CASE("selection: a move of several things is one undo step that moves each by the same amount") {
    Document doc;
    doc.load_text(rtview_test::kDemoScene, "", "demo.txt");
    REQUIRE(doc.has_scene());
    const rt::Scene before = doc.scene();
    const std::string text_before = doc.editor_text();
    const std::size_t depth = doc.undo_depth();
    // The glass sphere (6 1.5 0.8), the torus (4.5 0 0.25) and the lamp (2 3 5).
    GroupMove g(doc.scene(), {kObj0, kObj3, kLight0});
    CHECK(g.size() == 3);
    CHECK(g.left_out() == 0);
    // A drag: frames of partial moves, each from the start, then the release.
    g.apply(doc, {0.5, 0, 0});
    g.apply(doc, {1, 2, 3});
    doc.name_edit("Move 3 things");
    doc.commit();
    CHECK(doc.undo_depth() == depth + 1);
    CHECK(sphere_at(doc.scene(), 0) == rt::Vec3{7, 3.5, 3.8});
    CHECK(torus_at(doc.scene(), 3) == rt::Vec3{5.5, 2, 3.25});
    CHECK(doc.scene().lights[0].position == rt::Vec3{3, 5, 8});
    // Nothing else moved, and the text says the same as the scene.
    CHECK(doc.scene().objects[1] == before.objects[1]);
    CHECK(doc.scene().lights[1] == before.lights[1]);
    CHECK(parse_ok(doc.editor_text()) == doc.scene());
    CHECK(doc.editor_text().find("position 7 3.5 3.8") != std::string::npos);
    // One undo takes all three back, text and all; redo moves all three again.
    REQUIRE(doc.undo());
    CHECK(doc.last_step_name() == "Move 3 things");
    CHECK(doc.scene() == before);
    CHECK(doc.editor_text() == text_before);
    REQUIRE(doc.redo());
    CHECK(sphere_at(doc.scene(), 0) == rt::Vec3{7, 3.5, 3.8});
    CHECK(doc.scene().lights[0].position == rt::Vec3{3, 5, 8});
}

TEST_CASE("selection: delete and duplicate of several things are one replacement of the text") {
    const std::string text = rtview_test::kDemoScene;
    const rt::Scene s = parse_ok(text);
    SUBCASE("delete") {
        std::optional<GroupEdit> g = delete_items(text, s, {kLight1, kObj2, kObj0});
        REQUIRE(g);
        CHECK(g->done == 3);
        CHECK(g->select.empty());
        rt::Scene want = s;
        want.objects.erase(want.objects.begin() + 2);
        want.objects.erase(want.objects.begin());
        want.lights.erase(want.lights.begin() + 1);
        const std::string t = applied(whole_replacement(text, *g), text);
        CHECK(parse_ok(t) == want);
        // The rest of the text, comments included, as it was.
        CHECK(t.find("// a lens") != std::string::npos);
        CHECK(t.find("// glass ball") == std::string::npos);
    }
    SUBCASE("duplicate with an offset: each copy right after its original") {
        const rt::Vec3 d{0, 2, 0};
        std::optional<GroupEdit> g = duplicate_items(text, s, {kObj3, kObj0, kLight0}, d);
        REQUIRE(g);
        CHECK(g->done == 3);
        const rt::Scene got = parse_ok(applied(whole_replacement(text, *g), text));
        REQUIRE(got.objects.size() == s.objects.size() + 2);
        REQUIRE(got.lights.size() == s.lights.size() + 1);
        // Objects: sphere, its copy, tetrahedron, cylinder, torus, its copy, CSG.
        CHECK(g->select == std::vector<SceneItem>{{SceneItem::Kind::Object, 1}, {SceneItem::Kind::Object, 5},
                                                  {SceneItem::Kind::Light, 1}});
        CHECK(sphere_at(got, 0) == rt::Vec3{6, 1.5, 0.8});
        CHECK(sphere_at(got, 1) == rt::Vec3{6, 3.5, 0.8});
        CHECK(torus_at(got, 5) == rt::Vec3{4.5, 2, 0.25});
        CHECK(got.lights[1].position == rt::Vec3{2, 5, 5});
        CHECK(got.objects[6] == s.objects[4]);
        CHECK(got.lights[2] == s.lights[1]);
    }
    SUBCASE("replacements that overlap are not merged") {
        CHECK(!merge_replacements(text, {{10, 5, "a"}, {12, 3, "b"}}));
        const std::optional<TextReplacement> r = merge_replacements("abcdefgh", {{6, 1, "G"}, {1, 2, "BC"}});
        REQUIRE(r);
        CHECK(applied(*r, "abcdefgh") == "aBCdefGh");
    }
}

TEST_CASE("selection: the objects take the material of one, as one undo step") {
    Document doc;
    doc.load_text(rtview_test::kDemoScene, "", "demo.txt");
    const rt::Material red = doc.scene().objects[1].material;  // the tetrahedron's
    const std::size_t depth = doc.undo_depth();
    CHECK(give_material(doc, {kObj0, {SceneItem::Kind::Object, 1}, kObj2, kLight0}, red) == 2);
    doc.commit();
    CHECK(doc.undo_depth() == depth + 1);
    CHECK(doc.scene().objects[0].material == red);
    CHECK(doc.scene().objects[2].material == red);
    CHECK(parse_ok(doc.editor_text()) == doc.scene());
    REQUIRE(doc.undo());
    CHECK(doc.scene() == parse_ok(rtview_test::kDemoScene));
}

TEST_CASE("selection: a box finds what a pick of each pixel in it finds") {
    // Three spheres in a row across the view, seen from the origin along +x.
    rt::Scene s;
    for (double y : {0.0, 3.0, -3.0}) {
        rt::Object o;
        o.shape = rt::Sphere{{10, y, 0}, 1};
        s.objects.push_back(o);
    }
    rt::Camera cam;
    cam.position = {0, 0, 0};
    cam.centre = {10, 0, 0};
    cam.up = {10, 0, 1};
    cam.angle_x = 60;
    cam.angle_y = 45;
    s.camera = cam;
    auto world = rt::compile_world(s);
    const int W = 200, H = 150;
    const Rect image{10, 20, 400, 300};  // drawn at twice the film's size
    auto brute = [&](double x0, double y0, double x1, double y1) {
        std::set<int> out;
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i) {
                const double px = image.x + (i + 0.5) * 2, py = image.y + (j + 0.5) * 2;
                if (px < x0 || px > x1 || py < y0 || py > y1) continue;
                const rt::PickResult r = pick_at(*world, cam, image, W, H, px, py);
                if (r.object >= 0) out.insert(r.object);
            }
        return out;
    };
    // (Time enough for every ray asked for, however busy the machine.)
    auto found = [&](double x0, double y0, double x1, double y1, std::size_t rays, double seconds = 1e9) {
        std::set<int> out;
        for (const SceneItem& i : items_in_box(*world, cam, image, W, H, x1, y1, x0, y0, rays, seconds)) {  // (corners swapped)
            CHECK(i.kind == SceneItem::Kind::Object);
            out.insert(i.index);
        }
        return out;
    };
    // The middle sphere alone; the left half (the middle and one side); all; nothing.
    CHECK(found(190, 150, 230, 190, 1 << 20) == std::set<int>{0});
    CHECK(brute(190, 150, 230, 190) == std::set<int>{0});
    const std::set<int> left = found(10, 20, 210, 320, 1 << 20);
    CHECK(left == brute(10, 20, 210, 320));
    CHECK(left.size() == 2);
    CHECK(left.count(0) == 1);
    CHECK(found(10, 20, 410, 320, 1 << 20) == std::set<int>{0, 1, 2});
    CHECK(found(12, 22, 40, 40, 1 << 20).empty());
    // Fewer rays than pixels: a coarser grid still sees spheres this big.
    CHECK(found(10, 20, 410, 320, 500) == std::set<int>{0, 1, 2});
    // No time at all: every 8th row of the grid only (and the last), which still sees
    // all three, and as much as every pixel where one sphere fills the box.
    CHECK(found(10, 20, 410, 320, 1 << 20, 0.0) == std::set<int>{0, 1, 2});
    CHECK(found(190, 150, 230, 190, 1 << 20, 0.0) == brute(190, 150, 230, 190));
    // A box two pixels high (whose rows are all "first") and 1 wide at a sphere's edge.
    for (double x : {120.0, 160.0, 250.0, 290.0})
        CHECK(found(x, 100, x + 1, 103, 1 << 20, 0.0) == brute(x, 100, x + 1, 103));
    // Outside the picture: nothing, and no ray.
    CHECK(found(500, 500, 600, 600, 1 << 20).empty());
}

TEST_CASE("selection: the joint outline is each item's outline, less the border two selected ones share") {
    // 5 x 3 texels: A A B . C on the middle row.
    IdBuffer ids;
    ids.width = 5;
    ids.height = 3;
    ids.x1 = 5;
    ids.y1 = 3;
    const std::uint32_t A = 5, B = 9, C = 13;
    ids.ids = {0, 0, 0, 0, 0, A, A, B, 0, C, 0, 0, 0, 0, 0};
    const auto a = unit_segments(outline_edges(ids, A)), b = unit_segments(outline_edges(ids, B));
    const auto ab = unit_segments(outline_edges_of(ids, {A, B}));
    CHECK(a.size() == 6);  // a 2 x 1 rectangle
    CHECK(b.size() == 4);
    // A's and B's outlines together: the segment they share is one segment.
    std::set<std::tuple<int, int, int, int>> both = a;
    both.insert(b.begin(), b.end());
    CHECK(ab == both);
    CHECK(ab.size() == 9);
    CHECK(ab.count({2, 1, 2, 2}) == 1);  // the border between A and B stays
    CHECK(unit_segments(outline_edges_of(ids, {C})) == unit_segments(outline_edges(ids, C)));
    CHECK(outline_edges_of(ids, {}).empty());
    // Runs are joined: A's top edge is one segment of length 2.
    const std::vector<Edge> runs = outline_edges_of(ids, {A});
    CHECK(runs.size() == 4);
}

TEST_CASE("selection: undo and redo give back the selection of a step of several things") {
    Selection two, copies, other;
    add_all(two, {kObj0, kObj2});
    add_all(copies, {{SceneItem::Kind::Object, 1}, {SceneItem::Kind::Object, 4}});
    select_one(other, {kLight0, {}});
    SelectionSteps steps;
    steps.made(3, "Duplicate 2 things", two, copies);
    // Undone: 2 steps left, the step's name.
    REQUIRE(steps.undone(2, "Duplicate 2 things"));
    CHECK(*steps.undone(2, "Duplicate 2 things") == two);
    CHECK(!steps.undone(2, "Move sphere 1"));  // another step at that place
    CHECK(!steps.undone(3, "Duplicate 2 things"));
    REQUIRE(steps.redone(3, "Duplicate 2 things"));
    CHECK(*steps.redone(3, "Duplicate 2 things") == copies);
    // A new step at that depth (after the undo) replaces it.
    steps.made(3, "Delete 2 things", two, other);
    CHECK(!steps.redone(3, "Duplicate 2 things"));
    CHECK(*steps.undone(2, "Delete 2 things") == two);
    steps.made(2, "Delete 1 thing", other, Selection{});
    CHECK(!steps.undone(2, "Delete 2 things"));
}
