// ViewerApp's account of itself: --print-layout (the layout and what the frame
// showed, in words) and the digest of what a frame shows (see app.h).
#include "app.h"

#include <imgui.h>
#include <imgui_internal.h>  // the open popups: 1.86 has no public equivalent

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <algorithm>
#include <optional>

#include "diagnostic_text.h"
#include "probe.h"
#include "scene_writer.h"

namespace rtview {

namespace {

double clock_seconds(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double thread_cpu_seconds() { return clock_seconds(CLOCK_THREAD_CPUTIME_ID); }
double wall_seconds() { return clock_seconds(CLOCK_MONOTONIC); }

}  // namespace

void ViewerApp::frame_timing_begin() {
    frame_cpu0_ = thread_cpu_seconds();
    frame_wall0_ = wall_seconds();
}

void ViewerApp::frame_timing_end() {
    const double wall = wall_seconds() - frame_wall0_;
    longest_frame_ = std::max(longest_frame_, wall);
    if (wall > kStalledFrame) ++stalled_frames_;
    const double took = thread_cpu_seconds() - frame_cpu0_;
    slowest_frame_ = std::max(slowest_frame_, took);
    if (took > kSlowFrame) ++slow_frames_;
    if (took > 2 * kSlowFrame) ++very_slow_frames_;
    if (opt_.verbose && (took > kSlowFrame || wall > kStalledFrame))
        std::fprintf(stderr, "raytracer-view: slow frame %d: %.1f ms of UI-thread CPU, %.1f ms of wall time\n", frames_,
                     took * 1000, wall * 1000);
}

void ViewerApp::probe_frame() {
    if (!opt_.print_layout) return;
    // (Of the frames before this one.)
    probe("slow_frames", std::to_string(slow_frames_));
    probe("very_slow_frames", std::to_string(very_slow_frames_));
    probe("slowest_frame_ms", std::to_string(int(slowest_frame_ * 1000)));
    probe("stalled_frames", std::to_string(stalled_frames_));
    probe("longest_frame_ms", std::to_string(int(longest_frame_ * 1000)));
    const Document& doc = editor_.doc();
    probe("title", doc.title());
    probe("load", loader_.active() ? "loading" : doc.has_scene() ? "ready" : "no scene");
    probe("message", (status_.error() ? "error: " : "") + status_.text());
    std::string popups;
    for (const ImGuiPopupData& p : GImGui->OpenPopupStack)
        if (p.Window) popups += (popups.empty() ? "" : "|") + std::string(p.Window->Name);
    probe("popups", popups.empty() ? "none" : popups);
    probe("readout", tools_.readout_line().empty() ? "none" : tools_.readout_line());
    {
        const ImGuiIO& io = ImGui::GetIO();
        char pointer[96];
        std::snprintf(pointer, sizeof pointer, "%.0f %.0f%s%s", io.MousePos.x, io.MousePos.y,
                      io.WantCaptureMouse ? " ui" : "", ImGui::IsAnyMouseDown() ? " down" : "");
        probe("pointer", pointer);
    }
    const rt::RenderProgress p = render_.progress();
    // What another program would paste, once something was copied.
    if (!tools_.copied().empty()) {
        const char* clip = ImGui::GetClipboardText();
        probe("clipboard", clip ? clip : "");
    }
    // The picture rendered (not its place on the screen), and how far it has come.
    probe("film", std::to_string(p.width) + "x" + std::to_string(p.height) + " " + std::to_string(p.samples) +
                      " spp generation " + std::to_string(p.generation));
    probe("render", std::to_string(p.samples) + " " + (p.done ? "done" : p.running ? "running" : "idle"));
    // Whether the picture is of the scene the panels show (its world compiled, its
    // render on the screen), or of an older one while that one is made.
    probe("picture", !doc.has_scene() ? "none" : render_.picture_current(doc.content_version()) ? "current" : "updating");
    // As raytracer's options would ask for this render (scripts render its twin).
    probe("render_settings", "--samples " + std::to_string(render_.max_samples()) +
                                 (render_.aa_threshold() >= 0 ? " --aa-threshold " + rt::format_number(render_.aa_threshold())
                                                               : std::string()));
    probe("diagnostics", std::to_string(doc.diagnostics().size()) +
                             (doc.diagnostics().empty() ? "" : " " + doc.diagnostics().front().message));
    // What the scene and the text hold (a refused Open leaves both alone).
    probe("scene_size", doc.has_scene() ? std::to_string(doc.scene().objects.size()) + " objects " +
                                              std::to_string(doc.scene().planes.size()) + " planes " +
                                              std::to_string(doc.scene().lights.size()) + " lights"
                                        : std::string("none"));
    probe("editor_bytes", std::to_string(doc.editor_text().size()));
    probe("undo_depth", std::to_string(doc.undo_depth()) + (doc.edit_held() ? " held" : ""));
    probe("text", std::string(doc.unapplied() ? "unapplied" : doc.has_scene() ? "applied" : "no scene") + (doc.text_behind() ? " behind" : ""));
}

std::uint64_t ViewerApp::visible_key() const {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
    auto mix_text = [&mix](const std::string& s) { mix(text_hash(s)); };
    const Document& doc = editor_.doc();
    mix_text(status_.text());
    mix(status_.error());
    mix(doc.text_version());
    mix(doc.typed());
    mix(doc.scene_version());
    mix(doc.has_scene());
    const auto& diags = doc.diagnostics();
    mix(diags.size());
    for (std::size_t k = 0; k < diags.size() && k < 32; ++k) {
        mix(std::uint64_t(diags[k].line) << 32 | std::uint32_t(diags[k].col));
        mix_text(diags[k].message);
    }
    mix(loader_.active());
    if (loader_.active()) mix(std::uint64_t(loader_.progress().stage));
    mix(tools_.busy());
    mix(tools_.final_render_running());
    mix_text(tools_.readout_line());
    // A zoom key changes where the picture is after this frame's layout was made.
    const Rect zoomed = tools_.image_rect();
    for (double v : {zoomed.x, zoomed.y, zoomed.w, zoomed.h}) mix(std::uint64_t(std::llround(v * 16)));
    const rt::RenderProgress p = render_.progress();
    mix(p.generation);
    mix(std::uint64_t(p.samples));
    mix(p.done);
    mix(render_.paused());
    return h;
}
std::string ViewerApp::layout_text() const {
    float fb = layout_.fb_scale;
    auto px = [fb](const Rect& r) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%ld %ld %ld %ld", std::lround(r.x * fb), std::lround(r.y * fb),
                      std::lround(r.w * fb), std::lround(r.h * fb));
        return std::string(buf);
    };
    ImGuiIO& io = ImGui::GetIO();
    const Layout& l = layout_;
    Rect window{0, 0, io.DisplaySize.x, io.DisplaySize.y};
    Rect sidebar{window.w - l.sidebar_w, l.menu_h, l.sidebar_w, window.h - l.menu_h};
    Rect bar{0, window.h - l.status_h, l.area.w, l.status_h};
    Panels::Tab tab = panels_.current_tab();
    std::string s;
    s += "window " + px(window) + "\n";
    s += "area " + px(l.area) + "\n";
    s += "image " + px(l.image) + "\n";
    s += "film " + std::to_string(l.film_w) + " " + std::to_string(l.film_h) + "\n";
    s += "sidebar " + px(sidebar) + "\n";
    s += "camera " + px(l.camera_panel) + "\n";
    s += "outline " + px(tab == Panels::Objects ? l.outline : Rect{}) + "\n";
    s += "editor " + px(tab == Panels::Text ? l.editor : Rect{}) + "\n";
    s += "diagnostics " + px(tab == Panels::Text ? l.diagnostics : Rect{}) + "\n";
    s += "status " + px(bar) + "\n";
    // Where the move handle of the selection sits (its anchor) and what it moves
    // ("object 3", 1-based as in the outline), for tests that drag it.
    const Document& doc = editor_.doc();
    std::optional<SceneItem> item = item_of_selection(panels_.selection());
    std::optional<rt::Vec3> anchor;
    const std::vector<int>& path = panels_.selection().path;
    if (item && doc.has_scene() && nav_.has_view()) anchor = item_anchor(doc.scene(), *item, path);
    std::optional<ScreenPoint> at;
    if (anchor) at = screen_view().project(*anchor);
    const Selection& many = panels_.selected();
    if (!many.many.empty() && doc.has_scene() && nav_.has_view()) {
        // Several things: their handle at the centre ("group 3": how many it moves).
        const std::optional<rt::Vec3> centre = group_anchor(doc.scene(), many.many);
        if (centre) at = screen_view().project(*centre);
        if (at)
            s += "handle " + std::to_string(std::lround(at->x * fb)) + " " + std::to_string(std::lround(at->y * fb)) +
                 " group " + std::to_string(many.many.size()) + "\n";
        else s += "handle none\n";
    } else if (at) {
        const char* kind = item->kind == SceneItem::Kind::Object ? "object" : item->kind == SceneItem::Kind::Plane ? "plane" : "light";
        s += "handle " + std::to_string(std::lround(at->x * fb)) + " " + std::to_string(std::lround(at->y * fb)) + " " +
             kind + " " + std::to_string(item->index + 1);
        for (int k : path) s += k == 0 ? " left" : " right";  // an operand: "object 4 left"
        s += "\n";
    }
    else s += "handle none\n";
    for (const auto& [key, value] : probes()) s += "state " + key + " " + value + "\n";
    return s;
}

}  // namespace rtview
