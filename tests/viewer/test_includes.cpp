// A scene that includes other files, in the viewer: the items an include brings have no
// block in the scene file's text, so a panel or handle edit of one is refused (it could
// not be saved), while edits of the file's own items are written into their own blocks
// (found by their place among the own items); an included file changed on disk is read
// again, as a model file is.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/stat.h>

#include <string>

#include "document.h"
#include "scene_edits.h"
#include "scene_writer.h"
#include "scene_parser.h"
#include "scene_text.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {

using rt_test::slurp;
using rt_test::TempDir;

// Writes a file and gives it an mtime `seconds` from now, so that each version is
// told apart by its stamp even within one clock tick.
void put(const std::string& p, const std::string& text, int seconds) {
    rt_test::put(p, text);
    struct timespec t[2];
    ::clock_gettime(CLOCK_REALTIME, &t[0]);
    t[0].tv_sec += seconds;
    t[1] = t[0];
    ::utimensat(AT_FDCWD, p.c_str(), t, 0);
}

const char* kLib = "thing {\n  sphere { position 5 5 5 radius 1 }\n  box { corner_1 0 0 0 corner_2 1 1 1 }\n}\n"
                   "light { lamp { position 9 9 9 colour 1 1 1 } }\n";

// The own sphere comes after the include: scene object 2, the text's object 0.
const char* kMain = "include \"lib.txt\"\n"
                    "thing {\n"
                    "  sphere { position 1 0 0 radius 0.5 }  // mine\n"
                    "}\n"
                    "light { lamp { position 0 0 9 colour 2 2 2 } }\n"
                    "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
                    "picture_size { x_max 8 y_max 8 }\nend\n";

double radius_of(const rt::Scene& s, std::size_t i) { return std::get<rt::Sphere>(s.objects.at(i).shape).radius; }

rt::Scene parse_file(const std::string& path) {
    rt::ParseOptions o;
    o.base_dir = rt::folder_of(path);
    rt::ParseResult r = rt::parse_scene(slurp(path), o);
    REQUIRE(r.ok());
    return r.scene;
}

// The main scene and the file it includes, in a folder of their own, and a document
// that opened the main one.
struct Included {
    TempDir dir;
    const std::string main = (dir / "main.txt").string(), lib = (dir / "lib.txt").string();
    Document d;
    Included() {
        put(lib, kLib, 0);
        put(main, kMain, 0);
        REQUIRE(d.load_file(main).ok());
    }
};

}  // namespace

TEST_CASE("includes: own items are found by their place among the file's own items") {
    Included f;
    Document& d = f.d;
    const rt::Scene& s = d.scene();
    REQUIRE(s.objects.size() == 3);
    REQUIRE(s.lights.size() == 2);
    CHECK(included_file(s, ItemList::Object, 0)->file == "lib.txt");
    CHECK(included_file(s, ItemList::Object, 1)->file == "lib.txt");
    CHECK(included_file(s, ItemList::Object, 2) == nullptr);
    CHECK(included_file(s, ItemList::Light, 0) != nullptr);
    CHECK_FALSE(own_index(s, ItemList::Object, 0));
    CHECK(own_index(s, ItemList::Object, 2) == std::optional<std::size_t>(0));
    CHECK(own_index(s, ItemList::Light, 1) == std::optional<std::size_t>(0));
    CHECK(own_count(s, ItemList::Object) == 1);
    CHECK(own_count(s, ItemList::Plane) == 0);
    CHECK(layout_matches(scan_layout(d.editor_text()), s));
}

TEST_CASE("includes: an edit of an own item is written into its own block, comments kept, and saved") {
    Included f;
    Document& d = f.d;
    const std::string& main = f.main;
    std::get<rt::Sphere>(d.edit_object(2).shape).radius = 0.75;
    d.commit();
    CHECK(d.take_refusal().empty());
    CHECK(radius_of(d.scene(), 2) == 0.75);
    // Only the sphere's value changed: the include line and the comment stay.
    std::string want = kMain;
    want.replace(want.find("radius 0.5"), 10, "radius 0.75");
    CHECK(d.editor_text() == want);
    // A light after the include: its own block too.
    d.edit_light(1).position = {0, 1, 9};
    d.commit();
    want.replace(want.find("position 0 0 9"), 14, "position 0 1 9");
    CHECK(d.editor_text() == want);
    REQUIRE(d.save().ok());
    CHECK(slurp(main) == want);
    CHECK(slurp(f.lib) == kLib);
    CHECK(parse_file(main) == d.scene());
    // Undo takes both back, in the text and the scene alike.
    CHECK(d.undo());
    CHECK(d.undo());
    CHECK(d.editor_text() == kMain);
    CHECK(radius_of(d.scene(), 2) == 0.5);
}

TEST_CASE("includes: an edit of an included item is refused, so Save never loses or misplaces it") {
    Included f;
    Document& d = f.d;
    const std::string &main = f.main, &lib = f.lib;
    const rt::Scene before = d.scene();
    std::get<rt::Sphere>(d.edit_object(0).shape).radius = 2;
    CHECK(radius_of(d.scene(), 0) == 2);  // shown while the gesture lasts
    d.commit();
    const std::string why = d.take_refusal();
    CHECK(why.find("lib.txt") != std::string::npos);
    CHECK(why.find("object 1") != std::string::npos);
    CHECK(d.scene() == before);
    CHECK(d.editor_text() == kMain);
    CHECK_FALSE(d.can_undo());
    CHECK_FALSE(d.modified());
    // An included light, and an included object edited with an own one: nothing of it.
    d.edit_light(0).position = {1, 2, 3};
    d.commit();
    CHECK_FALSE(d.take_refusal().empty());
    std::get<rt::Sphere>(d.edit_object(2).shape).radius = 0.6;
    std::get<rt::Box>(d.edit_object(1).shape).corner2 = {2, 2, 2};
    d.commit();
    CHECK_FALSE(d.take_refusal().empty());
    CHECK(d.scene() == before);
    CHECK(d.editor_text() == kMain);
    REQUIRE(d.save().ok());
    CHECK(slurp(main) == kMain);
    CHECK(slurp(lib) == kLib);
    CHECK(parse_file(main) == d.scene());
}

TEST_CASE("includes: an included file changed on disk is read again, the text and its edits kept") {
    Included f;
    Document& d = f.d;
    const std::string &main = f.main, &lib = f.lib;
    CHECK(d.check_disk() == Document::DiskEvent::None);
    // An unsaved edit of an own item first: it stays, unsaved.
    std::get<rt::Sphere>(d.edit_object(2).shape).radius = 0.75;
    d.commit();
    REQUIRE(d.modified());
    const std::string text = d.editor_text();

    std::string lib2 = kLib;
    lib2.replace(lib2.find("radius 1"), 8, "radius 3");
    put(lib, lib2, 5);
    const std::uint64_t v = d.content_version();
    CHECK(d.check_disk() == Document::DiskEvent::IncludesReloaded);
    CHECK(d.content_version() > v);
    CHECK(radius_of(d.scene(), 0) == 3);
    CHECK(radius_of(d.scene(), 2) == 0.75);
    CHECK(d.editor_text() == text);
    CHECK(d.modified());
    CHECK(d.check_disk() == Document::DiskEvent::None);

    // One more item in the included file: the own sphere is object 3 now, and an edit
    // of it still finds its block.
    std::string lib3 = "thing { sphere { position 7 7 7 radius 0.25 } }\n" + lib2;
    put(lib, lib3, 10);
    CHECK(d.check_disk() == Document::DiskEvent::IncludesReloaded);
    REQUIRE(d.scene().objects.size() == 4);
    CHECK(radius_of(d.scene(), 3) == 0.75);
    std::get<rt::Sphere>(d.edit_object(3).shape).radius = 0.5;
    d.commit();
    CHECK(d.take_refusal().empty());
    CHECK(d.editor_text() == kMain);
    REQUIRE(d.save().ok());
    CHECK(parse_file(main) == d.scene());

    // Broken: said once, the scene stays as it was; mended: read again.
    put(lib, "thing { sphere { radius -1 } }\n", 15);
    CHECK(d.check_disk() == Document::DiskEvent::IncludeUnreadable);
    CHECK(d.model_problem().find("lib.txt") != std::string::npos);
    CHECK(d.check_disk() == Document::DiskEvent::None);
    CHECK(d.scene().objects.size() == 4);
    put(lib, kLib, 20);
    CHECK(d.check_disk() == Document::DiskEvent::IncludesReloaded);
    CHECK(d.scene().objects.size() == 3);
    CHECK(parse_file(main) == d.scene());
}

TEST_CASE("includes: a file included by an included file is watched too") {
    TempDir dir;
    const std::string main = (dir / "main.txt").string(), inner = (dir / "inner.txt").string();
    put(inner, "thing { sphere { position 2 2 2 radius 1 } }\n", 0);
    put((dir / "lib.txt").string(), "include \"inner.txt\"\n", 0);
    put(main, kMain, 0);
    Document d;
    REQUIRE(d.load_file(main).ok());
    REQUIRE(d.scene().objects.size() == 2);
    put(inner, "thing { sphere { position 2 2 2 radius 1.5 } }\n", 5);
    CHECK(d.check_disk() == Document::DiskEvent::IncludesReloaded);
    CHECK(radius_of(d.scene(), 0) == 1.5);
}

TEST_CASE("includes: structural edits work on own items, refuse included ones, and select the right item") {
    Included f;
    Document& d = f.d;
    const std::string text = d.editor_text();
    const rt::Scene s = d.scene();
    // Objects: lib's sphere and box (0, 1), the own sphere (2).
    CHECK_FALSE(delete_item(text, s, {SceneItem::Kind::Object, 0}));
    CHECK_FALSE(duplicate_item(text, s, {SceneItem::Kind::Object, 1}));
    CHECK_FALSE(switch_light_kind(text, s, 0));
    CHECK_FALSE(make_csg(text, s, 2, 0, rt::CsgType::Union));
    // The own sphere duplicated: the copy right after it, object 4 of the scene.
    auto e = duplicate_item(text, s, {SceneItem::Kind::Object, 2});
    REQUIRE(e);
    CHECK(e->select.index == 3);
    REQUIRE(d.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    REQUIRE(d.scene().objects.size() == 4);
    CHECK(d.scene().objects[3].origin == 0);
    CHECK(radius_of(d.scene(), 3) == 0.5);
    // Deleted again: only the file's own block goes (the copy took the line's comment
    // with it, as it does in any scene); the included items are as they were.
    e = delete_item(d.editor_text(), d.scene(), {SceneItem::Kind::Object, 3});
    REQUIRE(e);
    REQUIRE(d.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK(d.scene() == s);
    CHECK(d.editor_text().rfind("include \"lib.txt\"\n", 0) == 0);
    // The own lamp switched to a spotlight.
    e = switch_light_kind(d.editor_text(), d.scene(), 1);
    REQUIRE(e);
    REQUIRE(d.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK_FALSE(d.scene().lights[1].lamp);
    CHECK(d.scene().lights[0].lamp);
}

TEST_CASE("a CSG is not offered of a mesh or an instance: the format refuses them as operands") {
    const rt::Scene s = rt_test::parse_ok(
        "define { object cube { box { corner_1 0 0 0 corner_2 1 1 1 } } }\n"
        "thing { sphere { position 0 0 0 radius 1 } instance { object cube translate 3 0 0 } sphere { position 6 0 0 "
        "radius 1 } }\ncamera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
        "picture_size { x_max 8 y_max 8 }\nend\n");
    const std::string text = rt::write_scene(s);
    CHECK_FALSE(make_csg(text, s, 0, 1, rt::CsgType::Union));
    CHECK_FALSE(make_csg(text, s, 1, 2, rt::CsgType::Union));
    CHECK(make_csg(text, s, 0, 2, rt::CsgType::Union));
}
