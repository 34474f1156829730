// Zoom and pan of the picture in the image area, independent of the camera: where
// the picture is drawn, which picture pixel lies under a window point, zoom about the
// cursor, 1:1 and fit. Pure geometry in ImGui's window units (y down); "picture"
// pixels are those of the full-resolution film, whatever a preview's resolution.
#pragma once

#include <array>

#include "viewport.h"

namespace rtview {

// window = origin + scale * picture coordinate; picture pixel k covers [k, k+1).
struct ViewTransform {
    double x0 = 0, y0 = 0;
    double sx = 1, sy = 1;  // window units per picture pixel (equal unless fitted)
    Rect image(int film_w, int film_h) const { return {x0, y0, sx * film_w, sy * film_h}; }
    double to_picture_x(double px) const { return (px - x0) / sx; }
    double to_picture_y(double py) const { return (py - y0) / sy; }
    double to_window_x(double x) const { return x0 + x * sx; }
    double to_window_y(double y) const { return y0 + y * sy; }
};

// Framebuffer pixels per picture pixel beyond which the texture is drawn with
// nearest filtering (1:1 and closer) and a grid between pixels is drawn.
constexpr double kGridRatio = 8;
constexpr double kMinRatio = 1.0 / 16, kMaxRatio = 128;

class ImageView {
public:
    bool fitted() const { return fit_; }
    // The picture letterboxed in the area (the default; follows window resizes).
    void fit() { fit_ = true; }
    // The placement for this frame. Zoomed, along each axis the picture is centred
    // where it fits in the area, and otherwise leaves no gap at either side; with
    // `fb_scale` > 0 its corner is on a whole framebuffer pixel (texels not split).
    ViewTransform transform(const Rect& area, int film_w, int film_h, double fb_scale = 0) const;
    // Framebuffer pixels per picture pixel (1 at 1:1).
    double ratio(const Rect& area, int film_w, int film_h, double fb_scale) const;

    // Scale the picture by `factor` keeping the picture point under (px, py) there.
    void zoom_about(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py, double factor);
    // Mouse-wheel zoom: `steps` quarter-powers of two, landing on exact powers of two
    // (so 1:1 is reached by wheel too).
    void zoom_steps(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py, double steps);
    // One picture pixel per framebuffer pixel, keeping the picture point under
    // (px, py) there; on whole framebuffer pixels so that texels are not split.
    void one_to_one(const Rect& area, int film_w, int film_h, double fb_scale, double px, double py);
    // Moves the picture by (dx, dy) window units, as far as its edges allow.
    void pan(const Rect& area, int film_w, int film_h, double dx, double dy);

private:
    void set_from(const Rect& area, int film_w, int film_h, const ViewTransform& t);
    bool fit_ = true;
    double scale_ = 1;        // window units per picture pixel
    double cx_ = 0, cy_ = 0;  // picture coordinate shown at the area's centre
};

// The picture pixel under a window point; false outside the picture.
bool picture_pixel_at(const ViewTransform& t, int film_w, int film_h, double px, double py, int& x, int& y);
// The picture pixels [x0, x1) x [y0, y1) at least partly visible in the area.
std::array<int, 4> visible_pixels(const ViewTransform& t, const Rect& area, int film_w, int film_h);
// The texture's part that is visible, as UV in [0, 1], and the window rectangle it
// fills (the image rectangle cut to the area): for drawing with the area as clip.
void visible_uv(const ViewTransform& t, const Rect& area, int film_w, int film_h, Rect& window, std::array<double, 4>& uv);

}  // namespace rtview
