// The UI's font and style at a given scale: DejaVu Sans when the system has it (found
// at run time), else ImGui's built-in font; ImGui's dark style with the contrast fixes
// of ui_settings.h, sized for the scale. Called between frames by the hosts, which
// then recreate their font texture.
#pragma once

#include <string>

namespace rtview {

struct UiFont {
    std::string path;  // empty: ImGui's built-in font
    float pixels = 0;
};

// Rebuilds the font atlas and the style for `scale` (the UI scale setting times the
// screen's content scale). Not inside a frame.
UiFont build_ui_font_and_style(float scale);

}  // namespace rtview
