// The camera panel: the view's eye, angles and distance, and the scene camera's
// fields (see panels.h).
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

namespace {

// What the camera panel shows of the view (its eye, and its angles and distance), for
// scripts (probe.h).
void probe_view(const rt::Camera& view, const double angles[3]) {
    char shown[160];
    std::snprintf(shown, sizeof shown, "%.2f %.2f %.2f", angles[0], angles[1], angles[2]);
    probe("view_angles", shown);
    std::snprintf(shown, sizeof shown, "%.3f %.3f %.3f", view.position.x, view.position.y, view.position.z);
    probe("view_eye", shown);
}

}  // namespace

void Panels::draw_camera_panel() {
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    const Document& doc = editor_.doc();
    // Open at first where it leaves the outline and the properties room (at a large UI
    // scale in a small window it would fill the sidebar).
    ImGui::SetNextItemOpen(ImGui::GetIO().DisplaySize.y >= 32 * ImGui::GetTextLineHeightWithSpacing(), ImGuiCond_Once);
    bool open = ImGui::CollapsingHeader("Camera");
    if (open && !doc.has_scene()) {
        ImGui::TextDisabled("No scene yet.");
    } else if (open) {
        ImGui::BeginDisabled(!doc.has_scene());
        float speed = float(rtview::scene_extent(editor_.doc().scene(), render_.world()) * 0.002);
        // Room for the longest label at any font size (UI scale).
        float label_w = 0;
        for (const char* l : {"position", "up point", "angle x, y", "projection", "az, el, dist", "focus dist", "background"})
            label_w = std::max(label_w, ImGui::CalcTextSize(l).x);
        ImGui::PushItemWidth(-(label_w + ImGui::GetStyle().ItemInnerSpacing.x + 2));

        // The view: what the image shows. Moving it never edits the file.
        rt::Camera view = nav_.camera();
        bool differs = doc.has_scene() && nav_.differs_from(doc.scene().camera);
        ImGui::TextDisabled("View%s", differs ? " (moved; not in the file)" : " (= scene camera)");
        // The numbers in a column after the labels, whatever the face's widths.
        const float value_x = ImGui::CalcTextSize("centre ").x + ImGui::GetStyle().ItemSpacing.x;
        for (const auto& [label, p] : {std::pair<const char*, rt::Vec3>{"eye", view.position}, {"centre", view.centre}}) {
            ImGui::TextUnformatted(label);
            ImGui::SameLine(value_x);
            ImGui::TextWrapped("%.3f %.3f %.3f", p.x, p.y, p.z);
        }
        ViewAngles va = view_angles(view, nav_.world_up());
        double v3[3] = {va.azimuth, va.elevation, va.distance};
        NumberFieldSpec angles;
        angles.speed = 0.25f;
        angles.format = "%.2f";
        if (number_fields("az, el, dist", v3, 3, angles))
            nav_.set(set_view_angles(view, nav_.world_up(), {v3[0], std::clamp(v3[1], -89.0, 89.0), std::max(v3[2], 1e-6)}));
        probe_view(view, v3);
        if (layout_.fit == FitMode::Window && doc.has_scene()) {
            rt::Camera vc = fit_camera_to_aspect(view, layout_.film_w, layout_.film_h);
            char fitted[96];
            std::snprintf(fitted, sizeof fitted, "window shows angle_x %.1f (fitted to %dx%d)", vc.angle_x, layout_.film_w,
                          layout_.film_h);
            wrapped_hint(fitted);
        }
        ImGui::BeginDisabled(!differs);
        if (ImGui::Button("Set scene camera from view")) commands_.run(Command::SetSceneCamera);
        ImGui::EndDisabled();
        same_line_if_fits("Copy camera block");
        if (ImGui::Button("Copy camera block")) commands_.run(Command::CopyCamera);
        if (ImGui::Button("Frame (F)")) commands_.run(Command::FrameScene);
        same_line_if_fits("Reset view (R)");
        ImGui::BeginDisabled(!differs);
        if (ImGui::Button("Reset view (R)")) commands_.run(Command::ResetView);
        ImGui::EndDisabled();

        draw_scene_camera_fields(speed);
        ImGui::PopItemWidth();
        ImGui::EndDisabled();
    }
    layout_.camera_panel = item_block(top, width);
}

// The New: camera keys: the lens (aperture, focus distance) and the background.
// The focus distance shows the centre's distance while it is not given (0); "Focus
// here" in the picture's menu sets it to a surface.
bool Panels::draw_lens_fields(rt::Camera& cam, float speed) {
    bool changed = false;
    const double zero = 0;
    NumberFieldSpec lens;
    lens.speed = speed * 0.1f;
    lens.min = &zero;
    lens.clamp_typed = true;
    double aperture = cam.aperture;
    if (number_field("aperture", &aperture, lens)) {
        cam.aperture = std::max(0.0, aperture);
        changed = true;
    }
    probe_item("field_camera_aperture");
    const bool automatic = !(cam.focus_distance > 0);
    double focus = automatic ? rt::length(cam.centre - cam.position) : cam.focus_distance;
    NumberFieldSpec fs;
    fs.speed = speed;
    fs.format = automatic ? "%.3f (centre)" : "%.3f";
    if (number_field("focus dist", &focus, fs) && focus > 0) {
        cam.focus_distance = focus;
        changed = true;
    }
    probe_item("field_camera_focus_distance");
    if (!automatic) {
        same_line_if_fits("centre");
        if (ImGui::SmallButton("centre")) {
            cam.focus_distance = 0;  // back to the centre's distance (the key is left out)
            changed = true;
        }
    }
    float bg[3] = {float(cam.background.x), float(cam.background.y), float(cam.background.z)};
    if (ImGui::ColorEdit3("background", bg, ImGuiColorEditFlags_Float)) {
        cam.background = {from_widget(cam.background.x, bg[0], 3), from_widget(cam.background.y, bg[1], 3),
                          from_widget(cam.background.z, bg[2], 3)};
        changed = true;
    }
    probe_item("field_camera_background");
    return changed;
}

// The scene camera: part of the document (edits here are undoable edits of the
// file, and the view follows them).
void Panels::draw_scene_camera_fields(float speed) {
    const Document& doc = editor_.doc();
    ImGui::Separator();
    ImGui::TextDisabled("Scene camera (in the file)");
    // Disabled, not hidden, while the text blocks edits: the panels below keep their place.
    const bool blocked = !doc.edit_blocker().empty();
    ImGui::BeginDisabled(blocked);
    rt::Camera cam = doc.scene().camera;
    bool changed = false;
    changed |= drag_vec3("position", cam.position, speed);
    changed |= drag_vec3("centre", cam.centre, speed);
    changed |= drag_vec3("up point", cam.up, speed);
    double ang[2] = {cam.angle_x, cam.angle_y};
    const double amin = 0.5, amax = 179.5;
    NumberFieldSpec fov;
    fov.speed = 0.1f;
    fov.min = &amin;
    fov.max = &amax;
    fov.format = "%.2f deg";
    fov.clamp_typed = true;
    if (number_fields("angle x, y", ang, 2, fov)) {
        cam.angle_x = ang[0];
        cam.angle_y = ang[1];
        changed = true;
    }
    int proj = cam.projection == rt::Projection::Polar ? 1 : 0;
    if (ImGui::Combo("projection", &proj, "linear\0polar (equal angle)\0")) {
        cam.projection = proj ? rt::Projection::Polar : rt::Projection::Linear;
        changed = true;
    }
    // The New: keys in a section of their own, closed until a scene uses them: the
    // sidebar keeps its room for the outline and the text.
    const bool used = cam.aperture > 0 || cam.focus_distance > 0 || !(cam.background == rt::Colour{});
    ImGui::SetNextItemOpen(used, ImGuiCond_Once);
    const bool lens_open = ImGui::TreeNodeEx("Lens and background", ImGuiTreeNodeFlags_SpanAvailWidth);
    probe_item("camera_lens_section");
    if (lens_open) {
        changed |= draw_lens_fields(cam, speed);
        ImGui::TreePop();
    }
    ImGui::EndDisabled();
    if (blocked) changed = false;
    if (changed && !rt::camera_problem(cam)) editor_.doc().edit_camera() = cam;
    else if (changed) status_.set(std::string("Camera not changed: ") + rt::camera_problem(cam), true);
    bool error = true;
    if (std::string refused; take_number_refusal(refused, &error)) status_.set(refused, error);
}

}  // namespace rtview
