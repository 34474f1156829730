// Geometry and light fields from the schema: for every block kind, each key set through
// the document parses back (from the text) to the scene with that value set by hand;
// undo and redo restore the text byte for byte; a drag is one step; values the parser
// refuses are refused with the parser's own message; comments in a block survive.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <utility>

#include "block_patch.h"
#include "document.h"
#include "item_fields.h"
#include "scene_parser.h"
#include "scene_schema.h"
#include "scene_text.h"
#include "viewer_test_util.h"

using namespace rtview;
namespace sc = rt::schema;

namespace {

const char* const kScene = rtview_test::kDemoScene;
using rtview_test::parse_ok;

// The first error the parser reports for `text`.
std::string parser_error(const std::string& text) {
    rt::ParseResult r = rt::parse_scene(text);
    for (const auto& d : r.diagnostics)
        if (d.is_error()) return d.message;
    return {};
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    std::size_t p = s.find(from);
    REQUIRE(p != std::string::npos);
    return s.replace(p, from.size(), to);
}

ItemRef obj(int i, std::vector<int> path = {}) { return {{SceneItem::Kind::Object, i}, std::move(path)}; }
ItemRef plane(int i) { return {{SceneItem::Kind::Plane, i}, {}}; }
ItemRef light(int i) { return {{SceneItem::Kind::Light, i}, {}}; }

Field field(const rt::Scene& s, const ItemRef& ref, const std::string& label) {
    for (const Field& f : item_fields(s, ref))
        if (f.label == label) return f;
    FAIL("no field " << label);
    return {};
}

// The object `ref` names in `s` (for the hand-made expectations).
rt::Object& at(rt::Scene& s, const ItemRef& ref) {
    rt::Object* o = &s.objects[std::size_t(ref.item.index)];
    for (int k : ref.path) o = &std::get<rt::Csg>(o->shape).operands[std::size_t(k)];
    return *o;
}

// One committed edit through the document: the text parses to `want`, only the item's
// block changed, it is one undo step, and undo/redo give the texts back byte for byte.
std::string check_edit(const ItemRef& ref, const std::string& label, const FieldValue& v, const rt::Scene& want,
                       const std::string& text = kScene) {
    Document doc;
    doc.load_text(text, "", "t.txt");
    REQUIRE(doc.has_scene());
    FieldResult r = set_field(doc, ref, field(doc.scene(), ref, label), v);
    INFO(label << ": " << r.status.message());
    REQUIRE(r.applied());
    CHECK(r.status.ok());
    CHECK(doc.edit_held());
    CHECK(doc.scene() == want);  // live, before the commit
    doc.commit();
    const std::string edited = doc.editor_text();
    INFO("edited:\n" << edited);
    CHECK(parse_ok(edited) == want);
    CHECK(doc.scene() == want);
    CHECK(doc.undo_depth() == 1);
    // Only the item's block changed: the text around it is untouched.
    SceneLayout l = scan_layout(text);
    const std::vector<TextSpan>& spans = ref.item.kind == SceneItem::Kind::Object  ? l.objects
                                         : ref.item.kind == SceneItem::Kind::Plane ? l.planes
                                                                                   : l.lights;
    const TextSpan span = spans[std::size_t(ref.item.index)];
    const std::size_t tail = text.size() - span.end;
    CHECK(edited.compare(0, span.begin, text, 0, span.begin) == 0);
    CHECK(edited.size() >= tail);
    CHECK(edited.compare(edited.size() - tail, tail, text, span.end, tail) == 0);
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == text);
    CHECK(doc.scene() == parse_ok(text));
    REQUIRE(doc.redo());
    CHECK(doc.editor_text() == edited);
    CHECK(doc.scene() == want);
    return edited;
}

FieldValue number(double x) {
    FieldValue v;
    v.number = x;
    return v;
}
FieldValue vec(rt::Vec3 x) {
    FieldValue v;
    v.vec = x;
    return v;
}

}  // namespace

TEST_CASE("item fields: the keys of every block, from the schema") {
    const rt::Scene s = parse_ok(kScene);
    auto labels = [&](const ItemRef& r) {
        std::string out;
        for (const Field& f : item_fields(s, r)) out += (out.empty() ? "" : ",") + f.label;
        return out;
    };
    // (Every object's placement keys, rotation, scale and translate, come last but the material.)
    CHECK(labels(obj(0)) == "position,radius,rotation,scale,translate,material");
    CHECK(labels(obj(1)) == "vect1,vect2,vect3,vect4,rotation,scale,translate,material");
    CHECK(labels(obj(2)) == "end_1,end_2,radius,rotation,scale,translate,material");
    CHECK(labels(obj(3)) == "position,direction,major,minor,rotation,scale,translate,material");
    CHECK(labels(obj(4)) == "type,left,right,rotation,scale,translate,material");
    // An operand's material is not rendered (the CSG's is): it is not offered.
    CHECK(labels(obj(4, {0})) == "position,radius,rotation,scale,translate");
    CHECK(labels(obj(4, {1})) == "position,radius,rotation,scale,translate");
    CHECK(labels(plane(0)) == "point 1,point 2,point 3,point 4,material 1,material 2");
    CHECK(labels(plane(1)) == "point 1,point 2,point 3,point 4,material");
    CHECK(labels(light(0)) == "position,colour,size,radius");
    CHECK(labels(light(1)) == "position,colour,radius");
    CHECK(std::string(item_block_name(s, obj(4))) == "constructive_solid_geometry");
    CHECK(std::string(item_block_name(s, light(1))) == "spotlight");
    // Nothing for what is not there.
    CHECK(item_fields(s, obj(5)).empty());
    CHECK(item_fields(s, obj(0, {0})).empty());  // a sphere has no operands
    CHECK(item_fields(s, obj(4, {2})).empty());
    CHECK(item_block_name(s, light(2)) == nullptr);
    // Current values.
    auto r = field_value(s, obj(0), field(s, obj(0), "radius"));
    REQUIRE(r);
    CHECK(r->number == 0.8);
    auto p3 = field_value(s, plane(0), field(s, plane(0), "point 3"));
    CHECK(p3->vec == rt::Vec3{0.5, 1.5, 0});
    auto t = field_value(s, obj(4), field(s, obj(4), "type"));
    CHECK(t->choice == int(rt::CsgType::Difference));
    auto left = field_value(s, obj(4), field(s, obj(4), "left"));
    CHECK(left->operand == &std::get<rt::Csg>(s.objects[4].shape).operands[0]);
    auto m = field_value(s, obj(3), field(s, obj(3), "material"));
    CHECK_FALSE(m->has_material);
}

TEST_CASE("item fields: each object key, applied, written and parsed back") {
    const rt::Scene base = parse_ok(kScene);
    SUBCASE("sphere") {
        rt::Scene want = base;
        std::get<rt::Sphere>(want.objects[0].shape).radius = 1.25;
        std::string t = check_edit(obj(0), "radius", number(1.25), want);
        // Only the value changed: the comments in the block are still there.
        CHECK(t.find("radius 1.25  // big enough") != std::string::npos);
        CHECK(t.find("sphere {                         // glass ball") != std::string::npos);
        want = base;
        std::get<rt::Sphere>(want.objects[0].shape).position = {6, -2.5, 0.8};
        t = check_edit(obj(0), "position", vec({6, -2.5, 0.8}), want);
        CHECK(t.find("position 6 -2.5 0.8\n") != std::string::npos);
    }
    SUBCASE("tetrahedron") {
        for (int k = 0; k < 4; ++k) {
            rt::Scene want = base;
            rt::Vec3& v = std::get<rt::Tetrahedron>(want.objects[1].shape).v[k];
            v = v + rt::Vec3{0.25, 0.5, -0.125};
            check_edit(obj(1), "vect" + std::to_string(k + 1), vec(v), want);
        }
    }
    SUBCASE("cylinder") {
        rt::Scene want = base;
        std::get<rt::Cylinder>(want.objects[2].shape).end1 = {8, 1, 0};
        check_edit(obj(2), "end_1", vec({8, 1, 0}), want);
        want = base;
        std::get<rt::Cylinder>(want.objects[2].shape).end2 = {9, 0, 2};
        check_edit(obj(2), "end_2", vec({9, 0, 2}), want);
        want = base;
        std::get<rt::Cylinder>(want.objects[2].shape).radius = 0.75;
        std::string t = check_edit(obj(2), "radius", number(0.75), want);
        // The torus sharing the line is untouched.
        CHECK(t.find("radius 0.75 } torus { position 4.5 0 0.25 major 0.6 minor 0.2 }") != std::string::npos);
    }
    SUBCASE("torus, including a key the block did not give") {
        rt::Scene want = base;
        std::get<rt::Torus>(want.objects[3].shape).major = 0.9;
        check_edit(obj(3), "major", number(0.9), want);
        want = base;
        std::get<rt::Torus>(want.objects[3].shape).minor = 0.3;
        check_edit(obj(3), "minor", number(0.3), want);
        want = base;
        std::get<rt::Torus>(want.objects[3].shape).position = {4, 0, 0.25};
        check_edit(obj(3), "position", vec({4, 0, 0.25}), want);
        want = base;
        std::get<rt::Torus>(want.objects[3].shape).direction = {0, 1, 1};
        std::string t = check_edit(obj(3), "direction", vec({0, 1, 1}), want);
        CHECK(t.find("minor 0.2 direction 0 1 1 }") != std::string::npos);
        // A material where the object had none: the whole block is added.
        want = base;
        rt::Material m;
        m.colour = {0.2, 0.4, 0.6};
        want.objects[3].material = m;
        want.objects[3].has_material = true;
        FieldValue v;
        v.material = m;
        check_edit(obj(3), "material", v, want);
    }
    SUBCASE("CSG type, material and its operands' shapes") {
        rt::Scene want = base;
        std::get<rt::Csg>(want.objects[4].shape).type = rt::CsgType::Intersection;
        FieldValue v;
        v.choice = int(rt::CsgType::Intersection);
        std::string t = check_edit(obj(4), "type", v, want);
        CHECK(t.find("type I\n") != std::string::npos);
        CHECK(t.find("// a lens") != std::string::npos);
        for (int side = 0; side < 2; ++side) {
            want = base;
            std::get<rt::Sphere>(at(want, obj(4, {side})).shape).radius = 0.5;
            t = check_edit(obj(4, {side}), "radius", number(0.5), want);
            want = base;
            std::get<rt::Sphere>(at(want, obj(4, {side})).shape).position = {7, 0, 2};
            check_edit(obj(4, {side}), "position", vec({7, 0, 2}), want);
        }
        want = base;
        rt::Material m = want.objects[4].material;
        m.colour = {1, 0, 0};
        want.objects[4].material = m;
        FieldValue mv;
        mv.material = m;
        check_edit(obj(4), "material", mv, want);
    }
    SUBCASE("a CSG operand that is itself a CSG") {
        const std::string text = replaced(kScene, "left { sphere { position 7 -0.3 2.2 radius 0.8 } }",
                                          "left { constructive_solid_geometry { type U left { sphere { radius 2 } } "
                                          "right { cylinder { radius 0.1 } } } }");
        rt::Scene b2 = parse_ok(text);
        rt::Scene want = b2;
        std::get<rt::Cylinder>(at(want, obj(4, {0, 1})).shape).radius = 0.2;
        check_edit(obj(4, {0, 1}), "radius", number(0.2), want, text);
        want = b2;
        std::get<rt::Csg>(at(want, obj(4, {0})).shape).type = rt::CsgType::Difference;
        FieldValue v;
        v.choice = int(rt::CsgType::Difference);
        check_edit(obj(4, {0}), "type", v, want, text);
    }
}

TEST_CASE("item fields: planes and lights") {
    const rt::Scene base = parse_ok(kScene);
    for (int pl = 0; pl < 2; ++pl)
        for (int k = 0; k < 4; ++k) {
            CAPTURE(pl);
            CAPTURE(k);
            rt::Scene want = base;
            rt::Vec3& p = want.planes[std::size_t(pl)].point[k];
            p = p + rt::Vec3{0.5, 0.25, k == 3 ? 2.0 : 0.0};
            check_edit(plane(pl), "point " + std::to_string(k + 1), vec(p), want);
        }
    for (int k = 0; k < 2; ++k) {
        rt::Scene want = base;
        rt::Material& m = k == 0 ? want.planes[0].material : want.planes[0].material2;
        m.scattering = 0.25;
        m.colour = {0.5, 0, 0};
        FieldValue v;
        v.material = m;
        check_edit(plane(0), "material " + std::to_string(k + 1), v, want);
    }
    // The plane had no material block: one is added.
    rt::Scene want = base;
    want.planes[1].material = rt::Material{};
    want.planes[1].has_material = true;
    FieldValue mv;
    mv.material = rt::Material{};
    check_edit(plane(1), "material", mv, want);

    for (int li = 0; li < 2; ++li) {
        want = base;
        want.lights[std::size_t(li)].position = {1, 2, 3};
        std::string t = check_edit(light(li), "position", vec({1, 2, 3}), want);
        if (li == 0) CHECK(t.find("size 0.3 } // warm") != std::string::npos);
        want = base;
        want.lights[std::size_t(li)].colour = {10, 20, 30};
        check_edit(light(li), "colour", vec({10, 20, 30}), want);
    }
    want = base;
    want.lights[0].size = 0.5;
    check_edit(light(0), "size", number(0.5), want);
}

TEST_CASE("item fields: a spotlight edited in the panel still becomes the lamp it was") {
    Document doc;
    doc.load_text(kScene, "", "t.txt");
    auto e = switch_light_kind(doc.editor_text(), doc.scene(), 0);
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    REQUIRE_FALSE(doc.scene().lights[0].lamp);
    const ItemRef ref = light(0);
    REQUIRE(set_field(doc, ref, field(doc.scene(), ref, "position"), vec({-1, -2, 7})).applied());
    doc.commit();
    REQUIRE(set_field(doc, ref, field(doc.scene(), ref, "colour"), vec({5, 5, 5})).applied());
    doc.commit();
    e = switch_light_kind(doc.editor_text(), doc.scene(), 0);
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    const rt::Light& l = doc.scene().lights[0];
    CHECK(l.lamp);
    CHECK(l.size == 0.3);
    CHECK(l.position == rt::Vec3{-1, -2, 7});
    CHECK(l.colour == rt::Vec3{5, 5, 5});
    CHECK(parse_ok(doc.editor_text()) == doc.scene());
}

TEST_CASE("item fields: a drag is one undo step") {
    Document doc;
    doc.load_text(kScene, "", "t.txt");
    const ItemRef ref = obj(0);
    const Field f = field(doc.scene(), ref, "radius");
    for (int k = 1; k <= 30; ++k) {
        REQUIRE(set_field(doc, ref, f, number(0.8 + 0.01 * k)).applied());
        CHECK(std::get<rt::Sphere>(doc.scene().objects[0].shape).radius == 0.8 + 0.01 * k);
    }
    CHECK(doc.editor_text() == kScene);  // written once, at the end
    doc.commit();
    CHECK(doc.undo_depth() == 1);
    CHECK(std::get<rt::Sphere>(parse_ok(doc.editor_text()).objects[0].shape).radius == 0.8 + 0.01 * 30);
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == kScene);
    // Setting a value the item already has is no edit at all.
    REQUIRE(set_field(doc, ref, f, number(0.8)).applied());
    CHECK_FALSE(doc.edit_held());
}

TEST_CASE("item fields: what the parser refuses is refused, with its message") {
    const std::string text = kScene;
    Document doc;
    doc.load_text(text, "", "t.txt");
    struct Case {
        ItemRef ref;
        const char* label;
        FieldValue value;
        std::string from, to;  // the same value written into the text
    };
    const Case cases[] = {
        {obj(0), "radius", number(-1), "radius 0.8  //", "radius -1  //"},
        {obj(0), "radius", number(0), "radius 0.8  //", "radius 0  //"},
        {obj(2), "radius", number(-0.5), "radius 0.5 }", "radius -0.5 }"},
        {obj(2), "end_2", vec({8, 0, 0}), "end_2 8 0 2", "end_2 8 0 0"},
        {obj(1), "vect4", vec({6, -1.5, 0}), "vect4 5.8 -1.8 1.6", "vect4 6 -1.5 0"},
        {obj(3), "major", number(-0.1), "major 0.6", "major -0.1"},
        {obj(3), "minor", number(0), "minor 0.2", "minor 0"},
        {obj(3), "direction", vec({0, 0, 0}), "minor 0.2 }", "minor 0.2 direction 0 0 0 }"},
        {obj(4, {1}), "radius", number(-2), "position 7 0.5 2.2 radius 0.8", "position 7 0.5 2.2 radius -2"},
        {plane(1), "point 3", vec({20, 2, 0}), "point 3 20 0 1", "point 3 20 2 0"},
        {obj(0), "position", vec({1e16, 0, 0}), "position 6 1.5 0.8", "position 1e+16 1.5 0.8"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.label);
        const std::string want = parser_error(replaced(text, c.from, c.to));
        REQUIRE_FALSE(want.empty());
        FieldResult r = set_field(doc, c.ref, field(doc.scene(), c.ref, c.label), c.value);
        CHECK_FALSE(r.applied());
        CHECK(r.status.message() == want);
        CHECK_FALSE(doc.edit_held());
        doc.commit();
        CHECK(doc.editor_text() == text);
        CHECK_FALSE(doc.can_undo());
    }
    // Clamps as the parser clamps: translusans to 0..1, refractive_index to >= 1.
    rt::Material m = doc.scene().objects[0].material;
    m.translusans = 2;
    m.refractive_index = 0.5;
    FieldValue v;
    v.material = m;
    FieldResult r = set_field(doc, obj(0), field(doc.scene(), obj(0), "material"), v);
    REQUIRE(r.applied());
    doc.commit();
    const rt::Scene back = parse_ok(doc.editor_text());
    CHECK(back.objects[0].material.translusans == 1);
    CHECK(back.objects[0].material.refractive_index == 1);
    CHECK(back == doc.scene());
    // A warning of the parser lets the value through and says so.
    rt::Scene s = parse_ok(text);
    r = set_field(s, plane(1), field(s, plane(1), "point 4"), vec({20, 5, 5}));
    CHECK(r.applied());
    CHECK(r.warning == "plane: point 4 lies in the plane, so the lit side is arbitrary");
    CHECK(s.planes[1].point[3] == rt::Vec3{20, 5, 5});
}

TEST_CASE("block patch: only what it can do in place") {
    const rt::Scene s = parse_ok(kScene);
    // Another kind of block: written anew by the caller.
    rt::Light spot = s.lights[0];
    spot.lamp = false;
    CHECK_FALSE(patch_block("lamp { colour 60 60 50 position 2 3 5 size 0.3 }", s.lights[0], spot));
    // A key given twice: the last one counts, and is the one rewritten.
    rt::Light l = s.lights[1];
    rt::Light moved = l;
    moved.position = {0, -4, 4};
    auto t = patch_block("spotlight { position 9 9 9 colour 40 40 60 position 0 -4 3 }", l, moved);
    REQUIRE(t);
    CHECK(*t == "spotlight { position 9 9 9 colour 40 40 60 position 0 -4 4 }");
    // A closing brace on its own line: the new key goes on a line of its own.
    rt::Object torus = s.objects[3];
    rt::Object turned = torus;
    std::get<rt::Torus>(turned.shape).direction = {1, 0, 0};
    t = patch_block("torus {\n    position 4.5 0 0.25 major 0.6 minor 0.2\n  }", torus, turned);
    REQUIRE(t);
    CHECK(*t == "torus {\n    position 4.5 0 0.25 major 0.6 minor 0.2\n    direction 1 0 0\n  }");
    // Text that is not the item: refused.
    CHECK_FALSE(patch_block("torus { position 1 2 3 }", torus, turned));
}

TEST_CASE("item fields: with an unapplied draft, the edit reaches both texts with the block's comments") {
    Document doc;
    doc.load_text(kScene, "", "t.txt");
    doc.typing_text() += "// a draft line\n";
    doc.note_typed();
    REQUIRE(doc.editor_dirty());
    const ItemRef ref = obj(0);
    REQUIRE(set_field(doc, ref, field(doc.scene(), ref, "radius"), number(2)).applied());
    doc.commit();
    for (const std::string* t : {&std::as_const(doc).editor_text(), &doc.applied_text()}) {
        INFO(*t);
        CHECK(t->find("radius 2  // big enough") != std::string::npos);
        CHECK(std::get<rt::Sphere>(parse_ok(*t).objects[0].shape).radius == 2);
    }
    CHECK(std::as_const(doc).editor_text().find("// a draft line") != std::string::npos);
    CHECK_FALSE(doc.text_behind());
}

TEST_CASE("item fields: an edit through a field is named for the undo history by the field and the item") {
    const rt::Scene s = parse_ok(kScene);
    CHECK(item_label(s, obj(0)) == "sphere 1");
    CHECK(item_label(s, obj(4)) == "constructive_solid_geometry 5");
    CHECK(item_label(s, obj(4, {1})) == "right sphere of object 5");
    CHECK(item_label(s, plane(0)) == "chess_plane 1");
    CHECK(item_label(s, light(1)) == "spotlight 2");
    CHECK(item_label(s, light(2)).empty());
    Document doc;
    doc.load_text(kScene, "", "t.txt");
    REQUIRE(set_field(doc, obj(0), field(doc.scene(), obj(0), "radius"), number(0.5)).applied());
    doc.commit();
    REQUIRE(set_field(doc, obj(4, {1}), field(doc.scene(), obj(4, {1}), "position"), vec({7, 1, 2})).applied());
    doc.commit();
    REQUIRE(set_field(doc, plane(0), field(doc.scene(), plane(0), "point 2"), vec({2, 0.5, 0})).applied());
    doc.commit();
    CHECK(doc.undo_names(5) == std::vector<std::string>{"Edit point 2 of chess_plane 1",
                                                        "Edit position of right sphere of object 5",
                                                        "Edit radius of sphere 1"});
}

TEST_CASE("typed numbers: the whole text as the parser reads a number, or nothing with its message") {
    double v = 7;
    CHECK(parse_typed_number("1.5", v).ok());
    CHECK(v == 1.5);
    CHECK(parse_typed_number("  -2e3 ", v).ok());
    CHECK(v == -2000);
    v = 7;
    for (const char* bad : {"", "  ", "abc", "1e1x", "1,5", "0x10", "inf", "nan", "1e", "--1", "1 2"}) {
        const rt::Status st = parse_typed_number(bad, v);
        CHECK_FALSE(st.ok());
        CHECK(st.message().find("expected a number") != std::string::npos);
        CHECK(v == 7);  // untouched
    }
    const rt::Status big = parse_typed_number("1e16", v);
    CHECK(big.message() == "number '1e16' is out of range (magnitude at most 1e15)");
    CHECK(v == 7);
    CHECK(parse_typed_number("1e15", v).ok());
    const rt::Status ctrl = parse_typed_number(std::string("a\x01\xff", 3), v);
    CHECK(ctrl.message() == "expected a number, got 'a?" "?'");
    CHECK(parse_typed_number(std::string(10 << 20, '1'), v).message().find("...'") != std::string::npos);
}
