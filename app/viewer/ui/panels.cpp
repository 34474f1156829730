// The ImGui panels (see panels.h): menu bar, sidebar, status bar.
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
#include "probe.h"
#include "scene_schema.h"
#include "readout.h"
#include "render_request.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "shown_numbers.h"

namespace rtview {

namespace {

// Messages wrap at the panel's edge instead of running past it (at any UI scale).
void wrapped_coloured(const ImVec4& colour, const std::string& text) {
    ImGui::PushStyleColor(ImGuiCol_Text, colour);
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
}
void wrapped_hint(const std::string& text) {
    wrapped_coloured(ImGui::GetStyle().Colors[ImGuiCol_TextDisabled], text);
}

// SameLine() if a button labelled `next` still fits on the line, else the button goes
// on the next line (a row of buttons wraps instead of running past the panel's edge).
void same_line_if_fits(const char* next) {
    const ImGuiStyle& st = ImGui::GetStyle();
    const float w = ImGui::CalcTextSize(next, nullptr, true).x + 2 * st.FramePadding.x;
    const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (ImGui::GetItemRectMax().x + st.ItemSpacing.x + w <= right) ImGui::SameLine();
}

std::string fmt_vec(const rt::Vec3& v) {
    return rt::format_number(v.x) + " " + rt::format_number(v.y) + " " + rt::format_number(v.z);
}

// A short "where is it" for outline labels.
std::string shape_summary(const rt::Shape& s) {
    if (auto* sp = std::get_if<rt::Sphere>(&s)) return "at " + fmt_vec(sp->position);
    if (auto* t = std::get_if<rt::Torus>(&s)) return "at " + fmt_vec(t->position);
    if (auto* c = std::get_if<rt::Cylinder>(&s)) return fmt_vec(c->end1) + " .. " + fmt_vec(c->end2);
    if (auto* t = std::get_if<rt::Tetrahedron>(&s)) return "vect1 " + fmt_vec(t->v[0]);
    if (auto* m = std::get_if<rt::Mesh>(&s)) return m->file.substr(m->file.find_last_of('/') + 1) + " at " + fmt_vec(m->position);
    return {};
}

const rt::Object* resolve(const rt::Scene& s, const ItemRef& sel) {
    if (!sel.is(SceneItem::Kind::Object) || sel.item.index >= int(s.objects.size())) return nullptr;
    const rt::Object* o = &s.objects[std::size_t(sel.item.index)];
    for (int k : sel.path) {
        auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || k >= int(g->operands.size())) return nullptr;
        o = &g->operands[std::size_t(k)];
    }
    return o;
}

bool selection_valid(const rt::Scene& s, const ItemRef& sel) {
    if (sel.none()) return true;
    switch (sel.item.kind) {
        case SceneItem::Kind::Object: return resolve(s, sel) != nullptr;
        case SceneItem::Kind::Plane: return sel.item.index < int(s.planes.size());
        case SceneItem::Kind::Light: return sel.item.index < int(s.lights.size());
    }
    return false;
}

bool drag_vec3(const char* label, rt::Vec3& v, float speed, const char* format = "%.3f") {
    double a[3] = {v.x, v.y, v.z};
    NumberFieldSpec spec;
    spec.speed = speed;
    spec.format = format;
    if (!number_fields(label, a, 3, spec)) return false;
    v = {a[0], a[1], a[2]};
    return true;
}

Rect item_block(const ImVec2& top_left, float width) {
    ImVec2 end = ImGui::GetCursorScreenPos();
    return {top_left.x, top_left.y, width, end.y - top_left.y};
}

// The keys of a material block, from the schema: weights as 0..1 sliders (values
// above 1 are legal, the renderer normalises them: Ctrl+click to type one), clamped
// keys within their clamp, colours with a picker. Labels are the format's key names.
bool material_editor(const char* id, rt::Material& m) {
    namespace sc = rt::schema;
    ImGui::PushID(id);
    bool changed = false;
    for (const sc::Key<rt::Material>& k : sc::material_block().keys) {
        const std::string label(k.name);
        if (k.kind == sc::Kind::Vec3) {
            // The three numbers (typed whole, or dragged), and a swatch with a picker.
            rt::Vec3& c = k.access.vec3(m, 0);
            float col[3] = {float(c.x), float(c.y), float(c.z)};
            if (ImGui::ColorEdit3(("##pick" + label).c_str(), col,
                                  ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_NoInputs)) {
                // The channels as the picker shows them (three decimals); the others
                // as they were, not as a float holds them.
                c = {from_widget(c.x, col[0], 3), from_widget(c.y, col[1], 3), from_widget(c.z, col[2], 3)};
                changed = true;
            }
            ImGui::SameLine(0, ImGui::GetStyle().ItemInnerSpacing.x);
            ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - ImGui::GetFrameHeight() - ImGui::GetStyle().ItemInnerSpacing.x);
            changed |= drag_vec3(label.c_str(), c, 0.005f);
            probe_item(std::string("field_") + id + "_" + label);  // for scripts: "field_material_colour"
            continue;
        }
        if (k.kind != sc::Kind::Number) continue;
        double& v = k.access.number(m, 0);
        const bool clamped = k.range.rule == sc::Range::Rule::Clamp;
        const double lo = clamped ? k.range.min : 0;
        const double hi = clamped && k.range.max <= lo + 1 ? k.range.max : lo + (clamped ? 2 : 1);
        NumberFieldSpec spec;
        spec.slider = true;
        spec.min = &lo;
        spec.max = &hi;
        spec.clamp_typed = clamped && k.range.max <= lo + 1;
        changed |= number_field(label.c_str(), &v, spec);
        if (clamped && v < k.range.min) v = k.range.min;
    }
    double sum = m.reflection + m.refraction + m.scattering;
    if (sum != 0)
        ImGui::TextWrapped("used as: reflection %.2f, refraction %.2f, scattering %.2f", m.reflection / sum,
                           m.refraction / sum, m.scattering / sum);
    else
        wrapped_coloured(kWarnColour, "all weights 0: the surface renders black");
    ImGui::PopID();
    return changed;
}

// Where the menu bar's next header is drawn ("menu:Edit"), for scripts that open it
// (probe.h): its rectangle is known before BeginMenu() draws it.
void probe_menu_header(const char* label) {
    const ImGuiStyle& st = ImGui::GetStyle();
    const float fb = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.f;
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = ImGui::CalcTextSize(label).x + st.ItemSpacing.x, h = ImGui::GetFrameHeight();
    probe(std::string("menu:") + label, std::to_string(std::lround(p.x * fb)) + " " + std::to_string(std::lround(p.y * fb)) +
                                            " " + std::to_string(std::lround(w * fb)) + " " +
                                            std::to_string(std::lround(h * fb)));
}

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


// ---------------------------------------------------------------------------------
// Menu bar

// File: documents (new, open, save), models, images, quit.
void Panels::draw_file_menu(bool can) {
    probe_menu_header("File");
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("New scene", "Ctrl+N")) commands_.run(Command::NewScene);
        if (ImGui::MenuItem("Open...", "Ctrl+O")) commands_.run(Command::OpenDialog);
        if (ImGui::BeginMenu("Open Recent")) {
            if (editor_.recent().paths().empty()) ImGui::MenuItem("(none yet)", nullptr, false, false);
            for (const std::string& p : editor_.recent().paths())
                if (ImGui::MenuItem(p.c_str())) commands_.run(Command::Open, p);
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Open the default scene")) commands_.run(Command::OpenDefault);
        ImGui::Separator();
        if (ImGui::MenuItem("Add model...", nullptr, false, can)) commands_.run(Command::AddModelDialog);
        probe_item("menu:Add model");
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S")) commands_.run(Command::Save);
        if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) commands_.run(Command::SaveAsDialog);
        ImGui::Separator();
        if (ImGui::MenuItem("Save Image...", "Ctrl+P")) commands_.run(Command::SaveImageDialog);
        if (ImGui::MenuItem("Screenshot", "F12")) commands_.run(Command::Screenshot, "raytracer-view-screenshot.png");
        tools_.file_menu_items();
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) commands_.run(Command::Quit);
        ImGui::EndMenu();
    }
}

void Panels::draw_menu_bar() {
    if (!ImGui::BeginMainMenuBar()) return;
    const Document& doc = editor_.doc();
    const bool can = doc.has_scene() && !doc.editor_dirty() && !doc.text_behind();  // structural edits
    draw_file_menu(can);
    probe_menu_header("Edit");
    if (ImGui::BeginMenu("Edit")) {
        draw_undo_items();
        ImGui::Separator();
        if (ImGui::MenuItem("Edit scene text", "Ctrl+E")) commands_.run(Command::EditText);
        if (ImGui::MenuItem("Apply text", "Ctrl+Enter")) commands_.run(Command::ApplyText);
        if (ImGui::MenuItem("Revert text", nullptr, false, doc.editor_dirty())) commands_.run(Command::RevertText);
        ImGui::Separator();
        // Structural edits: written into the text as ordinary blocks, one undo step each.
        if (ImGui::BeginMenu("Add (in front of the view)", can)) {
            static const char* const kinds[] = {"sphere", "cylinder", "tetrahedron", "torus", "plane", "chess_plane", "lamp", "spotlight"};
            for (const char* k : kinds) {
                const bool chosen = ImGui::MenuItem(k);
                probe_item(std::string("menu:") + k);
                if (chosen) commands_.run(Command::AddItem, k);
            }
            ImGui::EndMenu();
        }
        probe_item("menu:Add in front");
        const bool has = can && !selection_.none();
        if (ImGui::MenuItem("Duplicate", "Ctrl+D", false, has)) commands_.run(Command::Duplicate);
        if (ImGui::MenuItem("Delete", "Del", false, has)) commands_.run(Command::Delete);
        const bool light = has && selection_.is(SceneItem::Kind::Light) &&
                           std::size_t(selection_.item.index) < doc.scene().lights.size();
        if (ImGui::MenuItem(light && !doc.scene().lights[std::size_t(selection_.item.index)].lamp ? "Make the spotlight a lamp"
                                                                                            : "Make the lamp a spotlight",
                            nullptr, false, light))
            commands_.run(Command::SwitchLight);
        ImGui::EndMenu();
    }
    probe_menu_header("View");
    if (ImGui::BeginMenu("View")) {
        if (ImGui::MenuItem("Frame the scene", "F")) commands_.run(Command::FrameScene);
        if (ImGui::MenuItem("Reset the view to the scene camera", "R")) commands_.run(Command::ResetView);
        if (ImGui::MenuItem("Set scene camera from view", "Ctrl+K", false, doc.has_scene() && nav_.differs_from(doc.scene().camera)))
            commands_.run(Command::SetSceneCamera);
        if (ImGui::MenuItem("Copy camera block of the view")) commands_.run(Command::CopyCamera);
        ImGui::Separator();
        if (ImGui::MenuItem("Picture frame (letterboxed, as rendered)", nullptr, layout_.fit == FitMode::Picture))
            commands_.run(Command::FitPicture);
        if (ImGui::MenuItem("Fill the window", nullptr, layout_.fit == FitMode::Window)) commands_.run(Command::FitWindow);
        ImGui::Separator();
        if (ImGui::MenuItem("Pause rendering", "Space", render_.paused())) commands_.run(Command::TogglePause);
        if (ImGui::MenuItem("Sidebar (drag its edge to resize)", "Tab", !layout_.sidebar_hidden))
            layout_.sidebar_hidden = !layout_.sidebar_hidden;
        ImGui::Separator();
        tools_.view_menu_items();
        ImGui::EndMenu();
    }
    probe_menu_header("Help");
    if (ImGui::BeginMenu("Help")) {
        if (ImGui::MenuItem("Mouse and keys...")) commands_.run(Command::Help);
        if (ImGui::MenuItem("Scene format...")) commands_.run(Command::FormatHelp);
        probe_item("menu:Scene_format");
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

// Undo and Redo, named by the step each takes ("Undo: Move sphere 3"), and the history:
// the steps undone (greyed, newest at the top) above the steps done, the latest first.
// A click on a step goes back to before it, or forward up to it.
void Panels::draw_undo_items() {
    constexpr std::size_t kShown = 20;
    const Document& doc = editor_.doc();
    const std::vector<std::string> undo = doc.undo_names(kShown), redo = doc.redo_names(kShown);
    const std::string u = undo.empty() ? "Undo" : "Undo: " + undo.front();
    const std::string r = redo.empty() ? "Redo" : "Redo: " + redo.front();
    probe("edit_menu", u + " | " + r);
    if (ImGui::MenuItem(u.c_str(), "Ctrl+Z", false, !undo.empty())) commands_.run(Command::Undo);
    if (ImGui::MenuItem(r.c_str(), "Ctrl+Y", false, !redo.empty())) commands_.run(Command::Redo);
    probe_menu_header("Undo history");
    if (!ImGui::BeginMenu("Undo history", !undo.empty() || !redo.empty())) return;
    std::string shown;
    for (std::size_t k = redo.size(); k-- > 0;) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        const bool chosen = ImGui::MenuItem((redo[k] + "##redo" + std::to_string(k)).c_str(), "undone");
        ImGui::PopStyleColor();
        probe_item("menu:redo:" + std::to_string(k + 1));
        shown += "redo:" + redo[k] + "|";
        if (chosen) commands_.run(Command::Redo, std::to_string(k + 1));
    }
    if (!redo.empty() && !undo.empty()) ImGui::Separator();
    for (std::size_t k = 0; k < undo.size(); ++k) {
        const bool chosen = ImGui::MenuItem((undo[k] + "##undo" + std::to_string(k)).c_str());
        probe_item("menu:undo:" + std::to_string(k + 1));
        shown += "undo:" + undo[k] + "|";
        if (chosen) commands_.run(Command::Undo, std::to_string(k + 1));
    }
    probe("undo_history", shown);
    ImGui::EndMenu();
}

// ---------------------------------------------------------------------------------
// Sidebar

void Panels::select(const ItemRef& s) {
    selection_ = s;
    scroll_to_selection_ = true;
    if (!s.none() && current_tab_ != Objects) want_tab_ = Objects;
}

void Panels::select_from_option(const std::string& spec) {
    std::istringstream in(spec);
    std::string kind;
    int n = 0;
    in >> kind >> n;
    const rt::Scene& s = editor_.doc().scene();
    if (kind == "object" && n >= 1 && n <= int(s.objects.size())) {
        // "object 5 left right": a CSG operand below it.
        ItemRef sel{{SceneItem::Kind::Object, n - 1}, {}};
        std::string side;
        while (in >> side && (side == "left" || side == "right")) sel.path.push_back(side == "left" ? 0 : 1);
        if (resolve(s, sel)) selection_ = sel;
    }
    if (kind == "plane" && n >= 1 && n <= int(s.planes.size())) selection_ = {{SceneItem::Kind::Plane, n - 1}, {}};
    if (kind == "light" && n >= 1 && n <= int(s.lights.size())) selection_ = {{SceneItem::Kind::Light, n - 1}, {}};
    scroll_to_selection_ = true;
}

double Panels::scene_extent() const {
    if (const rt::World* w = render_.world()) {
        rt::Aabb b = w->bounds();
        if (!b.empty() && rt::finite(b.lo) && rt::finite(b.hi)) return std::max(rt::length(b.hi - b.lo), 1e-3);
    }
    const rt::Camera& c = editor_.doc().scene().camera;
    return std::max(rt::length(c.centre - c.position), 1e-3);
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
    probe("selection", selection_name(selection_));
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
            (void)tools_.settings().set_sidebar_width(w / ui, false);  // saved on release
        }
        if (ImGui::IsItemDeactivated())
            if (rt::Status st = tools_.settings().set_sidebar_width(layout_.sidebar_w / ui); !st)
                status_.set("The sidebar's width was not saved: " + st.message(), true);
    }
    ImGui::End();
    ImGui::PopStyleVar(2);
}

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
        float speed = float(scene_extent() * 0.002);
        // Room for the longest label at any font size (UI scale).
        float label_w = 0;
        for (const char* l : {"position", "up point", "angle x, y", "projection", "az, el, dist"})
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
    ImGui::EndDisabled();
    if (blocked) changed = false;
    if (changed && !rt::camera_problem(cam)) editor_.doc().edit_camera() = cam;
    else if (changed) status_.set(std::string("Camera not changed: ") + rt::camera_problem(cam), true);
    if (std::string refused; take_number_refusal(refused)) status_.set(refused, true);
}

void Panels::draw_objects_tab() {
    if (!selection_valid(editor_.doc().scene(), selection_)) selection_ = {};
    // At least seven rows of the outline, whatever the UI scale.
    float h = std::max(ImGui::GetTextLineHeightWithSpacing() * 7, ImGui::GetContentRegionAvail().y * 0.45f);
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    // Long labels scroll sideways instead of being cut at the edge.
    if (ImGui::BeginChild("outline", ImVec2(0, h), true, ImGuiWindowFlags_HorizontalScrollbar)) draw_outline();
    ImGui::EndChild();
    layout_.outline = item_block(top, width);
    if (ImGui::BeginChild("properties", ImVec2(0, 0), false)) draw_properties();
    ImGui::EndChild();
}

void Panels::draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label) {
    ItemRef me{{SceneItem::Kind::Object, top}, path};
    auto* csg = std::get_if<rt::Csg>(&obj.shape);
    ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_SpanAvailWidth;
    if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
    if (csg) f |= ImGuiTreeNodeFlags_DefaultOpen;
    else f |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
    bool open = ImGui::TreeNodeEx("node", f, "%s", label.c_str());
    if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
    if (ImGui::IsItemClicked() && !ImGui::IsItemToggledOpen()) selection_ = me;
    if (selection_ == me && scroll_to_selection_) {
        ImGui::SetScrollHereY();
        scroll_to_selection_ = false;
    }
    if (csg && open) {
        for (std::size_t i = 0; i < csg->operands.size(); ++i) {
            const rt::Object& o = csg->operands[i];
            path.push_back(int(i));
            ImGui::PushID(int(i));
            draw_object_node(o, top, path, std::string(i == 0 ? "left: " : "right: ") + shape_name(o.shape));
            ImGui::PopID();
            path.pop_back();
        }
        ImGui::TreePop();
    }
}

void Panels::draw_outline() {
    if (!editor_.doc().has_scene()) {
        ImGui::TextDisabled(editor_.doc().has_errors() ? "No scene yet: fix the errors in the Text tab."
                                                       : "No scene yet.");
        return;
    }
    const rt::Scene& s = editor_.doc().scene();
    auto leaf = [&](const ItemRef& me, const std::string& label) {
        ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen |
                               ImGuiTreeNodeFlags_SpanAvailWidth;
        if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
        ImGui::TreeNodeEx("node", f, "%s", label.c_str());
        if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
        if (ImGui::IsItemClicked()) selection_ = me;
        if (selection_ == me && scroll_to_selection_) {
            ImGui::SetScrollHereY();
            scroll_to_selection_ = false;
        }
    };
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("objects", "Objects (%d)", int(s.objects.size()))) {
        // Clip long lists: only visible rows cost anything (scenes may hold many objects).
        for (int k = 0; k < int(s.objects.size()); ++k) {
            const rt::Object& o = s.objects[std::size_t(k)];
            std::vector<int> path;
            ImGui::PushID(k);
            std::string label = std::to_string(k + 1) + "  " + shape_name(o.shape) + "  " + shape_summary(o.shape);
            draw_object_node(o, k, path, label);
            ImGui::PopID();
            if (k > 2000 && !scroll_to_selection_) {
                ImGui::TextDisabled("... %d more (select them in the image)", int(s.objects.size()) - k - 1);
                break;
            }
        }
        ImGui::TreePop();
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("planes", "Planes (%d)", int(s.planes.size()))) {
        for (int k = 0; k < int(s.planes.size()); ++k) {
            ImGui::PushID(k);
            leaf({{SceneItem::Kind::Plane, k}, {}}, std::to_string(k + 1) + "  " + (s.planes[std::size_t(k)].chess ? "chess_plane" : "plane"));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("lights", "Lights (%d)", int(s.lights.size()))) {
        for (int k = 0; k < int(s.lights.size()); ++k) {
            const rt::Light& l = s.lights[std::size_t(k)];
            ImGui::PushID(k);
            leaf({{SceneItem::Kind::Light, k}, {}}, std::to_string(k + 1) + "  " + (l.lamp ? "lamp" : "spotlight") + "  at " + fmt_vec(l.position));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    if (s.lights.empty()) {
        // Whatever is added stays black until a light is: say so where lights are listed.
        const char* hint = "No lights: everything renders black. Right-click the picture > Add here > lamp.";
        wrapped_coloured(kWarnColour, hint);
        probe("outline_hint", hint);
    }
    scroll_to_selection_ = false;
}

void Panels::draw_properties() {
    if (!editor_.doc().has_scene()) return;
    const rt::Scene& s = editor_.doc().scene();
    if (!(field_message_.selection == selection_)) field_message_ = {};
    if (selection_.none()) {
        wrapped_hint("Click an object in the image or in the list above.");
        return;
    }
    const ItemRef ref = selection_;
    const char* block = item_block_name(s, ref);
    if (!block) return;
    // "Object 5: constructive_solid_geometry", "Object 5, left, right: sphere".
    std::string title;
    switch (selection_.item.kind) {
        case SceneItem::Kind::Object: title = "Object " + std::to_string(selection_.item.index + 1); break;
        case SceneItem::Kind::Plane: title = "Plane " + std::to_string(selection_.item.index + 1); break;
        case SceneItem::Kind::Light: title = "Light " + std::to_string(selection_.item.index + 1); break;
    }
    for (int k : selection_.path) title += k == 0 ? ", left" : ", right";
    title += std::string(": ") + block;
    ImGui::TextWrapped("%s", title.c_str());
    rt::SourceLoc loc;
    if (selection_.is(SceneItem::Kind::Object)) {
        if (const rt::Object* o = resolve(s, selection_)) loc = o->loc;
    } else if (selection_.is(SceneItem::Kind::Plane)) {
        loc = s.planes[std::size_t(selection_.item.index)].loc;
    } else {
        loc = s.lights[std::size_t(selection_.item.index)].loc;
    }
    if (loc.line > 0 && ImGui::SmallButton("show in text"))
        editor_.focus(int(offset_of(std::as_const(editor_.doc()).editor_text(), loc.line, loc.col)));
    if (!selection_.path.empty()) {
        if (loc.line > 0) same_line_if_fits("select the parent");
        const bool parent = ImGui::SmallButton("select the parent");
        probe_item("button_select_the_parent");
        if (parent) {
            selection_.path.pop_back();
            return;
        }
        wrapped_hint("A CSG operand: its shape counts; its colour and finish are the whole CSG's material (select "
                     "the parent to edit it).");
    }
    if (selection_.is(SceneItem::Kind::Light)) {
        // The block's kind: switching keeps the lamp's size for switching back.
        const bool lamp = s.lights[std::size_t(selection_.item.index)].lamp;
        if (ImGui::SmallButton(lamp ? "make it a spotlight" : "make it a lamp")) commands_.run(Command::SwitchLight);
        const char* what = lamp ? "(point light and glow)" : "(point light)";
        same_line_if_fits(what);
        ImGui::TextDisabled("%s", what);
    }
    ImGui::Separator();
    // Nothing here may change the scene while the text holds changes it could not be
    // written into: Save writes that text.
    const std::string blocked = editor_.doc().edit_blocker();
    if (!blocked.empty()) {
        wrapped_coloured(kWarnColour, blocked);
        probe("edits", "blocked");
    }
    ImGui::BeginDisabled(!blocked.empty());
    draw_fields(ref);
    ImGui::EndDisabled();
}

// One widget per key of the selected item's block, from the schema (item_fields.h):
// what the panel offers is what the format has. A change goes through set_field, so the
// parser's ranges apply; a refused value leaves the item as it was and says why.
void Panels::draw_fields(const ItemRef& ref) {
    Document& doc = editor_.doc();
    const std::vector<Field> fields = item_fields(doc.scene(), ref);
    // Room for the longest label, whatever the UI scale.
    const float label_w = field_label_width();
    const float size = float(scene_extent());
    // Dragging rounds to the digits shown: enough of them for a small scene.
    char vec_format[16];
    std::snprintf(vec_format, sizeof vec_format, "%%.%df", std::clamp(4 - int(std::floor(std::log10(size))), 3, 9));
    int operand = 0;
    std::string shown;  // the fields drawn, for scripts (probe.h)
    for (const Field& f : fields) {
        std::optional<FieldValue> cur = field_value(doc.scene(), ref, f);
        if (!cur) continue;
        shown += (shown.empty() ? "" : ",") + f.label;
        FieldValue v = *cur;
        ImGui::PushID(f.label.c_str());
        ImGui::PushItemWidth(-(label_w + ImGui::GetStyle().ItemInnerSpacing.x + 2));
        const bool changed = draw_field(ref, f, v, size, vec_format, operand);
        ImGui::PopItemWidth();
        {
            // Where the field is, for scripts that click on it, and its value as the
            // text will hold it (a drag's value before it reaches the text).
            std::string key = "field_" + f.label;
            std::replace(key.begin(), key.end(), ' ', '_');
            probe_item(key);
            if (f.kind == rt::schema::Kind::Number) probe("value_" + f.label, rt::format_number(cur->number));
            else if (f.kind == rt::schema::Kind::Vec3)
                probe("value_" + f.label, rt::format_number(cur->vec.x) + " " + rt::format_number(cur->vec.y) + " " +
                                              rt::format_number(cur->vec.z));
        }
        if (std::string refused; take_number_refusal(refused)) field_message_ = {selection_, f.label, refused, true};
        if (changed) {
            const FieldResult r = set_field(doc, ref, f, v);
            if (!r.status) field_message_ = {selection_, f.label, r.status.message(), true};
            // (A material's own warning is shown by its editor already.)
            else if (!r.warning.empty() && f.kind != rt::schema::Kind::Material) field_message_ = {selection_, f.label, r.warning, false};
            else if (field_message_.field == f.label) field_message_ = {};
        }
        if (field_message_.field == f.label && !field_message_.text.empty()) {
            wrapped_coloured(field_message_.error ? kErrorColour : kWarnColour, field_message_.text);
            probe("field_message", f.label + ": " + field_message_.text);
        }
        ImGui::PopID();
    }
    probe("fields", shown);
}

// The widget of one field of the kind the schema gives it, editing `v`; true if it
// changed. `size`: the scene's extent (drag speeds); `operand` counts a CSG's operands.
bool Panels::draw_field(const ItemRef& ref, const Field& f, FieldValue& v, float size, const char* vec_format,
                        int& operand) {
    namespace sc = rt::schema;
    bool changed = false;
    switch (f.kind) {
        case sc::Kind::Number: {
            NumberFieldSpec spec;
            spec.speed = std::max(float(std::fabs(v.number)) * 0.005f, size * 0.0005f);
            spec.format = "%.6g";
            changed = number_field(f.label.c_str(), &v.number, spec);
            break;
        }
        case sc::Kind::Vec3: {
            if (ref.item.kind == SceneItem::Kind::Light && f.key == "colour") {
                changed = light_colour_editor(v.vec);
                break;
            }
            changed = drag_vec3(f.label.c_str(), v.vec, size * 0.002f, vec_format);
            break;
        }
        case sc::Kind::Integer: {
            NumberFieldSpec spec;
            spec.format = "%.0f";
            changed = number_field(f.label.c_str(), &v.number, spec);
            break;
        }
        case sc::Kind::Choice: {
            const std::string now(f.choice->word_for(v.choice));
            if (ImGui::BeginCombo(f.label.c_str(), choice_label(f.key, now).c_str())) {
                std::vector<int> seen;
                for (const sc::Choice::Word& w : f.choice->words) {
                    if (std::find(seen.begin(), seen.end(), w.value) != seen.end()) continue;
                    seen.push_back(w.value);
                    if (ImGui::Selectable(choice_label(f.key, w.word).c_str(), w.value == v.choice) && w.value != v.choice) {
                        v.choice = w.value;
                        changed = true;
                    }
                }
                ImGui::EndCombo();
            }
            break;
        }
        case sc::Kind::Material: {
            ImGui::Separator();
            ImGui::TextWrapped("%s%s", f.label.c_str(), v.has_material ? "" : " (none in the file: the default)");
            changed = material_editor(f.label.c_str(), v.material);
            break;
        }
        case sc::Kind::File:
            // The model is read with the scene: a new name is typed in the scene text.
            ImGui::TextWrapped("%s: %s", f.label.c_str(), v.text.c_str());
            break;
        case sc::Kind::Operand: {
            // A CSG's operands: select one to edit its keys (also in the outline).
            const int side = operand++;
            std::string b = f.label + ": " + (v.operand ? sc::object_block(*v.operand).name.data() : "-");
            if (v.operand && ImGui::Button((b + " (edit)").c_str())) {
                selection_.path.push_back(side);
                scroll_to_selection_ = true;
            }
            break;
        }
    }
    return changed;
}

// A light's colour is an intensity (often >> 1 because of the 1/r^2 fall-off): its three
// numbers, and the same as a tint and a strength.
bool Panels::light_colour_editor(rt::Vec3& colour) {
    char shown[128];  // what the field shows, for scripts (probe.h)
    std::snprintf(shown, sizeof shown, "%.3f %.3f %.3f", colour.x, colour.y, colour.z);
    probe("light_colour", shown);
    bool changed = drag_vec3("colour", colour, float(std::max({colour.x, colour.y, colour.z, 1.0}) * 0.005));
    double intensity = std::max({colour.x, colour.y, colour.z, 0.0});
    rt::Vec3 tint = intensity > 0 ? colour / intensity : rt::Vec3{1, 1, 1};
    float col[3] = {float(tint.x), float(tint.y), float(tint.z)};
    bool tinted = false;
    if (ImGui::ColorEdit3("tint", col, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_NoInputs)) {
        tint = {col[0], col[1], col[2]};
        if (intensity == 0) intensity = 1;
        tinted = true;
    }
    ImGui::SameLine();
    const double zero = 0;
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6);
    NumberFieldSpec spec;
    spec.speed = float(std::max(intensity * 0.005, 0.01));
    spec.min = &zero;
    spec.format = "%.2f";
    if (number_field("intensity", &intensity, spec)) tinted = true;
    probe_item("field_intensity");
    if (tinted) {
        // As the colour field shows it: tint * intensity has noise in its last digits.
        const rt::Vec3 c = tint * intensity;
        colour = {as_shown(c.x, 3), as_shown(c.y, 3), as_shown(c.z, 3)};
        changed = true;
    }
    return changed;
}

// "U (union)" for the CSG types; other words as they are.
std::string Panels::choice_label(std::string_view key, std::string_view word) {
    if (key == "type") {
        if (word == "U") return "U (union)";
        if (word == "I") return "I (intersection)";
        if (word == "C") return "C (difference: left minus right)";
    }
    return std::string(word);
}

// The narrowest sidebar in which the property fields keep their labels whole and
// three numbers of a point stay readable.
float Panels::min_sidebar_width() {
    const ImGuiStyle& st = ImGui::GetStyle();
    const float number = ImGui::CalcTextSize("-00.000").x + 2 * st.FramePadding.x;
    const float fields = field_label_width() + st.ItemInnerSpacing.x + 2 + 3 * number + 2 * st.ItemInnerSpacing.x;
    // The sidebar's padding, and its and the properties' scroll bars.
    return std::ceil(fields + 2 * st.WindowPadding.x + 2 * st.ScrollbarSize);
}

// The widest label the property fields use, at the current font: every key of every
// block (and of the material block), so the layout does not jump between selections.
float Panels::field_label_width() {
    namespace sc = rt::schema;
    const float font = ImGui::GetFontSize();
    if (label_w_font_ == font) return label_w_;
    float w = 0;
    auto measure = [&w](std::string_view name, int count) {
        std::string l(name);
        if (count > 0) l += " " + std::to_string(count);
        w = std::max(w, ImGui::CalcTextSize(l.c_str()).x);
    };
    for (const auto& b : sc::object_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& b : sc::plane_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& b : sc::light_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& k : sc::material_block().keys) measure(k.name, k.count);
    measure("intensity", 0);
    label_w_ = w;
    label_w_font_ = font;
    return w;
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

namespace {

// Pieces of status-bar text flowed into rows: a piece stays on the current row if it
// fits (with its separator), else it starts a row of its own at the left, broken at
// spaces where it is wider than the bar (never inside a number), and what follows goes
// on after it. Returns the height of the rows below the first; draws them when `draw`,
// and gives their text in `shown` (for --print-layout).
struct StatusPiece {
    std::string text;
    const char* sep = "";
    const ImVec4* colour = nullptr;
};

float flow_status(const std::vector<StatusPiece>& pieces, float x, float left, float right, bool draw,
                  std::vector<std::string>* shown = nullptr) {
    const ImGuiStyle& st = ImGui::GetStyle();
    const auto measure = [](std::string_view t) { return ImGui::CalcTextSize(t.data(), t.data() + t.size()).x; };
    float extra = 0;
    bool first = true;
    for (const StatusPiece& p : pieces) {
        const std::string joined = p.sep + p.text;
        const float w = measure(joined);
        const bool fits = x + w <= right;
        const std::vector<std::string> rows = fits ? std::vector<std::string>{joined} : wrap_words(p.text, right - left, measure);
        if (shown) {
            if (fits && !shown->empty()) shown->back() += (first ? "" : " ") + joined;
            else shown->insert(shown->end(), rows.begin(), rows.end());
        }
        if (draw) {
            if (p.colour) ImGui::PushStyleColor(ImGuiCol_Text, *p.colour);
            for (std::size_t k = 0; k < rows.size(); ++k) {
                if (fits && !first) ImGui::SameLine();
                if (!fits && first && k == 0) ImGui::NewLine();
                if (!fits) ImGui::SetCursorPosX(left);
                ImGui::TextUnformatted(rows[k].c_str());
            }
            if (p.colour) ImGui::PopStyleColor();
        }
        if (fits) {
            x += w + st.ItemSpacing.x;
        } else {
            extra += float(rows.size()) * (ImGui::GetTextLineHeight() + st.ItemSpacing.y);
            x = left + measure(rows.back()) + st.ItemSpacing.x;
        }
        first = false;
    }
    return extra;
}

// "spp" names the progress bar's numbers: it stays beside them. The groups of a
// pixel readout ("RGB 0.107 0.107 0.125", three spaces apart) each move to the next
// row whole.
void add_status_line(std::vector<StatusPiece>& pieces, const std::string& text) {
    std::string rest = text;
    const char* sep = "";
    if (text.rfind("spp  ", 0) == 0) {
        pieces.push_back({"spp"});
        rest = text.substr(5);
        sep = " ";
    }
    for (std::size_t at = rest.find("   "); at != std::string::npos; at = rest.find("   ")) {
        pieces.push_back({rest.substr(0, at), sep});
        rest.erase(0, at + 3);
        sep = "   ";
    }
    pieces.push_back({rest, sep});
}

// The status bar's window padding (unscaled, as its one row always had).
const ImVec2 kStatusPadding(6, 4);

// The pieces of the status bar's usual contents at their usual width: the statistics
// with the message, and a pixel readout (a longer one makes the bar grow while the
// message stays: status_more_).
std::vector<StatusPiece> usual_stats() {
    std::vector<StatusPiece> p;
    add_status_line(p, "spp  00.00 Mrays/s  000.0 s  rendering  |  picture frame");
    return p;
}
std::vector<StatusPiece> usual_readout() {
    std::vector<StatusPiece> p;
    add_status_line(p, "spp  rendering  | x 000 y 000   RGB 0.000 0.000 0.000   64 spp   object 10 (sphere) at 0.00");
    return p;
}

// Where the text starts on the first row: after the button and the progress bar.
float status_text_x() {
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    return kStatusPadding.x + ImGui::GetFontSize() * (4.5f + 8) + 2 * spacing;
}

// The pieces followed by the last message, if there is one.
std::vector<StatusPiece> with_message(const StatusLine& status, std::vector<StatusPiece> pieces) {
    static const ImVec4 grey(0.75f, 0.75f, 0.75f, 1);
    if (!status.text().empty()) pieces.push_back({status.text(), "| ", status.error() ? &kErrorColour : &grey});
    return pieces;
}

}  // namespace

void Panels::draw_status_bar(const LoadStatus& load) {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - layout_.status_h));
    ImGui::SetNextWindowSize(ImVec2(float(layout_.area.w), layout_.status_h));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, kStatusPadding);
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                             ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                             ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (ImGui::Begin("##status", nullptr, flags)) {
        if (load.active) {
            // Loading in the background: its progress replaces the render's.
            if (ImGui::Button("Cancel", ImVec2(ImGui::GetFontSize() * 4.5f, 0))) commands_.run(Command::CancelLoad);
            ImGui::SameLine();
            ImGui::ProgressBar(float(load.fraction), ImVec2(ImGui::GetFontSize() * 8, 0));
            ImGui::SameLine();
            status_text(load.text + " (Esc cancels)", true);
        } else {
            rt::RenderProgress p = render_.progress();
            if (ImGui::Button(render_.paused() ? "Resume" : "Pause", ImVec2(ImGui::GetFontSize() * 4.5f, 0)))
                commands_.run(Command::TogglePause);
            ImGui::SameLine();
            double elapsed = p.done && render_.done_generation() == p.generation ? render_.done_elapsed() : p.elapsed;
            double frac = p.refining >= 0 ? rt::progress_fraction(p, render_.max_samples())
                                          : std::clamp((p.samples + p.pass_fraction) / std::max(1, render_.max_samples()), 0.0, 1.0);
            if (render_.time_limit() > 0) frac = std::max(frac, std::min(1.0, elapsed / render_.time_limit()));
            if (p.done) frac = 1;
            char buf[64];
            // Adaptive: how many pixels have not settled yet, until every one has.
            // (Thousands above 9999, rounded up: "305k px refining" fits the bar.)
            if (p.refining > 9999)
                std::snprintf(buf, sizeof buf, "%lldk px refining", static_cast<long long>((p.refining + 999) / 1000));
            else if (p.refining > 0) std::snprintf(buf, sizeof buf, "%lld px refining", static_cast<long long>(p.refining));
            else if (p.refining == 0) std::snprintf(buf, sizeof buf, "settled");
            else std::snprintf(buf, sizeof buf, "%d / %d", p.samples, render_.max_samples());
            if (render_.showing_preview()) {  // the view moves: the last render's state is not the picture's
                std::snprintf(buf, sizeof buf, "moving");
                frac = 0;
            }
            // As wide as its longest usual text (up to 100M pixels refining), at any UI scale.
            const float bar_w = std::max(ImGui::GetFontSize() * 8,
                                         ImGui::CalcTextSize("99999k px refining").x + ImGui::GetStyle().FramePadding.x * 4);
            ImGui::ProgressBar(float(frac), ImVec2(bar_w, 0), buf);
            ImGui::SameLine();
            double rate = elapsed > 0 ? double(p.rays) / elapsed : 0;
            const char* state = render_.paused() ? "paused"
                                : p.done         ? "done"
                                : render_.building() ? "building"
                                : p.running      ? "rendering"
                                                 : "idle";
            char preview[32] = "";
            if (render_.showing_preview())
                std::snprintf(preview, sizeof preview, "preview %dx%d", render_.last_preview_block(),
                              render_.last_preview_block());
            const char* shown = render_.showing_preview() ? preview : state;
            // Over the picture: the readout of the pixel under the cursor instead of the
            // statistics and the last message.
            char line[512];
            const char* unit = p.refining >= 0 ? "" : "spp  ";  // (an adaptive bar counts pixels)
            if (!tools_.readout_line().empty())
                std::snprintf(line, sizeof line, "%s%s  | %s", unit, shown, tools_.readout_line().c_str());
            else
                std::snprintf(line, sizeof line, "%s%.2f Mrays/s  %.1f s  %s  |  %s", unit, rate / 1e6, elapsed, shown,
                              layout_.fit == FitMode::Picture ? "picture frame" : "fill window");
            // An error stays beside the readout: it must be read, not hidden by a hover.
            status_text(line, tools_.readout_line().empty() || status_.error());
        }
    }
    ImGui::End();
    ImGui::PopStyleVar();
}

// The rows below the first that the status bar's usual contents need in a window
// `width` wide: the statistics with the message (the current one, and one of the usual
// length, so that the next message rarely changes the bar's height), or a readout.
float Panels::usual_status_extra(float width) const {
    const float left = kStatusPadding.x, right = width - kStatusPadding.x, x = status_text_x();
    StatusLine typical;
    typical.set("The scene camera is now the view (Ctrl+Z undoes)");
    return std::max({flow_status(with_message(status_, usual_stats()), x, left, right, false),
                     flow_status(with_message(typical, usual_stats()), x, left, right, false),
                     flow_status(usual_readout(), x, left, right, false)});
}

// The status bar's height in a window `width` wide: what its usual contents need
// rather than what it shows now, so the image area keeps its size when the mouse moves
// onto the picture, a dialog opens or a message comes. Known before the bar is drawn:
// the first frame has it right.
float Panels::status_height(float width) {
    float extra = usual_status_extra(width);
    // Shown text that needed more (a long object name), while the message and width last.
    if (status_more_.width == width && status_more_.font == ImGui::GetFontSize() && status_more_.text == status_.text())
        extra = std::max(extra, status_more_.extra);
    return std::ceil(ImGui::GetFrameHeight() + 8 * ImGui::GetFontSize() / 13.f + extra);
}

// The status bar's text right of the button and the progress bar, then the last message
// (`show_message`). What does not fit on the row goes on rows of its own below rather
// than being cut at the bar's edge (status_height() leaves room for them).
void Panels::status_text(const std::string& text, bool show_message) {
    std::vector<StatusPiece> shown;
    add_status_line(shown, text);
    if (show_message) shown = with_message(status_, std::move(shown));
    std::vector<std::string> rows;
    const float extra = flow_status(shown, ImGui::GetCursorPosX(), ImGui::GetWindowContentRegionMin().x,
                                    ImGui::GetWindowContentRegionMax().x, true, &rows);
    std::string all, drawn;
    for (const StatusPiece& p : shown) all += p.sep + p.text;
    for (const std::string& r : rows) drawn += (drawn.empty() ? "" : " || ") + r;
    probe("status_bar", all);
    if (show_message && status_.error()) {
        // Errors stay until the next message or until dismissed here.
        ImGui::SameLine();
        if (ImGui::SmallButton("x##dismiss")) status_.set("");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Dismiss this message");
    }
    probe("status_rows", drawn);
    const float width = ImGui::GetWindowWidth();
    if (extra > usual_status_extra(width)) status_more_ = {width, ImGui::GetFontSize(), status_.text(), extra};
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
