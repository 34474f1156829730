// Command line and the recent-files list.
#include <doctest/doctest.h>
#include <unistd.h>

#include <cstdlib>
#include <vector>

#include "options.h"
#include "recent_files.h"
#include "test_util.h"
#include "viewer_test_util.h"

using namespace rtview;

namespace {
const auto parse = rtview_test::parse_args;
}  // namespace

TEST_CASE("the headless command line of the issue parses") {
    Options o;
    CHECK(parse({"--headless", "s.txt", "--screenshot", "out.png", "--size", "1280x800", "--samples", "8", "--orbit",
                 "-30"},
                o) == "");
    CHECK(o.headless);
    CHECK(o.scene == "s.txt");
    CHECK(o.screenshot == "out.png");
    CHECK(o.width == 1280);
    CHECK(o.height == 800);
    CHECK(o.samples == 8);
    CHECK(o.orbit == -30);
    Options e;
    CHECK(parse({"--size=640x480", "--fit=picture", "--", "-odd-name.txt"}, e) == "");
    CHECK(e.width == 640);
    CHECK(e.fit == FitMode::Picture);
    CHECK(e.scene == "-odd-name.txt");
}

TEST_CASE("bad arguments are reported, not guessed") {
    Options o;
    CHECK_FALSE(parse({"--size", "12x"}, o).empty());
    CHECK_FALSE(parse({"--samples", "0"}, o).empty());
    CHECK_FALSE(parse({"--samples", "3.5"}, o).empty());
    CHECK_FALSE(parse({"--orbit"}, o).empty());
    CHECK_FALSE(parse({"--frobnicate"}, o).empty());
    CHECK_FALSE(parse({"a.txt", "b.txt"}, o).empty());
    CHECK_FALSE(parse({"--headless=yes"}, o).empty());
    CHECK_FALSE(parse({"--aa-threshold", "-0.1"}, o).empty());
    CHECK_FALSE(parse({"--aa-threshold", "3.5"}, o).empty());
    CHECK_FALSE(parse({"--aa-threshold", "fine"}, o).empty());
    CHECK_FALSE(o.aa_threshold);
    CHECK(parse({"--aa-threshold", "0.25"}, o).empty());
    CHECK(o.aa_threshold == 0.25);
    CHECK(parse({"--aa-threshold", "off"}, o).empty());  // every pixel the same samples
    CHECK(o.aa_threshold == -1);
    CHECK_FALSE(parse({"--aa-threshold", "Off"}, o).empty());
}

TEST_CASE("help describes every option of both binaries") {
    for (bool headless : {false, true}) {
        std::string h = help_text(headless);
        for (const char* opt : {"--headless", "--screenshot", "--size", "--samples", "--time-limit", "--aa-threshold",
                                "--orbit", "--fit",
                                "--threads", "--tab", "--select", "--view-scene", "--print-layout", "--verbose",
                                "--help", "--version"})
            CHECK_MESSAGE(h.find(opt) != std::string::npos, opt);
    }
    CHECK(help_text(false).find("Ctrl+Z") != std::string::npos);
}

TEST_CASE("recent files: newest first, no duplicates, at most ten, kept on disk") {
    rt_test::TempDir temp;
    const std::string dir = temp.path.string();
    std::string file = dir + "/cfg/raytracer-view/recent.txt";
    {
        RecentFiles r(file);
        for (int k = 0; k < 12; ++k) CHECK(r.add("/scenes/s" + std::to_string(k) + ".txt").ok());
        CHECK(r.add("/scenes/s5.txt").ok());
        REQUIRE(r.paths().size() == RecentFiles::kMax);
        CHECK(r.paths().front() == "/scenes/s5.txt");
        CHECK(r.paths()[1] == "/scenes/s11.txt");
    }
    RecentFiles again(file);
    CHECK(again.paths().size() == RecentFiles::kMax);
    CHECK(again.paths().front() == "/scenes/s5.txt");
    setenv("XDG_CONFIG_HOME", (dir + "/xdg").c_str(), 1);
    CHECK(RecentFiles::default_path() == dir + "/xdg/raytracer-view/recent.txt");
    unsetenv("XDG_CONFIG_HOME");
}
