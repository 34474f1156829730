// Zoom and pan of the picture (see image_view.h).
#include "image_view.h"

#include <algorithm>
#include <cmath>

namespace rtview {

namespace {

ViewTransform fitted_transform(const Rect& area, int film_w, int film_h) {
    Rect r = letterbox(area, film_w, film_h);
    ViewTransform t;
    t.x0 = r.x;
    t.y0 = r.y;
    t.sx = film_w > 0 ? r.w / film_w : 1;
    t.sy = film_h > 0 ? r.h / film_h : 1;
    return t;
}

// Where the picture's leading edge goes along one axis of the area [a0, a0 + size):
// centred if its `length` fits, else `wanted` moved just enough to leave no gap (the
// picture never shows the background beside it while part of it is cut off).
double place(double a0, double size, double length, double wanted) {
    if (length <= size) return a0 + (size - length) / 2;
    return std::clamp(wanted, a0 + size - length, a0);
}

}  // namespace

ViewTransform ImageView::transform(const Rect& area, int film_w, int film_h, double fb_scale) const {
    if (fit_ || film_w < 1 || film_h < 1) return fitted_transform(area, film_w, film_h);
    ViewTransform t;
    t.sx = t.sy = scale_;
    t.x0 = place(area.x, area.w, film_w * scale_, area.x + area.w / 2 - cx_ * scale_);
    t.y0 = place(area.y, area.h, film_h * scale_, area.y + area.h / 2 - cy_ * scale_);
    if (fb_scale > 0) {
        t.x0 = std::round(t.x0 * fb_scale) / fb_scale;
        t.y0 = std::round(t.y0 * fb_scale) / fb_scale;
    }
    return t;
}

double ImageView::ratio(const Rect& area, int film_w, int film_h, double fb_scale) const {
    ViewTransform t = transform(area, film_w, film_h);
    return std::min(t.sx, t.sy) * fb_scale;
}

void ImageView::set_from(const Rect& area, int film_w, int film_h, const ViewTransform& t) {
    fit_ = false;
    scale_ = t.sx;
    // Kept as placed (a pan past the edge is not remembered, so panning back moves
    // the picture at once).
    const double x0 = place(area.x, area.w, film_w * scale_, t.x0), y0 = place(area.y, area.h, film_h * scale_, t.y0);
    cx_ = (area.x + area.w / 2 - x0) / scale_;
    cy_ = (area.y + area.h / 2 - y0) / scale_;
}

void ImageView::zoom_about(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py,
                           double factor) {
    if (film_w < 1 || film_h < 1 || !(factor > 0) || !(fb_scale > 0)) return;
    ViewTransform t = transform(area, film_w, film_h);
    double s = std::min(t.sx, t.sy);
    double s1 = std::clamp(s * factor, kMinRatio / fb_scale, kMaxRatio / fb_scale);
    // The picture point under the cursor stays under it.
    double u = t.to_picture_x(px), v = t.to_picture_y(py);
    ViewTransform z;
    z.sx = z.sy = s1;
    z.x0 = px - u * s1;
    z.y0 = py - v * s1;
    set_from(area, film_w, film_h, z);
}

void ImageView::zoom_steps(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py,
                           double steps) {
    if (steps == 0 || film_w < 1 || film_h < 1 || !(fb_scale > 0)) return;
    double r = ratio(area, film_w, film_h, fb_scale);
    // Quarter stops on a ladder through 1: from an arbitrary (fitted) ratio the first
    // step lands on the ladder, later ones move along it.
    double q = 4 * std::log2(r);
    double target = steps > 0 ? std::floor(q + 1e-6) + steps : std::ceil(q - 1e-6) + steps;
    zoom_about(area, film_w, film_h, fb_scale, px, py, std::exp2(target / 4) / r);
}

void ImageView::one_to_one(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py) {
    if (film_w < 1 || film_h < 1 || !(fb_scale > 0)) return;
    ViewTransform t = transform(area, film_w, film_h);
    double s1 = 1 / fb_scale;
    double u = t.to_picture_x(px), v = t.to_picture_y(py);
    ViewTransform z;
    z.sx = z.sy = s1;
    // Whole framebuffer pixels: each texel then covers exactly one screen pixel.
    z.x0 = std::round((px - u * s1) * fb_scale) / fb_scale;
    z.y0 = std::round((py - v * s1) * fb_scale) / fb_scale;
    set_from(area, film_w, film_h, z);
}

void ImageView::pan(const Rect& area, int film_w, int film_h, double dx, double dy) {
    if (film_w < 1 || film_h < 1) return;
    ViewTransform t = transform(area, film_w, film_h);
    if (fit_) t.sy = t.sx;  // leaving the fit: one scale for both axes
    t.x0 += dx;
    t.y0 += dy;
    set_from(area, film_w, film_h, t);
}

bool picture_pixel_at(const ViewTransform& t, int film_w, int film_h, double px, double py, int& x, int& y) {
    double u = std::floor(t.to_picture_x(px)), v = std::floor(t.to_picture_y(py));
    if (!(u >= 0 && v >= 0 && u < film_w && v < film_h)) return false;
    x = int(u);
    y = int(v);
    return true;
}

std::array<int, 4> visible_pixels(const ViewTransform& t, const Rect& area, int film_w, int film_h) {
    auto lo = [](double v, int n) { return std::clamp(int(std::floor(v)), 0, n); };
    auto hi = [](double v, int n) { return std::clamp(int(std::ceil(v)), 0, n); };
    return {lo(t.to_picture_x(area.x), film_w), lo(t.to_picture_y(area.y), film_h),
            hi(t.to_picture_x(area.x + area.w), film_w), hi(t.to_picture_y(area.y + area.h), film_h)};
}

void visible_uv(const ViewTransform& t, const Rect& area, int film_w, int film_h, Rect& window, std::array<double, 4>& uv) {
    Rect img = t.image(film_w, film_h);
    double x0 = std::max(img.x, area.x), y0 = std::max(img.y, area.y);
    double x1 = std::min(img.x + img.w, area.x + area.w), y1 = std::min(img.y + img.h, area.y + area.h);
    if (x1 <= x0 || y1 <= y0 || img.w <= 0 || img.h <= 0) {
        window = {};
        uv = {0, 0, 0, 0};
        return;
    }
    window = {x0, y0, x1 - x0, y1 - y0};
    uv = {(x0 - img.x) / img.w, (y0 - img.y) / img.h, (x1 - img.x) / img.w, (y1 - img.y) / img.h};
}

}  // namespace rtview
