// Crash recovery of unsaved editor text: written while modified, found by the next
// session for the same file only, and gone once the text is saved or discarded.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <unistd.h>

#include "default_scene.h"
#include "document.h"
#include "new_scene.h"
#include "recovery.h"
#include "test_util.h"

using namespace rtview;
using rt_test::parse_ok;
namespace fs = std::filesystem;


TEST_CASE("recovery: unsaved text survives into the next session for the same file only") {
    rt_test::TempDir dir;
    {
        Recovery r(dir.path.string());
        CHECK(r.update("scene.txt", "thing { }", true).ok());
        // A "crash": the object goes away without discarding anything.
    }
    Recovery next(dir.path.string());
    auto text = next.find("scene.txt");
    REQUIRE(text);
    CHECK(*text == "thing { }");
    CHECK_FALSE(next.find("other.txt"));
}

TEST_CASE("recovery: each update writes the text as it is now") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("s.txt", "one", true).ok());
    CHECK(*Recovery(dir.path.string()).find("s.txt") == "one");
    CHECK(r.update("s.txt", "two", true).ok());
    CHECK(*Recovery(dir.path.string()).find("s.txt") == "two");
}

TEST_CASE("recovery: saving (no longer modified) or discarding removes the copy") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("s.txt", "draft", true).ok());
    REQUIRE(r.find("s.txt"));
    CHECK(r.update("s.txt", "draft", false).ok());
    CHECK_FALSE(r.find("s.txt"));
    CHECK(r.update("s.txt", "again", true).ok());
    REQUIRE(r.find("s.txt"));
    r.discard("s.txt");
    CHECK_FALSE(r.find("s.txt"));
    CHECK_FALSE(fs::exists(r.file_for("s.txt")));
}

TEST_CASE("recovery: a document that takes another name (Save As, Open) leaves no copy under the old one") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("old.txt", "draft", true).ok());
    REQUIRE(r.find("old.txt"));
    // Saved as new.txt: no longer modified, under its new name.
    CHECK(r.update("new.txt", "draft", false).ok());
    CHECK_FALSE(r.find("old.txt"));
    CHECK_FALSE(r.find("new.txt"));
    // Edited again and another file opened unmodified: the edit's copy goes too.
    CHECK(r.update("new.txt", "draft 2", true).ok());
    REQUIRE(r.find("new.txt"));
    CHECK(r.update("other.txt", "other", false).ok());
    CHECK_FALSE(r.find("new.txt"));
    CHECK(fs::is_empty(dir.path));
}

TEST_CASE("recovery: a failed write says why and keeps nothing half-written") {
    Recovery r("/proc/no-such-place/recovery");
    CHECK_FALSE(r.update("s.txt", "draft", true).ok());
    CHECK_FALSE(r.find("s.txt"));
}

namespace {

const char* const kScene = "thing {\n  sphere { position 5 0 1 radius 1 }  // the ball\n"
                           "  sphere { position 7 2 1 radius 0.5 }\n}\n"
                           "camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }\n"
                           "picture_size { x_max 32 y_max 24 }\nend\n";

}  // namespace

TEST_CASE("recovery: a held drag is kept as the items it changed, and read back into the text as its commit writes it") {
    rt_test::TempDir dir;
    const std::string path = (dir / "s.txt").string();
    rt_test::put(path, kScene);
    Document doc;
    REQUIRE(doc.load_file(path).ok());
    CHECK(doc.held_edit().empty());
    std::get<rt::Sphere>(doc.edit_object(1).shape).position = {7.25, 2.5, 1};
    const HeldEdit held = doc.held_edit();
    REQUIRE(held.objects == std::vector<std::size_t>{1});
    CHECK(held.items.objects.size() == 1);
    {
        // The text is as saved: the held edit's base is the document's file, and no
        // copy of the text is written.
        Recovery r((dir / "rec").string());
        REQUIRE(r.update_held(path, held, doc.saved_hash()).ok());
        CHECK_FALSE(fs::exists(r.file_for(path)));
        CHECK(fs::exists(r.held_file_for(path)));
    }
    Document committed = doc;
    committed.commit();
    const std::optional<std::string> found = Recovery((dir / "rec").string()).find(path);
    REQUIRE(found);
    CHECK(*found == committed.editor_text());
    CHECK(found->find("// the ball") != std::string::npos);  // the rest of the text as it was
}

TEST_CASE("recovery: a held edit goes only into the text it was made on") {
    rt_test::TempDir dir;
    const std::string path = (dir / "s.txt").string();
    const std::string typed = std::string(kScene) + "// typed\n";
    Document doc;
    doc.load_text(typed, path, "s.txt");
    std::get<rt::Sphere>(doc.edit_object(0).shape).radius = 1.5;
    const HeldEdit held = doc.held_edit();
    Recovery r((dir / "rec").string());
    REQUIRE(r.update(path, typed, true).ok());
    REQUIRE(r.update_held(path, held, r.written_hash()).ok());
    std::optional<std::string> found = Recovery((dir / "rec").string()).find(path);
    REQUIRE(found);
    CHECK(parse_ok(*found).objects[0] == doc.scene().objects[0]);
    CHECK(found->find("// typed") != std::string::npos);
    // The text changed (the first sphere deleted) and the held edit was not written
    // again: it is not put into a text whose object 1 is another one.
    const std::string deleted = std::string(kScene).erase(std::string(kScene).find("  sphere"), 49);
    REQUIRE(parse_ok(deleted).objects.size() == 1);
    REQUIRE(r.update(path, deleted, true).ok());
    found = Recovery((dir / "rec").string()).find(path);
    REQUIRE(found);
    CHECK(*found == deleted);
    // Nor into a text without such an item, or one that does not parse.
    HeldEdit second = held;
    second.objects = {1};
    CHECK(with_held_edit(deleted, second) == deleted);
    CHECK(with_held_edit("thing {", held) == "thing {");
    // An empty held edit removes its file; discard removes both.
    REQUIRE(r.update_held(path, held, r.written_hash()).ok());
    REQUIRE(fs::exists(r.held_file_for(path)));
    REQUIRE(r.update_held(path, HeldEdit{}, 0).ok());
    CHECK_FALSE(fs::exists(r.held_file_for(path)));
    REQUIRE(r.update_held(path, held, r.written_hash()).ok());
    r.discard(path);
    CHECK(fs::is_empty(dir / "rec"));
}

TEST_CASE("recovery: a drag in the unsaved default scene, or in a new scene, is found again") {
    for (const char* start : {rt::kDefaultScene, kNewScene}) {
        CAPTURE(start);
        rt_test::TempDir dir;
        Document doc;
        doc.load_text(start, "", "untitled.txt");
        doc.edit_camera().angle_x = 50;
        Recovery r(dir.path.string());
        REQUIRE(r.update_held("", doc.held_edit(), doc.saved_hash()).ok());
        const std::optional<std::string> found = Recovery(dir.path.string()).find("");
        REQUIRE(found);
        const rt::Scene scene = parse_ok(*found);
        CHECK(scene.camera.angle_x == 50);
        CHECK(scene.objects == parse_ok(start).objects);  // the text the drag was made in
    }
}

TEST_CASE("recovery: a live viewer's lock keeps its copy from a second viewer, until it ends") {
    rt_test::TempDir dir;
    std::optional<Recovery> a(std::in_place, dir.path.string());
    REQUIRE(a->claim("s.txt") == 0);
    REQUIRE(a->update("s.txt", "A's draft", true).ok());
    const std::string copy = a->file_for("s.txt");
    // B opens the same file: the lock is taken, and says by whom.
    Recovery b(dir.path.string());
    CHECK(b.claim("s.txt") == long(getpid()));
    CHECK(b.blocked("s.txt"));
    CHECK_FALSE(b.find("s.txt"));  // not offered as an earlier session's
    b.discard("s.txt");            // and never removed...
    CHECK(b.update("s.txt", "B's draft", true).ok());  // ...nor overwritten
    CHECK(b.update("s.txt", "B's draft", false).ok());
    REQUIRE(fs::exists(copy));
    CHECK(*Recovery(dir.path.string()).find("s.txt") == "A's draft");
    // Another file is B's own.
    CHECK(b.claim("t.txt") == 0);
    CHECK_FALSE(b.blocked("s.txt"));
    CHECK(b.claim("s.txt") == long(getpid()));
    // A ends (the lock goes with it): B takes the file, and A's text is on offer.
    a.reset();
    CHECK(b.claim("s.txt") == 0);
    CHECK_FALSE(b.blocked("s.txt"));
    REQUIRE(b.find("s.txt"));
    CHECK(*b.find("s.txt") == "A's draft");
}

TEST_CASE("recovery: the copies of ended sessions are listed with file, time and size; live ones are not") {
    rt_test::TempDir dir;
    Recovery live(dir.path.string());
    REQUIRE(live.claim("live.txt") == 0);
    REQUIRE(live.update("live.txt", "live text", true).ok());
    for (const char* doc : {"ended.txt", ""}) {  // "": the default scene, unsaved
        Recovery ended(dir.path.string());
        REQUIRE(ended.claim(doc) == 0);
        REQUIRE(ended.update(doc, *doc ? "12345" : "1234567", true).ok());
        // (Ends without discarding: a crash.)
    }
    Recovery start(dir.path.string());
    REQUIRE(start.claim("open.txt") == 0);
    REQUIRE(start.update("open.txt", "mine", true).ok());
    std::vector<Recovery::Orphan> list = start.orphans("open.txt");
    REQUIRE(list.size() == 2);
    std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return x.doc_path < y.doc_path; });
    CHECK(list[0].doc_path.empty());
    CHECK(list[0].bytes == 7);
    CHECK(list[1].doc_path == absolute_path("ended.txt"));
    CHECK(list[1].bytes == 5);
    CHECK(list[1].file == start.file_for("ended.txt"));
    CHECK(list[1].mtime > 0);
    // The document a viewer has open is not listed (its copy is offered on its own).
    CHECK(start.orphans("ended.txt").size() == 1);
    // Discarding one removes its files; one a viewer has opened since stays.
    Recovery other(dir.path.string());
    REQUIRE(other.claim("ended.txt") == 0);
    CHECK_FALSE(start.discard_orphan(list[1]));
    CHECK(fs::exists(list[1].file));
    CHECK(start.discard_orphan(list[0]));
    CHECK_FALSE(fs::exists(list[0].file));
    CHECK(start.orphans("open.txt").empty());
}

TEST_CASE("recovery: viewers showing the unsaved default scene side by side keep a copy each") {
    rt_test::TempDir dir;
    std::optional<Recovery> a(std::in_place, dir.path.string()), b(std::in_place, dir.path.string());
    REQUIRE(a->claim("") == 0);
    REQUIRE(b->claim("") == 0);  // not blocked: a slot of its own
    CHECK(a->file_for("") != b->file_for(""));
    REQUIRE(a->update("", "A's scene", true).ok());
    REQUIRE(b->update("", "B's scene", true).ok());
    CHECK(*a->find("") == "A's scene");
    CHECK(*b->find("") == "B's scene");
    // A ends: the next viewer on the default scene takes its slot and is offered its text;
    // B's copy is B's while B runs, and an orphan once it ends.
    a.reset();
    Recovery c(dir.path.string());
    REQUIRE(c.claim("") == 0);
    CHECK(*c.find("") == "A's scene");
    CHECK(c.orphans("").empty());
    b.reset();
    const std::vector<Recovery::Orphan> left = c.orphans("");
    REQUIRE(left.size() == 1);
    CHECK(left[0].doc_path.empty());
    CHECK(*c.read_orphan(left[0]) == "B's scene");
    CHECK(c.discard_orphan(left[0]));
    CHECK(c.orphans("").empty());
}
