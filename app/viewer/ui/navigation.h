// Mouse and fly keys in the image area, turned into Navigator gestures on the view
// camera. Reads ImGui's input once per frame (so a burst of pointer events between
// two frames is one view change) and respects WantCaptureMouse/Keyboard.
#pragma once

#include "navigator.h"
#include "layout.h"
#include "world.h"

namespace rtview {

class NavigationInput {
public:
    explicit NavigationInput(Navigator& nav) : nav_(nav) {}

    struct Result {
        bool clicked = false;  // a click (not a drag) ended: select under (x, y)
        bool shift = false;    // with Shift (a pan that did not move): add or take out
        double x = 0, y = 0;
    };
    // One frame of input. `usable`: a scene and a world exist and no modal is open.
    Result handle(const Layout& layout, const rt::World* world, bool usable, double scene_extent);
    // The view is in motion (a drag, flying, or the wheel within the last moments).
    bool moving(double now) const;

private:
    ViewGeometry geometry(const Layout& l) const;

    Navigator& nav_;
    int button_ = 0;
    double wheel_time_ = -1;
    bool flying_ = false;
    bool fly_armed_[6] = {};  // D A E Q W S went down without a modifier
    // A press of the left button with Shift: a pan once it moves, else a Shift+click.
    bool shift_press_ = false, shift_moved_ = false;
    double press_x_ = 0, press_y_ = 0;
};

}  // namespace rtview
