// The view camera and its gestures (see navigator.h).
#include "navigator.h"

#include <algorithm>
#include <cmath>

#include "camera_control.h"
#include "shapes.h"  // rt::Geometry: the objects' bounds

namespace rtview {

double focus_distance_to(const rt::Camera& camera, const rt::Vec3& point) {
    const rt::Vec3 f = camera.centre - camera.position;
    if (!(rt::length2(f) > 0)) return 0;
    return rt::dot(point - camera.position, rt::normalize(f));
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOrbitRadPerPixel = 0.3 * kPi / 180;  // a 600-pixel drag turns 180 degrees
constexpr double kClickSlop = 3;                       // pixels a click may move and stay a click

bool usable_camera(const rt::Camera& c) {
    return !rt::camera_problem(c) && rt::finite(c.position) && rt::finite(c.centre) && rt::finite(c.up);
}

}  // namespace

rt::Aabb frame_target(const rt::World& world) {
    rt::Aabb b;
    for (const rt::Aabb& ob : world.geometry->object_bounds)
        if (!ob.empty()) b.grow(ob);
    if (b.empty())
        for (const rt::ShadeLight& l : world.lights) b.grow(l.position);
    return b;
}

void Navigator::follow(const rt::Camera& scene_camera) {
    if (has_view_ && scene_camera == seen_scene_camera_) return;
    reset(scene_camera);
}

void Navigator::reset(const rt::Camera& scene_camera) {
    seen_scene_camera_ = scene_camera;
    up_ = world_up_of(scene_camera);
    view_ = scene_camera;
    has_view_ = true;
    gesture_ = Gesture::None;
}

bool Navigator::set_view(const rt::Camera& moved) {
    const rt::Camera c = tidy_camera(moved);
    // A degenerate camera would render nothing; keep the last good one.
    if (!usable_camera(c) || c == view_) return false;
    view_ = c;
    return true;
}

rt::Camera Navigator::display_camera(const ViewGeometry& g) const {
    return g.fit_to_window ? fit_camera_to_aspect(view_, g.film_w, g.film_h) : view_;
}

rt::Vec3 Navigator::pick_point_or(double px, double py, double fallback_distance, const rt::World* world,
                                  const ViewGeometry& g, bool* hit) const {
    rt::Camera vc = display_camera(g);
    if (world) {
        rt::PickResult r = pick_at(*world, vc, g.image, g.film_w, g.film_h, px, py);
        if (r.hit && std::isfinite(r.t)) {
            if (hit) *hit = true;
            return r.point;
        }
    }
    if (hit) *hit = false;
    rt::Ray ray = ray_at(vc, g.image, g.film_w, g.film_h, px, py);
    return ray.origin + ray.dir * fallback_distance;
}

void Navigator::press(int button, bool shift, double x, double y, const rt::World* world, const ViewGeometry& g) {
    if (!has_view_) return;
    gesture_ = (button == 0 && !shift) ? Gesture::Click : Gesture::Pan;
    press_x_ = x;
    press_y_ = y;
    press_camera_ = view_;
    anchor_ = pick_point_or(x, y, rt::length(view_.centre - view_.position), world, g);
}

bool Navigator::drag(double x, double y, const rt::World* world, const ViewGeometry& g) {
    if (gesture_ == Gesture::None) return false;
    double dx = x - press_x_, dy = y - press_y_;
    if (gesture_ == Gesture::Click && (std::fabs(dx) > kClickSlop || std::fabs(dy) > kClickSlop)) {
        gesture_ = Gesture::Orbit;
        // Pivot: the point under the cursor when the drag began (no farther than the
        // scene reaches), or the look-at point if the ray missed everything.
        bool hit = false;
        rt::Vec3 p = pick_point_or(press_x_, press_y_, 1, world, g, &hit);
        const double reach = scene_reach(press_camera_, world ? world->bounds() : rt::Aabb{});
        anchor_ = hit ? clamp_pivot(press_camera_.position, p, reach) : press_camera_.centre;
    }
    if (gesture_ == Gesture::Orbit) {
        // Rotation is relative to the camera at the press, so it never drifts.
        return set_view(orbit(press_camera_, anchor_, up_, -dx * kOrbitRadPerPixel, dy * kOrbitRadPerPixel));
    }
    if (gesture_ == Gesture::Pan) {
        rt::Camera vc = g.fit_to_window ? fit_camera_to_aspect(press_camera_, g.film_w, g.film_h) : press_camera_;
        rt::CameraBasis basis = rt::CameraBasis::make(vc, g.film_w, g.film_h, false);
        double i0, j0, i1, j1;
        window_to_film(g.image, g.film_w, g.film_h, press_x_, press_y_, i0, j0);
        window_to_film(g.image, g.film_w, g.film_h, x, y, i1, j1);
        return set_view(translate(press_camera_, pan_offset(basis, anchor_, i0, j0, i1, j1)));
    }
    return false;
}

bool Navigator::release() {
    bool click = gesture_ == Gesture::Click;
    gesture_ = Gesture::None;
    return click;
}

void Navigator::wheel(double notches, double x, double y, const rt::World* world, const ViewGeometry& g) {
    if (!has_view_ || notches == 0) return;
    rt::Vec3 target = pick_point_or(x, y, rt::length(view_.centre - view_.position), world, g);
    set_view(dolly(view_, target, notches));
}

void Navigator::fly(const rt::Vec3& local, double dt, bool fast, double scene_extent) {
    if (!has_view_ || rt::length2(local) == 0) return;
    double step = scene_extent * 0.35 * std::clamp(dt, 0.0, 0.1) * (fast ? 4 : 1);
    set_view(translate(view_, fly_offset(view_, up_, local, step)));
}

void Navigator::frame(const rt::Aabb& bounds, const ViewGeometry& g) {
    if (!has_view_) return;
    rt::Camera c = frame_bounds(display_camera(g), bounds);
    rt::Camera k = view_;
    k.position = c.position;
    k.centre = c.centre;
    k.up = c.up;
    set_view(k);
}

void Navigator::orbit_degrees(double degrees) {
    if (!has_view_) return;
    set_view(orbit(view_, view_.centre, up_, degrees * kPi / 180, 0));
}

}  // namespace rtview
