// The sidebar and its tabs, the selection, the render tab and the surround of the
// picture (see panels.h). The menu bar: menu_bar.cpp; the camera panel:
// camera_panel.cpp; the outline: outline.cpp; properties: properties.cpp; the status
// bar: status_bar.cpp.
#include "panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "camera_control.h"
#include "item_fields.h"
#include "imgui_common.h"
#include "number_field.h"
#include "layout.h"
#include "panel_widgets.h"
#include "probe.h"
#include "scene_schema.h"
#include "readout.h"
#include "render_request.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "shown_numbers.h"

namespace rtview {

void Panels::set_selected(const Selection& s) {
    sel_ = s;
    scroll_to_selection_ = true;
    if (!s.one.none() && current_tab_ != Objects) want_tab_ = Objects;
}

void Panels::select(const ItemRef& s) {
    select_one(sel_, s);
    scroll_to_selection_ = true;
    if (!s.none() && current_tab_ != Objects) want_tab_ = Objects;
}

void Panels::select_from_option(const std::string& spec) {
    std::istringstream in(spec);
    std::string kind;
    int n = 0;
    in >> kind >> n;
    sel_.many.clear();
    const rt::Scene& s = editor_.doc().scene();
    if (kind == "object" && n >= 1 && n <= int(s.objects.size())) {
        // "object 5 left right": a CSG operand below it.
        ItemRef sel{{SceneItem::Kind::Object, n - 1}, {}};
        std::string side;
        while (in >> side && (side == "left" || side == "right")) sel.path.push_back(side == "left" ? 0 : 1);
        if (resolve(s, sel)) sel_.one = sel;
    }
    if (kind == "plane" && n >= 1 && n <= int(s.planes.size())) sel_.one = {{SceneItem::Kind::Plane, n - 1}, {}};
    if (kind == "light" && n >= 1 && n <= int(s.lights.size())) sel_.one = {{SceneItem::Kind::Light, n - 1}, {}};
    scroll_to_selection_ = true;
}

// "object_3", "object_4_left", "plane_1", "light_2", "none": a selection in one word.
std::string Panels::selection_name(const ItemRef& s) {
    if (s.none()) return "none";
    std::string n = s.is(SceneItem::Kind::Object) ? "object_" : s.is(SceneItem::Kind::Plane) ? "plane_" : "light_";
    n += std::to_string(s.item.index + 1);
    for (int k : s.path) n += k == 0 ? "_left" : "_right";
    return n;
}

void Panels::draw_sidebar() {
    // (An undo or a reload may have taken selected things away, whichever tab shows.)
    if (editor_.doc().has_scene()) keep_existing(sel_, editor_.doc().scene());
    probe("selection", selection_name(sel_.one));
    if (layout_.sidebar_hidden) return;
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - layout_.sidebar_w, layout_.menu_h));
    ImGui::SetNextWindowSize(ImVec2(layout_.sidebar_w, io.DisplaySize.y - layout_.menu_h));
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                             ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                             ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (!ImGui::Begin("##sidebar", nullptr, flags)) {
        ImGui::End();
        return;
    }
    editor_.draw_banners();
    draw_camera_panel();
    if (editor_.wants_text_tab()) want_tab_ = Text;
    if (ImGui::BeginTabBar("tabs")) {
        static const char* const names[3] = {"Objects", "Text", "Render"};
        const Document& doc = editor_.doc();
        for (int t = 0; t < 3; ++t) {
            ImGuiTabItemFlags tf = want_tab_ == t ? ImGuiTabItemFlags_SetSelected : 0;
            std::string label = names[t];
            if (t == Text && (doc.editor_dirty() || doc.has_errors()))
                label += doc.has_errors() ? " (errors)" : " (unapplied)";
            if (t == Text) probe("text_tab", label);
            label += "###tab" + std::to_string(t);  // stable ID while the label changes
            const bool shown = ImGui::BeginTabItem(label.c_str(), nullptr, tf);
            probe_item(std::string("tab_") + names[t]);
            if (shown) {
                current_tab_ = t;
                if (want_tab_ == t) want_tab_ = -1;
                if (t == Objects) draw_objects_tab();
                if (t == Text) editor_.draw_text_tab(layout_);
                if (t == Render) draw_render_tab();
                ImGui::EndTabItem();
            }
        }
        ImGui::EndTabBar();
    }
    ImGui::End();
    draw_sidebar_edge();
}

// The sidebar's left edge, a few pixels either side: dragging it sets the sidebar's
// width, kept in the settings once the button is released.
void Panels::draw_sidebar_edge() {
    ImGuiIO& io = ImGui::GetIO();
    const float W = io.DisplaySize.x, ui = float(tools_.ui_scale());
    const float grip = std::max(6.f, std::round(ImGui::GetFontSize() * 0.4f));
    const float edge = W - layout_.sidebar_w;
    ImGui::SetNextWindowPos(ImVec2(edge - grip / 2, layout_.menu_h));
    ImGui::SetNextWindowSize(ImVec2(grip, io.DisplaySize.y - layout_.menu_h));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowMinSize, ImVec2(1, 1));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoBackground |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove |
                                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoFocusOnAppearing;
    if (ImGui::Begin("##sidebar_edge", nullptr, flags)) {
        ImGui::InvisibleButton("edge", ImVec2(grip, io.DisplaySize.y - layout_.menu_h));
        const bool active = ImGui::IsItemActive();
        if (ImGui::IsItemActivated()) edge_grab_ = (W - io.MousePos.x) - layout_.sidebar_w;
        if (ImGui::IsItemHovered() || active) {
            ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
            ImGui::GetWindowDrawList()->AddLine(ImVec2(edge, layout_.menu_h), ImVec2(edge, io.DisplaySize.y),
                                                ImGui::GetColorU32(ImGuiCol_SeparatorActive), 2);
        }
        if (active) {
            const float w = std::clamp(W - io.MousePos.x - edge_grab_, sidebar_min_width(W, ui), sidebar_max_width(W, ui));
            (void)tools_.settings().set_sidebar_share(w / W, false);  // saved on release
        }
        if (ImGui::IsItemDeactivated())
            if (rt::Status st = tools_.settings().set_sidebar_share(layout_.sidebar_w / W); !st)
                status_.set("The sidebar's width was not saved: " + st.message(), true);
    }
    ImGui::End();
    ImGui::PopStyleVar(2);
}

void Panels::draw_render_tab() {
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::CollapsingHeader("Picture")) {
        tools_.draw_panel();
        ImGui::Spacing();
    }
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 11);
    // Dragged live; typed values (Ctrl+click) apply on Enter, not a digit at a time:
    // "256" typed must not stop the render at 2 samples first.
    static const double kLeastSamples = 1, kMostSamples = rt::kMaxSamples, kNoLimit = 0, kMaxLimit = rt::kMaxTimeLimit;
    double samples = render_.max_samples();
    if (number_field("samples per pixel", &samples, {0.5f, &kLeastSamples, &kMostSamples, "%.0f", false, true}))
        render_.set_max_samples(int(std::clamp(std::round(samples), kLeastSamples, kMostSamples)));
    probe_item("field_samples");
    double limit = render_.time_limit();
    if (number_field("time limit (s)", &limit, {0.1f, &kNoLimit, &kMaxLimit, "%.1f", false, true}))
        render_.set_time_limit(std::clamp(limit, kNoLimit, kMaxLimit));
    if (ImGui::IsItemHovered() && !number_typing())
        ImGui::SetTooltip("Stop refining after this many seconds; 0: no limit. Drag, or Ctrl+click to type.");
    ImGui::PopItemWidth();
    bool paused = render_.paused();
    if (ImGui::Checkbox("Paused (Space)", &paused)) commands_.run(Command::TogglePause);
    ImGui::Separator();
    ImGui::Text("Render size");
    if (ImGui::RadioButton("fill the window", layout_.fit == FitMode::Window)) commands_.run(Command::FitWindow);
    std::string pic = "scene picture_size";
    if (editor_.doc().has_scene())
        pic += " (" + std::to_string(editor_.doc().scene().width) + "x" + std::to_string(editor_.doc().scene().height) +
               ", letterboxed)";
    if (ImGui::RadioButton(pic.c_str(), layout_.fit == FitMode::Picture)) commands_.run(Command::FitPicture);
    ImGui::Separator();
    rt::RenderProgress p = render_.progress();
    ImGui::TextWrapped("film %dx%d, %d render threads", p.width, p.height, render_.threads());
    ImGui::Text("rays traced: %.3g", double(p.rays));
    if (p.first_coarse_time >= 0)
        ImGui::TextWrapped("first coarse pass: %.1f ms (%dx%d blocks)", p.first_coarse_time * 1000, render_.last_coarse_block(),
                    render_.last_coarse_block());
    if (render_.last_preview_block() > 0)
        ImGui::TextWrapped("preview while moving: %dx%d blocks on %d threads", render_.last_preview_block(),
                           render_.last_preview_block(), render_.preview_threads());
    if (render_.last_latency_ms() >= 0) ImGui::TextWrapped("last view change to image: %.1f ms", render_.last_latency_ms());
    ImGui::Separator();
    if (ImGui::Button("Save image... (Ctrl+P)")) commands_.run(Command::SaveImageDialog);
    same_line_if_fits("Screenshot (F12)");
    if (ImGui::Button("Screenshot (F12)")) commands_.run(Command::Screenshot, "raytracer-view-screenshot.png");
}


void Panels::draw_surround() {
    const Rect& a = layout_.area;
    const Rect& im = layout_.image;
    if (im.w >= a.w && im.h >= a.h) return;
    // What lies outside the scene's picture is not rendered: a dimmed passepartout
    // shows where the picture ends.
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    ImU32 dim = IM_COL32(12, 12, 13, 255);
    auto fill = [&](double x0, double y0, double x1, double y1) {
        if (x1 > x0 && y1 > y0) dl->AddRectFilled(ImVec2(float(x0), float(y0)), ImVec2(float(x1), float(y1)), dim);
    };
    fill(a.x, a.y, a.x + a.w, im.y);                        // above
    fill(a.x, im.y + im.h, a.x + a.w, a.y + a.h);           // below
    fill(a.x, im.y, im.x, im.y + im.h);                     // left
    fill(im.x + im.w, im.y, a.x + a.w, im.y + im.h);        // right
    dl->AddRect(ImVec2(float(im.x) - 1, float(im.y) - 1), ImVec2(float(im.x + im.w) + 1, float(im.y + im.h) + 1),
                IM_COL32(70, 70, 74, 255));
}

}  // namespace rtview
