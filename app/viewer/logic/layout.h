// How the window is divided and what size of picture it renders (Layout, each frame): the film of the
// picture frame (the scene's picture_size, whatever the window), the sidebar's width
// (the user's, within what leaves the picture room) and status text flowed into rows
// without breaking a number. Pure arithmetic: unit-tested.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "options.h"
#include "viewport.h"

namespace rtview {

// Where everything is this frame (ImGui logical coordinates) and the film it implies.
struct Layout {
    float menu_h = 0, status_h = 0, sidebar_w = 0;
    bool sidebar_hidden = false;  // Tab: the picture alone
    float fb_scale = 1;
    Rect area;   // all space for the image
    Rect image;  // where the film is drawn (letterboxed in picture mode; zoomed by the picture tools)
    Rect fit_image;  // where it is drawn unzoomed
    int film_w = 1, film_h = 1;  // the picture rendered: picture_size in the picture frame, else the area's
    FitMode fit = FitMode::Picture;
    // Rectangles of some panels, for --print-layout.
    Rect camera_panel, editor, diagnostics, outline;
};

// The most pixels the viewer renders as one film (a larger picture_size would take
// gigabytes): "Render to file" makes pictures of any size.
constexpr std::int64_t kMaxFilmPixels = std::int64_t(4096) * 4096;

// The film of the picture frame: the scene's picture_size, or, past kMaxFilmPixels,
// the largest film of its aspect within it (so the viewer says the saved image is
// smaller). Zoom and pan only place this film on the screen.
void picture_film_size(int x_max, int y_max, int& film_w, int& film_h);

// The sidebar's width in a window `window_w` wide at UI scale `scale`: the share
// `wanted` of the window (as the user dragged it; <= 0: none yet) or else a third of
// the window, widened to `content_min` (the panels' fields whole) where that leaves
// the picture most of the window. Never narrower than a few words nor so wide that
// the picture has less than 40 % of the window.
float sidebar_width(float window_w, float scale, float content_min, double wanted);
// The limits sidebar_width() keeps to (a drag of the edge stops there).
float sidebar_min_width(float window_w, float scale);
float sidebar_max_width(float window_w, float scale);

// `text` broken into rows no wider than `width` (as `measure` says), at spaces only:
// a number such as "0.107" is never split (ImGui's own wrapping breaks after a '.').
// A word wider than a row on its own is cut where it must be.
std::vector<std::string> wrap_words(const std::string& text, float width,
                                    const std::function<float(std::string_view)>& measure);

// One line of `width` at most: `text` whole if it fits, else its longest start that
// fits with "..." after it (never inside a UTF-8 character; "" if not even "..." fits).
std::string elide_end(const std::string& text, float width, const std::function<float(std::string_view)>& measure);
// One line of `width` at most with "..." in the middle when `text` does not fit: its
// start and, mostly, its end (a path's file name) are kept.
std::string elide_middle(const std::string& text, float width, const std::function<float(std::string_view)>& measure);
// Pieces of a line, each {separator, text}: joined while whole pieces fit, then "..."
// (a number or a readout's group is never cut); the first piece is cut by characters
// (elide_end) when even it does not fit.
std::string elide_pieces(const std::vector<std::pair<std::string, std::string>>& pieces, float width,
                         const std::function<float(std::string_view)>& measure);

}  // namespace rtview
