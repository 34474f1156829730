// Pixel -> ray (docs/rendering.md §1), as the 2013 program (no half-pixel offset, pi = 3.14159),
// except that the picture is not mirrored unless asked to be.
#pragma once

#include "math.h"
#include "scene.h"

namespace rt {

struct CameraBasis {
    Vec3 origin, forward, up, side;  // side = forward x up, the original's column-0 side
    double tan_x = 0, tan_y = 0;     // linear: tan(angle/2)
    double half_x = 0, half_y = 0;   // degrees, for polar
    Projection projection = Projection::Linear;
    int width = 1, height = 1;
    bool mirror = false;
    // New: depth of field. The lens is a disc of radius `lens` (half the camera's
    // aperture; 0: the 2013 pinhole) across side and up; the plane `focus` along
    // forward is sharp (polar: the sphere of that radius).
    double lens = 0, focus = 1;

    [[nodiscard]] static CameraBasis make(const Camera& cam, int width, int height, bool mirror);

    // Direction (not normalised) through pixel coordinates (i, j); integers are the
    // original's sample points, fractions lie between them.
    [[nodiscard]] Vec3 direction(double i, double j) const;
    // normalize(direction(i0 + k * step, j)) for k < count, into out: the same vectors,
    // with what the row's pixels share (its vertical term) worked out once.
    void unit_directions(int i0, int step, int count, double j, Vec3* out) const;
    [[nodiscard]] Ray ray(double i, double j) const { return {origin, normalize(direction(i, j))}; }
    // The ray through the lens point (u, v) of [0, 1)^2 (concentric disc mapping) for the
    // pinhole ray's unit direction d: from that point of the lens to where the pinhole
    // ray meets the plane in focus.
    [[nodiscard]] Ray lens_ray(const Vec3& d, double u, double v) const;
};

// The original's degree factor.
constexpr double kDegree = 3.14159 / 180.0;

// Empty when the camera is valid; otherwise why not.
[[nodiscard]] const char* camera_problem(const Camera& cam);

}  // namespace rt
