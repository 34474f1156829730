// Named materials and objects (`define`) in the viewer's document: items that use a
// material by name are written back by name (moved, duplicated, made CSG operands), undo
// gives back the definitions a step changed, and a file read again whose includes bring
// another number of items drops the history that names items by their place.
#include <doctest/doctest.h>

#include <string>

#include "document.h"
#include "item_fields.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

using rt_test::TempDir;

const char* kGold =
    "define {\n"
    "  material gold { reflection 0.5 colour 1 0.8 0.2 }\n"
    "  object post { box { corner_1 0 0 0 corner_2 1 1 4 } }\n"
    "}\n"
    "thing {\n"
    "  sphere { position 1 0 0 radius 0.5 material gold }\n"
    "  sphere { position 3 0 0 radius 0.5 material { colour 0 0 1 } }\n"
    "  instance { object post material gold translate 5 0 0 }\n"
    "}\n"
    "light { lamp { position 0 0 9 colour 2 2 2 } }\n"
    "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
    "picture_size { x_max 8 y_max 8 }\nend\n";

// The document's scene is what its applied text parses to.
void check_scene_is_text(const Document& doc) {
    const rt::ParseResult r = rt::parse_scene(doc.applied_text(), doc.parse_options(doc.path()));
    REQUIRE(r.ok());
    CHECK(r.scene == doc.scene());
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("an object using a named material, moved, keeps the name in its block") {
    Document doc;
    doc.load_text(kGold, "", "gold");
    REQUIRE(doc.has_scene());
    REQUIRE(doc.scene().objects[0].material.named == 0);
    translate(doc.edit_object(0), {0, 2, 0});
    doc.commit();
    CHECK(doc.take_refusal() == "");
    CHECK(std::get<rt::Sphere>(doc.scene().objects[0].shape).position == rt::Vec3{1, 2, 0});
    CHECK(count(doc.editor_text(), "material gold") == 3);  // the definition's and the two uses
    CHECK(count(doc.editor_text(), "reflection 0.5") == 1);  // not spelled out in the block
    check_scene_is_text(doc);
}

TEST_CASE("a CSG of objects that use a named material writes its operands' materials by name") {
    Document doc;
    doc.load_text(kGold, "", "gold");
    const std::optional<SceneEdit> e = make_csg(doc.editor_text(), doc.scene(), 0, 1, rt::CsgType::Union);
    REQUIRE(e);
    // The edited text names the material in the CSG's block and its left operand.
    const std::string edited = rtview_test::applied(e->replacement, doc.editor_text());
    CHECK(count(edited, "material gold") == 4);
    CHECK(count(edited, "reflection 0.5") == 1);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    const rt::Csg& g = std::get<rt::Csg>(doc.scene().objects[0].shape);
    CHECK(doc.scene().objects[0].material.named == 0);
    CHECK(g.operands[0].material.named == 0);
    CHECK(g.operands[1].material.named == -1);
    check_scene_is_text(doc);
}

TEST_CASE("a duplicate moved by an offset keeps its named material by name") {
    Document doc;
    doc.load_text(kGold, "", "gold");
    const std::optional<SceneEdit> e = duplicate_item(doc.editor_text(), doc.scene(), {SceneItem::Kind::Object, 0}, {0, 3, 0});
    REQUIRE(e);  // (refused before: the copy spelled out read back as another material)
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    REQUIRE(doc.scene().objects.size() == 4);
    CHECK(doc.scene().objects[1].material.named == 0);
    CHECK(count(doc.editor_text(), "reflection 0.5") == 1);
    check_scene_is_text(doc);
}

TEST_CASE("undo past an applied text that changed only definitions gives them back") {
    Document doc;
    doc.load_text(kGold, "", "gold");
    const rt::Scene start = doc.scene();
    // A draft that changes the unused corner of `post`'s definition and gold's colour.
    std::string draft = doc.editor_text();
    draft.replace(draft.find("corner_2 1 1 4"), 14, "corner_2 1 1 6");
    doc.typing_text() = draft;
    doc.note_typed();
    REQUIRE(doc.apply_text());
    CHECK(!(doc.scene().defined == start.defined));
    // A panel edit after it, then undo both.
    translate(doc.edit_light(0), {1, 0, 0});
    doc.commit();
    const std::string end = doc.editor_text();
    REQUIRE(doc.undo());
    check_scene_is_text(doc);
    REQUIRE(doc.undo());  // the apply
    REQUIRE(doc.undo());  // the typing
    CHECK(doc.editor_text() == kGold);
    check_scene_is_text(doc);
    CHECK(doc.scene() == start);
    while (doc.redo()) check_scene_is_text(doc);
    CHECK(doc.editor_text() == end);
}

TEST_CASE("a file read again whose include brings more items drops the history naming items by place") {
    TempDir dir;
    const std::string lib = (dir.path / "lib.txt").string(), main = (dir.path / "main.txt").string();
    rt_test::put(lib, "light { lamp { position 9 9 9 colour 1 1 1 } }\n");
    const std::string text = "include \"lib.txt\"\nlight { lamp { position 0 0 9 colour 2 2 2 } }\n"
                             "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 8 y_max 8 }\nend\n";
    rt_test::put(main, text);
    Document doc;
    REQUIRE(doc.load_file(main));
    REQUIRE(doc.scene().lights.size() == 2);
    translate(doc.edit_light(1), {1, 0, 0});  // the own lamp, light 2 of the scene
    doc.commit();
    REQUIRE(doc.save());
    // Another program writes both files: the library gains a lamp before the own one.
    rt_test::put(lib, "light { lamp { position 9 9 9 colour 1 1 1 } lamp { position 8 8 8 colour 1 1 1 } }\n");
    const std::string changed = "// changed\n" + doc.editor_text();
    rt_test::put(main, changed);
    REQUIRE(doc.check_disk() == Document::DiskEvent::Reloaded);
    REQUIRE(doc.scene().lights.size() == 3);
    check_scene_is_text(doc);
    // The move named light 2, now an included lamp: only the reload is left to undo.
    CHECK(doc.undo_names(10) == std::vector<std::string>{"Reload from disk"});
    REQUIRE(doc.undo());
    CHECK(!doc.can_undo());
    CHECK(doc.scene().lights.size() == 3);
    CHECK(doc.scene().lights[2].position == rt::Vec3{1, 0, 9});
}

namespace {

const char* kShared =
    "define {\n"
    "  material gold { reflection 0.5 colour 1 0.8 0.2 }  // the gold\n"
    "  object post { box { corner_1 0 0 0 corner_2 1 1 4 material gold } }\n"
    "}\n"
    "thing {\n"
    "  sphere { position 1 0 0 radius 0.5 material gold }  // first\n"
    "  sphere { position 3 0 0 radius 0.5 material { colour 0 0 1 } }\n"
    "  instance { object post material gold translate 5 0 0 }\n"
    "  constructive_solid_geometry { type U material { colour 1 1 1 }\n"
    "    left { sphere { position 0 4 0 radius 1 material gold } } right { sphere { position 1 4 0 radius 1 } } }\n"
    "}\n"
    "special_thing { chess_plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1\n"
    "  material 1 { colour 1 1 1 } material 2 gold } }\n"
    "light { lamp { position 0 0 9 colour 2 2 2 } }\n"
    "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
    "picture_size { x_max 8 y_max 8 }\nend\n";

Field material_field(const rt::Scene& s, const ItemRef& ref, const char* label = "material") {
    for (const Field& f : item_fields(s, ref))
        if (f.kind == rt::schema::Kind::Material && f.label == label) return f;
    FAIL("no field " << label);
    return {};
}

}  // namespace

TEST_CASE("a material used by name is edited once for every user: its definition, one undo step, a delta of the users") {
    Document doc;
    doc.load_text(kShared, "", "shared");
    REQUIRE(doc.has_scene());
    const ItemRef first{{SceneItem::Kind::Object, 0}, {}};
    const Field f = material_field(doc.scene(), first);
    REQUIRE(named_material_of(doc.scene(), first, f) == 0);
    CHECK(named_material_of(doc.scene(), {{SceneItem::Kind::Object, 1}, {}}, f) == -1);
    // The first sphere, the instance (its own and its definition's), the CSG's operand,
    // the chess plane's second material: four things.
    CHECK(material_users(doc.scene(), 0) == 4);
    const std::uint64_t version = doc.content_version();
    const std::size_t depth = doc.undo_depth();
    for (double r : {0.4, 0.3, 0.25}) {  // a drag over three frames
        FieldValue v = *field_value(doc.scene(), first, f);
        v.material.reflection = r;
        REQUIRE(set_field(doc, first, f, v).applied());
    }
    doc.commit();
    CHECK(doc.take_refusal() == "");
    CHECK(doc.undo_depth() == depth + 1);
    CHECK(doc.undo_names(1) == std::vector<std::string>{"Edit material gold"});
    // The text: the definition rewritten (its comment kept), every block as it was.
    std::string want = kShared;
    want.replace(want.find("{ reflection 0.5 colour 1 0.8 0.2 }"), 35, "{ reflection 0.25 colour 1 0.8 0.2 }");
    CHECK(doc.editor_text() == want);
    check_scene_is_text(doc);
    const rt::Scene& s = doc.scene();
    CHECK(s.materials[0].material.reflection == 0.25);
    CHECK(s.objects[0].material.reflection == 0.25);
    CHECK(s.objects[2].material.reflection == 0.25);
    CHECK(std::get<rt::Instance>(s.objects[2].shape).defined->material.reflection == 0.25);
    CHECK(std::get<rt::Instance>(s.objects[2].shape).defined == s.defined[0].object);
    CHECK(std::get<rt::Csg>(s.objects[3].shape).operands[0].material.reflection == 0.25);
    CHECK(s.planes[0].material2.reflection == 0.25);
    CHECK(s.objects[1].material.reflection == 0);
    // The world hears of the users only.
    const rt::SceneDelta d = doc.changes_since(version);
    CHECK(!d.everything);
    CHECK(d.objects == std::vector<std::uint32_t>{0, 2, 3});
    CHECK(d.planes == std::vector<std::uint32_t>{0});
    // One undo gives back the text and the scene; redo the edit.
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == kShared);
    check_scene_is_text(doc);
    CHECK(doc.scene().objects[0].material.reflection == 0.5);
    REQUIRE(doc.redo());
    CHECK(doc.editor_text() == want);
    check_scene_is_text(doc);
}

TEST_CASE("a drag of a shared material cancelled leaves every user as it was") {
    Document doc;
    doc.load_text(kShared, "", "shared");
    const rt::Scene start = doc.scene();
    const ItemRef plane{{SceneItem::Kind::Plane, 0}, {}};
    const Field f = material_field(doc.scene(), plane, "material 2");
    FieldValue v = *field_value(doc.scene(), plane, f);
    v.material.colour = {0, 1, 0};
    REQUIRE(set_field(doc, plane, f, v).applied());
    CHECK(doc.scene().objects[0].material.colour == rt::Vec3{0, 1, 0});
    doc.cancel_edit();
    CHECK(doc.scene() == start);
    CHECK(doc.editor_text() == kShared);
}

TEST_CASE("Make local gives one thing its own copy of a named material; the others keep the name") {
    Document doc;
    doc.load_text(kShared, "", "shared");
    const ItemRef first{{SceneItem::Kind::Object, 0}, {}};
    const Field f = material_field(doc.scene(), first);
    REQUIRE(make_material_local(doc, first, f).applied());
    CHECK(doc.undo_depth() == 1);
    check_scene_is_text(doc);
    CHECK(named_material_of(doc.scene(), first, f) == -1);
    CHECK(doc.scene().objects[0].material.reflection == 0.5);  // the same values
    CHECK(material_users(doc.scene(), 0) == 3);
    CHECK(count(doc.editor_text(), "material gold") == 4);  // one fewer
    // Its own copy edited: gold stays.
    FieldValue v = *field_value(doc.scene(), first, f);
    v.material.reflection = 0.1;
    REQUIRE(set_field(doc, first, f, v).applied());
    doc.commit();
    check_scene_is_text(doc);
    CHECK(doc.scene().materials[0].material.reflection == 0.5);
    CHECK(doc.scene().planes[0].material2.reflection == 0.5);
    // A user's edit changes gold, not the local copy.
    const ItemRef inst{{SceneItem::Kind::Object, 2}, {}};
    const Field fi = material_field(doc.scene(), inst);
    v = *field_value(doc.scene(), inst, fi);
    v.material.reflection = 0.9;
    const FieldResult r = set_field(doc, inst, fi, v);
    INFO(r.status.message());
    REQUIRE(r.applied());
    doc.commit();
    check_scene_is_text(doc);
    CHECK(doc.scene().materials[0].material.reflection == 0.9);
    CHECK(doc.scene().objects[0].material.reflection == 0.1);
    CHECK(make_material_local(doc, first, f).status.message().find("not a named one") != std::string::npos);
}

TEST_CASE("a named material edited while the text has a draft that parses: carried into the draft, as an item edit is") {
    Document doc;
    doc.load_text(kShared, "", "shared");
    // The draft moves the first sphere (a user of gold) and the blue one, unapplied.
    std::string draft = kShared;
    draft.replace(draft.find("position 1 0 0"), 14, "position 1 2 0");
    draft.replace(draft.find("position 3 0 0"), 14, "position 3 1 0");
    doc.typing_text() = draft;
    doc.note_typed();
    REQUIRE(doc.unapplied());
    REQUIRE(doc.edit_blocker() == "");
    const ItemRef inst{{SceneItem::Kind::Object, 2}, {}};
    const Field f = material_field(doc.scene(), inst);
    FieldValue v = *field_value(doc.scene(), inst, f);
    v.material.reflection = 0.25;
    REQUIRE(set_field(doc, inst, f, v).applied());
    doc.commit();
    CHECK(doc.take_refusal() == "");
    CHECK(doc.scene().materials[0].material.reflection == 0.25);
    CHECK(doc.scene().objects[0].material.reflection == 0.25);
    // The draft keeps its moves and gains the definition; every block still names gold.
    CHECK(doc.unapplied());
    const std::string& text = doc.editor_text();
    CHECK(text.find("position 1 2 0 radius 0.5 material gold }  // first") != std::string::npos);
    CHECK(text.find("position 3 1 0") != std::string::npos);
    CHECK(count(text, "material gold") == count(kShared, "material gold"));
    CHECK(text.find("material gold { reflection 0.25") != std::string::npos);
    check_scene_is_text(doc);  // the applied text: the old positions, the new gold
    CHECK(doc.applied_text().find("position 1 0 0 radius 0.5 material gold") != std::string::npos);
    // Applying the draft gives both the moves and the new gold.
    REQUIRE(doc.apply_text());
    CHECK(std::get<rt::Sphere>(doc.scene().objects[0].shape).position == rt::Vec3{1, 2, 0});
    CHECK(doc.scene().objects[0].material.reflection == 0.25);
    CHECK(doc.scene().planes[0].material2.reflection == 0.25);
    // Undo goes back through the apply and the edit to the draft as typed.
    REQUIRE(doc.undo());
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == draft);
    CHECK(doc.scene().materials[0].material.reflection == 0.5);
}

TEST_CASE("a named material's definition edited from the panels keeps the comments and layout inside it") {
    std::string text = kShared;
    const std::string one_line = "{ reflection 0.5 colour 1 0.8 0.2 }  // the gold";
    const std::string laid_out = "{  // polished\n"
                                 "    reflection 0.5   // a mirror's half\n"
                                 "    colour 1 0.8 0.2 // warm\n"
                                 "  }";
    text.replace(text.find(one_line), one_line.size(), laid_out);
    Document doc;
    doc.load_text(text, "", "shared");
    REQUIRE(doc.has_scene());
    const ItemRef first{{SceneItem::Kind::Object, 0}, {}};
    const Field f = material_field(doc.scene(), first);
    FieldValue v = *field_value(doc.scene(), first, f);
    v.material.reflection = 0.25;  // a value given
    v.material.specular = 0.5;     // and one not given: added before the brace
    REQUIRE(set_field(doc, first, f, v).applied());
    doc.commit();
    CHECK(doc.take_refusal() == "");
    std::string want = text;
    want.replace(want.find(laid_out), laid_out.size(),
                 "{  // polished\n"
                 "    reflection 0.25   // a mirror's half\n"
                 "    colour 1 0.8 0.2 // warm\n"
                 "    specular 0.5\n"
                 "  }");
    CHECK(doc.editor_text() == want);
    check_scene_is_text(doc);
    CHECK(doc.scene().materials[0].material.specular == 0.5);
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == text);
}
