// Keys and colours the viewer's windows share. Keys are read by GLFW key code, as the
// GLFW backend reports them in io.KeysDown (letters are their upper-case ASCII codes;
// ImGui 1.86 maps only a few keys by name).
#pragma once

#include <imgui.h>

namespace rtview {

namespace keys {
constexpr int kA = 'A', kB = 'B', kC = 'C', kD = 'D', kE = 'E', kF = 'F', kK = 'K', kN = 'N', kO = 'O', kP = 'P', kQ = 'Q',
              kR = 'R', kS = 'S', kT = 'T', kW = 'W', kG = 'G', kY = 'Y', kU = 'U';
constexpr int k0 = 48, k1 = 49, kMinus = 45, kEqual = 61;
constexpr int kKp0 = 320, kKp1 = 321, kKpSubtract = 333, kKpAdd = 334, kF12 = 301;
}  // namespace keys

// The key went down this frame (or, with repeat, auto-repeated).
inline bool key_pressed(int k, bool repeat = false) {
    return k >= 0 && k < int(IM_ARRAYSIZE(ImGui::GetIO().KeysDown)) && ImGui::IsKeyPressed(k, repeat);
}
inline bool key_down(int k) { return k >= 0 && k < int(IM_ARRAYSIZE(ImGui::GetIO().KeysDown)) && ImGui::GetIO().KeysDown[k]; }
inline bool imgui_key_pressed(ImGuiKey k, bool repeat = false) { return key_pressed(ImGui::GetKeyIndex(k), repeat); }
inline bool escape_pressed() { return imgui_key_pressed(ImGuiKey_Escape); }

// Text that reports an error (a parse error, a file that cannot be read), a warning, or
// that all is well.
inline const ImVec4 kErrorColour{1.0f, 0.42f, 0.42f, 1.0f};
inline const ImVec4 kWarnColour{1.0f, 0.80f, 0.35f, 1.0f};
inline const ImVec4 kOkColour{0.55f, 0.85f, 0.55f, 1.0f};

}  // namespace rtview
