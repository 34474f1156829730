// The view camera and the gestures that move it (orbit, pan, dolly, fly, frame,
// reset). The view is not the document: a Navigator sees the scene only through a
// const rt::Camera and a const rt::World, so looking around can never edit, dirty or
// add undo steps to the file. No window, no GL: unit-tested.
#pragma once

#include "camera.h"
#include "viewport.h"
#include "world.h"

namespace rtview {

// Where the film is shown: the image rectangle (window coordinates) and the film size
// in pixels, with the camera as the film shows it (fitted to the window, or not).
struct ViewGeometry {
    Rect image;
    int film_w = 1, film_h = 1;
    bool fit_to_window = false;  // angle_x refitted to the film's aspect
};

// What F frames: the objects' bounds, or the lights' when there are no objects (lamps
// far from the objects would leave the objects small). Empty if there is neither.
rt::Aabb frame_target(const rt::World& world);

// The distance from the camera to `point` along its line of sight (a focus_distance
// that makes the point sharp); not positive for a point beside or behind the camera.
double focus_distance_to(const rt::Camera& camera, const rt::Vec3& point);

class Navigator {
public:
    // Follows the document's camera: when the scene camera differs from the one last
    // seen (a load, a camera-panel edit, undo, "Set scene camera from view"), the view
    // jumps to it. Navigation itself never changes the scene camera, so it is not undone.
    void follow(const rt::Camera& scene_camera);
    // Back to the scene camera (R).
    void reset(const rt::Camera& scene_camera);
    bool has_view() const { return has_view_; }

    // The view camera as a scene would hold it (the angles the scene's picture uses).
    const rt::Camera& camera() const { return view_; }
    // The camera the film is rendered with: in fit-to-window mode angle_x is refitted
    // to the film's aspect so pixels stay square.
    rt::Camera display_camera(const ViewGeometry& g) const;
    // True when the view is not the scene camera (the camera panel says so).
    bool differs_from(const rt::Camera& scene_camera) const { return has_view_ && !(view_ == scene_camera); }

    // Gestures. `world` may be null (nothing to pick: pivots fall back to the look-at
    // point). Buttons: 0 left (click to select, drag to orbit; with shift, pan),
    // 1 right and 2 middle (pan).
    void press(int button, bool shift, double x, double y, const rt::World* world, const ViewGeometry& g);
    // The pointer moved with the button still down. Returns true if the view changed.
    bool drag(double x, double y, const rt::World* world, const ViewGeometry& g);
    // The button went up: true if the gesture was a click (the caller selects).
    bool release();
    bool dragging() const { return gesture_ != Gesture::None; }
    bool is_click() const { return gesture_ == Gesture::Click; }
    double press_x() const { return press_x_; }
    double press_y() const { return press_y_; }
    void cancel_gesture() { gesture_ = Gesture::None; }

    // Puts the view somewhere directly (the camera panel's angles). False if the
    // camera is degenerate (the view stays).
    bool set(const rt::Camera& c) { return set_view(c); }

    // Wheel notches (positive: towards the point under the cursor).
    void wheel(double notches, double x, double y, const rt::World* world, const ViewGeometry& g);
    // Fly by `local` = (right, up, forward) keys held, for `dt` seconds.
    void fly(const rt::Vec3& local, double dt, bool fast, double scene_extent);
    // Keep the view direction and fit the bounds in view.
    void frame(const rt::Aabb& bounds, const ViewGeometry& g);
    // Turn about the look-at point (the headless --orbit).
    void orbit_degrees(double degrees);

    // The axis "up" for orbits and flights: the scene camera's up hint.
    rt::Vec3 world_up() const { return up_; }

private:
    bool set_view(const rt::Camera& c);  // rejects degenerate cameras
    rt::Vec3 pick_point_or(double px, double py, double fallback_distance, const rt::World* world,
                           const ViewGeometry& g, bool* hit = nullptr) const;

    rt::Camera view_;
    rt::Camera seen_scene_camera_;
    bool has_view_ = false;
    rt::Vec3 up_{0, 0, 1};

    enum class Gesture { None, Click, Orbit, Pan };
    Gesture gesture_ = Gesture::None;
    double press_x_ = 0, press_y_ = 0;
    rt::Camera press_camera_;
    rt::Vec3 anchor_;  // orbit pivot or pan anchor
};

}  // namespace rtview
