// Small ImGui pieces the panels share: wrapped messages, a row of buttons that wraps,
// a point as three number fields, an item's block on the screen, and the object a
// selection names.
#pragma once

#include <imgui.h>

#include <string>

#include "scene.h"
#include "scene_edits.h"
#include "viewport.h"

namespace rtview {

// Messages wrap at the panel's edge instead of running past it (at any UI scale).
void wrapped_coloured(const ImVec4& colour, const std::string& text);
void wrapped_hint(const std::string& text);
// SameLine() if a button labelled `next` still fits on the line, else the button goes
// on the next line (a row of buttons wraps instead of running past the panel's edge);
// `extra`: more width than the label's (a checkbox's box).
void same_line_if_fits(const char* next, float extra = 0);
bool drag_vec3(const char* label, rt::Vec3& v, float speed, const char* format = "%.3f");
// The rectangle from `top_left`, `width` wide, down to the cursor.
Rect item_block(const ImVec2& top_left, float width);
// The object (or CSG operand) a selection names; null if none.
const rt::Object* resolve(const rt::Scene& s, const ItemRef& sel);

}  // namespace rtview
