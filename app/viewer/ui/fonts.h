// The UI's fonts and style at a given scale: DejaVu Sans when the system has it (found
// at run time), else ImGui's built-in font; a fixed-width face (DejaVu Sans Mono, else
// ImGui's built-in font) for the scene text and anything laid out in columns; ImGui's dark style with the contrast fixes
// of ui_settings.h, sized for the scale. Called between frames by the hosts, which
// then recreate their font texture.
#pragma once

#include <imgui.h>

#include <string>

namespace rtview {

struct UiFont {
    std::string path;       // empty: ImGui's built-in font
    std::string mono_path;  // the fixed-width face; empty: ImGui's built-in font
    float pixels = 0;
};

// Rebuilds the font atlas and the style for `scale` (the UI scale setting times the
// screen's content scale). Not inside a frame.
UiFont build_ui_font_and_style(float scale);

// The fixed-width font of the atlas built last (the current font when there is none,
// as in a context without the hosts' fonts).
ImFont* mono_font();

}  // namespace rtview
