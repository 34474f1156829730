// The picture as the picture tools draw it (see image_tools.h): the film or the
// comparison, and the overlays on it: pixel grid, region, split labels, difference
// legend, display badge, zoom.
#include "image_tools.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <climits>
#include <cstdio>
#include <ctime>

#include "bounded_input.h"
#include "image_io.h"
#include "imgui_common.h"
#include "probe.h"
#include "render_request.h"

namespace rtview {

namespace {

ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

// Text with a dark box behind it, legible on any picture.
void label(ImDrawList* dl, ImVec2 at, const std::string& text, ImU32 colour = IM_COL32(255, 255, 255, 255)) {
    ImVec2 sz = ImGui::CalcTextSize(text.c_str());
    float pad = ImGui::GetFontSize() * 0.25f;
    dl->AddRectFilled(ImVec2(at.x - pad, at.y - pad), ImVec2(at.x + sz.x + pad, at.y + sz.y + pad), rgba(0, 0, 0, 190),
                      pad);
    dl->AddText(at, colour, text.c_str());
}

}  // namespace

// Where the picture stands this frame: what every overlay below is placed by.
struct ImageTools::PictureGeometry {
    ViewTransform t;
    Rect img;              // the picture, in window units
    double ratio = 1;      // screen pixels per picture pixel
    ImVec2 a0, a1;         // the area for the picture (everything is clipped to it)
    ImVec2 p0, p1;         // the picture's corners
    bool nearest = false;  // nearest filtering from 1:1 up: every film pixel a crisp square
    bool comparing = false;  // a compare image of this very film is ready
};

void ImageTools::draw() {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    if (!f_.texture || !f_.texture->valid() || !f_.film || f_.film->empty()) return;
    PictureGeometry g;
    g.t = transform();
    g.img = g.t.image(film_w(), film_h());
    g.ratio = zoom_ratio();
    g.a0 = ImVec2(float(f_.area.x), float(f_.area.y));
    g.a1 = ImVec2(float(f_.area.x + f_.area.w), float(f_.area.y + f_.area.h));
    g.p0 = ImVec2(float(g.img.x), float(g.img.y));
    g.p1 = ImVec2(float(g.img.x + g.img.w), float(g.img.y + g.img.h));
    // Sharp pixels from 1:1 up once zoomed; fitted, a picture_size film is shown
    // smoothly at the letterbox's size.
    g.nearest = view_.fitted() ? std::fabs(g.ratio - 1) < 1e-6 : g.ratio >= 1 - 1e-6;
    g.comparing = compare_ != Compare::Off && compare_texture_.valid() && compare_made_w_ == f_.film->width() &&
                  compare_made_h_ == f_.film->height();
    f_.texture->set_nearest(g.nearest);
    dl->PushClipRect(g.a0, g.a1, true);
    draw_picture(dl, g);
    if (g.ratio >= kGridRatio) draw_pixel_grid(dl, g);
    draw_region_outline(dl, g);
    const Snapshot* snap = compared();
    if (snap && compare_ != Compare::Off) {
        const std::string a = "A  snapshot " + std::to_string(snap->id) + "  " + clock_time(snap->time);
        if (compare_ == Compare::Split && g.comparing) draw_split_labels(dl, g, a);
        else if (compare_ == Compare::Difference) draw_difference_legend(dl, g, a, *snap);
    }
    if (!view_.fitted()) draw_zoom_label(dl, g);
    draw_display_badge(dl, g);
    dl->PopClipRect();
    probe("zoom", view_.fitted() ? "fit" : std::to_string(g.ratio));
}

// The live picture; or, comparing, the difference image, or snapshot | live either
// side of the split line.
void ImageTools::draw_picture(ImDrawList* dl, const PictureGeometry& g) {
    FilmTexture& texture = *f_.texture;
    if (g.comparing && compare_ == Compare::Difference) {
        compare_texture_.set_nearest(g.nearest);
        dl->AddImage(compare_texture_.id(), g.p0, g.p1);
    } else if (g.comparing && compare_ == Compare::Split) {
        compare_texture_.set_nearest(g.nearest);
        float sx = float(g.img.x + split_ * g.img.w);
        dl->PushClipRect(g.a0, ImVec2(std::max(g.a0.x, std::min(sx, g.a1.x)), g.a1.y), true);
        dl->AddImage(compare_texture_.id(), g.p0, g.p1);
        dl->PopClipRect();
        dl->PushClipRect(ImVec2(std::min(g.a1.x, std::max(sx, g.a0.x)), g.a0.y), g.a1, true);
        dl->AddImage(texture.id(), g.p0, g.p1);
        dl->PopClipRect();
    } else {
        dl->AddImage(texture.id(), g.p0, g.p1);
    }
}

// Lines between the picture's pixels, at high zoom.
void ImageTools::draw_pixel_grid(ImDrawList* dl, const PictureGeometry& g) {
    const ViewTransform& t = g.t;
    const Rect& img = g.img;
    std::array<int, 4> v = visible_pixels(t, f_.area, film_w(), film_h());
    ImU32 c = rgba(128, 128, 128, 110);
    for (int x = v[0]; x <= v[2]; ++x) {
        float wx = float(t.to_window_x(x));
        dl->AddLine(ImVec2(wx, float(std::max(img.y, f_.area.y))), ImVec2(wx, float(std::min(img.y + img.h, f_.area.y + f_.area.h))), c);
    }
    for (int y = v[1]; y <= v[3]; ++y) {
        float wy = float(t.to_window_y(y));
        dl->AddLine(ImVec2(float(std::max(img.x, f_.area.x)), wy), ImVec2(float(std::min(img.x + img.w, f_.area.x + f_.area.w)), wy), c);
    }
}

// The region with its label, and the rectangle being dragged.
void ImageTools::draw_region_outline(ImDrawList* dl, const PictureGeometry& g) {
    const ViewTransform& t = g.t;
    const float fs = ImGui::GetFontSize();
    auto outline = [&](const PixelRect& r, ImU32 colour) {
        ImVec2 q0(float(t.to_window_x(r.x0)), float(t.to_window_y(r.y0))), q1(float(t.to_window_x(r.x1)), float(t.to_window_y(r.y1)));
        dl->AddRect(ImVec2(q0.x - 1, q0.y - 1), ImVec2(q1.x + 1, q1.y + 1), rgba(0, 0, 0, 200), 0, 0, 3);
        dl->AddRect(q0, q1, colour, 0, 0, 1.5f);
    };
    if (region_active()) {
        outline(region_rect_, rgba(255, 210, 60));
        char buf[64];
        std::snprintf(buf, sizeof buf, "region  %d spp%s", region_.samples(), region_.done() ? "" : "  rendering");
        probe("region", std::to_string(region_.samples()) + (region_.done() ? " spp done" : " spp rendering"));
        label(dl, ImVec2(float(t.to_window_x(region_rect_.x0)) + fs * 0.3f, float(t.to_window_y(region_rect_.y0)) + fs * 0.3f), buf);
    }
    if (drag_ == Drag::Region) {
        ImGuiIO& io = ImGui::GetIO();
        PixelRect r = region_from_drag(t, film_w(), film_h(), drag_x_, drag_y_, io.MousePos.x, io.MousePos.y);
        if (!r.empty()) outline(r, rgba(255, 255, 255));
    }
}

// The split line, "A  snapshot ..." left of it and "B  live" right of it.
void ImageTools::draw_split_labels(ImDrawList* dl, const PictureGeometry& g, const std::string& a) {
    const float fs = ImGui::GetFontSize();
    float sx = float(g.img.x + split_ * g.img.w);
    dl->AddLine(ImVec2(sx, std::max(g.p0.y, g.a0.y)), ImVec2(sx, std::min(g.p1.y, g.a1.y)), rgba(0, 0, 0, 220), 4);
    dl->AddLine(ImVec2(sx, std::max(g.p0.y, g.a0.y)), ImVec2(sx, std::min(g.p1.y, g.a1.y)), rgba(255, 255, 255), 2);
    float top = std::max(g.p0.y, g.a0.y) + fs * 0.5f;
    ImVec2 asz = ImGui::CalcTextSize(a.c_str());
    label(dl, ImVec2(sx - asz.x - fs * 0.6f, top), a);
    label(dl, ImVec2(sx + fs * 0.6f, top), "B  live");
}

// What the difference image compares, its statistics and its scale: black (no
// difference) to white (1 / scale or more); or why there is none.
void ImageTools::draw_difference_legend(ImDrawList* dl, const PictureGeometry& g, const std::string& a,
                                        const Snapshot& snap) {
    const float fs = ImGui::GetFontSize();
    char buf[160];
    if (!g.comparing) {
        if (snap.image.width == f_.film->width() && snap.image.height == f_.film->height()) return;  // on its way
        std::snprintf(buf, sizeof buf, "The snapshot is %dx%d, the picture %dx%d: no difference image (K keeps a new one)",
                      snap.image.width, snap.image.height, f_.film->width(), f_.film->height());
        label(dl, ImVec2(std::max(g.p0.x, g.a0.x) + fs * 0.5f, std::max(g.p0.y, g.a0.y) + fs * 0.5f), buf);
        probe("difference", std::string("sizes differ: ") + buf);
        return;
    }
    std::snprintf(buf, sizeof buf, "|A - B| x %d   max %.4g   mean %.3g   %zu pixels differ", 1 << diff_scale_log2_,
                  diff_stats_.max_abs, diff_stats_.mean_abs, diff_stats_.differing);
    probe("difference", buf);
    float top = std::max(g.p0.y, g.a0.y) + fs * 0.5f;
    label(dl, ImVec2(std::max(g.p0.x, g.a0.x) + fs * 0.5f, top), a + "  vs  live");
    float by = top + fs * 1.8f, bx = std::max(g.p0.x, g.a0.x) + fs * 0.5f;
    label(dl, ImVec2(bx, by), buf);
    float gy = by + fs * 1.6f, gw = fs * 10;
    dl->AddRectFilledMultiColor(ImVec2(bx, gy), ImVec2(bx + gw, gy + fs * 0.7f), rgba(0, 0, 0), rgba(255, 255, 255),
                                rgba(255, 255, 255), rgba(0, 0, 0));
    dl->AddRect(ImVec2(bx - 1, gy - 1), ImVec2(bx + gw + 1, gy + fs * 0.7f + 1), rgba(128, 128, 128));
    char end[32];
    std::snprintf(end, sizeof end, "%.3g", 1.0 / (1 << diff_scale_log2_));
    label(dl, ImVec2(bx + gw + fs * 0.6f, gy - fs * 0.15f), std::string("0 .. ") + end);
}

// While the picture is shown otherwise than saved (exposure, tone curve, clipped
// marks): a badge saying so in its bottom-left corner.
void ImageTools::draw_display_badge(ImDrawList* dl, const PictureGeometry& g) {
    const std::string text = display_badge(display_);
    probe("display_badge", text.empty() ? "none" : text);
    if (text.empty()) return;
    const float fs = ImGui::GetFontSize();
    const ImVec2 sz = ImGui::CalcTextSize(text.c_str());
    const float x = std::max(g.p0.x, g.a0.x) + fs * 0.6f, y = std::min(g.p1.y, g.a1.y) - sz.y - fs * 0.6f;
    label(dl, ImVec2(x, y), text, rgba(255, 215, 120));
}

// The zoom in the area's corner, when not fitted.
void ImageTools::draw_zoom_label(ImDrawList* dl, const PictureGeometry& g) {
    const float fs = ImGui::GetFontSize();
    char buf[48];
    if (std::fabs(g.ratio - 1) < 1e-6) std::snprintf(buf, sizeof buf, "1:1");
    else std::snprintf(buf, sizeof buf, "%.0f%%", g.ratio * 100);
    ImVec2 sz = ImGui::CalcTextSize(buf);
    label(dl, ImVec2(g.a1.x - sz.x - fs * 0.6f, g.a1.y - sz.y - fs * 0.6f), buf);
}

}  // namespace rtview
