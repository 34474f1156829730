// Window <-> film mapping and picking (see viewport.h).
#include "viewport.h"

#include <algorithm>
#include <cmath>

namespace rtview {

Rect letterbox(const Rect& area, int picture_w, int picture_h) {
    if (picture_w < 1 || picture_h < 1 || area.w <= 0 || area.h <= 0) return area;
    double s = std::min(area.w / picture_w, area.h / picture_h);
    Rect r;
    r.w = std::max(1.0, std::floor(picture_w * s));
    r.h = std::max(1.0, std::floor(picture_h * s));
    r.x = area.x + std::floor((area.w - r.w) / 2);
    r.y = area.y + std::floor((area.h - r.h) / 2);
    return r;
}

void window_to_film(const Rect& image, int film_w, int film_h, double px, double py, double& i, double& j) {
    double u = image.w > 0 ? (px - image.x) / image.w * film_w : 0;
    double v = image.h > 0 ? (py - image.y) / image.h * film_h : 0;
    // Texel k covers [k, k+1) on screen but shows the sample taken at k.
    i = u - 0.5;
    j = v - 0.5;
}

rt::Ray ray_at(const rt::Camera& view_camera, const Rect& image, int film_w, int film_h, double px, double py) {
    double i, j;
    window_to_film(image, film_w, film_h, px, py, i, j);
    return rt::CameraBasis::make(view_camera, film_w, film_h, false).ray(i, j);
}

rt::Ray texel_ray_at(const rt::Camera& view_camera, const Rect& image, int film_w, int film_h, double px,
                     double py) {
    double i, j;
    window_to_film(image, film_w, film_h, px, py, i, j);
    // The exact ray of the texel under the point: what the user sees there.
    return rt::CameraBasis::make(view_camera, film_w, film_h, false).ray(std::floor(i + 0.5), std::floor(j + 0.5));
}

rt::PickResult pick_at(const rt::World& world, const rt::Camera& view_camera, const Rect& image, int film_w,
                       int film_h, double px, double py) {
    return rt::pick(world, texel_ray_at(view_camera, image, film_w, film_h, px, py));
}

}  // namespace rtview
