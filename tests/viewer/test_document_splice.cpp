// Structural edits spliced into the document (Document::replace_text with an ItemSplice):
// after each Add, Duplicate, Delete, lamp <-> spotlight and operand deletion, and after
// every undo and redo of them, the document holds exactly what a fresh parse of its text
// gives: the same scene (and the same line and column for every item), the same text
// as the edit's replacement made by hand, and the same layout as a scan of the text.
// And the edit was spliced (only its block parsed), not parsed whole.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include "document.h"
#include "placement.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "selection.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

std::string with_crlf(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '\n') out += '\r';
        out += c;
    }
    return out;
}

std::string with_tabs(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s.compare(i, 2, "  ") == 0 && (i == 0 || s[i - 1] == '\n' || s[i - 1] == '\t')) {
            out += '\t';
            ++i;
        } else {
            out += s[i];
        }
    }
    return out;
}

void same_locs(const rt::Object& a, const rt::Object& b) {
    CHECK(a.loc.line == b.loc.line);
    CHECK(a.loc.col == b.loc.col);
    const rt::Csg* x = std::get_if<rt::Csg>(&a.shape);
    const rt::Csg* y = std::get_if<rt::Csg>(&b.shape);
    REQUIRE((x == nullptr) == (y == nullptr));
    if (x)
        for (std::size_t k = 0; k < x->operands.size() && k < y->operands.size(); ++k) same_locs(x->operands[k], y->operands[k]);
}

// The document agrees with a fresh parse of its text, item positions included (unless
// `locs` is false), and its layout with a fresh scan.
void agrees_with_parse(Document& doc, bool locs = true) {
    const std::string& text = std::as_const(doc).editor_text();
    INFO("text:\n" << text);
    const rt::ParseResult r = rt::parse_scene(text);
    REQUIRE(r.ok());
    REQUIRE(doc.has_scene());
    CHECK(doc.scene() == r.scene);
    REQUIRE(doc.scene().objects.size() == r.scene.objects.size());
    REQUIRE(doc.scene().planes.size() == r.scene.planes.size());
    REQUIRE(doc.scene().lights.size() == r.scene.lights.size());
    for (std::size_t i = 0; i < r.scene.objects.size() && locs; ++i) {
        INFO("object " << i);
        same_locs(doc.scene().objects[i], r.scene.objects[i]);
    }
    for (std::size_t i = 0; i < r.scene.planes.size() && locs; ++i) {
        CHECK(doc.scene().planes[i].loc.line == r.scene.planes[i].loc.line);
        CHECK(doc.scene().planes[i].loc.col == r.scene.planes[i].loc.col);
    }
    for (std::size_t i = 0; i < r.scene.lights.size() && locs; ++i) {
        CHECK(doc.scene().lights[i].loc.line == r.scene.lights[i].loc.line);
        CHECK(doc.scene().lights[i].loc.col == r.scene.lights[i].loc.col);
    }
    if (locs) {
        CHECK(doc.scene().camera_loc.line == r.scene.camera_loc.line);
        CHECK(doc.scene().camera_loc.col == r.scene.camera_loc.col);
    }
    CHECK(doc.diagnostics().size() == r.diagnostics.size());
    const SceneLayout fresh = scan_layout(text);
    const SceneLayout* kept = doc.layout();
    REQUIRE(kept != nullptr);
    auto same_spans = [](const std::vector<TextSpan>& a, const std::vector<TextSpan>& b) {
        REQUIRE(a.size() == b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
            CHECK(a[i].begin == b[i].begin);
            CHECK(a[i].end == b[i].end);
        }
    };
    same_spans(kept->objects, fresh.objects);
    same_spans(kept->planes, fresh.planes);
    same_spans(kept->lights, fresh.lights);
    same_spans(kept->cameras, fresh.cameras);
    CHECK(kept->append_at == fresh.append_at);
}

// Makes the edit through the document (spliced), checks it against the replacement
// made by hand and a fresh parse, then undo, redo and undo again.
void check_spliced(Document& doc, const std::optional<SceneEdit>& e, bool keep = false) {
    REQUIRE(e.has_value());
    REQUIRE(e->splice.has_value());
    const std::string before = std::as_const(doc).editor_text();
    const std::string after = rtview_test::applied(e->replacement, before);
    const std::uint64_t spliced = doc.spliced_count();
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "edit", &*e->splice));
    CHECK(doc.spliced_count() == spliced + 1);
    CHECK(std::as_const(doc).editor_text() == after);
    agrees_with_parse(doc);
    REQUIRE(doc.undo());
    CHECK(std::as_const(doc).editor_text() == before);
    agrees_with_parse(doc);
    REQUIRE(doc.redo());
    CHECK(std::as_const(doc).editor_text() == after);
    agrees_with_parse(doc);
    CHECK(doc.spliced_count() == spliced + 3);
    if (!keep) {
        REQUIRE(doc.undo());
        CHECK(std::as_const(doc).editor_text() == before);
        agrees_with_parse(doc);
    }
}

Placement on_floor(rt::Vec3 p) {
    Placement at;
    at.point = p;
    at.normal = {0, 0, 1};
    return at;
}

const std::string kDemo = rtview_test::kDemoScene;

}  // namespace

TEST_CASE("document splice: every structural edit, its undo and redo equal a parse of the spliced text") {
    for (const std::string& text : {kDemo, with_crlf(kDemo), with_tabs(kDemo)}) {
        Document doc;
        doc.load_text(text, "", "demo.txt");
        REQUIRE(doc.has_scene());
        REQUIRE(doc.diagnostics().empty());
        agrees_with_parse(doc);
        const auto& t = std::as_const(doc).editor_text();
        using K = SceneItem::Kind;
        for (NewItem k : kNewItems) {
            INFO("add " << new_item_name(k));
            check_spliced(doc, add_item(t, doc.scene(), k, on_floor({5, 0.5, 0}), doc.layout()));
        }
        for (int i = 0; i < int(doc.scene().objects.size()); ++i) {
            INFO("object " << i);
            check_spliced(doc, duplicate_item(t, doc.scene(), {K::Object, i}, {}, doc.layout()));
            check_spliced(doc, duplicate_item(t, doc.scene(), {K::Object, i}, {0.5, 0, 0}, doc.layout()));
            check_spliced(doc, delete_item(t, doc.scene(), {K::Object, i}, doc.layout()));
        }
        for (int i = 0; i < 2; ++i) {
            INFO("plane and light " << i);
            check_spliced(doc, duplicate_item(t, doc.scene(), {K::Plane, i}, {}, doc.layout()));
            check_spliced(doc, delete_item(t, doc.scene(), {K::Plane, i}, doc.layout()));
            check_spliced(doc, duplicate_item(t, doc.scene(), {K::Light, i}, {0, 0, 1}, doc.layout()));
            check_spliced(doc, delete_item(t, doc.scene(), {K::Light, i}, doc.layout()));
            check_spliced(doc, switch_light_kind(t, doc.scene(), i, doc.layout()));
        }
        // The lens's operands (object 5, a CSG).
        check_spliced(doc, delete_operand(t, doc.scene(), 4, {0}, doc.layout()));
        check_spliced(doc, delete_operand(t, doc.scene(), 4, {1}, doc.layout()));
    }
}

TEST_CASE("document splice: a new section where the list was empty, and every item deleted in turn") {
    Document doc;
    doc.load_text("// only a camera\r\ncamera { position 0 0 0 centre 10 0 0 up 10 0 1 angle_x 60 angle_y 45 }\n"
                  "picture_size { x_max 32 y_max 24 }\nend\n",
                  "", "empty.txt");
    REQUIRE(doc.has_scene());
    const auto& t = std::as_const(doc).editor_text();
    for (NewItem k : {NewItem::Sphere, NewItem::Plane, NewItem::Lamp, NewItem::Torus, NewItem::ChessPlane})
        check_spliced(doc, add_item(t, doc.scene(), k, on_floor({5, 0, 0}), doc.layout()), true);
    CHECK(doc.scene().objects.size() == 2);
    CHECK(doc.scene().planes.size() == 2);
    CHECK(doc.scene().lights.size() == 1);
    while (!doc.scene().objects.empty())
        check_spliced(doc, delete_item(t, doc.scene(), {SceneItem::Kind::Object, 0}, doc.layout()), true);
    check_spliced(doc, delete_item(t, doc.scene(), {SceneItem::Kind::Light, 0}, doc.layout()), true);
    // All of it back, step by step, and forward again.
    while (doc.undo()) agrees_with_parse(doc);
    while (doc.redo()) agrees_with_parse(doc);
    CHECK(doc.scene().objects.empty());
}

TEST_CASE("document splice: random edits, undos and redos stay equal to a parse") {
    // A grid of spheres with comments between some, two per line on some lines.
    std::string text = "// a grid\nthing {\n";
    for (int i = 0; i < 40; ++i) {
        text += "  sphere { position " + std::to_string(i % 8) + " " + std::to_string(i / 8) + " 0.4 radius 0.4 }";
        text += i % 3 == 0 ? " sphere { position 30 " + std::to_string(i) + " 1 radius 0.2 }\n"
                           : i % 5 == 0 ? "  // five\n" : "\n";
    }
    text += "}\nspecial_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 } }\n"
            "light { lamp { position 2 3 9 colour 90 90 90 size 0.2 } }\n"
            "camera { position -10 -10 8 centre 4 3 0 up 4 3 1 angle_x 60 angle_y 45 }\n"
            "picture_size { x_max 32 y_max 24 }\nend\n";
    Document doc;
    doc.load_text(text, "", "grid.txt");
    INFO(doc.diagnostics().size() << " " << (doc.diagnostics().empty() ? "" : doc.diagnostics()[0].message));
    REQUIRE(doc.has_scene());
    std::mt19937 rng(41);
    const auto& t = std::as_const(doc).editor_text();
    int made = 0;
    bool locs = true;
    for (int step = 0; step < 300; ++step) {
        const int n = int(doc.scene().objects.size());
        const int op = int(rng() % 7);
        const int i = n > 0 ? int(rng() % unsigned(n)) : 0;
        std::optional<SceneEdit> e;
        if (op == 0) e = add_item(t, doc.scene(), NewItem::Sphere, on_floor({double(rng() % 9), 2, 0}), doc.layout());
        else if (op == 1 && n > 0) e = duplicate_item(t, doc.scene(), {SceneItem::Kind::Object, i}, {}, doc.layout());
        else if (op == 2 && n > 0)
            e = duplicate_item(t, doc.scene(), {SceneItem::Kind::Object, i}, {0, 0.5, 0}, doc.layout());
        else if (op == 3 && n > 0) e = delete_item(t, doc.scene(), {SceneItem::Kind::Object, i}, doc.layout());
        else if (op == 6 && n > 0) {
            // A panel edit between them: its block patched, its undo and redo too.
            translate(doc.edit_object(std::size_t(i)), {0.25, 0, 0});
            doc.commit();
            // (A panel edit leaves the positions of the items after its block as they
            // were, as before splices: from here on only the scene's values and the
            // layout are compared.)
            locs = false;
        } else if (op == 4) doc.undo();
        else doc.redo();
        if (e) {
            REQUIRE(e->splice.has_value());
            const std::uint64_t before = doc.spliced_count();
            REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "e", &*e->splice));
            CHECK(doc.spliced_count() == before + 1);
            ++made;
        }
        if (step % 7 == 0 || e) agrees_with_parse(doc, locs);
    }
    agrees_with_parse(doc, locs);
    CHECK(made > 100);
}

TEST_CASE("document splice: a block that does not read alone, or a text with warnings, is parsed whole") {
    // The new block names an object defined in the text: read alone it has no definition.
    const std::string text = "define { object post { cylinder { end_1 0 0 0 end_2 0 0 2 radius 0.1 } } }\n"
                             "thing {\n  instance { object post translate 1 0 0 }\n}\n"
                             "light { lamp { position 2 3 9 colour 90 90 90 size 0.2 } }\n"
                             "camera { position -10 -10 8 centre 4 3 0 up 4 3 1 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 32 y_max 24 }\nend\n";
    Document doc;
    doc.load_text(text, "", "post.txt");
    INFO(doc.diagnostics().size() << " " << (doc.diagnostics().empty() ? "" : doc.diagnostics()[0].message));
    REQUIRE(doc.has_scene());
    const auto& t = std::as_const(doc).editor_text();
    std::optional<SceneEdit> e = duplicate_item(t, doc.scene(), {SceneItem::Kind::Object, 0}, {}, doc.layout());
    REQUIRE(e.has_value());
    REQUIRE(e->splice.has_value());
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "dup", &*e->splice));
    CHECK(doc.spliced_count() == 0);
    CHECK(doc.scene().objects.size() == 2);
    agrees_with_parse(doc);
    // Deleting needs no parse: spliced.
    e = delete_item(t, doc.scene(), {SceneItem::Kind::Object, 1}, doc.layout());
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "del", &*e->splice));
    CHECK(doc.spliced_count() == 1);
    agrees_with_parse(doc);
    REQUIRE(doc.undo());
    agrees_with_parse(doc);
    REQUIRE(doc.undo());
    agrees_with_parse(doc);
    CHECK(doc.scene().objects.size() == 1);
}

namespace {

// A group edit through Document::splice_texts (one undo step, every part spliced in one pass)
// against the same edits made one by one in a second document and a fresh parse of the
// text, then undone and redone (spliced too).
void check_group(const std::string& text, const std::vector<SceneItem>& items, bool del, rt::Vec3 offset) {
    Document doc, one_by_one;
    doc.load_text(text, "", "demo.txt");
    one_by_one.load_text(text, "", "demo.txt");
    REQUIRE(doc.has_scene());
    const std::string& t = std::as_const(doc).editor_text();
    const std::optional<GroupEdit> g = del ? delete_items(t, doc.scene(), items, doc.layout())
                                           : duplicate_items(t, doc.scene(), items, offset, doc.layout());
    REQUIRE(g);
    REQUIRE(g->splices.size() == g->done);
    const std::string before = t;
    const rt::Scene scene_before = doc.scene();
    // The merged replacement (what the text became before splicing) is the text's answer.
    const std::string after = rtview_test::applied(whole_replacement(before, *g), before);
    const std::uint64_t content = doc.content_version();
    const std::size_t depth = doc.undo_depth();
    REQUIRE(doc.splice_texts(g->splices, "group"));
    CHECK(doc.undo_depth() == depth + 1);
    CHECK(doc.spliced_count() == g->done);
    CHECK(doc.group_passes() == 1);  // (in one pass, not edit by edit)
    CHECK(t == after);
    agrees_with_parse(doc);
    // The world hears of each object as a splice, in order.
    const rt::SceneDelta d = doc.changes_since(content);
    CHECK(!d.everything);
    std::size_t objects = 0;
    for (const Document::SpliceEdit& e : g->splices) objects += e.splice.list == ItemList::Object;
    CHECK(d.object_splices.size() == objects);
    for (const rt::SceneDelta::Splice& s : d.object_splices) CHECK(s.insert == !del);
    // The same edits one at a time.
    for (const Document::SpliceEdit& e : g->splices)
        REQUIRE(one_by_one.replace_text(e.replacement.offset, e.replacement.length, e.replacement.text, "e", &e.splice));
    CHECK(one_by_one.spliced_count() == g->done);
    CHECK(std::as_const(one_by_one).editor_text() == after);
    CHECK(one_by_one.scene() == doc.scene());
    REQUIRE(doc.undo());
    CHECK(t == before);
    CHECK(doc.scene() == scene_before);
    agrees_with_parse(doc);
    REQUIRE(doc.redo());
    CHECK(t == after);
    agrees_with_parse(doc);
    CHECK(doc.spliced_count() == 3 * g->done);
    CHECK(doc.group_passes() == 3);
    REQUIRE(doc.undo());
    CHECK(t == before);
    agrees_with_parse(doc);
}

}  // namespace

TEST_CASE("document splice: a group delete or duplicate is one step, spliced in one pass, as the edits one by one") {
    using K = SceneItem::Kind;
    const std::vector<std::vector<SceneItem>> sets = {
        {{K::Light, 1}, {K::Object, 2}, {K::Object, 0}},
        {{K::Object, 3}, {K::Object, 0}, {K::Light, 0}, {K::Plane, 1}},
        {{K::Object, 4}, {K::Object, 3}, {K::Object, 1}, {K::Object, 0}},
        {{K::Plane, 0}, {K::Plane, 1}, {K::Light, 0}, {K::Light, 1}},
    };
    // Copies of two blocks on one line, and of every object. (Deleting two blocks on one
    // line is refused: their deletions would both take the line's end.)
    const std::vector<std::vector<SceneItem>> copies = {
        {{K::Object, 2}, {K::Object, 3}},
        {{K::Object, 4}, {K::Object, 3}, {K::Object, 2}, {K::Object, 1}, {K::Object, 0}},
    };
    for (const std::string& text : {kDemo, with_crlf(kDemo), with_tabs(kDemo)}) {
        for (const std::vector<SceneItem>& items : sets) {
            INFO("items " << items.size() << ", first " << items[0].index);
            check_group(text, items, true, {});
            check_group(text, items, false, {});
            check_group(text, items, false, {0, 2, 0});
        }
        for (const std::vector<SceneItem>& items : copies) {
            INFO("copies of " << items.size());
            check_group(text, items, false, {});
            check_group(text, items, false, {0, 2, 0});
        }
    }
}

TEST_CASE("document splice: a group of edits where one cannot be spliced changes nothing") {
    Document doc;
    doc.load_text(kDemo, "", "demo.txt");
    const std::string& t = std::as_const(doc).editor_text();
    using K = SceneItem::Kind;
    std::optional<GroupEdit> g = delete_items(t, doc.scene(), {{K::Object, 0}, {K::Object, 3}, {K::Light, 1}}, doc.layout());
    REQUIRE(g);
    REQUIRE(g->splices.size() == 3);
    // The last one (the first object's) told the wrong index: its block is not where it says.
    g->splices.back().splice.index = 1;
    const std::string before = t;
    const rt::Scene scene = doc.scene();
    const std::uint64_t version = doc.text_version();
    CHECK(!doc.splice_texts(g->splices, "group"));
    CHECK(t == before);
    CHECK(doc.scene() == scene);
    CHECK(doc.undo_depth() == 0);
    CHECK(doc.spliced_count() == 0);
    CHECK(doc.text_version() == version);
    agrees_with_parse(doc);
    // Made right, it is made.
    g->splices.back().splice.index = 0;
    REQUIRE(doc.splice_texts(g->splices, "group"));
    agrees_with_parse(doc);
    CHECK(doc.scene().objects.size() == scene.objects.size() - 2);
}
