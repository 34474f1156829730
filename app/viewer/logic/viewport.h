// Where the film sits in the window and which film pixel lies under a window point:
// the letterboxing of the "picture size" mode and the pixel -> ray mapping that
// picking, orbit pivots and dolly targets share.
#pragma once

#include "camera.h"
#include "world.h"

namespace rtview {

struct Rect {
    double x = 0, y = 0, w = 0, h = 0;  // top-left origin, y down
    bool contains(double px, double py) const { return px >= x && py >= y && px < x + w && py < y + h; }
};

// The largest rectangle of the picture's aspect centred in `area`, on whole pixels.
Rect letterbox(const Rect& area, int picture_w, int picture_h);

// Continuous film coordinates (as CameraBasis::direction takes them) of a window
// point shown inside `image`, for a film of film_w x film_h. Film pixel k is sampled
// at coordinate k and drawn over [k, k+1), so a texel's centre maps to exactly k.
void window_to_film(const Rect& image, int film_w, int film_h, double px, double py, double& i, double& j);

// The nearest object, plane or lamp glow under a window point; `hit` false on a miss.
rt::PickResult pick_at(const rt::World& world, const rt::Camera& view_camera, const Rect& image, int film_w,
                       int film_h, double px, double py);

// The ray through a window point (continuous: for pans, pivots and dolly targets).
rt::Ray ray_at(const rt::Camera& view_camera, const Rect& image, int film_w, int film_h, double px, double py);

// The sample ray of the texel under a window point (picking uses it).
rt::Ray texel_ray_at(const rt::Camera& view_camera, const Rect& image, int film_w, int film_h, double px,
                     double py);

}  // namespace rtview
