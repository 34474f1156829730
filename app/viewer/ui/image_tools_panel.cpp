// The picture tools' panel (see image_tools.h): display, zoom, compare, snapshots,
// region, and their menu items.
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

// A hint that wraps at the panel's edge instead of running off it.
void hint(const char* text) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextDisabled("%s", text);
    ImGui::PopTextWrapPos();
}

}  // namespace

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
        view_.one_to_one(f_.area, film_w(), film_h(), f_.fb_scale, f_.area.x + f_.area.w / 2, f_.area.y + f_.area.h / 2);
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
        view_.one_to_one(f_.area, film_w(), film_h(), f_.fb_scale, f_.area.x + f_.area.w / 2, f_.area.y + f_.area.h / 2);
    if (ImGui::MenuItem("Zoom to fit", "Home", view_.fitted())) view_.fit();
    ImGui::Separator();
    if (ImGui::MenuItem("Keep snapshot", "K")) keep_snapshot();
    if (ImGui::BeginMenu("Compare with snapshot", !snapshots_.list().empty())) {
        if (ImGui::MenuItem("Off", "B", compare_ == Compare::Off)) set_compare(0);
        if (ImGui::MenuItem("Side by side", "B", compare_ == Compare::Split)) set_compare(1);
        if (ImGui::MenuItem("Difference", "B", compare_ == Compare::Difference)) set_compare(2);
        if (ImGui::MenuItem("The snapshot before", "Shift+B", false, snapshots_.list().size() > 1)) next_snapshot();
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Clear render region", "C", false, region_active())) clear_region();
    ImGui::Separator();
    if (ImGui::MenuItem("Larger UI", "Ctrl++")) set_ui_scale(next_ui_scale(settings_.ui_scale(), +1));
    if (ImGui::MenuItem("Smaller UI", "Ctrl+-")) set_ui_scale(next_ui_scale(settings_.ui_scale(), -1));
    if (ImGui::MenuItem("Reset UI size", "Ctrl+0", false, settings_.ui_scale() != 1)) set_ui_scale(1);
}

}  // namespace rtview
