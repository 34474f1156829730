// The picture tools (see image_tools.h): state, input, the region, snapshots and the
// per-frame update (drawing: image_overlays.cpp; the panel: image_tools_panel.cpp;
// Render to file: render_dialog.cpp). Keys are read
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

constexpr double kSplitGrab = 5;          // window units either side of the split line
constexpr double kReadoutRefresh = 0.25;  // seconds: the hovered pixel's value while rendering
constexpr double kDiffRefresh = 0.25;     // seconds between difference images while rendering

}  // namespace

std::string clock_time(std::time_t t) {
    char buf[32];
    std::strftime(buf, sizeof buf, "%H:%M:%S", std::localtime(&t));
    return buf;
}

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
        t.sx = f_.image.w / film_w();
        t.sy = f_.image.h / film_h();
        return t;
    }
    return view_.transform(f_.area, film_w(), film_h(), f_.fb_scale);
}

Rect ImageTools::image_rect() const { return transform().image(film_w(), film_h()); }

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
        view_.one_to_one(f_.area, film_w(), film_h(), f_.fb_scale, cx, cy);
        message("Zoom 1:1");
    }
    if (key_pressed(ImGui::GetKeyIndex(ImGuiKey_Home))) {
        view_.fit();
        message("Zoom to fit");
    }
    if (key_pressed(keys::kK)) keep_snapshot();
    if (key_pressed(keys::kB)) {
        if (io.KeyShift) next_snapshot();
        else set_compare((int(compare_) + 1) % 3);
    }
    if (key_pressed(keys::kC) && region_active()) clear_region();
}

bool ImageTools::handle_mouse() {
    ImGuiIO& io = ImGui::GetIO();
    const double mx = io.MousePos.x, my = io.MousePos.y;
    if (drag_ != Drag::None) {
        const int button = drag_ == Drag::Pan ? 1 : 0;
        if (drag_ == Drag::Pan) {
            view_.pan(f_.area, film_w(), film_h(), mx - drag_last_x_, my - drag_last_y_);
        } else if (drag_ == Drag::Split) {
            Rect img = image_rect();
            if (img.w > 0) split_ = std::clamp((mx - img.x) / img.w, 0.0, 1.0);
            ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
        }
        drag_last_x_ = mx;
        drag_last_y_ = my;
        if (!ImGui::IsMouseDown(button)) {
            if (drag_ == Drag::Region) {
                PixelRect r = region_from_drag(transform(), film_w(), film_h(), drag_x_, drag_y_, mx, my);
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
        view_.zoom_steps(f_.area, film_w(), film_h(), f_.fb_scale, mx, my, io.MouseWheel > 0 ? 1 : -1);
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

void ImageTools::start_region(const PixelRect& r) {
    if (!f_.world) return;
    if (r.empty()) return;
    region_rect_ = r;
    region_world_ = f_.world;
    region_camera_ = f_.view_camera;
    region_samples_ = f_.max_samples;
    region_w_ = f_.film_w;
    region_h_ = f_.film_h;
    region_.start(f_.world, f_.view_camera, f_.film_w, f_.film_h, r, f_.max_samples, f_.time_limit);
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
            (snapshots_.list().size() > 1 ? "; B compares, Shift+B goes through the snapshots" : "; B compares"));
}

void ImageTools::next_snapshot() {
    const std::vector<Snapshot>& list = snapshots_.list();
    if (list.empty()) {
        message("No snapshot to compare with: K keeps one", true);
        return;
    }
    // Newest to oldest, then the newest again.
    const Snapshot* now = compared();
    std::size_t k = list.size() - 1;
    for (std::size_t i = 0; i < list.size(); ++i)
        if (&list[i] == now) k = i == 0 ? list.size() - 1 : i - 1;
    compare_id_ = list[k].id;
    compare_made_id_ = -1;
    if (compare_ == Compare::Off) compare_ = Compare::Split;
    message("Comparing with snapshot " + std::to_string(list[k].id) + " of " + std::to_string(list.size()) + " (" +
            clock_time(list[k].time) + ")");
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

void ImageTools::update() {
    restart_region_if_needed();
    if (!region_error_said_ && region_active() && region_.done() && !region_.error().empty()) {
        region_error_said_ = true;
        message("Render region stopped: " + region_.error(), true);
    }
    update_compare();
    update_readout();

    if (final_.active() && final_.done()) {
        const std::string what = final_.summary();
        const rt::Status written = final_.write();
        if (written) {
            render_result_ = RenderResult::Saved;
            render_result_text_ = what;
            message("Saved to " + render_path_ + " (" + what + ")");
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
                      picture_pixel_at(transform(), film_w(), film_h(), io.MousePos.x, io.MousePos.y, x, y);
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
    const int fx = x, fy = y;
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

}  // namespace rtview
