// What the last drawn frame showed, in words, for scripts that drive the window
// (--print-layout): parts of the UI name the state of what they drew ("render_dialog"
// -> "saved out.png") with probe(); the app prints the frame's list after the frame.
// Only drawn frames write it, so a script that reads it sees what is on the screen.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rtview {

// Records `value` under `key` for the frame being drawn (the UI thread only; values
// are kept to one line, and keys to one word: "menu:Add here" is "menu:Add_here").
void probe(const std::string& key, const std::string& value);
// Records where the last ImGui item was drawn, "x y w h" in framebuffer pixels (what
// xdotool and screenshots use), under `key`: for scripts that click on it. Nothing
// when the item is scrolled out of sight.
void probe_item(const std::string& key);
// The frame's records, in the order made; cleared by begin_probe_frame().
const std::vector<std::pair<std::string, std::string>>& probes();
void begin_probe_frame();

}  // namespace rtview
