// The modal dialogs (see dialogs.h).
#include "dialogs.h"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <string>

#include "fonts.h"
#include "imgui_common.h"
#include "probe.h"
#include "options.h"
#include "scene_writer.h"

namespace rtview {

namespace {

const char* title_of(Dialogs::Kind k) {
    switch (k) {
        case Dialogs::Kind::Unsaved: return "Unsaved changes";
        case Dialogs::Kind::SaveErrors: return "The scene text has errors";
        case Dialogs::Kind::Open: return "Open scene or model";
        case Dialogs::Kind::SaveAs: return "Save scene as";
        case Dialogs::Kind::SaveImage: return "Save image";
        case Dialogs::Kind::AddModel: return "Add model";
        case Dialogs::Kind::Texture: return "Choose texture";
        case Dialogs::Kind::Help: return "Mouse and keys";
        case Dialogs::Kind::Format: return "Scene format";
        case Dialogs::Kind::None: break;
    }
    return "";
}

}  // namespace

void Dialogs::run_pending() {
    if (!has_pending_) return;
    has_pending_ = false;
    commands_.run(pending_, pending_arg_, true);
}

bool Dialogs::begin(Kind k) {
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    return ImGui::BeginPopupModal(title_of(k), nullptr, ImGuiWindowFlags_AlwaysAutoResize);
}

void Dialogs::start_browser() {
    switch (request_) {
        case Kind::Open:
            file_.start(FileDialog::Mode::Open, {".txt", ".obj", ".ply"}, "Scenes (*.txt), models (*.obj, *.ply)", path_);
            break;
        case Kind::AddModel: file_.start(FileDialog::Mode::Open, {".obj", ".ply"}, "Models (*.obj, *.ply)", path_); break;
        case Kind::Texture:
            file_.start(FileDialog::Mode::Open, {".png", ".jpg", ".jpeg"}, "Images (*.png, *.jpg, *.jpeg)", path_);
            break;
        case Kind::SaveAs:
            file_.start(FileDialog::Mode::Save, {".txt"}, "Scenes (*.txt)", path_);
            if (!refusal_.empty()) file_.refuse(refusal_);
            refusal_.clear();
            break;
        case Kind::SaveImage: file_.start(FileDialog::Mode::Save, {".png", ".ppm"}, "Images (*.png, *.ppm)", path_); break;
        default: break;
    }
}

void Dialogs::draw_chooser(Kind k, const char* button, Command c) {
    if (!begin(k)) return;
    const FileDialog::Result r = file_.draw(button);
    if (r != FileDialog::Result::None) ImGui::CloseCurrentPopup();
    if (r == FileDialog::Result::Go) commands_.run(c, file_.path());
    ImGui::EndPopup();
}

void Dialogs::draw(const std::string& doc_name, bool has_path, const char* image_mode) {
    start_browser();
    if (request_ != Kind::None) ImGui::OpenPopup(title_of(request_));
    request_ = Kind::None;

    if (begin(Kind::Unsaved)) {
        draw_unsaved(doc_name, has_path);
        ImGui::EndPopup();
    }
    if (begin(Kind::SaveErrors)) {
        draw_save_errors();
        ImGui::EndPopup();
    }
    if (begin(Kind::Open)) {
        const FileDialog::Result r = file_.draw("Open");
        if (!recent_.paths().empty()) {
            ImGui::TextDisabled("Recent:");
            for (const std::string& p : recent_.paths())
                if (ImGui::Selectable(p.c_str())) {
                    ImGui::CloseCurrentPopup();
                    commands_.run(Command::Open, p);
                }
        }
        if (r != FileDialog::Result::None) ImGui::CloseCurrentPopup();
        if (r == FileDialog::Result::Go) commands_.run(Command::Open, file_.path());
        ImGui::EndPopup();
    }
    if (begin(Kind::SaveAs)) {
        draw_save_as();
        ImGui::EndPopup();
    }
    if (begin(Kind::SaveImage)) {
        ImGui::TextDisabled("The picture as rendered so far (%s); .png or .ppm, or .pfm or .exr for the unclamped floats.", image_mode);
        const FileDialog::Result r = file_.draw("Save");
        if (r != FileDialog::Result::None) ImGui::CloseCurrentPopup();
        if (r == FileDialog::Result::Go) commands_.run(Command::SaveImage, file_.path());
        ImGui::EndPopup();
    }
    draw_chooser(Kind::AddModel, "Add", Command::AddModel);
    draw_chooser(Kind::Texture, "Choose", Command::SetTexture);
    if (begin(Kind::Help)) {
        std::string help = help_text(false);
        std::size_t at = help.find("Mouse and keys");
        // Its columns are laid out with spaces: they line up only in a fixed-width face.
        ImGui::PushFont(mono_font());
        ImGui::TextUnformatted(at == std::string::npos ? help.c_str() : help.c_str() + at);
        ImGui::PopFont();
        if (ImGui::Button("Close") || escape_pressed()) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    if (begin(Kind::Format)) {
        // The blocks line up as text to copy: a fixed-width face, in a box that scrolls
        // when the window is smaller than the text.
        static const std::string reference = rt::format_reference();
        ImGui::PushFont(mono_font());
        const ImVec2 text = ImGui::CalcTextSize(reference.c_str());
        const ImVec2 screen = ImGui::GetMainViewport()->WorkSize;
        const ImGuiStyle& style = ImGui::GetStyle();
        const ImVec2 box(std::min(text.x + 2 * style.WindowPadding.x + style.ScrollbarSize, 0.9f * screen.x),
                         std::min(text.y + 2 * style.WindowPadding.y + style.ScrollbarSize, 0.75f * screen.y));
        ImGui::BeginChild("reference", box, true, ImGuiWindowFlags_HorizontalScrollbar);
        ImGui::TextUnformatted(reference.c_str());
        ImGui::EndChild();
        ImGui::PopFont();
        if (ImGui::Button("Copy to clipboard")) ImGui::SetClipboardText(reference.c_str());
        ImGui::SameLine();
        if (ImGui::Button("Close") || escape_pressed()) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

void Dialogs::draw_save_errors() {
    ImGui::TextUnformatted("The scene text does not parse:");
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.42f, 0.42f, 1.0f));
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 32);
    ImGui::TextWrapped("%s", save_problem_.c_str());
    ImGui::PopStyleColor();
    ImGui::TextWrapped("Saved as it is, the file will not open in raytracer (nor show a picture here) until the "
                       "errors are fixed.");
    ImGui::PopTextWrapPos();
    const bool save = ImGui::Button("Save it anyway");
    probe_item("button_save_anyway");
    if (save) {
        ImGui::CloseCurrentPopup();
        if (commands_.run(save_command_, save_arg_, true)) {
            run_pending();
        } else if (save_command_ == Command::SaveAs) {
            // Back to the path as typed, with why it could not be written.
            show(Kind::SaveAs, save_arg_);
            refusal_ = commands_.failure();
        } else {
            has_pending_ = false;
        }
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || escape_pressed()) {
        ImGui::CloseCurrentPopup();
        has_pending_ = false;
    }
}

// Save As: a save that fails leaves the dialog open with the path as typed and why.
void Dialogs::draw_save_as() {
    const FileDialog::Result r = file_.draw("Save");
    if (r == FileDialog::Result::Cancel) {
        ImGui::CloseCurrentPopup();
        has_pending_ = false;
    } else if (r == FileDialog::Result::Go) {
        if (commands_.run(Command::SaveAs, file_.path())) {
            ImGui::CloseCurrentPopup();
            run_pending();
        } else if (request_ != Kind::None) {
            ImGui::CloseCurrentPopup();  // another question (the text has errors) takes over
        } else {
            file_.refuse(commands_.failure());  // the path stays, to be corrected
        }
    }
}

void Dialogs::draw_unsaved(const std::string& doc_name, bool has_path) {
    ImGui::Text("%s has unsaved changes.", doc_name.c_str());
    const bool save = ImGui::Button("Save");
    probe_item("button_unsaved_save");
    if (save) {
        ImGui::CloseCurrentPopup();
        if (!has_path) {
            show(Kind::SaveAs, doc_name);  // the pending action runs after Save As
        } else if (commands_.run(Command::Save)) {
            run_pending();
        } else if (request_ != Kind::SaveErrors) {
            has_pending_ = false;  // the save failed: the window stays, with its message
        }  // (else the text has errors: the pending action waits for "Save it anyway")
    }
    ImGui::SameLine();
    const bool discard = ImGui::Button("Discard changes");
    probe_item("button_unsaved_discard");
    if (discard) {
        ImGui::CloseCurrentPopup();
        run_pending();
    }
    ImGui::SameLine();
    const bool cancel = ImGui::Button("Cancel");
    probe_item("button_unsaved_cancel");
    if (cancel || escape_pressed()) {
        ImGui::CloseCurrentPopup();
        has_pending_ = false;
    }
}

}  // namespace rtview
