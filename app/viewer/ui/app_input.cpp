// ViewerApp's input (see app.h): the keyboard shortcuts, Escape and Ctrl keys closing
// menus, and what a click on the picture selects or focuses on.
#include "app.h"

#include <imgui.h>
#include <imgui_internal.h>  // the open popups' stack: 1.86 has no public equivalent

#include <cstdio>
#include <ctime>
#include <string>

#include "imgui_common.h"

namespace rtview {

bool ViewerApp::close_menus_for_keys() {
    ImGuiContext& g = *GImGui;
    if (g.OpenPopupStack.empty()) return false;
    // A modal dialog (or a popup not drawn yet) handles its own keys.
    for (const ImGuiPopupData& p : g.OpenPopupStack)
        if (!p.Window || (p.Window->Flags & ImGuiWindowFlags_Modal)) return false;
    if (imgui_key_pressed(ImGuiKey_Escape)) {
        ImGui::ClosePopupsExceptModals();
        return true;
    }
    if (ImGui::GetIO().KeyCtrl)
        for (int k = 'A'; k <= 'Z'; ++k)
            if (key_pressed(k)) {
                ImGui::ClosePopupsExceptModals();
                break;
            }
    return false;
}

void ViewerApp::handle_shortcuts() {
    ImGuiIO& io = ImGui::GetIO();
    bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl) {
        if (key_pressed(keys::kS)) run(shift ? Command::SaveAsDialog : Command::Save);
        if (key_pressed(keys::kQ)) run(Command::Quit);  // asks first if there are unsaved edits
        if (key_pressed(keys::kO)) run(Command::OpenDialog);
        if (key_pressed(keys::kN)) run(Command::NewScene);
        if (key_pressed(keys::kP)) run(Command::SaveImageDialog);
        if (key_pressed(keys::kE)) run(Command::EditText);
        if (key_pressed(keys::kK)) run(Command::SetSceneCamera);
        if (imgui_key_pressed(ImGuiKey_Enter) || imgui_key_pressed(ImGuiKey_KeyPadEnter)) run(Command::ApplyText);
        // In a text field, Ctrl+Z/Y belong to the field's own undo.
        if (!io.WantTextInput) {
            if (imgui_key_pressed(ImGuiKey_Z, true)) run(shift ? Command::Redo : Command::Undo);
            else if (imgui_key_pressed(ImGuiKey_Y, true)) run(Command::Redo);
        }
    }
    if (key_pressed(keys::kF12)) {
        char name[64];
        std::time_t t = std::time(nullptr);
        std::strftime(name, sizeof name, "raytracer-view-%Y%m%d-%H%M%S.png", std::localtime(&t));
        run(Command::Screenshot, name);
    }
    if (loader_.active() && imgui_key_pressed(ImGuiKey_Escape) && !esc_closed_menu_ &&
        !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId))
        run(Command::CancelLoad);
    if (!io.WantCaptureKeyboard && ctrl && !io.KeyAlt && key_pressed(keys::kD)) run(Command::Duplicate);
    if (!io.WantCaptureKeyboard && !ctrl && !io.KeyAlt) {
        escape_clears_selection();
        if (imgui_key_pressed(ImGuiKey_Delete)) run(Command::Delete);
        if (imgui_key_pressed(ImGuiKey_Space)) run(Command::TogglePause);
        if (key_pressed(keys::kF)) run(Command::FrameScene);
        if (key_pressed(keys::kR)) run(Command::ResetView);
        // The handle: move, turn, size (Blender's G/R/S; R and S are the view's here).
        const int handle_keys[3] = {keys::kG, keys::kY, keys::kU};
        for (int k = 0; k < 3; ++k)
            if (key_pressed(handle_keys[k]) && !move_.dragging()) {
                move_.set_mode(HandleMode(k));
                if (k > 0 && !panels_.selected().many.empty()) {
                    status_.set("Several things selected: they share the move handle; turning and sizing work on "
                                "one thing at a time (click one alone)");
                    continue;
                }
                status_.set(k == 0   ? "Move handle (G): arrows along x/y/z, the square in the view plane"
                            : k == 1 ? "Turn handle (Y): a ring turns about its axis, the outer circle about the view; "
                                       "Shift snaps to 15 degrees"
                                     : "Size handle (U): a box sizes along the object's own axis, the middle one all "
                                       "three; Shift snaps to tenths");
            }
        // The picture alone, as Tab hides the panels of image editors.
        if (imgui_key_pressed(ImGuiKey_Tab) && !io.KeyShift && !ImGui::IsAnyItemActive()) {
            layout_.sidebar_hidden = !layout_.sidebar_hidden;
            status_.set(layout_.sidebar_hidden ? "Sidebar hidden (Tab shows it)" : "Sidebar shown (drag its edge to resize)");
        }
    }
}

void ViewerApp::escape_clears_selection() {
    if (!imgui_key_pressed(ImGuiKey_Escape) || esc_closed_menu_ || move_.dragging() || box_active_ || loader_.active() ||
        ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId) || panels_.selection().none())
        return;
    panels_.clear_selection();
    status_.set("Nothing selected (Esc)");
}

void ViewerApp::pick_item(const ItemRef& s, Pick how) {
    const Selection& now = panels_.selected();
    if (how == Pick::Toggle) {
        if (s.none()) return;  // (Shift+click on nothing keeps the selection)
        Selection g = now;
        toggle(g, s.item);
        panels_.set_selected(g);
        status_.set(g.one.none() ? std::string("Nothing selected")
                                 : selection_summary(g) + " (Shift+click adds or takes out; Esc: none)");
        return;
    }
    // The context menu over one of several selected things is for all of them.
    if (how == Pick::KeepGroup && !now.many.empty() && !s.none() && is_selected(now, s.item)) return;
    panels_.select(s);
}

void ViewerApp::select_at(double px, double py, Pick how) {
    const rt::World* w = render_.world();
    if (!w) return;
    // What is drawn over the picture comes first: the selection's handle (it stays
    // selected), a light's marker.
    if (move_.over_handle(editor_.doc(), panels_.selected(), screen_view(), px, py)) return;
    if (int light = move_.light_under(px, py); light >= 0) {
        pick_item({{SceneItem::Kind::Light, light}, {}}, how);
        return;
    }
    // The world of the scene before an edit (the new one still compiles) numbers the
    // objects as that scene did: what it would pick is another object of this one.
    if (render_.world_version() != editor_.doc().content_version()) {
        status_.set("The picture is being updated to the edited scene: click again once it shows it");
        return;
    }
    rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    rt::PickResult r = pick_at(*w, vc, layout_.image, layout_.film_w, layout_.film_h, px, py);
    ItemRef s;
    if (r.object >= 0) s = {{SceneItem::Kind::Object, r.object}, {}};
    else if (r.plane >= 0) s = {{SceneItem::Kind::Plane, r.plane}, {}};
    else if (r.light >= 0) s = {{SceneItem::Kind::Light, r.light}, {}};
    pick_item(s, how);
}

void ViewerApp::focus_at(double px, double py) {
    const rt::World* w = render_.world();
    Document& doc = editor_.doc();
    if (!w || !doc.has_scene()) return;
    if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
        status_.set(blocked, true);
        return;
    }
    const rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    const rt::PickResult r = pick_at(*w, vc, layout_.image, layout_.film_w, layout_.film_h, px, py);
    if (!r.hit) {
        status_.set("Nothing under the cursor to focus on", true);
        return;
    }
    const rt::Camera view = nav_.camera();
    const bool moved = nav_.differs_from(doc.scene().camera);
    rt::Camera cam = doc.scene().camera;
    const double d = focus_distance_to(cam, r.point), dv = focus_distance_to(view, r.point);
    if (!(d > 0)) {
        status_.set("That point is behind the scene camera: focus not changed", true);
        return;
    }
    cam.focus_distance = d;
    if (!doc.set_camera(cam)) return;
    if (moved && dv > 0) {
        // The view stays where it was (a scene camera edit would take it back), with
        // the same focus.
        nav_.follow(doc.scene().camera);
        rt::Camera v = view;
        v.focus_distance = dv;
        nav_.set(v);
    }
    char msg[160];
    std::snprintf(msg, sizeof msg, "Focus distance %.4g%s (Ctrl+Z undoes)", d,
                  cam.aperture > 0 ? "" : "; set the camera's aperture to see the blur");
    status_.set_about_step(msg, doc.history_changes());
}

}  // namespace rtview
