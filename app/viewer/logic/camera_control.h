// Camera motions of the viewer as pure functions on rt::Camera: orbit, pan, dolly,
// fly, frame and the aspect fit of the displayed view. No window, no GL: unit-tested.
// A camera here is a rig of three points (position, centre, up point); every motion
// moves the rig rigidly, so the up hint can never become parallel to the view.
#pragma once

#include "camera.h"
#include "math.h"
#include "scene.h"

namespace rtview {

// The axis the user thinks of as "up": the file camera's up hint (up - centre), made
// orthogonal to nothing, just normalised; +z if the camera has none.
rt::Vec3 world_up_of(const rt::Camera& cam);

// The camera as displayed in a viewport of width x height pixels: angle_y is kept and
// angle_x widened or narrowed so pixels are square. Position, centre, up unchanged.
rt::Camera fit_camera_to_aspect(const rt::Camera& cam, int width, int height);

// Moves the whole rig by `offset`.
rt::Camera translate(const rt::Camera& cam, const rt::Vec3& offset);

// Rotates the rig about `pivot`: first by `yaw` radians about `world_up`, then by
// `elevation` radians raising the eye over the pivot. The elevation is clamped so the
// view direction stays between 1 and 179 degrees from world_up (no flipping over).
rt::Camera orbit(const rt::Camera& cam, const rt::Vec3& pivot, const rt::Vec3& world_up, double yaw,
                 double elevation);

// How far from the eye the scene reaches: to the farthest corner of `bounds` (its
// objects and lights; empty bounds count for nothing), and at least to the camera's
// centre.
double scene_reach(const rt::Camera& cam, const rt::Aabb& bounds);
// An orbit pivot picked at `pivot` on a ray from `eye`, moved along that ray to at
// most `reach` from the eye: a far point of an infinite plane would swing the eye far
// out of the scene, while the point under the cursor still stays under it.
rt::Vec3 clamp_pivot(const rt::Vec3& eye, const rt::Vec3& pivot, double reach);

// Rig offset that moves the point `anchor` (seen at pixel (i0, j0) of `view`) to
// pixel (i1, j1): the grabbed point follows the cursor. Exact for linear projection.
rt::Vec3 pan_offset(const rt::CameraBasis& view, const rt::Vec3& anchor, double i0, double j0, double i1,
                    double j1);

// Rig offset that moves the eye along the ray towards `target` by the fraction
// 1 - 0.8^notches (negative notches move away). Moving along the ray through the
// cursor keeps the point under the cursor in place.
rt::Vec3 dolly_offset(const rt::Vec3& eye, const rt::Vec3& target, double notches);

// The wheel's dolly: the eye moves by dolly_offset() and the rig is scaled about
// `target` by the same factor, so the look-at point comes along and the distance the
// camera panel shows ("dist") shrinks or grows with the step; the view direction and
// the point under the cursor stay.
rt::Camera dolly(const rt::Camera& cam, const rt::Vec3& target, double notches);

// Fly step: `local` is (right, up, forward) in units of `step`; up is world_up.
rt::Vec3 fly_offset(const rt::Camera& cam, const rt::Vec3& world_up, const rt::Vec3& local, double step);

// Keeps the view direction and moves the rig so the bounding sphere of `bounds`
// fills the view (with a little margin). Returns cam unchanged for empty bounds.
rt::Camera frame_bounds(const rt::Camera& cam, const rt::Aabb& bounds);

// Azimuth and elevation (degrees) of the view direction relative to world_up, and the
// eye-to-centre distance: the camera panel shows them.
struct ViewAngles {
    double azimuth = 0, elevation = 0, distance = 0;
};
ViewAngles view_angles(const rt::Camera& cam, const rt::Vec3& world_up);
// Places the eye at the given azimuth/elevation/distance around the centre (inverse
// of view_angles); the up point follows rigidly.
rt::Camera set_view_angles(const rt::Camera& cam, const rt::Vec3& world_up, const ViewAngles& a);

// Pixel of a world point in `view` (continuous coordinates as CameraBasis::direction
// takes them). False if the point is behind the eye. Linear projection only is exact.
bool project(const rt::CameraBasis& view, const rt::Vec3& p, double& i, double& j);

// The camera with its three points (eye, centre, up point) on a decimal grid at least
// ten million times finer than the eye-to-centre distance: the view turns by under
// 1e-7 radians (a ten-thousandth of a pixel), and the numbers a scene file gets from
// the view ("Set scene camera from view") are short decimals, not 17 digits of the
// rounding noise of an orbit's sines and cosines.
rt::Camera tidy_camera(const rt::Camera& cam);

// Rodrigues rotation of v about unit axis k by angle radians.
rt::Vec3 rotate(const rt::Vec3& v, const rt::Vec3& k, double angle);

}  // namespace rtview
