// Crash recovery of unsaved editor text: written while modified, found by the next
// session for the same file only, and gone once the text is saved or discarded.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "recovery.h"
#include "test_util.h"

using namespace rtview;
namespace fs = std::filesystem;


TEST_CASE("recovery: unsaved text survives into the next session for the same file only") {
    rt_test::TempDir dir;
    {
        Recovery r(dir.path.string());
        CHECK(r.update("scene.txt", "thing { }", true, 10.0).ok());
        // A "crash": the object goes away without discarding anything.
    }
    Recovery next(dir.path.string());
    auto text = next.find("scene.txt");
    REQUIRE(text);
    CHECK(*text == "thing { }");
    CHECK_FALSE(next.find("other.txt"));
}

TEST_CASE("recovery: writes at most every interval, and only changed text") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("s.txt", "one", true, 0.0, 3.0).ok());
    CHECK(r.update("s.txt", "two", true, 1.0, 3.0).ok());  // too soon
    CHECK(*Recovery(dir.path.string()).find("s.txt") == "one");
    CHECK(r.update("s.txt", "two", true, 4.0, 3.0).ok());
    CHECK(*Recovery(dir.path.string()).find("s.txt") == "two");
}

TEST_CASE("recovery: saving (no longer modified) or discarding removes the copy") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("s.txt", "draft", true, 0.0).ok());
    REQUIRE(r.find("s.txt"));
    CHECK(r.update("s.txt", "draft", false, 10.0).ok());
    CHECK_FALSE(r.find("s.txt"));
    CHECK(r.update("s.txt", "again", true, 20.0).ok());
    REQUIRE(r.find("s.txt"));
    r.discard("s.txt");
    CHECK_FALSE(r.find("s.txt"));
    CHECK_FALSE(fs::exists(r.file_for("s.txt")));
}

TEST_CASE("recovery: a document that takes another name (Save As, Open) leaves no copy under the old one") {
    rt_test::TempDir dir;
    Recovery r(dir.path.string());
    CHECK(r.update("old.txt", "draft", true, 0.0).ok());
    REQUIRE(r.find("old.txt"));
    // Saved as new.txt: no longer modified, under its new name.
    CHECK(r.update("new.txt", "draft", false, 10.0).ok());
    CHECK_FALSE(r.find("old.txt"));
    CHECK_FALSE(r.find("new.txt"));
    // Edited again and another file opened unmodified: the edit's copy goes too.
    CHECK(r.update("new.txt", "draft 2", true, 20.0).ok());
    REQUIRE(r.find("new.txt"));
    CHECK(r.update("other.txt", "other", false, 30.0).ok());
    CHECK_FALSE(r.find("new.txt"));
    CHECK(fs::is_empty(dir.path));
}

TEST_CASE("recovery: a failed write says why and keeps nothing half-written") {
    Recovery r("/proc/no-such-place/recovery");
    CHECK_FALSE(r.update("s.txt", "draft", true, 0.0).ok());
    CHECK_FALSE(r.find("s.txt"));
}
