// ImGui input -> view camera gestures (see navigation.h).
#include "navigation.h"

#include "imgui_common.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace rtview {

namespace {

constexpr double kWheelSettle = 0.4;  // seconds after the last notch the view counts as moving
constexpr double kClickSlop = 3;      // pixels a Shift+click may move and stay a click (as a plain one)


}  // namespace

ViewGeometry NavigationInput::geometry(const Layout& l) const {
    return {l.image, l.film_w, l.film_h, l.fit == FitMode::Window};
}

bool NavigationInput::moving(double now) const {
    return nav_.dragging() || flying_ || (wheel_time_ >= 0 && now - wheel_time_ < kWheelSettle);
}

NavigationInput::Result NavigationInput::handle(const Layout& layout, const rt::World* world, bool usable,
                                                double scene_extent) {
    Result res;
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    ViewGeometry g = geometry(layout);
    const bool shift_click = shift_press_ && !shift_moved_ && std::abs(mx - press_x_) <= kClickSlop &&
                             std::abs(my - press_y_) <= kClickSlop;
    if (!nav_.dragging()) {
        bool over = usable && !io.WantCaptureMouse && layout.image.contains(mx, my);
        if (over) {
            int button = -1;
            if (ImGui::IsMouseClicked(0)) button = 0;
            else if (ImGui::IsMouseClicked(1)) button = 1;
            else if (ImGui::IsMouseClicked(2)) button = 2;
            if (button >= 0) {
                button_ = button;
                shift_press_ = button == 0 && io.KeyShift;
                shift_moved_ = false;
                press_x_ = mx, press_y_ = my;
                nav_.press(button, io.KeyShift, mx, my, world, g);
            }
            if (io.MouseWheel != 0 && !nav_.dragging()) {
                nav_.wheel(io.MouseWheel, mx, my, world, g);
                wheel_time_ = ImGui::GetTime();
            }
        }
    } else if (!ImGui::IsMouseDown(button_) || !usable) {
        res.x = nav_.press_x();
        res.y = nav_.press_y();
        res.clicked = nav_.release() && usable;
        if (shift_click && usable) res.clicked = res.shift = true;
        shift_press_ = false;
    } else if (shift_click) {
        // A Shift+click in the making: the view stays put until it moves farther.
    } else {
        shift_moved_ = true;
        // Only the pointer's position at this frame counts: all the motion events
        // since the last frame are one view change.
        nav_.drag(mx, my, world, g);
    }

    // WASD/QE fly, scaled to the scene so that any scene crosses in a few seconds.
    // A key flies only if it went down without Ctrl/Alt: releasing Ctrl a moment
    // before the S of Ctrl+S must not turn into a step backwards.
    static const int fly_keys[6] = {keys::kD, keys::kA, keys::kE, keys::kQ, keys::kW, keys::kS};
    bool free_keys = usable && !io.WantCaptureKeyboard;
    for (int k = 0; k < 6; ++k) {
        if (!key_down(fly_keys[k]) || !free_keys) fly_armed_[k] = false;
        else if (key_pressed(fly_keys[k]) && !io.KeyCtrl && !io.KeyAlt && !io.KeySuper) fly_armed_[k] = true;
    }
    auto held = [&](int k) { return fly_armed_[k] && !io.KeyCtrl && !io.KeyAlt ? 1.0 : 0.0; };
    rt::Vec3 local{held(0) - held(1), held(2) - held(3), held(4) - held(5)};
    flying_ = rt::length2(local) > 0;
    if (flying_) nav_.fly(local, double(io.DeltaTime), io.KeyShift, scene_extent);
    return res;
}

}  // namespace rtview
