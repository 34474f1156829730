// UI scale steps and their settings file, font discovery, and the contrast of the
// colours text sits on.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "test_util.h"
#include "ui_settings.h"

using namespace rtview;
namespace fs = std::filesystem;

namespace {

using rt_test::TempDir;

}  // namespace

TEST_CASE("Ctrl+ and Ctrl- step through the UI scales") {
    CHECK(next_ui_scale(1, +1) == 1.25);
    CHECK(next_ui_scale(1.75, +1) == 2);
    CHECK(next_ui_scale(2, +1) == 2.5);
    CHECK(next_ui_scale(3, +1) == 3);
    CHECK(next_ui_scale(1, -1) == 0.75);
    CHECK(next_ui_scale(0.75, -1) == 0.75);
    CHECK(next_ui_scale(1.3, -1) == 1.25);  // a value between steps goes to the step below
    CHECK(next_ui_scale(1.3, +1) == 1.5);
}

TEST_CASE("the UI scale is saved beside the recent files and read back") {
    TempDir dir;
    std::string file = (dir.path / "sub" / "settings.txt").string();
    {
        UiSettings s(file);
        CHECK(s.ui_scale() == 1);
        CHECK(s.set_ui_scale(2).ok());
    }
    {
        UiSettings s(file);
        CHECK(s.ui_scale() == 2);
        CHECK(s.set_ui_scale(99).ok());
        CHECK(s.ui_scale() == UiSettings::kMaxScale);
    }
    // Unknown settings survive a save; nonsense values are ignored.
    {
        std::ofstream out(file);
        out << "theme dark\nui_scale banana\n";
    }
    UiSettings s(file);
    CHECK(s.ui_scale() == 1);
    CHECK(s.set_ui_scale(1.5).ok());
    std::ifstream in(file);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(all.find("ui_scale 1.5") != std::string::npos);
    CHECK(all.find("theme dark") != std::string::npos);
}

TEST_CASE("the sidebar's width is kept in the settings as a share of the window, beside the UI scale") {
    TempDir dir;
    std::string file = (dir.path / "settings.txt").string();
    {
        UiSettings s(file);
        CHECK(s.sidebar_share() == 0);  // none yet: the layout chooses
        CHECK(s.set_ui_scale(2).ok());
        CHECK(s.set_sidebar_share(0.3125, false).ok());  // while dragging: not yet written
        CHECK(s.sidebar_share() == 0.3125);
    }
    CHECK(UiSettings(file).sidebar_share() == 0);
    {
        UiSettings s(file);
        CHECK(s.set_sidebar_share(0.3125).ok());  // released
    }
    UiSettings s(file);
    CHECK(s.sidebar_share() == 0.3125);
    CHECK(s.ui_scale() == 2);
    // Nonsense is ignored, on reading and on setting; shares are kept within limits.
    CHECK(s.set_sidebar_share(-3).ok());
    CHECK(s.set_sidebar_share(std::nan("")).ok());
    CHECK(s.sidebar_share() == 0.3125);
    CHECK(s.set_sidebar_share(7).ok());
    CHECK(s.sidebar_share() == UiSettings::kMaxSidebarShare);
    {
        std::ofstream out(file);
        out << "sidebar_share -7\nui_scale 1.5\n";
    }
    CHECK(UiSettings(file).sidebar_share() == 0);
    {
        std::ofstream out(file);
        out << "sidebar_share 1e300\n";
    }
    CHECK(UiSettings(file).sidebar_share() == UiSettings::kMaxSidebarShare);
    // An absolute width of earlier versions is dropped: the layout chooses.
    {
        std::ofstream out(file);
        out << "sidebar_width 940\nui_scale 2\n";
    }
    UiSettings old(file);
    CHECK(old.sidebar_share() == 0);
    CHECK(old.set_ui_scale(2).ok());
    std::ifstream in(file);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(all.find("sidebar_width") == std::string::npos);
}

TEST_CASE("the UI font is found under a data folder's fonts/") {
    TempDir dir;
    CHECK(find_ui_font_in({(dir.path / "none").string(), ""}).empty());
    fs::create_directories(dir.path / "share/fonts/truetype/dejavu");
    std::string font = (dir.path / "share/fonts/truetype/dejavu/DejaVuSans.ttf").string();
    std::ofstream(font) << "not really a font";
    CHECK(find_ui_font_in({(dir.path / "none").string(), (dir.path / "share").string()}) == font);
    CHECK(find_ui_font_in({(dir.path / "share/").string()}) == font);
}

TEST_CASE("text is legible on the colours it sits on") {
    CHECK(contrast_ratio(kWhite, Rgb{0, 0, 0}) == doctest::Approx(21));
    CHECK(contrast_ratio(kWhite, kWhite) == doctest::Approx(1));
    // ImGui's default progress bar colour under white text: what was hard to read.
    CHECK(contrast_ratio(kWhite, Rgb{0.90f, 0.70f, 0.00f}) < 3);
    CHECK(contrast_ratio(kWhite, kProgressFill) >= 4.5);
    CHECK(contrast_ratio(kHintText, kPanelBackground) >= 7);
}
