// The document model: undoable panel edits written back into the text, applying
// drafts with errors, atomic saves, and reacting to changes made on disk.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "default_scene.h"
#include "document.h"
#include "image_io.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "viewer_test_util.h"

using namespace rtview;
using rtview_test::parse_ok;

namespace {

using rt_test::slurp;
using rt_test::TempDir;
const auto spit = rt_test::put;

// Rewriting a file within one mtime tick and at the same size would hide the change
// from a stat-based watcher; tests make each version distinguishable.
void bump_mtime(const std::string& p, int seconds) {
    struct stat st {};
    stat(p.c_str(), &st);
    std::string cmd = "touch -d @" + std::to_string(st.st_mtim.tv_sec + seconds) + " '" + p + "'";
    std::system(cmd.c_str());
}

}  // namespace

TEST_CASE("a slider drag is one undo step, written into the text when it ends") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const rt::Scene original = d.scene();
    const std::string text = d.editor_text();
    std::uint64_t v0 = d.scene_version();
    for (int k = 1; k <= 10; ++k) d.edit().objects[1].material.reflection = k * 0.07;
    CHECK(d.scene_version() > v0);      // every step restarts the render
    CHECK(d.editor_text() == text);     // the text is written once, at the end
    d.commit();
    CHECK(parse_ok(d.editor_text()) == d.scene());
    CHECK(d.scene().objects[1].material.reflection == doctest::Approx(0.7));
    CHECK(d.modified());
    CHECK(d.title() == "default.txt* - raytracer-view");
    REQUIRE(d.undo());
    CHECK(d.scene() == original);
    CHECK(d.editor_text() == text);
    CHECK_FALSE(d.modified());
    CHECK(d.title() == "default.txt - raytracer-view");
    REQUIRE(d.redo());
    CHECK(d.scene().objects[1].material.reflection == doctest::Approx(0.7));
    CHECK_FALSE(d.redo());
}

TEST_CASE("applying text with errors keeps the scene and never touches the text") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const rt::Scene good = d.scene();
    std::uint64_t sv = d.scene_version(), tv = d.text_version();
    d.typing_text().insert(0, "oops ");
    std::string typed = d.editor_text();
    CHECK_FALSE(d.apply_text());
    REQUIRE(d.has_errors());
    CHECK(d.diagnostics().front().line == 1);
    CHECK(d.diagnostics().front().col == 1);
    CHECK(d.editor_text() == typed);
    CHECK(d.scene() == good);
    CHECK(d.scene_version() == sv);
    CHECK(d.text_version() == tv);
    CHECK(d.editor_dirty());
}

TEST_CASE("a live check parsed off the UI thread is taken only for the text it checked") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    d.typing_text().insert(0, "oops ");
    d.note_typed();
    Document::TextCheck c = d.text_check();
    CHECK(c.text == d.editor_text());
    // Typed on while it parsed: the check is for an older text, and is not taken.
    d.typing_text().insert(0, "x");
    d.note_typed();
    CHECK_FALSE(d.take_check(c.key, rt::parse_scene(c.text, c.options).diagnostics));
    CHECK_FALSE(d.has_errors());
    // The check of the text as it is: its errors are the document's.
    c = d.text_check();
    CHECK(d.take_check(c.key, rt::parse_scene(c.text, c.options).diagnostics));
    REQUIRE(d.has_errors());
    CHECK(d.diagnostics().front().line == 1);
    CHECK(d.diagnostics().front().col == 1);
}

TEST_CASE("a good apply is undoable, and undo brings the draft back unapplied") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const rt::Scene before = d.scene();
    std::string& t = d.typing_text();
    t.replace(t.find("radius 1.3"), 10, "radius 2.5");
    std::string draft = t;
    REQUIRE(d.apply_text());
    CHECK(std::get<rt::Sphere>(d.scene().objects[1].shape).radius == 2.5);
    CHECK_FALSE(d.editor_dirty());
    REQUIRE(d.undo());
    CHECK(d.scene() == before);
    CHECK(d.editor_text() == draft);  // the typed text is not lost
    CHECK(d.editor_dirty());
}

TEST_CASE("an apply parsed off the UI thread is applied only to the text it parsed") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const rt::Scene before = d.scene();
    const std::uint64_t key0 = d.text_key();
    CHECK(std::as_const(d).editor_text() == d.editor_text());
    CHECK(d.text_key() == key0);  // reading the text is not typing into it
    std::string& t = d.typing_text();
    t.replace(t.find("radius 1.3"), 10, "radius 2.5");
    d.note_typed();
    Document::TextCheck c = d.begin_apply();
    CHECK(c.text == d.editor_text());
    // Typed on while it parsed: the parse is of an older text and changes nothing.
    d.typing_text().replace(t.find("radius 2.5"), 10, "radius 3.5");
    d.note_typed();
    CHECK_FALSE(d.finish_apply(c.key, rt::parse_scene(c.text, c.options)).has_value());
    CHECK(d.scene() == before);
    CHECK(d.editor_dirty());
    // The parse of the text as it is: applied as apply_text() applies it, one undo step.
    const std::size_t depth = d.undo_depth();
    c = d.begin_apply();
    std::optional<bool> ok = d.finish_apply(c.key, rt::parse_scene(c.text, c.options));
    REQUIRE(ok.has_value());
    CHECK(*ok);
    CHECK(std::get<rt::Sphere>(d.scene().objects[1].shape).radius == 3.5);
    CHECK_FALSE(d.editor_dirty());
    CHECK(d.undo_depth() > depth);
    // A text with errors: false, the scene kept, the errors listed.
    d.typing_text().insert(0, "oops ");
    d.note_typed();
    const rt::Scene good = d.scene();
    c = d.begin_apply();
    ok = d.finish_apply(c.key, rt::parse_scene(c.text, c.options));
    REQUIRE(ok.has_value());
    CHECK_FALSE(*ok);
    CHECK(d.has_errors());
    CHECK(d.scene() == good);
}

TEST_CASE("a big draft is not parsed to know whether panel edits may go into it: a check says") {
    Document d;
    // A text over the size parsed on the UI thread (a long comment at the end).
    std::string big = std::string(rt::kDefaultScene) + "// " + std::string(Document::kSyncParseBytes, 'x') + "\n";
    d.load_text(big, "", "big.txt");
    REQUIRE(d.has_scene());
    CHECK(d.edit_blocker().empty());  // no draft
    CHECK_FALSE(d.blocker_pending());
    d.typing_text().insert(0, "// a comment\n");
    d.note_typed();
    // Not known yet: edits wait, and a check is wanted.
    CHECK_FALSE(d.edit_blocker().empty());
    CHECK(d.blocker_pending());
    Document::TextCheck c = d.text_check();
    REQUIRE(d.take_check(c.key, rt::parse_scene(c.text, c.options).diagnostics));
    CHECK(d.edit_blocker().empty());  // it parses
    CHECK_FALSE(d.blocker_pending());
    // A draft with an error: blocked once its check says so.
    d.typing_text().insert(0, "oops ");
    d.note_typed();
    CHECK(d.blocker_pending() == false);  // (asked for only through edit_blocker())
    const std::string waiting = d.edit_blocker();
    CHECK(d.blocker_pending());
    c = d.text_check();
    REQUIRE(d.take_check(c.key, rt::parse_scene(c.text, c.options).diagnostics));
    CHECK_FALSE(d.blocker_pending());
    CHECK(d.edit_blocker().find("errors") != std::string::npos);
    CHECK(d.edit_blocker() != waiting);
}

TEST_CASE("a panel edit is carried into a draft that parses") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    std::string& t = d.typing_text();
    t.insert(0, "// my note\n");  // a draft change (still the same scene)
    d.edit().camera.angle_y = 50;
    d.commit();
    CHECK(d.editor_text().rfind("// my note\n", 0) == 0);
    CHECK(parse_ok(d.editor_text()).camera.angle_y == 50);
    CHECK_FALSE(d.text_behind());
}

TEST_CASE("a panel edit that cannot be written into a broken draft is not made: text and scene never disagree") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const rt::Scene scene = d.scene();
    d.typing_text().insert(0, "{ broken\n");  // (after `end` it would be ignored)
    const std::string draft = d.editor_text();
    CHECK_FALSE(d.edit_blocker().empty());  // the panels say so before an edit
    d.edit().lights[0].colour = {1, 2, 3};
    d.commit();
    CHECK(d.editor_text() == draft);  // the user's text untouched
    CHECK(d.scene() == scene);        // and the scene as it was
    CHECK_FALSE(d.text_behind());
    CHECK_FALSE(d.take_refusal().empty());
    CHECK(d.take_refusal().empty());  // said once
    // Saving that text asks first; the answer names the error.
    const std::optional<std::string> problem = d.save_problem();
    REQUIRE(problem);
    CHECK(problem->rfind(d.name() + ":1:", 0) == 0);
    CHECK_FALSE(d.apply_parsing_draft());
    d.revert_text();  // drop the draft: edits are possible again
    CHECK(d.edit_blocker().empty());
    CHECK_FALSE(d.save_problem());
    d.edit().lights[0].colour = {1, 2, 3};
    d.commit();
    CHECK(parse_ok(d.editor_text()) == d.scene());
    CHECK(d.scene().lights[0].colour == rt::Vec3{1, 2, 3});
}

TEST_CASE("saving applies a draft that parses first, so the file is the scene shown") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    std::string& t = d.typing_text();
    t.replace(t.find("radius 1\n"), 9, "radius 0.75\n");
    CHECK_FALSE(d.save_problem());
    CHECK(d.apply_parsing_draft());
    CHECK_FALSE(d.editor_dirty());
    CHECK(parse_ok(d.editor_text()) == d.scene());
    CHECK_FALSE(d.apply_parsing_draft());  // nothing left to apply
}

TEST_CASE("a file that does not parse opens with its text and errors, and no scene") {
    Document d;
    d.load_text("thing { sphere { radius x } }", "", "bad.txt");
    CHECK_FALSE(d.has_scene());
    CHECK(d.has_errors());
    CHECK_FALSE(d.modified());
    CHECK(d.editor_text() == "thing { sphere { radius x } }");
    // The file as it is: no changes of the user's until they type.
    CHECK_FALSE(d.unapplied());
    d.typing_text() += " ";
    d.note_typed();
    CHECK(d.unapplied());
    CHECK(d.modified());
}

TEST_CASE("revert without a scene goes back to the file's text, never to an empty one") {
    TempDir dir;
    const std::string p = (dir / "s.txt").string();
    spit(p, "thing {\nend\n");
    Document d;
    REQUIRE(d.load_file(p).ok());
    REQUIRE_FALSE(d.has_scene());
    // A broken file: Revert brings back its text.
    d.typing_text() += "// typed\n";
    d.note_typed();
    d.revert_text();
    CHECK(d.editor_text() == "thing {\nend\n");
    // Fixed, applied and saved; then the apply is undone: no scene again, and the file
    // as saved (it parses) is not kept. Revert leaves the text as it is.
    d.typing_text() = rt::kDefaultScene;
    d.note_typed();
    REQUIRE(d.apply_text());
    REQUIRE(d.save().ok());
    REQUIRE(d.undo());
    REQUIRE_FALSE(d.has_scene());
    const std::string text = d.editor_text();
    d.revert_text();
    CHECK(d.editor_text() == text);
    CHECK(text == rt::kDefaultScene);
}

TEST_CASE("save writes the editor text atomically and clears the modified mark") {
    TempDir dir;
    std::string p = (dir / "scene.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    CHECK(d.name() == "scene.txt");
    d.edit().camera.position = {-2, 0, 3};
    d.commit();
    REQUIRE(d.modified());
    REQUIRE(d.save().ok());
    CHECK_FALSE(d.modified());
    CHECK(slurp(p) == d.editor_text());
    CHECK(dir.files() == std::vector<std::string>{"scene.txt"});  // no temporary left
    CHECK(parse_ok(slurp(p)).camera.position == rt::Vec3{-2, 0, 3});  // the file has the camera
    // A draft with errors is saved as typed: the user's text is what gets saved.
    d.typing_text() += "\nnot valid {";
    REQUIRE(d.save().ok());
    CHECK(slurp(p) == d.editor_text());
}

TEST_CASE("a failed save reports why and leaves the document modified") {
    TempDir dir;
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    CHECK_FALSE(d.save().ok());  // no file name yet
    d.edit().camera.angle_y = 40;
    d.commit();
    CHECK_FALSE(d.save_as((dir / "missing/dir/x.txt").string()).ok());
    CHECK(d.modified());
    CHECK(d.path().empty());
    REQUIRE(d.save_as((dir / "x.txt").string()).ok());
    CHECK(d.name() == "x.txt");
    CHECK_FALSE(d.modified());
}

TEST_CASE("an outside change reloads by itself when there are no unsaved edits") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    CHECK(d.check_disk() == Document::DiskEvent::None);
    std::string other = rt::kDefaultScene;
    other.replace(other.find("radius 1.3"), 10, "radius 0.7");
    spit(p, other);
    bump_mtime(p, 5);
    CHECK(d.check_disk() == Document::DiskEvent::Reloaded);
    CHECK(std::get<rt::Sphere>(d.scene().objects[1].shape).radius == 0.7);
    CHECK(d.editor_text() == other);
    CHECK_FALSE(d.modified());
    CHECK(d.check_disk() == Document::DiskEvent::None);
}

TEST_CASE("a file that becomes no scene text on disk is not read in: the scene and its text stay") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    const rt::Scene scene = d.scene();
    spit(p, std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10));
    bump_mtime(p, 5);
    CHECK(d.check_disk() == Document::DiskEvent::NotText);
    CHECK(d.disk_problem() == "not a scene text: a NUL byte at byte 8 (a binary file?)");
    CHECK(d.editor_text() == rt::kDefaultScene);
    CHECK(d.scene() == scene);
    CHECK_FALSE(d.can_undo());
    CHECK(d.check_disk() == Document::DiskEvent::None);  // said once
}

TEST_CASE("a camera edit is a real edit: an outside change is then a conflict") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    rt::Camera moved = d.scene().camera;
    moved.position = {-4, 1, 3};
    REQUIRE(d.set_camera(moved));
    std::string other = rt::kDefaultScene;
    other.replace(other.find("radius 1.3"), 10, "radius 0.7");
    spit(p, other);
    bump_mtime(p, 5);
    CHECK(d.check_disk() == Document::DiskEvent::Conflict);
    CHECK(d.scene().camera == moved);
}

TEST_CASE("an outside change with unsaved edits is a conflict; reloading is undoable") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    d.edit().objects[0].material.colour = {1, 0, 0};
    d.commit();
    std::string mine = d.editor_text();
    std::string other = std::string(rt::kDefaultScene) + "\n// edited elsewhere\n";
    spit(p, other);
    bump_mtime(p, 5);
    CHECK(d.check_disk() == Document::DiskEvent::Conflict);
    CHECK(d.disk_conflict());
    CHECK(d.editor_text() == mine);  // nothing replaced behind the user's back
    d.resolve_conflict_reload();
    CHECK_FALSE(d.disk_conflict());
    CHECK(d.editor_text() == other);
    CHECK_FALSE(d.modified());
    REQUIRE(d.undo());
    CHECK(d.editor_text() == mine);
}

TEST_CASE("our own saves are not taken for outside changes") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    d.edit().camera.angle_y = 33;
    d.commit();
    REQUIRE(d.save().ok());
    CHECK(d.check_disk() == Document::DiskEvent::None);
    CHECK_FALSE(d.disk_conflict());
}

TEST_CASE("a scene that becomes broken on disk shows its errors but keeps rendering the last good one") {
    TempDir dir;
    std::string p = (dir / "s.txt").string();
    spit(p, rt::kDefaultScene);
    Document d;
    REQUIRE(d.load_file(p).ok());
    rt::Scene good = d.scene();
    spit(p, "thing { sphere { radius } }\n");
    bump_mtime(p, 5);
    CHECK(d.check_disk() == Document::DiskEvent::Reloaded);
    CHECK(d.has_scene());
    CHECK(d.scene() == good);
    CHECK(d.has_errors());
    CHECK(d.editor_text() == "thing { sphere { radius } }\n");
}

namespace {

// A scene text of about `bytes` bytes: a grid of spheres, a plane and two lights.
std::string big_scene_text(std::size_t bytes) {
    rt::Scene s = parse_ok(rt::kDefaultScene);
    rt::Object proto = s.objects[0];
    s.objects.clear();
    for (int k = 0; rt::write_scene(s).size() < bytes; k += 64) {
        for (int j = 0; j < 64; ++j) {
            rt::Object o = proto;
            o.shape = rt::Sphere{{double(k + j) * 0.01, 0.5 * (j % 7), 1}, 0.25};
            s.objects.push_back(o);
        }
    }
    return rt::write_scene(s);
}

}  // namespace

TEST_CASE("a panel edit rewrites only its own block, and its undo step is small") {
    Document d;
    std::string text = big_scene_text(200000);
    d.load_text(text, "", "big.txt");
    REQUIRE(d.has_scene());
    std::size_t n = d.scene().objects.size();
    d.edit_object(n / 2).material.reflection = 0.25;
    d.commit();
    const std::string& after = d.editor_text();
    CHECK(parse_ok(after) == d.scene());
    // Everything before and after the object's block is as it was.
    std::size_t p = 0;
    while (p < text.size() && text[p] == after[p]) ++p;
    std::size_t s = 0;
    while (s < text.size() - p && text[text.size() - 1 - s] == after[after.size() - 1 - s]) ++s;
    CHECK(text.size() - p - s < 400);
    CHECK(d.undo_bytes() < 4000);
    REQUIRE(d.undo());
    CHECK(d.editor_text() == text);
}

TEST_CASE("the undo byte budget holds over 1,000 edits of a 1 MB document") {
    Document d;
    const std::string text = big_scene_text(1 << 20);
    REQUIRE(text.size() >= (1u << 20));
    d.load_text(text, "", "big.txt");
    REQUIRE(d.has_scene());
    const std::size_t budget = 256 << 10;
    d.set_undo_budget(budget);
    std::size_t n = d.scene().objects.size();
    std::vector<double> reflection_after;  // object 7's reflection after each edit
    for (int k = 0; k < 1000; ++k) {
        switch (k % 4) {
            case 0: d.edit_object(7).material.reflection = 0.001 * k; break;
            case 1: d.edit_object((std::size_t(k) * 37) % n).material.colour = {0.1, 0.001 * k, 0.3}; break;
            case 2: d.edit_light(0).position.z = 5 + 0.01 * k; break;
            default: d.edit_camera().angle_y = 30 + 0.01 * k; break;
        }
        d.commit();
        reflection_after.push_back(d.scene().objects[7].material.reflection);
        CHECK(d.undo_bytes() <= budget);
    }
    CHECK(parse_ok(d.editor_text()) == d.scene());
    std::size_t depth = d.undo_depth();
    CHECK(depth > 50);     // the budget holds many steps of this size...
    CHECK(depth < 1000);   // ...but not all of them: the oldest went
    // Every step still held undoes exactly.
    for (std::size_t k = 0; k < depth; ++k) {
        REQUIRE(d.undo());
        CHECK(d.scene().objects[7].material.reflection == reflection_after[1000 - 2 - k]);
    }
    CHECK_FALSE(d.undo());
    CHECK(parse_ok(d.editor_text()) == d.scene());
    // With the default budget (64 MB) all steps of such edits fit.
    Document e;
    e.load_text(text, "", "big.txt");
    for (int k = 0; k < 300; ++k) {
        e.edit_light(1).colour = {1, 1, 0.001 * k};
        e.commit();
    }
    CHECK(e.undo_depth() == 300);
    CHECK(e.undo_bytes() < 300 * 4096);  // a step is its block, not a copy of the text
    CHECK(parse_ok(e.editor_text()) == e.scene());
}

namespace {

// The reference keeps a full copy of the document after every step; the document
// keeps only what each step changed. Random panel edits, typing, applies,
// reverts, undos and redos must agree with the copies at every point.
void check_against_full_copies(std::uint32_t seed) {
    struct Snap {
        std::string editor, applied;
        rt::Scene scene;
        bool behind, dirty;
        bool operator==(const Snap& o) const {
            return editor == o.editor && applied == o.applied && scene == o.scene && behind == o.behind &&
                   dirty == o.dirty;
        }
    };
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    auto snap = [&] {
        return Snap{std::as_const(d).editor_text(), d.applied_text(), d.scene(), d.text_behind(), d.editor_dirty()};
    };
    std::vector<Snap> states{snap()};  // states[k]: after k steps
    std::size_t at = 0;                // where the document is in `states`
    std::uint32_t rng = seed;
    auto next = [&](std::uint32_t n) {
        rng = rng * 1664525u + 1013904223u;
        return (rng >> 8) % n;
    };
    // Typing is not a step until something else happens: then it becomes one, first.
    std::size_t depth = 0;
    auto before_op = [&] {
        depth = d.undo_depth();
        Snap now = snap();
        if (now.editor != states[at].editor) {
            states.resize(at + 1);
            states.push_back(now);
            ++at;
            ++depth;
        }
    };
    auto stepped = [&] {
        if (d.undo_depth() == depth) {
            states[at] = snap();  // no new step (for example an apply of the same scene)
            return;
        }
        REQUIRE(d.undo_depth() == depth + 1);
        states.resize(at + 1);
        states.push_back(snap());
        ++at;
    };
    for (int k = 0; k < 300; ++k) {
        double r = 0.01 * double(next(100));
        int op = int(next(9));
        if (op != 3) before_op();
        switch (op) {
            case 0: d.edit_object(next(6)).material.reflection = r; d.commit(); stepped(); break;
            case 1: d.edit_light(next(2)).colour = {r, 1, 2}; d.commit(); stepped(); break;
            case 2: d.edit_camera().angle_y = 30 + r; d.commit(); stepped(); break;
            case 3: {
                // Typing: a comment at the start (the text keeps parsing) or a stray word.
                std::string& t = d.typing_text();
                t.insert(0, next(4) == 0 ? "stray " : "// typed " + std::to_string(k) + "\n");
                break;
            }
            case 4: d.apply_text(); stepped(); break;
            case 5: d.revert_text(); stepped(); break;
            case 6:
            case 7:
                if (d.undo()) {
                    REQUIRE(at > 0);
                    --at;
                } else {
                    CHECK(at == 0);
                }
                break;
            default:
                if (d.redo()) ++at;
                break;
        }
        REQUIRE(at < states.size());
        if (op != 3) {
            CHECK(snap() == states[at]);
            CHECK(d.undo_depth() == at);
        }
    }
    before_op();
    // All the way back, and forward again.
    while (d.undo()) {
        --at;
        CHECK(snap() == states[at]);
    }
    CHECK(at == 0);
    while (d.redo()) {
        ++at;
        CHECK(snap() == states[at]);
    }
}

}  // namespace

TEST_CASE("undo and redo of edit steps give back exactly the states a full-copy history would") {
    for (std::uint32_t seed : {12345u, 1u, 2u, 77u, 4242u}) {
        CAPTURE(seed);
        check_against_full_copies(seed);
    }
}

TEST_CASE("every undo step has a name: the edit's own, or what it changed; undo and redo say which they took") {
    using Names = std::vector<std::string>;
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const Document& cd = d;
    CHECK(cd.undo_names(5).empty());
    d.name_edit("not an edit");  // nothing pending: no name is kept for later
    // A named panel edit: its first name stays; while it is pending it is the next undo.
    std::get<rt::Sphere>(d.edit_object(1).shape).position.y += 0.5;
    d.name_edit("Move sphere 2");
    d.name_edit("Move it again");
    CHECK(cd.undo_names(5) == Names{"Move sphere 2"});
    d.commit();
    // Unnamed edits are named by what they changed.
    d.edit_light(0).colour = {1, 2, 3};
    d.commit();
    rt::Camera cam = cd.scene().camera;
    cam.position.x -= 1;
    d.edit_camera() = cam;
    d.commit();
    std::get<rt::Sphere>(d.edit().objects[0].shape).radius = 0.5;
    std::get<rt::Sphere>(d.edit().objects[1].shape).radius = 0.5;
    d.commit();
    CHECK(cd.undo_names(9) == Names{"Edit the scene", "Edit the scene camera", "Edit light 1", "Move sphere 2"});
    CHECK(cd.undo_names(2) == Names{"Edit the scene", "Edit the scene camera"});
    // Typing is a step of its own once something else happens; so is applying it.
    d.typing_text() += "// a comment\n";
    d.note_typed();
    CHECK(cd.undo_names(1) == Names{"Typing in the scene text"});
    REQUIRE(d.apply_text());
    CHECK(cd.undo_names(3) == Names{"Apply the scene text", "Typing in the scene text", "Edit the scene"});
    // A structural edit carries the caller's name.
    const std::string& text = cd.editor_text();
    REQUIRE(d.replace_text(text.find("end\n"), 0, "light { lamp { position 1 1 9 } }\n", "Add a lamp"));
    CHECK(cd.undo_names(1) == Names{"Add a lamp"});
    // Undo and redo say which step they took, and the lists follow.
    REQUIRE(d.undo());
    CHECK(d.last_step_name() == "Add a lamp");
    REQUIRE(d.undo());
    CHECK(d.last_step_name() == "Apply the scene text");
    CHECK(cd.redo_names(5) == Names{"Apply the scene text", "Add a lamp"});
    CHECK(cd.undo_names(1) == Names{"Typing in the scene text"});
    REQUIRE(d.redo());
    CHECK(d.last_step_name() == "Apply the scene text");
    CHECK(cd.redo_names(5) == Names{"Add a lamp"});
    // A new edit ends the redo branch; a pending one already hides it.
    d.edit_light(0).colour = {4, 5, 6};
    CHECK(cd.redo_names(5).empty());
    CHECK(cd.undo_names(1) == Names{"Edit light 1"});
    d.cancel_edit();
    CHECK(cd.redo_names(5) == Names{"Add a lamp"});
    // A new document has no history.
    d.load_text(rt::kDefaultScene, "", "default.txt");
    CHECK(cd.undo_names(5).empty());
    CHECK(cd.redo_names(5).empty());
}

// Found by the edit fuzzer: a structural edit planned while a drag held an edit landed
// on the wrong bytes once replace_text committed the drag (rewriting the dragged block).
TEST_CASE("a structural edit is refused while an edit is held, and changes nothing") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const std::string text = d.editor_text();
    std::get<rt::Sphere>(d.edit_object(0).shape).position.x += 0.123456;
    const rt::Scene dragged = d.scene();
    // Delete object 1: one replacement planned on the text as it is now.
    const std::size_t at = text.find("  sphere {"), end = text.find("  sphere {", at + 1);
    CHECK_FALSE(d.replace_text(at, end - at, ""));
    CHECK(d.edit_held());
    CHECK(d.editor_text() == text);
    CHECK(d.scene() == dragged);
    d.commit();
    CHECK(parse_ok(d.editor_text()) == d.scene());
}

// Found by the edit fuzzer: a drag far out (or a move whose rounding merges a tiny
// tetrahedron's corners) wrote a text that does not parse.
TEST_CASE("an edit the text cannot hold is undone at the commit, with a message") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const std::string text = d.editor_text();
    const rt::Scene scene = d.scene();
    std::get<rt::Sphere>(d.edit_object(0).shape).position.x = 1e16;
    d.commit();
    CHECK(d.editor_text() == text);
    CHECK(d.scene() == scene);
    CHECK_FALSE(d.can_undo());
    CHECK(d.take_refusal().find("1e15") != std::string::npos);
    d.edit_camera().position.z = -2e15;
    d.commit();
    CHECK(d.editor_text() == text);
    CHECK(d.scene() == scene);
    CHECK_FALSE(d.take_refusal().empty());

    d.load_text("thing { tetrahedron { vect1 1000000 0 0 vect2 1000000.0000001 0 0 vect3 1000000 0.0000001 0 "
                "vect4 1000000 0 0.0000001 } }\n"
                "camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }\n"
                "picture_size { x_max 32 y_max 24 }\nend\n",
                "", "tiny.txt");
    const std::string tiny = d.editor_text();
    translate(d.edit_object(0), {1, 0, 0});  // rounded to 12 digits: the corners merge
    d.commit();
    CHECK(d.editor_text() == tiny);
    CHECK_FALSE(d.take_refusal().empty());
    CHECK(parse_ok(d.editor_text()) == d.scene());
}

// Found by the edit fuzzer: 0 and -0 are equal, so an edit that left -0 where the text
// said 0 wrote nothing for it, and the scene no longer was the text's, bit for bit.
TEST_CASE("a zero's sign follows the text: the scene holds exactly what its text reads") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    // The chess plane's point 1 is 0 0 0.
    d.edit_plane(0).point[0].y = -0.0;  // alone: no change at all
    d.commit();
    CHECK_FALSE(d.can_undo());
    CHECK_FALSE(std::signbit(d.scene().planes[0].point[0].y));
    // Beside a real change: written as it is.
    rt::Plane& p = d.edit_plane(0);
    p.point[0].x = 0.5;
    p.point[0].y = -0.0;
    d.commit();
    const rt::Scene read = parse_ok(d.editor_text());
    CHECK(read.planes[0].point[0].x == 0.5);
    CHECK(std::signbit(read.planes[0].point[0].y));
    CHECK(std::signbit(d.scene().planes[0].point[0].y));
}

namespace {

// The document's source positions are those a parse of its text gives: every item's
// (a CSG's operands too), the definitions', the camera's and the diagnostics'.
void check_positions_are_texts(const Document& doc) {
    const rt::ParseResult r = rt::parse_scene(doc.editor_text());
    REQUIRE(r.ok());
    const rt::Scene& s = doc.scene();
    REQUIRE(s.objects.size() == r.scene.objects.size());
    auto same = [](const rt::SourceLoc& a, const rt::SourceLoc& b) { return a.line == b.line && a.col == b.col; };
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
        INFO("object " << i << " at " << s.objects[i].loc.line << ":" << s.objects[i].loc.col << ", the text's "
                       << r.scene.objects[i].loc.line << ":" << r.scene.objects[i].loc.col);
        CHECK(same(s.objects[i].loc, r.scene.objects[i].loc));
    }
    for (std::size_t i = 0; i < s.lights.size(); ++i) CHECK(same(s.lights[i].loc, r.scene.lights[i].loc));
    for (std::size_t i = 0; i < s.planes.size(); ++i) CHECK(same(s.planes[i].loc, r.scene.planes[i].loc));
    for (std::size_t i = 0; i < s.materials.size(); ++i) CHECK(same(s.materials[i].loc, r.scene.materials[i].loc));
    CHECK(same(s.camera_loc, r.scene.camera_loc));
    REQUIRE(doc.diagnostics().size() == r.diagnostics.size());
    for (std::size_t i = 0; i < r.diagnostics.size(); ++i) {
        CHECK(doc.diagnostics()[i].line == r.diagnostics[i].line);
        CHECK(doc.diagnostics()[i].col == r.diagnostics[i].col);
    }
}

}  // namespace

TEST_CASE("a panel edit that adds a line moves the positions of everything after it, and undo moves them back") {
    const std::string text =
        "define { material gold { reflection 0.5 colour 1 0.8 0.2 } }\n"
        "thing {\n"
        "  sphere { position 1 0 0 radius 0.5\n"
        "  }\n"
        "  sphere { position 3 0 0 radius 0.5 } sphere { position 5 0 0 radius 0.5 material gold }\n"
        "}\n"
        "special_thing { plane { point 1 0 0 -1 point 2 1 0 -1 point 3 0 1 -1 } }\n"
        "light { lamp { position 0 0 9 colour 2 2 2 } }\n"
        "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
        "picture_size { x_max 8 y_max 8 }\nend\nnot read\n";
    Document doc;
    doc.load_text(text, "", "lines");
    REQUIRE(doc.has_scene());
    REQUIRE(doc.diagnostics().size() == 1);  // the warning for the text after `end`
    check_positions_are_texts(doc);
    // A key the first sphere did not give goes on a line of its own before its brace.
    doc.edit_object(0).transform.edit().scale = {2, 2, 2};
    doc.commit();
    REQUIRE(doc.take_refusal() == "");
    INFO(doc.editor_text());
    REQUIRE(doc.editor_text().find("    scale 2 2 2\n  }") != std::string::npos);
    CHECK(doc.scene().objects[1].loc.line == 6);
    check_positions_are_texts(doc);
    // A change within a line moves the columns after it on that line.
    doc.edit_object(1).transform.edit().translate = {0, 0, 12.5};
    doc.commit();
    CHECK(doc.scene().objects[2].loc.line == 6);
    check_positions_are_texts(doc);
    REQUIRE(doc.undo());
    check_positions_are_texts(doc);
    REQUIRE(doc.undo());
    CHECK(doc.editor_text() == text);
    CHECK(doc.scene().objects[1].loc.line == 5);
    check_positions_are_texts(doc);
    REQUIRE(doc.redo());
    check_positions_are_texts(doc);
    REQUIRE(doc.redo());
    check_positions_are_texts(doc);
}
