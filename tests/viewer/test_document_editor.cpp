// The document editor's crash-recovery copy as the viewer keeps it, tick by tick: a
// drag writes only the items it changed, never a copy of the text; the text is copied
// once the drag ends; a save leaves no copy. (No window: ticks are called by hand.)
#include <doctest/doctest.h>
#include <stdlib.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "editor.h"
#include "recovery.h"
#include "test_util.h"

using namespace rtview;
namespace fs = std::filesystem;

namespace {

const char* const kScene = "thing {\n  sphere { position 5 0 1 radius 1 }  // the ball\n"
                           "  sphere { position 7 2 1 radius 0.5 }\n}\n"
                           "camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }\n"
                           "picture_size { x_max 32 y_max 24 }\nend\n";

// Ticks `ed` (as the viewer does each second) until `done` holds, polling up to a
// minute: the writes run on another thread, and a tick while one is under way skips.
template <class F>
bool eventually(DocumentEditor& ed, F done) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (;;) {
        ed.idle_tick();
        if (done()) return true;
        if (std::chrono::steady_clock::now() > end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

double found_x(const Recovery& r, const std::string& path) {
    const std::optional<std::string> t = r.find(path);
    if (!t) return -1;
    const rt::ParseResult p = rt::parse_scene(*t);
    return p.ok() ? std::get<rt::Sphere>(p.scene.objects[1].shape).position.x : -1;
}

}  // namespace

TEST_CASE("recovery in the viewer: a drag is kept every tick as its items, the text only once it ends") {
    rt_test::TempDir dir;
    ::setenv("XDG_STATE_HOME", (dir / "state").c_str(), 1);
    const std::string path = (dir / "s.txt").string();
    rt_test::put(path, kScene);
    StatusLine status;
    Recovery disk((dir / "state/raytracer-view/recovery").string());
    {
        DocumentEditor ed(true, status);
        REQUIRE(ed.doc().load_file(path).ok());
        ed.replaced();
        for (int tick = 1; tick <= 3; ++tick) {
            CAPTURE(tick);
            const double x = 7 + 0.25 * tick;
            std::get<rt::Sphere>(ed.doc().edit_object(1).shape).position.x = x;
            CHECK(eventually(ed, [&] { return found_x(disk, path) == x; }));
            CHECK_FALSE(fs::exists(disk.file_for(path)));  // no copy of the text
        }
        // Released: the text has the move; the next tick copies it, the held file goes.
        ed.doc().commit();
        CHECK(eventually(ed, [&] { return fs::exists(disk.file_for(path)) && !fs::exists(disk.held_file_for(path)); }));
        CHECK(disk.find(path) == ed.doc().editor_text());
        // Typed on: each tick writes what changed since the last.
        ed.doc().typing_text() += "// more\n";
        ed.doc().note_typed();
        CHECK(eventually(ed, [&] { return disk.find(path) == ed.doc().editor_text(); }));
        // Saved: no copy is left (one older than the file would be offered after a crash).
        REQUIRE(ed.doc().save().ok());
        ed.saved();
        CHECK_FALSE(fs::exists(disk.file_for(path)));
        CHECK_FALSE(fs::exists(disk.held_file_for(path)));
        // A drag after the save, and the viewer is killed: its items are found again.
        std::get<rt::Sphere>(ed.doc().edit_object(0).shape).radius = 2;
        CHECK(eventually(ed, [&] { return fs::exists(disk.held_file_for(path)); }));
    }
    const std::optional<std::string> found = disk.find(path);
    REQUIRE(found);
    CHECK(std::get<rt::Sphere>(rt::parse_scene(*found).scene.objects[0].shape).radius == 2);
    {
        // The next start offers it: found off the UI thread, shown by a later tick.
        DocumentEditor ed(true, status);
        REQUIRE(ed.doc().load_file(path).ok());
        ed.replaced();
        CHECK(eventually(ed, [&] { return ed.recovery_offered(); }));
        CHECK(ed.recovered_text() == *found);
        CHECK(fs::exists(disk.held_file_for(path)));  // kept while on offer
    }
    ::unsetenv("XDG_STATE_HOME");
}
