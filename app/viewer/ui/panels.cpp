// The ImGui panels (see panels.h): menu bar, sidebar, status bar.
#include "panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include "camera_control.h"
#include "readout.h"
#include "scene_text.h"
#include "scene_writer.h"

namespace rtview {

namespace {

const ImVec4 kErrorColour{1.0f, 0.42f, 0.42f, 1.0f};
const ImVec4 kWarnColour{1.0f, 0.80f, 0.35f, 1.0f};
const ImVec4 kOkColour{0.55f, 0.85f, 0.55f, 1.0f};

std::string fmt_vec(const rt::Vec3& v) {
    return rt::format_number(v.x) + " " + rt::format_number(v.y) + " " + rt::format_number(v.z);
}

// A short "where is it" for outline labels.
std::string shape_summary(const rt::Shape& s) {
    if (auto* sp = std::get_if<rt::Sphere>(&s)) return "at " + fmt_vec(sp->position);
    if (auto* t = std::get_if<rt::Torus>(&s)) return "at " + fmt_vec(t->position);
    if (auto* c = std::get_if<rt::Cylinder>(&s)) return fmt_vec(c->end1) + " .. " + fmt_vec(c->end2);
    if (auto* t = std::get_if<rt::Tetrahedron>(&s)) return "vect1 " + fmt_vec(t->v[0]);
    return {};
}

void shape_details(const rt::Shape& s) {
    if (auto* sp = std::get_if<rt::Sphere>(&s)) {
        ImGui::Text("position %s", fmt_vec(sp->position).c_str());
        ImGui::Text("radius   %s", rt::format_number(sp->radius).c_str());
    } else if (auto* t = std::get_if<rt::Tetrahedron>(&s)) {
        for (int i = 0; i < 4; ++i) ImGui::Text("vect%d %s", i + 1, fmt_vec(t->v[i]).c_str());
    } else if (auto* c = std::get_if<rt::Cylinder>(&s)) {
        ImGui::Text("end_1  %s", fmt_vec(c->end1).c_str());
        ImGui::Text("end_2  %s", fmt_vec(c->end2).c_str());
        ImGui::Text("radius %s", rt::format_number(c->radius).c_str());
    } else if (auto* t = std::get_if<rt::Torus>(&s)) {
        ImGui::Text("position  %s", fmt_vec(t->position).c_str());
        ImGui::Text("direction %s", fmt_vec(t->direction).c_str());
        ImGui::Text("major %s  minor %s", rt::format_number(t->major).c_str(), rt::format_number(t->minor).c_str());
    } else if (auto* g = std::get_if<rt::Csg>(&s)) {
        ImGui::Text("type %c, operands: %s / %s", char(g->type),
                    g->operands.size() > 0 ? shape_name(g->operands[0].shape) : "-",
                    g->operands.size() > 1 ? shape_name(g->operands[1].shape) : "-");
    }
}

const rt::Object* resolve(const rt::Scene& s, const Selection& sel) {
    if (sel.kind != Selection::Kind::Object || sel.index < 0 || sel.index >= int(s.objects.size())) return nullptr;
    const rt::Object* o = &s.objects[std::size_t(sel.index)];
    for (int k : sel.path) {
        auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || k >= int(g->operands.size())) return nullptr;
        o = &g->operands[std::size_t(k)];
    }
    return o;
}

bool selection_valid(const rt::Scene& s, const Selection& sel) {
    switch (sel.kind) {
        case Selection::Kind::None: return true;
        case Selection::Kind::Object: return resolve(s, sel) != nullptr;
        case Selection::Kind::Plane: return sel.index >= 0 && sel.index < int(s.planes.size());
        case Selection::Kind::Light: return sel.index >= 0 && sel.index < int(s.lights.size());
    }
    return false;
}

bool drag_vec3(const char* label, rt::Vec3& v, float speed) {
    double a[3] = {v.x, v.y, v.z};
    if (!ImGui::DragScalarN(label, ImGuiDataType_Double, a, 3, speed, nullptr, nullptr, "%.3f")) return false;
    v = {a[0], a[1], a[2]};
    return true;
}

Rect item_block(const ImVec2& top_left, float width) {
    ImVec2 end = ImGui::GetCursorScreenPos();
    return {top_left.x, top_left.y, width, end.y - top_left.y};
}

bool material_editor(const char* id, rt::Material& m) {
    ImGui::PushID(id);
    bool changed = false;
    const double zero = 0, one = 1, ior_max = 3;
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 9);
    // Weights are normalised by their sum when rendering, so values above 1 are legal:
    // Ctrl+click a slider to type one.
    changed |= ImGui::SliderScalar("reflection", ImGuiDataType_Double, &m.reflection, &zero, &one, "%.3f");
    changed |= ImGui::SliderScalar("refraction", ImGuiDataType_Double, &m.refraction, &zero, &one, "%.3f");
    changed |= ImGui::SliderScalar("scattering", ImGuiDataType_Double, &m.scattering, &zero, &one, "%.3f");
    changed |= ImGui::SliderScalar("translusans", ImGuiDataType_Double, &m.translusans, &zero, &one, "%.3f",
                                   ImGuiSliderFlags_AlwaysClamp);
    const double ior_min = 1;
    changed |= ImGui::SliderScalar("refractive_index", ImGuiDataType_Double, &m.refractive_index, &ior_min, &ior_max,
                                   "%.3f", ImGuiSliderFlags_AlwaysClamp);
    float col[3] = {float(m.colour.x), float(m.colour.y), float(m.colour.z)};
    if (ImGui::ColorEdit3("colour", col, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR)) {
        m.colour = {col[0], col[1], col[2]};
        changed = true;
    }
    ImGui::PopItemWidth();
    double sum = m.reflection + m.refraction + m.scattering;
    if (sum != 0)
        ImGui::TextDisabled("used as: reflection %.2f, refraction %.2f, scattering %.2f", m.reflection / sum,
                            m.refraction / sum, m.scattering / sum);
    else
        ImGui::TextColored(kWarnColour, "all weights 0: the surface renders black");
    ImGui::PopID();
    return changed;
}

}  // namespace


// ---------------------------------------------------------------------------------
// Menu bar

void Panels::draw_menu_bar() {
    if (!ImGui::BeginMainMenuBar()) return;
    const Document& doc = editor_.doc();
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Open...", "Ctrl+O")) commands_.run(Command::OpenDialog);
        if (ImGui::BeginMenu("Open Recent")) {
            if (editor_.recent().paths().empty()) ImGui::MenuItem("(none yet)", nullptr, false, false);
            for (const std::string& p : editor_.recent().paths())
                if (ImGui::MenuItem(p.c_str())) commands_.run(Command::Open, p);
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Open the default scene")) commands_.run(Command::OpenDefault);
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
    if (ImGui::BeginMenu("Edit")) {
        if (ImGui::MenuItem("Undo", "Ctrl+Z", false, doc.can_undo() || doc.editing())) commands_.run(Command::Undo);
        if (ImGui::MenuItem("Redo", "Ctrl+Y", false, doc.can_redo())) commands_.run(Command::Redo);
        ImGui::Separator();
        if (ImGui::MenuItem("Edit scene text", "Ctrl+E")) commands_.run(Command::EditText);
        if (ImGui::MenuItem("Apply text", "Ctrl+Enter")) commands_.run(Command::ApplyText);
        if (ImGui::MenuItem("Revert text", nullptr, false, doc.editor_dirty())) commands_.run(Command::RevertText);
        ImGui::Separator();
        // Structural edits: written into the text as ordinary blocks, one undo step each.
        const bool can = doc.has_scene() && !doc.editor_dirty() && !doc.text_behind();
        if (ImGui::BeginMenu("Add (in front of the view)", can)) {
            static const char* const kinds[] = {"sphere", "cylinder", "tetrahedron", "torus", "plane", "chess_plane", "lamp", "spotlight"};
            for (const char* k : kinds)
                if (ImGui::MenuItem(k)) commands_.run(Command::AddItem, k);
            ImGui::EndMenu();
        }
        const bool has = can && selection_.kind != Selection::Kind::None;
        if (ImGui::MenuItem("Duplicate", "Ctrl+D", false, has)) commands_.run(Command::Duplicate);
        if (ImGui::MenuItem("Delete", "Del", false, has)) commands_.run(Command::Delete);
        const bool light = has && selection_.kind == Selection::Kind::Light && selection_.index >= 0 &&
                           std::size_t(selection_.index) < doc.scene().lights.size();
        if (ImGui::MenuItem(light && !doc.scene().lights[std::size_t(selection_.index)].lamp ? "Make the spotlight a lamp"
                                                                                            : "Make the lamp a spotlight",
                            nullptr, false, light))
            commands_.run(Command::SwitchLight);
        ImGui::EndMenu();
    }
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
        ImGui::Separator();
        tools_.view_menu_items();
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        if (ImGui::MenuItem("Mouse and keys...")) commands_.run(Command::Help);
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

// ---------------------------------------------------------------------------------
// Sidebar

void Panels::select(const Selection& s) {
    selection_ = s;
    scroll_to_selection_ = true;
    if (s.kind != Selection::Kind::None && current_tab_ != Objects) want_tab_ = Objects;
}

void Panels::select_from_option(const std::string& spec) {
    std::istringstream in(spec);
    std::string kind;
    int n = 0;
    in >> kind >> n;
    const rt::Scene& s = editor_.doc().scene();
    if (kind == "object" && n >= 1 && n <= int(s.objects.size())) selection_ = {Selection::Kind::Object, n - 1, {}};
    if (kind == "plane" && n >= 1 && n <= int(s.planes.size())) selection_ = {Selection::Kind::Plane, n - 1, {}};
    if (kind == "light" && n >= 1 && n <= int(s.lights.size())) selection_ = {Selection::Kind::Light, n - 1, {}};
    scroll_to_selection_ = true;
}

double Panels::scene_size() const {
    if (const rt::World* w = render_.world()) {
        rt::Aabb b = w->bounds();
        if (!b.empty() && rt::finite(b.lo) && rt::finite(b.hi)) return std::max(rt::length(b.hi - b.lo), 1e-3);
    }
    const rt::Camera& c = editor_.doc().scene().camera;
    return std::max(rt::length(c.centre - c.position), 1e-3);
}

void Panels::draw_sidebar() {
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
            if (ImGui::BeginTabItem(label.c_str(), nullptr, tf)) {
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
}

void Panels::draw_camera_panel() {
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    const Document& doc = editor_.doc();
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    bool open = ImGui::CollapsingHeader("Camera");
    if (open && !doc.has_scene()) {
        ImGui::TextDisabled("No scene yet.");
    } else if (open) {
        ImGui::BeginDisabled(!doc.has_scene());
        float speed = float(scene_size() * 0.002);
        // Room for the longest label at any font size (UI scale).
        float label_w = 0;
        for (const char* l : {"position", "up point", "angle x, y", "projection", "az, el, dist"})
            label_w = std::max(label_w, ImGui::CalcTextSize(l).x);
        ImGui::PushItemWidth(-(label_w + ImGui::GetStyle().ItemInnerSpacing.x + 2));

        // The view: what the image shows. Moving it never edits the file.
        rt::Camera view = nav_.camera();
        bool differs = doc.has_scene() && nav_.differs_from(doc.scene().camera);
        ImGui::TextDisabled("View%s", differs ? " (moved; not in the file)" : " (= scene camera)");
        ImGui::Text("eye    %.3f %.3f %.3f", view.position.x, view.position.y, view.position.z);
        ImGui::Text("centre %.3f %.3f %.3f", view.centre.x, view.centre.y, view.centre.z);
        ViewAngles va = view_angles(view, nav_.world_up());
        double v3[3] = {va.azimuth, va.elevation, va.distance};
        if (ImGui::DragScalarN("az, el, dist", ImGuiDataType_Double, v3, 3, 0.25f, nullptr, nullptr, "%.2f"))
            nav_.set(set_view_angles(view, nav_.world_up(), {v3[0], std::clamp(v3[1], -89.0, 89.0), std::max(v3[2], 1e-6)}));
        if (layout_.fit == FitMode::Window && doc.has_scene()) {
            rt::Camera vc = fit_camera_to_aspect(view, layout_.film_w, layout_.film_h);
            ImGui::TextDisabled("window shows angle_x %.1f (fitted to %dx%d)", vc.angle_x, layout_.film_w, layout_.film_h);
        }
        ImGui::BeginDisabled(!differs);
        if (ImGui::Button("Set scene camera from view")) commands_.run(Command::SetSceneCamera);
        ImGui::EndDisabled();
        ImGui::SameLine();
        if (ImGui::Button("Copy camera block")) commands_.run(Command::CopyCamera);
        if (ImGui::Button("Frame (F)")) commands_.run(Command::FrameScene);
        ImGui::SameLine();
        ImGui::BeginDisabled(!differs);
        if (ImGui::Button("Reset view (R)")) commands_.run(Command::ResetView);
        ImGui::EndDisabled();

        // The scene camera: part of the document (edits here are undoable edits of
        // the file, and the view follows them).
        ImGui::Separator();
        ImGui::TextDisabled("Scene camera (in the file)");
        rt::Camera cam = doc.scene().camera;
        bool changed = false;
        changed |= drag_vec3("position", cam.position, speed);
        changed |= drag_vec3("centre", cam.centre, speed);
        changed |= drag_vec3("up point", cam.up, speed);
        double ang[2] = {cam.angle_x, cam.angle_y};
        const double amin = 0.5, amax = 179.5;
        if (ImGui::DragScalarN("angle x, y", ImGuiDataType_Double, ang, 2, 0.1f, &amin, &amax, "%.2f deg")) {
            cam.angle_x = ang[0];
            cam.angle_y = ang[1];
            changed = true;
        }
        int proj = cam.projection == rt::Projection::Polar ? 1 : 0;
        if (ImGui::Combo("projection", &proj, "linear\0polar (equal angle)\0")) {
            cam.projection = proj ? rt::Projection::Polar : rt::Projection::Linear;
            changed = true;
        }
        ImGui::PopItemWidth();
        if (changed && !rt::camera_problem(cam)) editor_.doc().edit_camera() = cam;
        ImGui::EndDisabled();
    }
    layout_.camera_panel = item_block(top, width);
}

void Panels::draw_objects_tab() {
    if (!selection_valid(editor_.doc().scene(), selection_)) selection_ = {};
    // At least seven rows of the outline, whatever the UI scale.
    float h = std::max(ImGui::GetTextLineHeightWithSpacing() * 7, ImGui::GetContentRegionAvail().y * 0.45f);
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    if (ImGui::BeginChild("outline", ImVec2(0, h), true)) draw_outline();
    ImGui::EndChild();
    layout_.outline = item_block(top, width);
    if (ImGui::BeginChild("properties", ImVec2(0, 0), false)) draw_properties();
    ImGui::EndChild();
}

void Panels::draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label) {
    Selection me{Selection::Kind::Object, top, path};
    auto* csg = std::get_if<rt::Csg>(&obj.shape);
    ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_SpanAvailWidth;
    if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
    if (csg) f |= ImGuiTreeNodeFlags_DefaultOpen;
    else f |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
    bool open = ImGui::TreeNodeEx("node", f, "%s", label.c_str());
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
    auto leaf = [&](Selection me, const std::string& label) {
        ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen |
                               ImGuiTreeNodeFlags_SpanAvailWidth;
        if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
        ImGui::TreeNodeEx("node", f, "%s", label.c_str());
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
            leaf({Selection::Kind::Plane, k, {}}, std::to_string(k + 1) + "  " + (s.planes[std::size_t(k)].chess ? "chess_plane" : "plane"));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("lights", "Lights (%d)", int(s.lights.size()))) {
        for (int k = 0; k < int(s.lights.size()); ++k) {
            const rt::Light& l = s.lights[std::size_t(k)];
            ImGui::PushID(k);
            leaf({Selection::Kind::Light, k, {}}, std::to_string(k + 1) + "  " + (l.lamp ? "lamp" : "spotlight") + "  at " + fmt_vec(l.position));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    scroll_to_selection_ = false;
}

void Panels::draw_properties() {
    if (!editor_.doc().has_scene()) return;
    const rt::Scene& s = editor_.doc().scene();
    switch (selection_.kind) {
        case Selection::Kind::None:
            ImGui::TextDisabled("Click an object in the image or in the list above.");
            break;
        case Selection::Kind::Object: {
            const rt::Object* o = resolve(s, selection_);
            if (!o) break;
            ImGui::Text("Object %d: %s", selection_.index + 1, shape_name(o->shape));
            if (o->loc.line > 0) {
                ImGui::SameLine();
                if (ImGui::SmallButton("show in text")) {
                    editor_.focus(int(offset_of(std::as_const(editor_.doc()).editor_text(), o->loc.line, o->loc.col)));
                }
            }
            shape_details(o->shape);
            ImGui::Separator();
            if (!selection_.path.empty()) {
                ImGui::TextWrapped("A CSG operand: only the whole CSG's material is rendered.");
                if (ImGui::Button("Select the whole CSG")) selection_.path.clear();
                break;
            }
            ImGui::Text(o->has_material ? "Material" : "Material (none in the file: object default)");
            rt::Material m = o->material;
            if (material_editor("material", m)) {
                rt::Object& e = editor_.doc().edit_object(std::size_t(selection_.index));
                e.material = m;
                e.has_material = true;
            }
            break;
        }
        case Selection::Kind::Plane: {
            const rt::Plane& p = s.planes[std::size_t(selection_.index)];
            ImGui::Text("Plane %d: %s", selection_.index + 1, p.chess ? "chess_plane" : "plane");
            for (int i = 0; i < 4; ++i) ImGui::Text("point %d  %s", i + 1, fmt_vec(p.point[i]).c_str());
            ImGui::Separator();
            ImGui::Text(p.chess ? "Material 1" : "Material");
            rt::Material m = p.material;
            if (material_editor("m1", m)) {
                rt::Plane& e = editor_.doc().edit_plane(std::size_t(selection_.index));
                e.material = m;
                e.has_material = true;
            }
            if (p.chess) {
                ImGui::Text("Material 2");
                rt::Material m2 = p.material2;
                if (material_editor("m2", m2)) {
                    rt::Plane& e = editor_.doc().edit_plane(std::size_t(selection_.index));
                    e.material2 = m2;
                    e.has_material2 = true;
                }
            }
            break;
        }
        case Selection::Kind::Light: {
            rt::Light l = s.lights[std::size_t(selection_.index)];
            ImGui::Text("Light %d: %s", selection_.index + 1, l.lamp ? "lamp (point light and glow)" : "spotlight (point light)");
            bool changed = false;
            ImGui::PushItemWidth(-ImGui::GetFontSize() * 9);
            changed |= drag_vec3("position", l.position, float(scene_size() * 0.002));
            // Light colours are intensities (often >> 1 because of the 1/r^2 fall-off):
            // edit them as a tint and a strength.
            double intensity = std::max({l.colour.x, l.colour.y, l.colour.z, 0.0});
            rt::Vec3 tint = intensity > 0 ? l.colour / intensity : rt::Vec3{1, 1, 1};
            float col[3] = {float(tint.x), float(tint.y), float(tint.z)};
            if (ImGui::ColorEdit3("tint", col, ImGuiColorEditFlags_Float)) {
                tint = {col[0], col[1], col[2]};
                if (intensity == 0) intensity = 1;
                changed = true;
            }
            const double zero = 0;
            if (ImGui::DragScalar("intensity", ImGuiDataType_Double, &intensity, float(std::max(intensity * 0.005, 0.01)),
                                  &zero, nullptr, "%.2f"))
                changed = true;
            if (l.lamp) {
                if (ImGui::DragScalar("glow size", ImGuiDataType_Double, &l.size, 0.005f, nullptr, nullptr, "%.3f"))
                    changed = true;
            }
            ImGui::PopItemWidth();
            ImGui::TextDisabled("colour %s", fmt_vec(l.colour).c_str());
            if (changed) {
                l.colour = tint * intensity;
                rt::Light& e = editor_.doc().edit_light(std::size_t(selection_.index));
                e.position = l.position;
                e.colour = l.colour;
                e.size = l.size;
            }
            break;
        }
    }
}

void Panels::draw_render_tab() {
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::CollapsingHeader("Picture")) {
        tools_.draw_panel();
        ImGui::Spacing();
    }
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 11);
    int samples = render_.max_samples();
    ImGui::InputInt("samples per pixel", &samples, 1, 16);
    render_.set_max_samples(std::clamp(samples, 1, 65536));
    double limit = render_.time_limit();
    const double step = 1, fast = 10;
    ImGui::InputScalar("time limit (s)", ImGuiDataType_Double, &limit, &step, &fast, "%.1f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Stop refining after this many seconds; 0: no limit.");
    render_.set_time_limit(std::max(0.0, limit));
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
    ImGui::Text("film %dx%d, %d render threads", p.width, p.height, render_.threads());
    ImGui::Text("rays traced: %.3g", double(p.rays));
    if (p.first_coarse_time >= 0)
        ImGui::Text("first coarse pass: %.1f ms (%dx%d blocks)", p.first_coarse_time * 1000, render_.last_coarse_block(),
                    render_.last_coarse_block());
    if (render_.last_latency_ms() >= 0) ImGui::Text("last view change to image: %.1f ms", render_.last_latency_ms());
    ImGui::Separator();
    if (ImGui::Button("Save image... (Ctrl+P)")) commands_.run(Command::SaveImageDialog);
    ImGui::SameLine();
    if (ImGui::Button("Screenshot (F12)")) commands_.run(Command::Screenshot, "raytracer-view-screenshot.png");
}

void Panels::draw_status_bar(const LoadStatus& load) {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - layout_.status_h));
    ImGui::SetNextWindowSize(ImVec2(float(layout_.area.w), layout_.status_h));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(6, 4));
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
            ImGui::Text("%s (Esc cancels)", load.text.c_str());
        } else {
            rt::RenderProgress p = render_.progress();
            if (ImGui::Button(render_.paused() ? "Resume" : "Pause", ImVec2(ImGui::GetFontSize() * 4.5f, 0)))
                commands_.run(Command::TogglePause);
            ImGui::SameLine();
            double elapsed = p.done && render_.done_generation() == p.generation ? render_.done_elapsed() : p.elapsed;
            double frac = std::clamp((p.samples + p.pass_fraction) / std::max(1, render_.max_samples()), 0.0, 1.0);
            if (render_.time_limit() > 0) frac = std::max(frac, std::min(1.0, elapsed / render_.time_limit()));
            if (p.done) frac = 1;
            char buf[64];
            std::snprintf(buf, sizeof buf, "%d / %d", p.samples, render_.max_samples());
            ImGui::ProgressBar(float(frac), ImVec2(ImGui::GetFontSize() * 8, 0), buf);
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
            if (!tools_.readout_line().empty())
                ImGui::Text("spp  %s  | %s", shown, tools_.readout_line().c_str());
            else
                ImGui::Text("spp  %.2f Mrays/s  %.1f s  %s  |  %s", rate / 1e6, elapsed, shown,
                            layout_.fit == FitMode::Picture ? "picture frame" : "fill window");
        }
        if (!status_.text().empty() && (load.active || tools_.readout_line().empty())) {
            ImGui::SameLine();
            ImGui::TextColored(status_.error() ? kErrorColour : ImVec4(0.75f, 0.75f, 0.75f, 1), "| %s",
                               status_.text().c_str());
        }
    }
    ImGui::End();
    ImGui::PopStyleVar();
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
