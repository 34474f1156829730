// ViewerApp's structural edits: one text replacement each (scene_edits.h), applied by
// the document as one undo step, where added items go, and the picture's context menu.
// The text must be the scene's: a draft is applied or reverted first.
#include "app.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "paths.h"
#include "probe.h"
#include "scene_edits.h"
#include "status_notes.h"

namespace rtview {

Placement ViewerApp::new_item_placement(bool object) {
    const bool pointed = place_x_ >= 0;
    const std::pair<double, double> at{place_x_, place_y_};
    place_x_ = place_y_ = -1;
    const PictureView view{render_.world(),
                           nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window}),
                           layout_.image, layout_.film_w, layout_.film_h};
    const Document& doc = editor_.doc();
    return rtview::new_item_placement(view, doc.has_scene() ? &doc.scene() : nullptr, object,
                                      pointed ? std::optional(at) : std::nullopt);
}

rt::Vec3 ViewerApp::duplicate_offset(const rt::Scene& scene) const {
    // One object-width to the right in the view, so that the copy is seen (a round
    // step: the copy's numbers stay as short as the original's).
    rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    rt::Vec3 right = rt::normalize(rt::cross(vc.centre - vc.position, nav_.world_up()));
    double step = 2.5 * typical_object_size(scene);
    double q = std::pow(10.0, std::floor(std::log10(step > 0 ? step : 1.0)) - 1);
    rt::Vec3 off = right * step;
    off = {std::round(off.x / q) * q, std::round(off.y / q) * q, std::round(off.z / q) * q};
    return rt::finite(off) ? off : rt::Vec3{};
}


bool ViewerApp::scene_edit(const std::string& arg, Command c) {
    Document& doc = editor_.doc();
    if (!doc.has_scene() || loader_.active()) return false;
    if (doc.editor_dirty() || doc.text_behind()) {
        status_.set("The scene text has unapplied changes: apply (Ctrl+Enter) or revert them first", true);
        return false;
    }
    if (doc.edit_held()) {
        // (The edit would be planned on the scene as dragged so far, but the text the
        // drag writes only when it ends.)
        status_.set("Finish the drag first", true);
        return false;
    }
    // The text's layout as the document keeps it: an edit of a big scene does not scan
    // the whole text again.
    const SceneLayout* layout = doc.layout();
    const std::string& text = std::as_const(doc).editor_text();
    const rt::Scene& scene = doc.scene();
    if ((c == Command::Delete || c == Command::Duplicate) && !panels_.selected().many.empty()) return group_edit(c);
    std::optional<SceneEdit> e;
    std::string done, name;  // the status bar's message; the undo step's name
    std::optional<SceneItem> sel = item_of_selection(panels_.selection());
    const std::string label = sel ? item_label(scene, ItemRef{*sel, {}}) : std::string();
    switch (c) {
        case Command::AddItem: {
            const std::optional<NewItem> kind = new_item_kind(arg);
            if (!kind) return false;
            e = add_item(text, scene, *kind, new_item_placement(new_item_is_object(*kind)), layout, render_.world());
            done = std::string("Added a ") + arg;
            name = std::string("Add a ") + arg;
            break;
        }
        case Command::AddModel:
            if (!(e = model_edit(arg))) return false;
            done = "Added " + base_name(arg);
            name = "Add model " + base_name(arg);
            break;
        case Command::Duplicate: {
            if (!sel) return false;
            e = duplicate_item(text, scene, *sel, duplicate_offset(scene), layout);
            done = "Duplicated";
            name = "Duplicate " + label;
            break;
        }
        case Command::Delete: {
            if (!sel) return false;
            const ItemRef& ref = panels_.selection();
            const bool operand = !ref.path.empty();  // its CSG becomes the other operand
            e = operand ? delete_operand(text, scene, sel->index, ref.path, layout) : delete_item(text, scene, *sel, layout);
            done = operand ? "Deleted the operand: its CSG is the other operand now" : "Deleted";
            name = "Delete " + (operand ? item_label(scene, ref) : label);
            break;
        }
        case Command::SwitchLight:
            if (!sel || sel->kind != SceneItem::Kind::Light) return false;
            e = switch_light_kind(text, scene, sel->index, layout);
            done = scene.lights[std::size_t(sel->index)].lamp ? "The lamp is a spotlight now (its size is kept)"
                                                              : "The spotlight is a lamp now";
            name = "Make " + label + (scene.lights[std::size_t(sel->index)].lamp ? " a spotlight" : " a lamp");
            break;
        case Command::MakeCsg: {
            char type = arg.empty() ? 'U' : arg[0];
            int other = arg.size() > 2 ? std::atoi(arg.c_str() + 2) : -1;
            if (!sel || sel->kind != SceneItem::Kind::Object || (type != 'U' && type != 'I' && type != 'C')) return false;
            e = make_csg(text, scene, sel->index, other, rt::CsgType(type));
            done = "Made a CSG of the two objects";
            name = "Make a CSG of objects " + std::to_string(sel->index + 1) + " and " + std::to_string(other + 1);
            break;
        }
        default: return false;
    }
    if (!e || !doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, name,
                                e->splice ? &*e->splice : nullptr)) {
        status_.set("Cannot do that to this scene text", true);
        return false;
    }
    panels_.select({e->select, {}});
    status_.set_about_step(done + " (Ctrl+Z undoes)" + light_note(doc), doc.history_changes());
    return true;
}

std::optional<SceneEdit> ViewerApp::model_edit(const std::string& path) {
    Document& doc = editor_.doc();
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path file = fs::absolute(path, ec).lexically_normal();
    const rt::ModelStore::Loaded l = doc.models().load(file.string());
    if (!l.model) {
        const std::string line = l.error.line > 0 ? ":" + std::to_string(l.error.line) : "";
        status_.set("Cannot add " + path + line + ": " + l.error.message, true);
        return std::nullopt;
    }
    // Named from the scene's folder when it is in it, else by its absolute path.
    const std::string name = scene_file_name(file.string(), doc.path());
    place_x_ = std::exchange(model_place_x_, -1);
    place_y_ = std::exchange(model_place_y_, -1);
    const SceneLayout* layout = doc.layout();
    std::optional<SceneEdit> e =
        add_model(std::as_const(doc).editor_text(), doc.scene(), name, *l.model, new_item_placement(true), layout);
    if (!e) status_.set("Cannot add a mesh to this scene text", true);
    return e;
}

void ViewerApp::handle_context_menu(bool usable) {
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    if (usable && ImGui::IsMouseClicked(1) && !io.WantCaptureMouse && layout_.image.contains(mx, my)) {
        rclick_armed_ = true;
        rclick_x_ = mx;
        rclick_y_ = my;
    }
    if (rclick_armed_ && !ImGui::IsMouseDown(1)) {
        rclick_armed_ = false;
        // A right drag pans; only a click (the pointer stayed put) opens the menu.
        if (std::hypot(mx - rclick_x_, my - rclick_y_) < 4 && usable) {
            menu_prev_selection_ = panels_.selection();
            menu_readout_ = tools_.readout_line();  // the menu takes the hover away
            select_at(rclick_x_, rclick_y_, Pick::KeepGroup);
            ImGui::OpenPopup("image_menu");
        }
    }
}

void ViewerApp::draw_context_menu() {
    if (!ImGui::BeginPopup("image_menu")) return;
    const ItemRef& sel = panels_.selection();
    const rt::Scene& scene = editor_.doc().scene();
    // (probe_item: where the rows are, for scripts that click them)
    if (ImGui::BeginMenu("Add here")) {
        for (NewItem kind : kNewItems) {
            const char* k = new_item_name(kind);
            const bool chosen = ImGui::MenuItem(k);
            probe_item(std::string("menu:") + k);
            if (chosen) {
                place_x_ = rclick_x_;
                place_y_ = rclick_y_;
                run(Command::AddItem, k);
            }
        }
        const bool model = ImGui::MenuItem("model...");
        probe_item("menu:model");
        if (model) {
            place_x_ = rclick_x_;
            place_y_ = rclick_y_;
            run(Command::AddModelDialog);
        }
        ImGui::EndMenu();
    }
    probe_item("menu:Add here");
    bool has = !sel.none();
    const std::size_t many = panels_.selected().many.size();
    const std::string all = many ? " " + std::to_string(many) + " things" : std::string();
    if (ImGui::MenuItem(("Duplicate" + all).c_str(), "Ctrl+D", false, has)) run(Command::Duplicate);
    if (ImGui::MenuItem(("Delete" + all).c_str(), "Del", false, has)) run(Command::Delete);
    if (!many && sel.is(SceneItem::Kind::Light) && std::size_t(sel.item.index) < scene.lights.size()) {
        bool lamp = scene.lights[std::size_t(sel.item.index)].lamp;
        const char* label = lamp ? "Make it a spotlight" : "Make it a lamp";
        const bool chosen = ImGui::MenuItem(label);
        probe_item(std::string("menu:") + label);
        if (chosen) run(Command::SwitchLight);
    }
    const ItemRef& prev = menu_prev_selection_;
    if (!many && sel.is(SceneItem::Kind::Object) && prev.is(SceneItem::Kind::Object) && prev.item.index != sel.item.index &&
        std::size_t(prev.item.index) < scene.objects.size()) {
        std::string label = "CSG of object " + std::to_string(prev.item.index + 1) + " and this one";
        if (ImGui::BeginMenu(label.c_str())) {
            std::string other = " " + std::to_string(sel.item.index);
            auto csg = [&](const char* type) {
                panels_.select(prev);  // the left operand
                run(Command::MakeCsg, type + other);
            };
            if (ImGui::MenuItem("union")) csg("U");
            if (ImGui::MenuItem("intersection")) csg("I");
            if (ImGui::MenuItem("difference (first minus this)")) csg("C");
            ImGui::EndMenu();
        }
    }
    const bool focus = ImGui::MenuItem("Focus here");
    probe_item("menu:Focus here");
    if (focus) focus_at(rclick_x_, rclick_y_);
    ImGui::Separator();
    // The pixel's readout, as the status line showed it.
    if (ImGui::MenuItem("Copy pixel", "Ctrl+C", false, !menu_readout_.empty())) tools_.copy_pixel(menu_readout_);
    ImGui::EndPopup();
}

}  // namespace rtview
