// The menu bar: File, Edit (with the undo history), View, Render, Help (see panels.h).
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

}  // namespace

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
            for (NewItem kind : kNewItems) {
                const char* k = new_item_name(kind);
                const bool chosen = ImGui::MenuItem(k);
                probe_item(std::string("menu:") + k);
                if (chosen) commands_.run(Command::AddItem, k);
            }
            ImGui::EndMenu();
        }
        probe_item("menu:Add in front");
        const bool has = can && !sel_.one.none();
        const std::string all = sel_.many.empty() ? std::string() : " " + std::to_string(sel_.many.size()) + " things";
        if (ImGui::MenuItem(("Duplicate" + all).c_str(), "Ctrl+D", false, has)) commands_.run(Command::Duplicate);
        if (ImGui::MenuItem(("Delete" + all).c_str(), "Del", false, has)) commands_.run(Command::Delete);
        const bool light = has && sel_.many.empty() && sel_.one.is(SceneItem::Kind::Light) &&
                           std::size_t(sel_.one.item.index) < doc.scene().lights.size();
        if (ImGui::MenuItem(light && !doc.scene().lights[std::size_t(sel_.one.item.index)].lamp ? "Make the spotlight a lamp"
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

}  // namespace rtview
