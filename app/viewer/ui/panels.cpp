// The ImGui panels of ViewerApp: menu bar, sidebar (camera, outline and properties,
// scene text editor, render settings), status bar, modal dialogs and the film quad.
// Panels read the document and change it only through Document::edit()/apply etc.
#include <imgui.h>
#include <imgui_internal.h>  // GetActiveID, ClearActiveID: 1.86 has no public equivalent
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app.h"
#include "scene_text.h"
#include "scene_writer.h"

namespace rtview {

namespace {

const ImVec4 kErrorColour{1.0f, 0.42f, 0.42f, 1.0f};
const ImVec4 kWarnColour{1.0f, 0.80f, 0.35f, 1.0f};
const ImVec4 kOkColour{0.55f, 0.85f, 0.55f, 1.0f};

const char* shape_name(const rt::Shape& s) {
    switch (s.index()) {
        case 0: return "sphere";
        case 1: return "tetrahedron";
        case 2: return "cylinder";
        case 3: return "torus";
        default: {
            switch (std::get<rt::Csg>(s).type) {
                case rt::CsgType::Union: return "CSG union";
                case rt::CsgType::Intersection: return "CSG intersection";
                case rt::CsgType::Difference: return "CSG difference";
            }
            return "CSG";
        }
    }
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

// Guarded: the headless binary has no key map, and index -1 means "not mapped".
bool imgui_escape_pressed() {
    int k = ImGui::GetKeyIndex(ImGuiKey_Escape);
    return k >= 0 && ImGui::IsKeyPressed(k, false);
}

Rect item_block(const ImVec2& top_left, float width) {
    ImVec2 end = ImGui::GetCursorScreenPos();
    return {top_left.x, top_left.y, width, end.y - top_left.y};
}

}  // namespace

// ---------------------------------------------------------------------------------
// Menu bar

void ViewerApp::draw_menu_bar() {
    if (!ImGui::BeginMainMenuBar()) return;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Open...", "Ctrl+O")) {
            path_input_.clear();
            open_open_popup_ = true;
        }
        if (ImGui::BeginMenu("Open Recent")) {
            if (recent_.paths().empty()) ImGui::MenuItem("(none yet)", nullptr, false, false);
            for (const std::string& p : recent_.paths())
                if (ImGui::MenuItem(p.c_str())) request(Action::Open, p);
            ImGui::EndMenu();
        }
        if (ImGui::MenuItem("Open the default scene")) request(Action::OpenDefault);
        ImGui::Separator();
        if (ImGui::MenuItem("Save", "Ctrl+S")) do_save();
        if (ImGui::MenuItem("Save As...", "Ctrl+Shift+S")) {
            path_input_ = doc_.path().empty() ? doc_.name() : doc_.path();
            open_save_as_popup_ = true;
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Save Image...", "Ctrl+P")) {
            std::string base = doc_.path().empty() ? doc_.name() : doc_.path();
            std::size_t dot = base.find_last_of('.');
            path_input_ = (dot == std::string::npos ? base : base.substr(0, dot)) + ".png";
            open_image_popup_ = true;
        }
        if (ImGui::MenuItem("Screenshot", "F12")) screenshot_request_ = "raytracer-view-screenshot.png";
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) request(Action::Quit);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        if (ImGui::MenuItem("Undo", "Ctrl+Z", false, doc_.can_undo() || doc_.editing())) doc_.undo();
        if (ImGui::MenuItem("Redo", "Ctrl+Y", false, doc_.can_redo())) doc_.redo();
        ImGui::Separator();
        if (ImGui::MenuItem("Edit scene text", "Ctrl+E")) {
            want_tab_ = 1;
            focus_editor_ = true;
        }
        if (ImGui::MenuItem("Apply text", "Ctrl+Enter")) {
            bool ok = doc_.apply_text();
            status(ok ? "Applied the scene text" : "The scene text has errors", !ok);
        }
        if (ImGui::MenuItem("Revert text", nullptr, false, doc_.editor_dirty())) doc_.revert_text();
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        if (ImGui::MenuItem("Frame the scene", "F")) frame_scene();
        if (ImGui::MenuItem("Reset to the file's camera", "R")) reset_camera();
        ImGui::Separator();
        if (ImGui::MenuItem("Fill the window", nullptr, fit_ == FitMode::Window)) fit_ = FitMode::Window;
        if (ImGui::MenuItem("Scene picture size (letterboxed)", nullptr, fit_ == FitMode::Picture)) fit_ = FitMode::Picture;
        ImGui::Separator();
        if (ImGui::MenuItem("Pause rendering", "Space", paused_)) toggle_pause();
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        if (ImGui::MenuItem("Mouse and keys...")) open_help_popup_ = true;
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

// ---------------------------------------------------------------------------------
// Sidebar

void ViewerApp::draw_sidebar() {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - sidebar_w_, menu_h_));
    ImGui::SetNextWindowSize(ImVec2(sidebar_w_, io.DisplaySize.y - menu_h_));
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                             ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                             ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (!ImGui::Begin("##sidebar", nullptr, flags)) {
        ImGui::End();
        return;
    }
    if (recovery_offer_) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("Unsaved text of %s from an earlier session (the viewer did not close normally) was kept.",
                           doc_.name().c_str());
        ImGui::PopStyleColor();
        if (ImGui::Button("Restore it")) {
            doc_.restore_draft(recovered_text_);
            recovery_offer_ = false;
            want_tab_ = 1;
            status("Restored the unsaved text into the editor (Ctrl+Enter applies it, Ctrl+Z undoes)");
        }
        ImGui::SameLine();
        if (ImGui::Button("Discard it")) {
            recovery_.discard(doc_.path());
            recovery_offer_ = false;
        }
        ImGui::Separator();
    }
    if (doc_.disk_conflict()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("%s changed on disk, and you have unsaved edits here.", doc_.name().c_str());
        ImGui::PopStyleColor();
        if (ImGui::Button("Reload from disk")) {
            doc_.resolve_conflict_reload();
            status("Reloaded " + doc_.name() + " (Ctrl+Z brings your edits back)");
        }
        ImGui::SameLine();
        if (ImGui::Button("Keep mine")) doc_.resolve_conflict_keep();
        ImGui::Separator();
    }
    draw_camera_panel();
    if (ImGui::BeginTabBar("tabs")) {
        static const char* const names[3] = {"Objects", "Text", "Render"};
        for (int t = 0; t < 3; ++t) {
            ImGuiTabItemFlags tf = want_tab_ == t ? ImGuiTabItemFlags_SetSelected : 0;
            std::string label = names[t];
            if (t == 1 && (doc_.editor_dirty() || doc_.has_errors()))
                label += doc_.has_errors() ? " (errors)" : " (unapplied)";
            label += "###tab" + std::to_string(t);  // stable ID while the label changes
            if (ImGui::BeginTabItem(label.c_str(), nullptr, tf)) {
                current_tab_ = t;
                if (want_tab_ == t) want_tab_ = -1;
                if (t == 0) draw_objects_tab();
                if (t == 1) draw_text_tab();
                if (t == 2) draw_render_tab();
                ImGui::EndTabItem();
            }
        }
        ImGui::EndTabBar();
    }
    ImGui::End();
}

void ViewerApp::draw_camera_panel() {
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::CollapsingHeader("Camera")) {
        ImGui::BeginDisabled(!doc_.has_scene());
        rt::Camera cam = doc_.scene().camera;
        bool changed = false;
        float speed = float(scene_size() * 0.002);
        ImGui::PushItemWidth(-84);
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
        ViewAngles va = view_angles(cam, world_up());
        double v3[3] = {va.azimuth, va.elevation, va.distance};
        if (ImGui::DragScalarN("az, el, dist", ImGuiDataType_Double, v3, 3, 0.25f, nullptr, nullptr, "%.2f")) {
            cam = set_view_angles(cam, world_up(), {v3[0], std::clamp(v3[1], -89.0, 89.0), std::max(v3[2], 1e-6)});
            changed = true;
        }
        ImGui::PopItemWidth();
        if (changed) set_camera(cam);
        if (fit_ == FitMode::Window && doc_.has_scene()) {
            rt::Camera vc = view_camera();
            ImGui::TextDisabled("window shows angle_x %.1f (fitted to %dx%d)", vc.angle_x, film_w_, film_h_);
        }
        if (ImGui::Button("Copy camera block")) {
            ImGui::SetClipboardText(rt::write_camera(doc_.scene().camera).c_str());
            status("Copied the camera block to the clipboard");
        }
        ImGui::SameLine();
        if (ImGui::Button("Frame (F)")) frame_scene();
        ImGui::SameLine();
        if (ImGui::Button("Reset (R)")) reset_camera();
        ImGui::EndDisabled();
    }
    camera_panel_ = item_block(top, width);
}

void ViewerApp::draw_objects_tab() {
    if (!selection_valid(doc_.scene(), selection_)) selection_ = {};
    float h = std::max(120.f, ImGui::GetContentRegionAvail().y * 0.45f);
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    if (ImGui::BeginChild("outline", ImVec2(0, h), true)) draw_outline();
    ImGui::EndChild();
    outline_rect_ = item_block(top, width);
    if (ImGui::BeginChild("properties", ImVec2(0, 0), false)) draw_properties();
    ImGui::EndChild();
}

void ViewerApp::draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label) {
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

void ViewerApp::draw_outline() {
    if (!doc_.has_scene()) {
        ImGui::TextDisabled("No scene yet: fix the errors in the Text tab.");
        return;
    }
    const rt::Scene& s = doc_.scene();
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

bool ViewerApp::material_editor(const char* id, rt::Material& m) {
    ImGui::PushID(id);
    bool changed = false;
    const double zero = 0, one = 1, ior_max = 3;
    ImGui::PushItemWidth(-120);
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

void ViewerApp::draw_properties() {
    if (!doc_.has_scene()) return;
    const rt::Scene& s = doc_.scene();
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
                    want_tab_ = 1;
                    focus_editor_ = true;
                    pending_cursor_ = int(offset_of(doc_.editor_text(), o->loc.line, o->loc.col));
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
                rt::Object& e = doc_.edit().objects[std::size_t(selection_.index)];
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
                rt::Plane& e = doc_.edit().planes[std::size_t(selection_.index)];
                e.material = m;
                e.has_material = true;
            }
            if (p.chess) {
                ImGui::Text("Material 2");
                rt::Material m2 = p.material2;
                if (material_editor("m2", m2)) {
                    rt::Plane& e = doc_.edit().planes[std::size_t(selection_.index)];
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
            ImGui::PushItemWidth(-120);
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
                rt::Light& e = doc_.edit().lights[std::size_t(selection_.index)];
                e.position = l.position;
                e.colour = l.colour;
                e.size = l.size;
            }
            break;
        }
    }
}

// ---------------------------------------------------------------------------------
// Scene text editor

int ViewerApp::editor_callback(ImGuiInputTextCallbackData* data) {
    auto* app = static_cast<ViewerApp*>(data->UserData);
    if (data->EventFlag == ImGuiInputTextFlags_CallbackAlways) {
        // ImGui 1.86 has no call to place the cursor of a text field: do it from inside.
        if (app->pending_cursor_ >= 0) {
            int p = std::min(app->pending_cursor_, data->BufTextLen);
            data->CursorPos = data->SelectionStart = data->SelectionEnd = p;
            app->pending_cursor_ = -1;
        }
        app->editor_cursor_ = data->CursorPos;
    }
    return 0;
}

void ViewerApp::draw_text_tab() {
    bool can_apply = doc_.editor_dirty() || doc_.has_errors();
    ImGui::BeginDisabled(!can_apply);
    if (ImGui::Button("Apply (Ctrl+Enter)")) {
        bool ok = doc_.apply_text();
        status(ok ? "Applied the scene text" : "The scene text has errors; still showing the last good scene", !ok);
    }
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!doc_.editor_dirty() && !doc_.text_behind());
    if (ImGui::Button("Revert")) doc_.revert_text();
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (doc_.editor_dirty()) ImGui::TextColored(kWarnColour, "unapplied changes");
    else ImGui::TextColored(kOkColour, "text = scene");
    if (doc_.text_behind()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("Panel edits are not in this text: it has unapplied changes that do not parse. "
                           "Apply uses the text; Revert drops the text changes.");
        ImGui::PopStyleColor();
    }

    const auto& diags = doc_.diagnostics();
    float line = ImGui::GetTextLineHeightWithSpacing();
    float diag_h = line * float(std::clamp(int(diags.size()), 1, 6)) + ImGui::GetStyle().WindowPadding.y * 2;
    float editor_h = std::max(line * 4, ImGui::GetContentRegionAvail().y - diag_h - ImGui::GetStyle().ItemSpacing.y);

    // Escape in an ImGui text field reverts everything typed since it was focused.
    // The user's text must never be lost, so Escape just leaves the field instead.
    if (editor_active_ && imgui_escape_pressed()) ImGui::ClearActiveID();
    if (doc_.text_version() != editor_seen_version_) {
        // The document replaced the text (undo, reload, panel edit): an active field
        // keeps its own copy, so make it let go and take the new text.
        if (editor_id_ != 0 && ImGui::GetActiveID() == editor_id_) {
            ImGui::ClearActiveID();
            focus_editor_ = true;
            pending_cursor_ = editor_cursor_;
        }
        editor_seen_version_ = doc_.text_version();
    }
    if (focus_editor_) {
        ImGui::SetKeyboardFocusHere();
        focus_editor_ = false;
    }
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    bool changed = ImGui::InputTextMultiline("##scene_text", &doc_.editor_text(), ImVec2(-1, editor_h),
                                             ImGuiInputTextFlags_AllowTabInput | ImGuiInputTextFlags_CallbackAlways,
                                             &ViewerApp::editor_callback, this);
    editor_id_ = ImGui::GetItemID();
    editor_active_ = ImGui::IsItemActive();
    editor_rect_ = {top.x, top.y, width, editor_h};
    if (changed) check_due_ = ImGui::GetTime() + 0.3;  // live check once typing pauses

    diag_rect_ = {ImGui::GetCursorScreenPos().x, ImGui::GetCursorScreenPos().y, width, diag_h};
    if (ImGui::BeginChild("diagnostics", ImVec2(0, diag_h), true)) {
        if (diags.empty()) ImGui::TextDisabled(doc_.editor_dirty() ? "No errors (Ctrl+Enter applies)." : "No errors.");
        for (std::size_t k = 0; k < diags.size(); ++k) {
            const rt::Diagnostic& d = diags[k];
            std::string text = std::to_string(d.line) + ":" + std::to_string(d.col) + ": " +
                               (d.is_error() ? "error: " : "warning: ") + d.message;
            ImGui::PushID(int(k));
            ImGui::PushStyleColor(ImGuiCol_Text, d.is_error() ? kErrorColour : kWarnColour);
            if (ImGui::Selectable(text.c_str())) {
                pending_cursor_ = int(offset_of(doc_.editor_text(), d.line, d.col));
                focus_editor_ = true;
            }
            ImGui::PopStyleColor();
            ImGui::PopID();
        }
    }
    ImGui::EndChild();
}

// ---------------------------------------------------------------------------------
// Render settings and status

void ViewerApp::draw_render_tab() {
    ImGui::PushItemWidth(-150);
    int samples = max_samples_;
    ImGui::InputInt("samples per pixel", &samples, 1, 16);
    samples = std::clamp(samples, 1, 65536);
    if (samples != max_samples_) {
        max_samples_ = samples;
        settings_changed_ = true;
    }
    double limit = time_limit_;
    const double step = 1, fast = 10;
    ImGui::InputScalar("time limit (s)", ImGuiDataType_Double, &limit, &step, &fast, "%.1f");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Stop refining after this many seconds; 0: no limit.");
    limit = std::max(0.0, limit);
    if (limit != time_limit_) {
        time_limit_ = limit;
        settings_changed_ = true;
    }
    ImGui::PopItemWidth();
    bool paused = paused_;
    if (ImGui::Checkbox("Paused (Space)", &paused)) toggle_pause();
    ImGui::Separator();
    ImGui::Text("Render size");
    if (ImGui::RadioButton("fill the window", fit_ == FitMode::Window)) fit_ = FitMode::Window;
    std::string pic = "scene picture_size";
    if (doc_.has_scene()) pic += " (" + std::to_string(doc_.scene().width) + "x" + std::to_string(doc_.scene().height) + ", letterboxed)";
    if (ImGui::RadioButton(pic.c_str(), fit_ == FitMode::Picture)) fit_ = FitMode::Picture;
    ImGui::Separator();
    rt::RenderProgress p = renderer_.progress();
    ImGui::Text("film %dx%d, %d render threads", p.width, p.height, renderer_.threads());
    ImGui::Text("rays traced: %.3g", double(p.rays));
    if (p.first_coarse_time >= 0) ImGui::Text("first coarse pass: %.1f ms", p.first_coarse_time * 1000);
    if (last_latency_ms_ >= 0) ImGui::Text("last view change to image: %.1f ms", last_latency_ms_);
    ImGui::Separator();
    if (ImGui::Button("Save image... (Ctrl+P)")) {
        std::string base = doc_.path().empty() ? doc_.name() : doc_.path();
        std::size_t dot = base.find_last_of('.');
        path_input_ = (dot == std::string::npos ? base : base.substr(0, dot)) + ".png";
        open_image_popup_ = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Screenshot (F12)")) screenshot_request_ = "raytracer-view-screenshot.png";
}

void ViewerApp::draw_status_bar() {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - status_h_));
    ImGui::SetNextWindowSize(ImVec2(float(area_.w), status_h_));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(6, 4));
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                             ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                             ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (ImGui::Begin("##status", nullptr, flags)) {
        rt::RenderProgress p = renderer_.progress();
        if (ImGui::Button(paused_ ? "Resume" : "Pause", ImVec2(ImGui::GetFontSize() * 4.5f, 0))) toggle_pause();
        ImGui::SameLine();
        double elapsed = p.done && done_generation_ == p.generation ? done_elapsed_ : p.elapsed;
        double frac = std::clamp((p.samples + p.pass_fraction) / std::max(1, max_samples_), 0.0, 1.0);
        if (time_limit_ > 0) frac = std::max(frac, std::min(1.0, elapsed / time_limit_));
        if (p.done) frac = 1;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%d / %d", p.samples, max_samples_);
        ImGui::ProgressBar(float(frac), ImVec2(ImGui::GetFontSize() * 8, 0), buf);
        ImGui::SameLine();
        double rate = elapsed > 0 ? double(p.rays) / elapsed : 0;
        const char* state = paused_ ? "paused" : p.done ? "done" : building_.valid() ? "building" : p.running ? "rendering" : "idle";
        ImGui::Text("spp  pass %d  %.2f Mrays/s  %.1f s  %s", p.passes, rate / 1e6, elapsed, state);
        if (!status_text_.empty()) {
            ImGui::SameLine();
            ImGui::TextColored(status_error_ ? kErrorColour : ImVec4(0.75f, 0.75f, 0.75f, 1), "| %s", status_text_.c_str());
        }
    }
    ImGui::End();
    ImGui::PopStyleVar();
}

// ---------------------------------------------------------------------------------
// Dialogs

void ViewerApp::draw_popups() {
    if (open_unsaved_popup_) ImGui::OpenPopup("Unsaved changes");
    if (open_open_popup_) ImGui::OpenPopup("Open scene");
    if (open_save_as_popup_) ImGui::OpenPopup("Save scene as");
    if (open_image_popup_) ImGui::OpenPopup("Save image");
    if (open_help_popup_) ImGui::OpenPopup("Mouse and keys");
    bool focus_path = open_open_popup_ || open_save_as_popup_ || open_image_popup_;
    open_unsaved_popup_ = open_open_popup_ = open_save_as_popup_ = open_image_popup_ = open_help_popup_ = false;

    ImVec2 centre = ImGui::GetMainViewport()->GetCenter();
    auto path_field = [&](const char* hint) {
        if (focus_path) ImGui::SetKeyboardFocusHere();
        ImGui::SetNextItemWidth(ImGui::GetFontSize() * 30);
        return ImGui::InputTextWithHint("##path", hint, &path_input_, ImGuiInputTextFlags_EnterReturnsTrue);
    };

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("%s has unsaved changes.", doc_.name().c_str());
        if (ImGui::Button("Save")) {
            ImGui::CloseCurrentPopup();
            if (doc_.path().empty()) {
                path_input_ = doc_.name();
                open_save_as_popup_ = true;  // the pending action runs after Save As
            } else {
                std::string err = doc_.save();
                if (err.empty()) {
                    Action a = pending_action_;
                    pending_action_ = Action::None;
                    perform(a, pending_path_);
                } else {
                    status("Save failed: " + err, true);
                    pending_action_ = Action::None;
                }
            }
        }
        ImGui::SameLine();
        if (ImGui::Button("Discard changes")) {
            ImGui::CloseCurrentPopup();
            Action a = pending_action_;
            pending_action_ = Action::None;
            perform(a, pending_path_);
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || imgui_escape_pressed()) {
            ImGui::CloseCurrentPopup();
            pending_action_ = Action::None;
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Open scene", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        bool go = path_field("scene file path");
        if (!recent_.paths().empty()) {
            ImGui::TextDisabled("Recent:");
            for (const std::string& p : recent_.paths())
                if (ImGui::Selectable(p.c_str())) path_input_ = p;
        }
        go |= ImGui::Button("Open");
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || imgui_escape_pressed()) ImGui::CloseCurrentPopup();
        else if (go && !path_input_.empty()) {
            ImGui::CloseCurrentPopup();
            request(Action::Open, path_input_);
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save scene as", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        bool go = path_field("new scene file path");
        go |= ImGui::Button("Save");
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || imgui_escape_pressed()) {
            ImGui::CloseCurrentPopup();
            pending_action_ = Action::None;
        } else if (go && !path_input_.empty()) {
            ImGui::CloseCurrentPopup();
            if (do_save_as(path_input_) && pending_action_ != Action::None) {
                Action a = pending_action_;
                pending_action_ = Action::None;
                perform(a, pending_path_);
            }
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Save image", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextDisabled("The film as rendered so far (%s); .png or .ppm.",
                            fit_ == FitMode::Window ? "window size" : "picture size");
        bool go = path_field("image path (.png or .ppm)");
        go |= ImGui::Button("Save");
        ImGui::SameLine();
        if (ImGui::Button("Cancel") || imgui_escape_pressed()) ImGui::CloseCurrentPopup();
        else if (go && !path_input_.empty()) {
            ImGui::CloseCurrentPopup();
            do_save_image(path_input_);
        }
        ImGui::EndPopup();
    }

    ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Mouse and keys", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        std::string help = help_text(false);
        std::size_t at = help.find("Mouse and keys");
        ImGui::TextUnformatted(at == std::string::npos ? help.c_str() : help.c_str() + at);
        if (ImGui::Button("Close") || imgui_escape_pressed()) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

// ---------------------------------------------------------------------------------
// The film

void ViewerApp::draw_film() {
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    ImVec2 p0(float(image_.x), float(image_.y)), p1(float(image_.x + image_.w), float(image_.y + image_.h));
    if (film_.valid() && (doc_.has_scene() || started_world_)) {
        // 1:1 in framebuffer pixels: nearest filtering shows the film's pixels exactly.
        bool exact = std::fabs(image_.w * fb_scale_ - film_.width()) < 0.5 &&
                     std::fabs(image_.h * fb_scale_ - film_.height()) < 0.5;
        film_.set_nearest(exact);
        dl->AddImage(film_.id(), p0, p1);
    }
    if (!doc_.has_scene()) {
        const char* msg = "No image: the scene text has errors (see the Text tab).";
        ImVec2 sz = ImGui::CalcTextSize(msg);
        dl->AddText(ImVec2(float(area_.x + (area_.w - sz.x) / 2), float(area_.y + (area_.h - sz.y) / 2)),
                    ImGui::GetColorU32(kErrorColour), msg);
    }
}

}  // namespace rtview
