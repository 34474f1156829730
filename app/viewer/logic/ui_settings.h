// Settings the viewer remembers beside the recent files ($XDG_CONFIG_HOME/
// raytracer-view/settings.txt): the UI scale and the sidebar's width; plus where the UI font is found and the
// colours whose contrast the panels rely on.
#pragma once

#include <string>
#include <vector>

#include "status.h"

namespace rtview {

class UiSettings {
public:
    static constexpr double kMinScale = 0.75, kMaxScale = 3;
    static constexpr double kMinSidebarShare = 0.05, kMaxSidebarShare = 0.95;

    // `file` empty: settings.txt beside the recent-files list (memory only if there is
    // no config directory).
    explicit UiSettings(std::string file = {});
    static std::string default_path();

    double ui_scale() const { return ui_scale_; }
    // Sets (clamped) and saves; success, or why saving failed.
    rt::Status set_ui_scale(double scale);
    // The sidebar's width as the user dragged it, as a share of the window's (so that
    // a width chosen in a large window suits a small one); 0: none yet (the layout's
    // own choice).
    double sidebar_share() const { return sidebar_share_; }
    // Sets it (clamped to kMinSidebarShare..kMaxSidebarShare), and saves unless `keep`
    // is false (while the edge is dragged).
    rt::Status set_sidebar_share(double share, bool keep = true);
    void load();

private:
    rt::Status save() const;
    std::string file_;
    double ui_scale_ = 1;
    double sidebar_share_ = 0;
    std::vector<std::string> other_lines_;  // settings this version does not know: kept
};

// Ctrl+ / Ctrl-: the next step of 0.75, 1, 1.25, 1.5, 1.75, 2, 2.5, 3 up or down.
double next_ui_scale(double scale, int direction);

// The UI font: $RAYTRACER_VIEW_FONT if it names a file, else DejaVu Sans (Debian's
// fonts-dejavu-core) under the fonts folder of $XDG_DATA_DIRS or the usual places.
// Empty if none is found: the caller falls back to ImGui's built-in font.
std::string find_ui_font();
// The fixed-width face of the scene text editor and of text laid out in columns:
// $RAYTRACER_VIEW_MONO_FONT if it names a file, else DejaVu Sans Mono (the same
// package), Liberation Mono or Noto Sans Mono. Empty if none is found: the caller
// falls back to ImGui's built-in font, which is fixed-width too.
std::string find_mono_font();
enum class FontFace { Ui, Mono };
// The same searches over given data folders (each containing fonts/), for tests.
std::string find_font_in(const std::vector<std::string>& data_dirs, FontFace face);
inline std::string find_ui_font_in(const std::vector<std::string>& data_dirs) {
    return find_font_in(data_dirs, FontFace::Ui);
}

// Font sizes at scale 1, in pixels: DejaVu Sans is drawn larger than ImGui's
// bitmap font, whose 13 px is its native size.
constexpr float kUiFontPixels = 15.f, kFallbackFontPixels = 13.f;

// Colours (linear 0..1 sRGB components as ImGui takes them) chosen for legible text.
struct Rgb {
    float r, g, b;
};
constexpr Rgb kPanelBackground{0.06f, 0.06f, 0.06f};   // ImGui dark style's WindowBg
constexpr Rgb kHintText{0.68f, 0.68f, 0.72f};         // TextDisabled: hints and notes
constexpr Rgb kProgressFill{0.16f, 0.38f, 0.66f};     // progress bar (white text on it)
constexpr Rgb kWhite{1, 1, 1};
// WCAG 2 contrast ratio of two sRGB colours (1 .. 21; 4.5 is the bar for text).
double contrast_ratio(const Rgb& a, const Rgb& b);

}  // namespace rtview
