// A group Delete or Duplicate (Document::splice_texts) is made in one pass over the
// text and the lists, and so are its undo and redo. Random groups (objects, planes and
// lights; adjacent and spread; deletes and duplicates) are made so and, in a second
// document, as the same edits one by one (each a single splice, replace_text): both
// must then hold the same text, scene, source positions (those of a fresh parse too),
// layout and changes for the world, after the group, its undo, its redo and an undo
// and redo again.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include "document.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "selection.h"

using namespace rtview;

namespace {

bool same_loc(const rt::SourceLoc& a, const rt::SourceLoc& b) { return a.line == b.line && a.col == b.col; }

bool same_locs(const rt::Object& a, const rt::Object& b) {
    if (!same_loc(a.loc, b.loc)) return false;
    const rt::Csg* x = std::get_if<rt::Csg>(&a.shape);
    const rt::Csg* y = std::get_if<rt::Csg>(&b.shape);
    if ((x == nullptr) != (y == nullptr)) return false;
    if (!x) return true;
    if (x->operands.size() != y->operands.size()) return false;
    for (std::size_t k = 0; k < x->operands.size(); ++k)
        if (!same_locs(x->operands[k], y->operands[k])) return false;
    return true;
}

// Every source position of `a` is that of `b`.
void same_positions(const rt::Scene& a, const rt::Scene& b) {
    REQUIRE(a.objects.size() == b.objects.size());
    REQUIRE(a.planes.size() == b.planes.size());
    REQUIRE(a.lights.size() == b.lights.size());
    REQUIRE(a.materials.size() == b.materials.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < a.objects.size(); ++i) wrong += !same_locs(a.objects[i], b.objects[i]);
    for (std::size_t i = 0; i < a.planes.size(); ++i) wrong += !same_loc(a.planes[i].loc, b.planes[i].loc);
    for (std::size_t i = 0; i < a.lights.size(); ++i) wrong += !same_loc(a.lights[i].loc, b.lights[i].loc);
    for (std::size_t i = 0; i < a.materials.size(); ++i) wrong += !same_loc(a.materials[i].loc, b.materials[i].loc);
    CHECK(wrong == 0);
    CHECK(same_loc(a.camera_loc, b.camera_loc));
}

bool same_spans(const std::vector<TextSpan>& a, const std::vector<TextSpan>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].begin != b[i].begin || a[i].end != b[i].end) return false;
    return true;
}

void same_layout(const SceneLayout& a, const SceneLayout& b) {
    CHECK(same_spans(a.objects, b.objects));
    CHECK(same_spans(a.planes, b.planes));
    CHECK(same_spans(a.lights, b.lights));
    CHECK(same_spans(a.cameras, b.cameras));
    CHECK(a.append_at == b.append_at);
}

void same_delta(const rt::SceneDelta& a, const rt::SceneDelta& b) {
    CHECK(!a.everything);
    CHECK(a.everything == b.everything);
    CHECK(a.object_splices == b.object_splices);
    CHECK(a.objects == b.objects);
    CHECK(a.all_planes == b.all_planes);
    CHECK(a.all_lights == b.all_lights);
}

// The group's document and the one-by-one document agree, and both agree with a fresh
// parse and scan of the text; the world hears the same of both since the versions given.
void agree(Document& doc, Document& ref, std::uint64_t doc_from, std::uint64_t ref_from) {
    const std::string& text = std::as_const(doc).editor_text();
    REQUIRE(text == std::as_const(ref).editor_text());
    CHECK(doc.scene() == ref.scene());
    same_positions(doc.scene(), ref.scene());
    const rt::ParseResult fresh = rt::parse_scene(text);
    REQUIRE(fresh.ok());
    CHECK(doc.scene() == fresh.scene);
    same_positions(doc.scene(), fresh.scene);
    const SceneLayout* kept = doc.layout();
    REQUIRE(kept != nullptr);
    same_layout(*kept, *ref.layout());
    same_layout(*kept, scan_layout(text));
    same_delta(doc.changes_since(doc_from), ref.changes_since(ref_from));
}

// A scene with its lists in several sections each, objects two to a line on some
// lines, comments, a CSG object and a named material between the sections.
std::string scene_text(bool crlf) {
    std::string t = "// groups\ndefine { material gold { reflection 0.5 colour 1 0.8 0.2 } }\nthing {\n";
    for (int i = 0; i < 24; ++i) {
        t += "  sphere { position " + std::to_string(i % 6) + " " + std::to_string(i / 6) + " 0.4 radius 0.4 }";
        t += i % 4 == 1 ? " torus { position 9 " + std::to_string(i) + " 0.2 major 0.5 minor 0.1 }\n"
                        : i % 5 == 0 ? "  // five\n" : "\n";
        if (i == 10)
            t += "  constructive_solid_geometry { type C\n    left { sphere { position 7 -0.3 2.2 radius 0.8 } }\n"
                 "    right { sphere { position 7 0.5 2.2 radius 0.8 } } }\n";
    }
    t += "}\nspecial_thing {\n  plane { point 1 20 0 0  point 2 20 1 0  point 3 20 0 1  point 4 0 0 0 }\n"
         "  plane { point 1 0 20 0  point 2 1 20 0  point 3 0 20 1  point 4 0 0 0 }\n}\n"
         "light {\n  lamp { position 2 3 9 colour 90 90 90 size 0.2 } // warm\n"
         "  lamp { position -2 3 9 colour 30 30 30 size 0.2 }\n  spotlight { colour 40 40 60 position 0 -4 3 }\n}\n"
         "define { material silver { reflection 0.8 colour 0.9 0.9 0.9 } }\nthing {\n";
    for (int i = 0; i < 8; ++i)
        t += "  cylinder { end_1 " + std::to_string(i) + " 5 0 end_2 " + std::to_string(i) + " 5 2 radius 0.3 }\n";
    t += "}\nspecial_thing { plane { point 1 0 0 -1  point 2 1 0 -1  point 3 0 1 -1  point 4 0 0 1 } }\n"
         "light { lamp { position 5 5 5 colour 10 10 10 size 0.1 } }\n"
         "camera { position -10 -10 8 centre 4 3 0 up 4 3 1 angle_x 60 angle_y 45 }\n"
         "picture_size { x_max 32 y_max 24 }\nend\n";
    if (!crlf) return t;
    std::string out;
    for (char c : t) {
        if (c == '\n') out += '\r';
        out += c;
    }
    return out;
}

// `count` items of the scene: a run of neighbours in one list, or spread over all three.
std::vector<SceneItem> pick(const rt::Scene& s, std::mt19937& rng, int count) {
    using K = SceneItem::Kind;
    const K kinds[3] = {K::Object, K::Plane, K::Light};
    const std::size_t sizes[3] = {s.objects.size(), s.planes.size(), s.lights.size()};
    std::vector<SceneItem> out;
    if (rng() % 2 == 0) {
        int k = int(rng() % 3);
        if (sizes[k] == 0) k = 0;  // (a list emptied by a group delete stays empty)
        const int first = int(rng() % sizes[k]);
        for (int i = first; i < first + count && std::size_t(i) < sizes[k]; ++i) out.push_back({kinds[k], i});
        return out;
    }
    for (int n = 0; n < count; ++n) {
        int k = rng() % 4 == 0 ? int(1 + rng() % 2) : 0;
        if (sizes[k] == 0) k = 0;
        out.push_back({kinds[k], int(rng() % sizes[k])});
    }
    return out;
}

// The group made both ways, then undone, redone, undone and redone in both documents
// (the one-by-one document a step per edit); it stays made or is undone at the end.
void check_group(Document& doc, Document& ref, const std::vector<Document::SpliceEdit>& edits, bool keep) {
    const std::uint64_t passes = doc.group_passes();
    std::uint64_t from = doc.content_version(), ref_from = ref.content_version();
    REQUIRE(doc.splice_texts(edits, "group"));
    CHECK(doc.group_passes() == passes + 1);
    for (const Document::SpliceEdit& e : edits)
        REQUIRE(ref.replace_text(e.replacement.offset, e.replacement.length, e.replacement.text, "e", &e.splice));
    agree(doc, ref, from, ref_from);
    for (int round = 0; round < 2; ++round) {
        from = doc.content_version(), ref_from = ref.content_version();
        REQUIRE(doc.undo());
        for (std::size_t k = 0; k < edits.size(); ++k) REQUIRE(ref.undo());
        agree(doc, ref, from, ref_from);
        if (round == 1 && !keep) break;
        from = doc.content_version(), ref_from = ref.content_version();
        REQUIRE(doc.redo());
        for (std::size_t k = 0; k < edits.size(); ++k) REQUIRE(ref.redo());
        agree(doc, ref, from, ref_from);
    }
    CHECK(doc.group_passes() == passes + (keep ? 5 : 4));
}

}  // namespace

TEST_CASE("document splice group: random groups in one pass equal their edits spliced one by one") {
    for (bool crlf : {false, true}) {
        Document doc, ref;
        doc.load_text(scene_text(crlf), "", "groups.txt");
        ref.load_text(scene_text(crlf), "", "groups.txt");
        REQUIRE(doc.has_scene());
        REQUIRE(doc.diagnostics().empty());
        std::mt19937 rng(crlf ? 7 : 41);
        int made = 0, deletes = 0;
        for (int step = 0; step < 80; ++step) {
            const std::string& t = std::as_const(doc).editor_text();
            const std::vector<SceneItem> items = pick(doc.scene(), rng, int(1 + rng() % 6));
            const bool del = rng() % 2 == 0 && doc.scene().objects.size() > 12;
            const rt::Vec3 offset = rng() % 2 ? rt::Vec3{0, 0, 0} : rt::Vec3{0, 0.5, 1};
            std::optional<GroupEdit> g = del ? delete_items(t, doc.scene(), items, doc.layout())
                                             : duplicate_items(t, doc.scene(), items, offset, doc.layout());
            // (A delete of two blocks on one line is refused: both would take its end.)
            if (!g || g->splices.empty()) continue;
            INFO("step " << step << (del ? " delete " : " duplicate ") << g->splices.size());
            check_group(doc, ref, g->splices, rng() % 3 != 0);
            ++made;
            deletes += del;
        }
        CHECK(made > 50);
        CHECK(deletes > 15);
    }
}

TEST_CASE("document splice group: a group the one pass does not take (a delete and a copy) goes edit by edit") {
    Document doc, ref;
    doc.load_text(scene_text(false), "", "groups.txt");
    ref.load_text(scene_text(false), "", "groups.txt");
    const std::string& t = std::as_const(doc).editor_text();
    using K = SceneItem::Kind;
    // Object 30 deleted and object 3 copied, the last in the text first.
    std::optional<SceneEdit> del = delete_item(t, doc.scene(), {K::Object, 30}, doc.layout());
    std::optional<SceneEdit> dup = duplicate_item(t, doc.scene(), {K::Object, 3}, {0, 1, 0}, doc.layout());
    REQUIRE(del);
    REQUIRE(dup);
    REQUIRE(del->splice);
    REQUIRE(dup->splice);
    REQUIRE(del->replacement.offset > dup->replacement.offset);
    const std::vector<Document::SpliceEdit> edits = {{del->replacement, *del->splice}, {dup->replacement, *dup->splice}};
    std::uint64_t from = doc.content_version(), ref_from = ref.content_version();
    REQUIRE(doc.splice_texts(edits, "mixed"));
    for (const Document::SpliceEdit& e : edits)
        REQUIRE(ref.replace_text(e.replacement.offset, e.replacement.length, e.replacement.text, "e", &e.splice));
    agree(doc, ref, from, ref_from);
    CHECK(doc.spliced_count() == 2);
    from = doc.content_version(), ref_from = ref.content_version();
    REQUIRE(doc.undo());
    REQUIRE(ref.undo());
    REQUIRE(ref.undo());
    agree(doc, ref, from, ref_from);
    from = doc.content_version(), ref_from = ref.content_version();
    REQUIRE(doc.redo());
    REQUIRE(ref.redo());
    REQUIRE(ref.redo());
    agree(doc, ref, from, ref_from);
    CHECK(doc.spliced_count() == 6);
    CHECK(doc.group_passes() == 0);
}
