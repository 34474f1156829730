// ViewerApp with several things selected (see app.h, selection.h): the box select on the
// picture (Ctrl+Shift+left drag), and Delete and Duplicate of all of them as one step.
#include "app.h"

#include <imgui.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "imgui_common.h"
#include "status_notes.h"

namespace rtview {

bool ViewerApp::box_select(bool usable) {
    ImGuiIO& io = ImGui::GetIO();
    const double mx = io.MousePos.x, my = io.MousePos.y;
    if (box_active_) {
        if (!usable || escape_pressed()) {
            box_active_ = false;
            status_.set("Box select cancelled");
            return true;
        }
        if (ImGui::IsMouseDown(0)) return true;
        box_active_ = false;
        finish_box(box_x0_, box_y0_, mx, my);
        return true;
    }
    // Ctrl alone draws a render region (the picture tools'); Ctrl with Shift selects.
    if (!usable || io.WantCaptureMouse || !io.KeyCtrl || !io.KeyShift || io.KeyAlt || !ImGui::IsMouseClicked(0) ||
        !layout_.image.contains(mx, my) || !nav_.has_view() || move_.dragging())
        return false;
    box_active_ = true;
    box_x0_ = mx;
    box_y0_ = my;
    status_.set("Box select: release to add what the box sees to the selection (Esc cancels)");
    return true;
}

void ViewerApp::finish_box(double x0, double y0, double x1, double y1) {
    const rt::World* w = render_.world();
    if (!w || !editor_.doc().has_scene()) return;
    // (As for a click: the world of the scene before an edit numbers its things as that
    // scene did.)
    if (render_.world_version() != editor_.doc().content_version()) {
        status_.set("The picture is being updated to the edited scene: draw the box again once it shows it");
        return;
    }
    const rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    const std::vector<SceneItem> seen = items_in_box(*w, vc, layout_.image, layout_.film_w, layout_.film_h, x0, y0, x1, y1);
    // Planes reach everywhere: a box around things on a floor would always take the
    // floor too. They count only when the box sees nothing else.
    std::vector<SceneItem> things;
    for (const SceneItem& i : seen)
        if (i.kind != SceneItem::Kind::Plane) things.push_back(i);
    for (int l : move_.lights_in_box(x0, y0, x1, y1))
        if (std::find(things.begin(), things.end(), SceneItem{SceneItem::Kind::Light, l}) == things.end())
            things.push_back({SceneItem::Kind::Light, l});
    if (things.empty()) things = seen;
    if (things.empty()) {
        status_.set("The box saw nothing to select");
        return;
    }
    Selection s = panels_.selected();
    add_all(s, things);
    panels_.set_selected(s);
    status_.set(selection_summary(s) + " (Shift+click adds or takes out one; Esc: none)");
}

void ViewerApp::draw_box() const {
    if (!box_active_) return;
    const ImVec2 m = ImGui::GetIO().MousePos;
    const ImVec2 a(float(std::min<double>(box_x0_, m.x)), float(std::min<double>(box_y0_, m.y)));
    const ImVec2 b(float(std::max<double>(box_x0_, m.x)), float(std::max<double>(box_y0_, m.y)));
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    const float s = ImGui::GetFontSize() / 13.f;
    dl->AddRectFilled(a, b, IM_COL32(255, 170, 30, 40));
    dl->AddRect(a, b, IM_COL32(0, 0, 0, 170), 0, 0, 3.f * s);
    dl->AddRect(a, b, IM_COL32(255, 170, 30, 255), 0, 0, 1.4f * s);
}

bool ViewerApp::group_edit(Command c) {
    Document& doc = editor_.doc();
    const Selection before = panels_.selected();
    const SceneLayout* layout = doc.layout();
    const std::string& text = std::as_const(doc).editor_text();
    const rt::Scene& scene = doc.scene();
    const bool del = c == Command::Delete;
    std::optional<GroupEdit> g = del ? delete_items(text, scene, before.many, layout)
                                     : duplicate_items(text, scene, before.many, duplicate_offset(scene), layout);
    const std::string what = g ? std::to_string(g->done) + (g->done == 1 ? " thing" : " things") : std::string();
    const std::string name = (del ? "Delete " : "Duplicate ") + what;
    // Spliced item by item where it can be (a million-object scene is not parsed again),
    // else as one replacement of the text.
    const auto whole = [&] {
        const TextReplacement r = whole_replacement(text, *g);
        return !r.empty() && doc.replace_text(r.offset, r.length, r.text, name);
    };
    if (!g || !((!g->splices.empty() && doc.splice_texts(g->splices, name)) || whole())) {
        status_.set(g || before.many.empty() ? "Cannot do that to this scene text"
                                             : "Cannot do that: these things come from included files (edit them there)",
                    true);
        return false;
    }
    Selection after;
    add_all(after, g->select);  // the copies; nothing after a delete
    panels_.set_selected(after);
    selection_steps_.made(doc.undo_depth(), name, before, after);
    std::string said = (del ? "Deleted " : "Duplicated ") + what;
    if (g->skipped) said += " (" + std::to_string(g->skipped) + " from included files left as they are)";
    status_.set_about_step(said + " (Ctrl+Z undoes)" + light_note(doc), doc.history_changes());
    return true;
}

}  // namespace rtview
