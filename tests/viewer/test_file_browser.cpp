// The file browser's model: what a folder lists (folders first, the filter, hidden
// files), typed paths and Tab completion, and folders that cannot hang or break it
// (FIFOs, symlink loops, unreadable folders, a folder of more entries than it lists).
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <vector>

#include "file_browser.h"
#include "test_util.h"

using namespace rtview;
namespace fs = std::filesystem;

namespace {

void touch(const fs::path& p, const std::string& text = "x") { std::ofstream(p) << text; }

std::vector<std::string> names(const FileBrowser& b) {
    std::vector<std::string> n;
    for (const FileEntry& e : b.entries()) n.push_back(e.name + (e.folder ? "/" : ""));
    return n;
}

}  // namespace

TEST_CASE("file browser: folders first, then the files the filter admits, by name") {
    rt_test::TempDir dir;
    fs::create_directory(dir / "zeta");
    fs::create_directory(dir / "Alpha");
    touch(dir / "b.txt");
    touch(dir / "A.TXT");
    touch(dir / "c.png");
    touch(dir / ".hidden.txt");
    FileBrowser b({".txt"}, dir.path.string());
    CHECK(b.folder() == dir.path.string());
    CHECK(names(b) == std::vector<std::string>{"Alpha/", "zeta/", "A.TXT", "b.txt"});
    b.set_show_all(true);
    CHECK(names(b) == std::vector<std::string>{"Alpha/", "zeta/", "A.TXT", "b.txt", "c.png"});
    b.set_show_hidden(true);
    CHECK(names(b).size() == 6);
    CHECK(b.error().empty());
}

TEST_CASE("file browser: typed paths resolve against the folder, with .. and ~") {
    rt_test::TempDir dir;
    fs::create_directory(dir / "sub");
    FileBrowser b({}, dir.path.string());
    CHECK(b.resolve("x.txt") == (dir.path / "x.txt").string());
    CHECK(b.resolve("sub/../y.txt") == (dir.path / "y.txt").string());
    CHECK(b.resolve("/etc/hosts") == "/etc/hosts");
    CHECK(b.resolve("") == dir.path.string());
    const char* home = std::getenv("HOME");
    if (home && *home) CHECK(b.resolve("~/f") == (fs::path(home) / "f").lexically_normal().string());
    CHECK(b.go("sub"));
    CHECK(b.folder() == (dir.path / "sub").string());
    CHECK(b.up());
    CHECK(b.folder() == dir.path.string());
    CHECK_FALSE(b.go("missing"));
    CHECK(b.error().find("is not a folder") != std::string::npos);
    CHECK(b.folder() == dir.path.string());  // stays where it was
}

TEST_CASE("file browser: Tab completes the shared part, a lone folder with its slash") {
    rt_test::TempDir dir;
    fs::create_directory(dir / "scenes");
    touch(dir / "scenes" / "glass.txt");
    touch(dir / "scene-a.txt");
    touch(dir / "scene-b.txt");
    touch(dir / "other.png");
    FileBrowser b({".txt"}, dir.path.string());
    std::vector<std::string> cands;
    CHECK(b.complete("sc", &cands) == "scene");
    CHECK(cands == std::vector<std::string>{"scenes/", "scene-a.txt", "scene-b.txt"});
    CHECK(b.complete("scenes") == "scenes/");
    CHECK(b.complete("scenes/g", &cands) == "scenes/glass.txt");
    CHECK(cands.empty());
    CHECK(b.complete("oth") == "oth");  // filtered out: nothing to complete
    CHECK(b.complete("zzz") == "zzz");
    CHECK(b.complete(dir.path.string() + "/scene-") == dir.path.string() + "/scene-");
    CHECK(b.complete(std::string(10 << 20, 'q')) == std::string(10 << 20, 'q'));  // a 10 MB text is no problem
}

TEST_CASE("file browser: FIFOs, symlink loops and unreadable folders are listed without being opened") {
    rt_test::TempDir dir;
    REQUIRE(::mkfifo((dir / "pipe.txt").c_str(), 0600) == 0);
    fs::create_symlink(dir / "loop.txt", dir / "loop.txt");
    fs::create_directory(dir / "closed");
    FileBrowser b({".txt"}, dir.path.string());  // would block here if it opened the FIFO
    const std::vector<std::string> n = names(b);
    CHECK(std::find(n.begin(), n.end(), "pipe.txt") != n.end());
    CHECK(std::find(n.begin(), n.end(), "loop.txt") != n.end());
    ::chmod((dir / "closed").c_str(), 0);
    if (::geteuid() != 0) {  // root reads any folder
        CHECK_FALSE(b.go("closed"));
        CHECK_FALSE(b.error().empty());
        CHECK(b.folder() == dir.path.string());
    }
}

TEST_CASE("file browser: a folder with more entries than it lists stops at the limit") {
    rt_test::TempDir dir;
    for (std::size_t k = 0; k < FileBrowser::kMaxEntries + 10; ++k) touch(dir / ("f" + std::to_string(k) + ".txt"), "");
    FileBrowser b({".txt"}, dir.path.string());
    CHECK(b.truncated());
    CHECK(b.entries().size() == FileBrowser::kMaxEntries);
}
