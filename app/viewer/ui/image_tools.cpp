// The picture tools (see image_tools.h): input, textures and drawing. Keys are read
// as the GLFW backend reports them in io.KeysDown (GLFW key codes; ImGui 1.86 maps
// only a few), like the app's own shortcuts.
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

// "3 s", "1 min 20 s", "2 h 5 min": a time left as a person would say it.
std::string format_duration(double seconds) {
    char buf[48];
    const long t = std::lround(std::max(0.0, std::min(seconds, 1e7)));
    if (t < 60) std::snprintf(buf, sizeof buf, "%ld s", std::max(1L, t));
    else if (t < 3600) std::snprintf(buf, sizeof buf, "%ld min %ld s", t / 60, t % 60);
    else std::snprintf(buf, sizeof buf, "%ld h %ld min", t / 3600, (t % 3600) / 60);
    return buf;
}

constexpr double kSplitGrab = 5;          // window units either side of the split line
constexpr double kReadoutRefresh = 0.25;  // seconds: the hovered pixel's value while rendering
constexpr double kDiffRefresh = 0.25;     // seconds between difference images while rendering

ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

// A hint that wraps at the panel's edge instead of running off it.
void hint(const char* text) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextDisabled("%s", text);
    ImGui::PopTextWrapPos();
}

// Text with a dark box behind it, legible on any picture.
void label(ImDrawList* dl, ImVec2 at, const std::string& text, ImU32 colour = IM_COL32(255, 255, 255, 255)) {
    ImVec2 sz = ImGui::CalcTextSize(text.c_str());
    float pad = ImGui::GetFontSize() * 0.25f;
    dl->AddRectFilled(ImVec2(at.x - pad, at.y - pad), ImVec2(at.x + sz.x + pad, at.y + sz.y + pad), rgba(0, 0, 0, 190),
                      pad);
    dl->AddText(at, colour, text.c_str());
}

std::string clock_time(std::time_t t) {
    char buf[32];
    std::strftime(buf, sizeof buf, "%H:%M:%S", std::localtime(&t));
    return buf;
}

}  // namespace

ImageTools::ImageTools(bool verbose, rt::ThreadPool& pool) : verbose_(verbose), region_(pool), final_(pool) {}

ImageTools::~ImageTools() {
    region_.cancel();
    final_.cancel();
}

void ImageTools::message(const std::string& text, bool error) {
    message_ = text;
    message_error_ = error;
    has_message_ = true;
    if (verbose_) {
        std::printf("message: %s\n", text.c_str());
        std::fflush(stdout);
    }
}

void ImageTools::copy_pixel(const std::string& readout) {
    if (readout.empty()) return;
    ImGui::SetClipboardText(readout.c_str());
    copied_ = readout;
    message("Copied to the clipboard: " + readout);
}

bool ImageTools::take_message(std::string& text, bool& error) {
    if (!has_message_) return false;
    text = message_;
    error = message_error_;
    has_message_ = false;
    return true;
}

bool ImageTools::take_ui_scale_change() {
    bool c = ui_scale_changed_;
    ui_scale_changed_ = false;
    return c;
}

bool ImageTools::busy() const {
    return drag_ != Drag::None || final_.active() || (region_active() && !region_.done());
}

ViewTransform ImageTools::transform() const {
    if (view_.fitted()) {
        // Exactly where the app fits the film, so that picking and the picture agree.
        ViewTransform t;
        t.x0 = f_.image.x;
        t.y0 = f_.image.y;
        t.sx = f_.image.w / pic_w();
        t.sy = f_.image.h / pic_h();
        return t;
    }
    return view_.transform(f_.area, pic_w(), pic_h(), f_.fb_scale);
}

Rect ImageTools::image_rect() const { return transform().image(pic_w(), pic_h()); }

double ImageTools::zoom_ratio() const {
    ViewTransform t = transform();
    return std::min(t.sx, t.sy) * f_.fb_scale;
}

void ImageTools::set_exposure(double stops) {
    display_.exposure = std::clamp(stops, -kMaxExposure, kMaxExposure);
    char buf[64];
    std::snprintf(buf, sizeof buf, "Exposure %+.1f stops", display_.exposure);
    message(buf);
}

void ImageTools::set_ui_scale(double s) {
    if (s == settings_.ui_scale()) return;
    const rt::Status saved = settings_.set_ui_scale(s);
    ui_scale_changed_ = true;
    if (!saved) message("UI scale not saved: " + saved.message(), true);
    else message("UI scale " + std::to_string(int(std::lround(settings_.ui_scale() * 100))) + "%");
}

void ImageTools::set_compare(int mode) {
    if (mode != 0 && snapshots_.list().empty()) {
        message("No snapshot to compare with: K keeps one", true);
        return;
    }
    compare_ = Compare(std::clamp(mode, 0, 2));
    message(compare_ == Compare::Split        ? "Compare: snapshot | live (drag the line)"
            : compare_ == Compare::Difference ? "Compare: difference"
                                              : "Compare off");
}

// ---------------------------------------------------------------------------------
// Input

void ImageTools::handle_keys() {
    ImGuiIO& io = ImGui::GetIO();
    const bool plus = key_pressed(keys::kEqual, true) || key_pressed(keys::kKpAdd, true);
    const bool minus = key_pressed(keys::kMinus, true) || key_pressed(keys::kKpSubtract, true);
    const bool zero = key_pressed(keys::k0) || key_pressed(keys::kKp0);
    if (io.KeyCtrl && !io.KeyAlt) {
        // The UI scale works even in a text field: it is never text.
        double s = settings_.ui_scale();
        if (plus) s = next_ui_scale(s, +1);
        if (minus) s = next_ui_scale(s, -1);
        if (zero) s = 1;
        set_ui_scale(s);
        if (f_.keys_free && key_pressed(keys::kR) && !io.KeyShift && f_.scene) open_render_dialog();
        if (f_.keys_free && key_pressed(keys::kC) && !io.KeyShift && !readout_text_.empty()) copy_pixel(readout_text_);
        return;
    }
    if (!f_.keys_free || io.KeyAlt || io.KeySuper) return;
    if (plus) set_exposure(display_.exposure + 1);
    if (minus) set_exposure(display_.exposure - 1);
    if (zero) set_exposure(0);
    if (key_pressed(keys::kT)) {
        display_.curve = display_.curve == ToneCurve::Clip ? ToneCurve::Soft : ToneCurve::Clip;
        message(display_.curve == ToneCurve::Soft ? "Tone curve: soft" : "Tone curve: clip");
    }
    if (key_pressed(keys::kO)) {
        display_.show_clipped = !display_.show_clipped;
        message(display_.show_clipped ? "Marking clipped pixels" : "Clipped pixels not marked");
    }
    ImVec2 m = io.MousePos;
    bool over = f_.area.contains(m.x, m.y);
    double cx = over ? m.x : f_.area.x + f_.area.w / 2, cy = over ? m.y : f_.area.y + f_.area.h / 2;
    if (key_pressed(keys::k1) || key_pressed(keys::kKp1)) {
        view_.one_to_one(f_.area, pic_w(), pic_h(), f_.fb_scale, cx, cy);
        message("Zoom 1:1");
    }
    if (key_pressed(ImGui::GetKeyIndex(ImGuiKey_Home))) {
        view_.fit();
        message("Zoom to fit");
    }
    if (key_pressed(keys::kK)) keep_snapshot();
    if (key_pressed(keys::kB)) set_compare((int(compare_) + 1) % 3);
    if (key_pressed(keys::kC) && region_active()) clear_region();
}

bool ImageTools::handle_mouse() {
    ImGuiIO& io = ImGui::GetIO();
    const double mx = io.MousePos.x, my = io.MousePos.y;
    if (drag_ != Drag::None) {
        const int button = drag_ == Drag::Pan ? 1 : 0;
        if (drag_ == Drag::Pan) {
            view_.pan(f_.area, pic_w(), pic_h(), mx - drag_last_x_, my - drag_last_y_);
        } else if (drag_ == Drag::Split) {
            Rect img = image_rect();
            if (img.w > 0) split_ = std::clamp((mx - img.x) / img.w, 0.0, 1.0);
            ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
        }
        drag_last_x_ = mx;
        drag_last_y_ = my;
        if (!ImGui::IsMouseDown(button)) {
            if (drag_ == Drag::Region) {
                PixelRect r = region_from_drag(transform(), pic_w(), pic_h(), drag_x_, drag_y_, mx, my);
                if (r.empty()) message("The region must overlap the picture", true);
                else start_region(r);
            }
            drag_ = Drag::None;
        }
        return true;
    }
    if (!f_.mouse_free || !f_.area.contains(mx, my) || !film_ready()) return false;
    // Ctrl+wheel: zoom about the cursor (the plain wheel stays the camera's dolly).
    if (io.KeyCtrl && io.MouseWheel != 0) {
        view_.zoom_steps(f_.area, pic_w(), pic_h(), f_.fb_scale, mx, my, io.MouseWheel > 0 ? 1 : -1);
        return true;
    }
    Rect img = image_rect();
    const bool near_split = compare_ == Compare::Split && img.contains(mx, my) &&
                            std::fabs(mx - (img.x + split_ * img.w)) <= kSplitGrab;
    if (near_split) ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
    auto begin = [&](Drag d) {
        drag_ = d;
        drag_x_ = drag_last_x_ = mx;
        drag_y_ = drag_last_y_ = my;
        return true;
    };
    if (ImGui::IsMouseClicked(0) && near_split && !io.KeyCtrl) return begin(Drag::Split);
    if (io.KeyCtrl && ImGui::IsMouseClicked(0) && f_.scene) return begin(Drag::Region);
    if (io.KeyCtrl && (ImGui::IsMouseClicked(1) || ImGui::IsMouseClicked(2))) return begin(Drag::Pan);
    // Ctrl held over the picture belongs to the picture tools: no camera gesture starts.
    return io.KeyCtrl && (ImGui::IsMouseClicked(0) || ImGui::IsMouseClicked(1) || ImGui::IsMouseClicked(2));
}

// ---------------------------------------------------------------------------------
// Region

void ImageTools::start_region(const PixelRect& r) {
    if (!f_.world) return;
    PixelRect fr = scale_region(r, pic_w(), pic_h(), f_.film_w, f_.film_h);
    if (fr.empty()) return;
    region_rect_ = r;
    region_film_rect_ = fr;
    region_world_ = f_.world;
    region_camera_ = f_.view_camera;
    region_samples_ = f_.max_samples;
    region_w_ = f_.film_w;
    region_h_ = f_.film_h;
    region_.start(f_.world, f_.view_camera, f_.film_w, f_.film_h, fr, f_.max_samples, f_.time_limit);
    region_error_said_ = false;
    char buf[128];
    std::snprintf(buf, sizeof buf, "Render region %d,%d - %d,%d (%dx%d); C clears it", r.x0, r.y0, r.x1, r.y1,
                  r.width(), r.height());
    message(buf);
}

void ImageTools::restart_region_if_needed() {
    if (!region_active()) return;
    if (!region_fits(f_.film_w, f_.film_h)) {
        clear_region();  // a new film size renders everything again
        return;
    }
    // An edit or a camera move re-renders the region only; the rest keeps its picture.
    // More samples refine it on from the ones it has.
    if (!f_.world) return;
    const bool same = f_.world == region_world_ && f_.view_camera == region_camera_;
    if (same && f_.max_samples > region_samples_ && region_.raise_samples(f_.max_samples))
        region_samples_ = f_.max_samples;
    else if (!same || f_.max_samples != region_samples_)
        start_region(region_rect_);
}

void ImageTools::clear_region() {
    if (!region_active()) return;
    region_.cancel();
    region_rect_ = {};
    region_world_ = nullptr;
    message("Render region cleared");
}

// ---------------------------------------------------------------------------------
// Snapshots

void ImageTools::keep_snapshot() {
    if (!film_ready() || !f_.scene) {
        message("No picture to keep yet", true);
        return;
    }
    rt::Image img = f_.film->linear_picture(*f_.renderer, f_.now);
    int samples = f_.renderer->progress().samples;
    const Snapshot* s = snapshots_.add(std::move(img), samples, *f_.scene, std::time(nullptr));
    if (!s) {
        message("The picture is too big to keep as a snapshot", true);
        return;
    }
    compare_id_ = 0;  // compare with the newest
    compare_made_id_ = -1;
    message("Kept snapshot " + std::to_string(s->id) + (s->change.empty() ? "" : " (" + s->change + ")") +
            "; B compares");
}

const Snapshot* ImageTools::compared() const {
    if (snapshots_.list().empty()) return nullptr;
    if (compare_id_ > 0)
        if (const Snapshot* s = snapshots_.find(compare_id_)) return s;
    return &snapshots_.list().back();
}

void ImageTools::update_compare() {
    const Snapshot* snap = compared();
    if (compare_ == Compare::Off || !snap || !film_ready()) return;
    const int w = f_.film->width(), h = f_.film->height();
    bool same = compare_made_id_ == snap->id && compare_made_w_ == w && compare_made_h_ == h;
    std::vector<std::uint8_t> bytes;
    if (compare_ == Compare::Split) {
        if (same && compare_made_display_ == display_ && compare_made_film_ == ~std::uint64_t(0)) return;
        const rt::Image& src = snap->image;
        if (src.width == w && src.height == h) map_to_rgba8(src, display_, bytes);
        else map_to_rgba8(resample_nearest(src, w, h), display_, bytes);
        compare_made_film_ = ~std::uint64_t(0);
    } else {
        // The live side changes while rendering: a new difference a few times a second.
        bool fresh = same && compare_made_film_ == f_.film->updates();
        if (fresh && compare_made_display_ == display_) return;
        if (same && compare_made_time_ >= 0 && f_.now - compare_made_time_ < kDiffRefresh &&
            !f_.renderer->progress().done)
            return;
        // Pixel by pixel only: a snapshot of another size (the window's picture before a
        // resize) shows another view, and resampling it would count every edge.
        if (snap->image.width != w || snap->image.height != h) {
            compare_made_id_ = -1;  // nor is the side-by-side texture a difference image
            compare_made_w_ = compare_made_h_ = 0;
            return;
        }
        rt::Image live = f_.film->linear_picture(*f_.renderer, f_.now);
        if (!difference_rgba8(snap->image, live, std::exp2(double(diff_scale_log2_)), bytes, &diff_stats_)) return;
        compare_made_film_ = f_.film->updates();
    }
    compare_texture_.upload(bytes, w, h, {0, 0, w, h});
    compare_made_id_ = snap->id;
    compare_made_w_ = w;
    compare_made_h_ = h;
    compare_made_display_ = display_;
    compare_made_time_ = f_.now;
}

// ---------------------------------------------------------------------------------
// Per frame

void ImageTools::update() {
    restart_region_if_needed();
    if (!region_error_said_ && region_active() && region_.done() && !region_.error().empty()) {
        region_error_said_ = true;
        message("Render region stopped: " + region_.error(), true);
    }
    update_compare();
    update_readout();

    if (final_.active() && final_.done()) {
        rt::RenderProgress p = final_.progress();
        const rt::Status written = final_.write();
        if (written) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "%dx%d, %d samples per pixel, %.1f s", p.width, p.height, p.samples,
                          p.elapsed);
            render_result_ = RenderResult::Saved;
            render_result_text_ = buf;
            message("Saved to " + render_path_ + " (" + buf + ")");
        } else {
            render_result_ = RenderResult::Failed;
            render_result_text_ = written.message();
            message("Cannot write " + render_path_ + ": " + written.message(), true);
        }
    }
}

void ImageTools::update_readout() {
    ImGuiIO& io = ImGui::GetIO();
    int x = -1, y = -1;
    const bool over = f_.mouse_free && film_ready() &&
                      picture_pixel_at(transform(), pic_w(), pic_h(), io.MousePos.x, io.MousePos.y, x, y);
    if (!over) {
        readout_text_.clear();
        readout_x_ = readout_y_ = -1;
        return;
    }
    // While a button is held (orbiting, panning, dragging a region) the picture moves
    // under the cursor: no readout, and no float copies of the film.
    if (ImGui::IsAnyMouseDown()) return;
    // A new pixel at once; the same pixel a few times a second while samples arrive,
    // and at once when the render ends or restarts (its last samples must show).
    const rt::RenderProgress progress = f_.renderer->progress();
    const bool render_turned = progress.done != readout_done_ || progress.generation != readout_generation_;
    if (x == readout_x_ && y == readout_y_ && !render_turned && f_.now - readout_time_ < kReadoutRefresh) return;
    PixelReadout r;
    r.x = x;
    r.y = y;
    // The film may be a preview of the picture at the size it is shown.
    int fx = x, fy = y;
    picture_to_film_pixel(x, y, pic_w(), pic_h(), f_.film_w, f_.film_h, fx, fy);
    r.has_colour = f_.film->linear_at(*f_.renderer, f_.now, render_turned ? 0 : kReadoutRefresh, fx, fy, r.linear);
    r.samples = f_.film->samples_at(fx, fy, f_.renderer->sample_count(fx, fy));  // adaptive: each its own
    if (f_.world && f_.scene) {
        r.hit = pick_pixel(*f_.world, f_.view_camera, f_.film_w, f_.film_h, fx, fy);
        r.hit_name = outline_name(*f_.scene, r.hit);
    }
    std::string text = format_readout(r);
    if (verbose_ && text != readout_text_) {
        std::printf("readout: %s\n", text.c_str());
        std::fflush(stdout);
    }
    readout_text_ = text;
    readout_x_ = x;
    readout_y_ = y;
    readout_time_ = f_.now;
    readout_done_ = progress.done;
    readout_generation_ = progress.generation;
}

// ---------------------------------------------------------------------------------
// Drawing

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
    g.img = g.t.image(pic_w(), pic_h());
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
    std::array<int, 4> v = visible_pixels(t, f_.area, pic_w(), pic_h());
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
        PixelRect r = region_from_drag(t, pic_w(), pic_h(), drag_x_, drag_y_, io.MousePos.x, io.MousePos.y);
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

// ---------------------------------------------------------------------------------
// Panel and dialog

void ImageTools::draw_panel() {
    ImGui::PushID("picture-tools");
    draw_display_controls();
    ImGui::Separator();
    draw_zoom_controls();
    ImGui::Separator();
    draw_compare_controls();
    draw_snapshot_list();
    ImGui::Separator();
    draw_region_controls();
    ImGui::Separator();
    if (ImGui::Button("Render to file... (Ctrl+R)") && f_.scene) open_render_dialog();
    ImGui::PopID();
}

// Exposure, tone curve and the clipped-pixel overlay.
void ImageTools::draw_display_controls() {
    float ex = float(display_.exposure);
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 10);
    if (ImGui::SliderFloat("exposure (stops)", &ex, -10, 10, "%+.1f")) display_.exposure = std::round(ex * 10) / 10;
    ImGui::SameLine();
    if (ImGui::SmallButton("0")) display_.exposure = 0;
    int curve = display_.curve == ToneCurve::Soft ? 1 : 0;
    ImGui::TextUnformatted("tone curve:");
    ImGui::SameLine();
    if (ImGui::RadioButton("clip", curve == 0)) display_.curve = ToneCurve::Clip;
    ImGui::SameLine();
    if (ImGui::RadioButton("soft (T)", curve == 1)) display_.curve = ToneCurve::Soft;
    ImGui::Checkbox("mark clipped pixels (O)", &display_.show_clipped);
    hint("+ / - one stop, 0 resets. Display only: saved images are unchanged.");
}

void ImageTools::draw_zoom_controls() {
    double ratio = zoom_ratio();
    if (view_.fitted()) ImGui::Text("zoom: fit (%.0f%%)", ratio * 100);
    else ImGui::Text("zoom: %.0f%%%s", ratio * 100, std::fabs(ratio - 1) < 1e-6 ? " (1:1)" : "");
    ImGui::SameLine();
    if (ImGui::SmallButton("Fit (Home)")) view_.fit();
    ImGui::SameLine();
    if (ImGui::SmallButton("1:1 (1)"))
        view_.one_to_one(f_.area, pic_w(), pic_h(), f_.fb_scale, f_.area.x + f_.area.w / 2, f_.area.y + f_.area.h / 2);
    hint("Ctrl+wheel zooms about the cursor, Ctrl+right drag pans the picture.");
}

// "Keep snapshot", the compare mode and the difference image's scale.
void ImageTools::draw_compare_controls() {
    if (ImGui::Button("Keep snapshot (K)")) keep_snapshot();
    int mode = int(compare_);
    ImGui::TextUnformatted("compare (B):");
    ImGui::SameLine();
    bool picked = ImGui::RadioButton("off", &mode, 0);
    ImGui::SameLine();
    picked |= ImGui::RadioButton("split", &mode, 1);
    ImGui::SameLine();
    picked |= ImGui::RadioButton("difference", &mode, 2);
    if (picked && mode != int(compare_)) set_compare(mode);
    if (compare_ == Compare::Difference) {
        ImGui::SetNextItemWidth(ImGui::GetFontSize() * 10);
        int s = diff_scale_log2_;
        // The slider moves through powers of two and shows the factor itself: its
        // format is the factor's text (ImGui prints a format without '%' as it is).
        const std::string factor = "x " + std::to_string(1 << s);
        char shown[32];
        std::snprintf(shown, sizeof shown, factor.c_str(), s);
        probe("difference_scale", shown);
        if (ImGui::SliderInt("difference scale", &s, 0, 10, factor.c_str(), ImGuiSliderFlags_NoInput)) {
            diff_scale_log2_ = s;
            compare_made_id_ = -1;
        }
    }
}

// The kept snapshots, newest first: click one to compare with it, x removes it.
void ImageTools::draw_snapshot_list() {
    const Snapshot* current = compared();
    int remove = 0;
    for (auto it = snapshots_.list().rbegin(); it != snapshots_.list().rend(); ++it) {
        const Snapshot& s = *it;
        ImGui::PushID(s.id);
        std::string text = "#" + std::to_string(s.id) + "  " + clock_time(s.time) + "  " + std::to_string(s.samples) +
                           " spp  " + (s.change.empty() ? "first" : s.change);
        if (ImGui::Selectable(text.c_str(), current == &s, 0, ImVec2(ImGui::GetContentRegionAvail().x - ImGui::GetFontSize() * 2, 0))) {
            compare_id_ = s.id;
            compare_made_id_ = -1;
            if (compare_ == Compare::Off) compare_ = Compare::Split;
        }
        ImGui::SameLine();
        if (ImGui::SmallButton("x")) remove = s.id;
        ImGui::PopID();
    }
    if (remove) {
        snapshots_.remove(remove);
        compare_made_id_ = -1;
        if (snapshots_.list().empty()) compare_ = Compare::Off;
    }
    if (snapshots_.list().empty()) hint("No snapshots: K keeps the picture to compare with later.");
    else ImGui::TextDisabled("%zu kept, %.0f MB of %.0f MB", snapshots_.list().size(), snapshots_.bytes() / 1048576.0,
                             snapshots_.max_bytes() / 1048576.0);
}

void ImageTools::draw_region_controls() {
    if (region_active()) {
        ImGui::Text("region %d,%d - %d,%d (%dx%d), %d spp", region_rect_.x0, region_rect_.y0, region_rect_.x1,
                    region_rect_.y1, region_rect_.width(), region_rect_.height(), region_.samples());
        ImGui::SameLine();
        if (ImGui::SmallButton("Clear (C)")) clear_region();
    } else {
        hint("Ctrl+drag in the picture: refine only that region.");
    }
}

void ImageTools::file_menu_items() {
    if (ImGui::MenuItem("Render to File...", "Ctrl+R", false, f_.scene != nullptr)) open_render_dialog();
}

void ImageTools::view_menu_items() {
    if (ImGui::BeginMenu("Exposure")) {
        if (ImGui::MenuItem("One stop brighter", "+")) set_exposure(display_.exposure + 1);
        if (ImGui::MenuItem("One stop darker", "-")) set_exposure(display_.exposure - 1);
        if (ImGui::MenuItem("Reset", "0", false, display_.exposure != 0)) set_exposure(0);
        ImGui::Separator();
        if (ImGui::MenuItem("Soft tone curve", "T", display_.curve == ToneCurve::Soft))
            display_.curve = display_.curve == ToneCurve::Soft ? ToneCurve::Clip : ToneCurve::Soft;
        if (ImGui::MenuItem("Mark clipped pixels", "O", display_.show_clipped)) display_.show_clipped = !display_.show_clipped;
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Zoom 1:1", "1"))
        view_.one_to_one(f_.area, pic_w(), pic_h(), f_.fb_scale, f_.area.x + f_.area.w / 2, f_.area.y + f_.area.h / 2);
    if (ImGui::MenuItem("Zoom to fit", "Home", view_.fitted())) view_.fit();
    ImGui::Separator();
    if (ImGui::MenuItem("Keep snapshot", "K")) keep_snapshot();
    if (ImGui::BeginMenu("Compare with snapshot", !snapshots_.list().empty())) {
        if (ImGui::MenuItem("Off", "B", compare_ == Compare::Off)) set_compare(0);
        if (ImGui::MenuItem("Side by side", "B", compare_ == Compare::Split)) set_compare(1);
        if (ImGui::MenuItem("Difference", "B", compare_ == Compare::Difference)) set_compare(2);
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Clear render region", "C", false, region_active())) clear_region();
    ImGui::Separator();
    if (ImGui::MenuItem("Larger UI", "Ctrl++")) set_ui_scale(next_ui_scale(settings_.ui_scale(), +1));
    if (ImGui::MenuItem("Smaller UI", "Ctrl+-")) set_ui_scale(next_ui_scale(settings_.ui_scale(), -1));
    if (ImGui::MenuItem("Reset UI size", "Ctrl+0", false, settings_.ui_scale() != 1)) set_ui_scale(1);
}

void ImageTools::open_render_dialog() {
    if (render_path_.empty()) {
        // "scene.txt" -> "scene.png", beside the scene.
        std::string base = f_.scene_path.empty() ? "render" : f_.scene_path;
        std::size_t dot = base.find_last_of('.'), slash = base.find_last_of('/');
        if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) base.resize(dot);
        render_path_ = base + ".png";
    }
    focus_render_path_ = true;
    render_samples_ = std::max(1, f_.max_samples);
    render_error_.clear();
    render_result_ = RenderResult::None;
    open_render_popup_ = true;
}

void ImageTools::draw_popups() {
    if (open_render_popup_) ImGui::OpenPopup("Render to file");
    open_render_popup_ = false;
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::BeginPopupModal("Render to file", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    if (final_.active()) draw_render_progress();
    else if (render_result_ != RenderResult::None) draw_render_result();
    else draw_render_setup();
    ImGui::EndPopup();
}

// While the final render runs: its progress, the time it will still take, Cancel.
void ImageTools::draw_render_progress() {
    const float fs = ImGui::GetFontSize();
    rt::RenderProgress p = final_.progress();
    const double f = final_.fraction();
    ImGui::Text("Rendering %s (%dx%d)", render_path_.c_str(), p.width, p.height);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d%%  %.1f s", int(f * 100), p.elapsed);
    ImGui::ProgressBar(float(f), ImVec2(fs * 24, 0), buf);
    // From the rate so far, once there is one to go by.
    if (f > 0.02 && p.elapsed > 0.5)
        ImGui::Text("about %s left", format_duration(p.elapsed * (1 - f) / f).c_str());
    else
        ImGui::TextDisabled("estimating the time left...");
    probe("render_dialog", "rendering " + std::to_string(int(f * 100)) + "%");
    if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
        final_.cancel();
        message("Render to file cancelled; " + render_path_ + " not written");
        ImGui::CloseCurrentPopup();
    }
}

// After the final render: where the picture went (or why it did not), until closed.
void ImageTools::draw_render_result() {
    const bool saved = render_result_ == RenderResult::Saved;
    if (saved) {
        ImGui::TextColored(ImVec4(0.55f, 0.85f, 0.55f, 1), "Saved to %s", render_path_.c_str());
        ImGui::TextDisabled("%s", render_result_text_.c_str());
    } else {
        ImGui::TextColored(ImVec4(1.0f, 0.42f, 0.42f, 1.0f), "Cannot write %s", render_path_.c_str());
        ImGui::TextWrapped("%s", render_result_text_.c_str());
    }
    probe("render_dialog", (saved ? "saved " : "failed ") + render_path_);
    if (ImGui::Button("Close") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape)) ||
        ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Enter))) {
        render_result_ = RenderResult::None;
        ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Render again...")) render_result_ = RenderResult::None;
}

// Before the final render: the file, the samples, the time limit.
void ImageTools::draw_render_setup() {
    const float fs = ImGui::GetFontSize();
    if (!f_.scene) {
        ImGui::TextUnformatted("The scene has errors: nothing to render.");
    } else {
        ImGui::Text("The scene at its picture_size, %dx%d, on the renderer of `raytracer`.", f_.scene->width,
                    f_.scene->height);
        ImGui::Checkbox("through the scene's camera (as `raytracer SCENE` renders it), not the view",
                        &render_scene_camera_);
    }
    ImGui::SetNextItemWidth(fs * 24);
    if (focus_render_path_) ImGui::SetKeyboardFocusHere();
    focus_render_path_ = false;
    bool go = bounded_input("##file", "picture.png or .ppm", render_path_, PATH_MAX, ImGuiInputTextFlags_EnterReturnsTrue);
    probe("render_field", ImGui::IsItemActive() ? "active" : "idle");
    ImGui::SameLine();
    if (ImGui::Button("Browse...")) {
        render_browser_.start(FileDialog::Mode::Save, {".png", ".ppm"}, "Images (*.png, *.ppm)", render_path_);
        ImGui::OpenPopup("Choose the picture file");
    }
    ImGui::SameLine();
    ImGui::TextUnformatted("file");
    // (Escape there closes the browser only.)
    const bool browsing = ImGui::IsPopupOpen("Choose the picture file");
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Choose the picture file", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        const FileDialog::Result r = render_browser_.draw("Choose");
        if (r == FileDialog::Result::Go) render_path_ = render_browser_.path();
        if (r != FileDialog::Result::None) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    ImGui::SetNextItemWidth(fs * 8);
    ImGui::InputInt("samples per pixel", &render_samples_);
    render_samples_ = std::clamp(render_samples_, 1, rt::kMaxSamples);
    ImGui::SetNextItemWidth(fs * 8);
    ImGui::InputDouble("time limit (s, 0: none)", &render_time_limit_, 1, 10, "%.1f");
    render_time_limit_ = std::clamp(render_time_limit_, 0.0, rt::kMaxTimeLimit);
    // Samples only where a pixel stands out or its samples disagree (raytracer --aa-threshold).
    ImGui::Checkbox("adaptive, threshold", &render_adaptive_);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(fs * 6);
    ImGui::InputDouble("##aa", &render_aa_threshold_, 0.01, 0.1, "%.3f");
    render_aa_threshold_ = std::clamp(render_aa_threshold_, 0.0, rt::kMaxAaThreshold);
    if (!render_error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.42f, 0.42f, 1.0f), "%s", render_error_.c_str());
    probe("render_dialog", "setup");
    go |= ImGui::Button("Render");
    ImGui::SameLine();
    if (ImGui::Button("Close") || (!browsing && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape)))) {
        ImGui::CloseCurrentPopup();
    } else if (go && f_.scene) {
        rt::Scene scene = *f_.scene;
        if (!render_scene_camera_) scene.camera = f_.render_camera;
        const rt::RenderRequest request =
            final_render_request(render_samples_, render_time_limit_, render_adaptive_ ? render_aa_threshold_ : -1);
        render_error_ = final_.start(scene, render_path_, request, f_.world.get()).message();
    }
}

}  // namespace rtview
