// ViewerApp's commands: what menus, panels, dialogs and keys ask for (commands.h),
// the view's commands, undo and redo, and saving the scene and the picture.
#include "app.h"

#include <imgui.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "default_scene.h"
#include "image_io.h"
#include "new_scene.h"
#include "paths.h"
#include "scene_writer.h"
#include "status_notes.h"

namespace rtview {

bool ViewerApp::run(Command c, const std::string& arg, bool confirmed) {
    Document& doc = editor_.doc();
    auto ask_first = [&](Command cmd) {
        if (confirmed || !doc.modified()) return false;
        dialogs_.ask_unsaved(cmd, arg);
        return true;
    };
    switch (c) {
        case Command::OpenDialog: dialogs_.show(Dialogs::Kind::Open); return true;
        case Command::Open:
            if (ask_first(c)) return true;
            start_load(arg);
            return true;
        case Command::OpenDefault:
            if (ask_first(c)) return true;
            loader_.cancel();
            doc.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
            after_document_replaced();
            status_.set("Opened the built-in default scene");
            return true;
        case Command::NewScene:
            if (ask_first(c)) return true;
            loader_.cancel();
            doc.load_text(kNewScene, "", kNewSceneName);
            after_document_replaced();
            // A new scene is written by hand: the text, ready for typing.
            panels_.show_tab(Panels::Text);
            editor_.focus();
            status_.set(std::string("New scene ") + kNewSceneName + ": Ctrl+Enter applies the text, Ctrl+S saves it");
            return true;
        case Command::CancelLoad: return cancel_load();
        case Command::Save: return do_save(confirmed);
        case Command::SaveAsDialog: dialogs_.show(Dialogs::Kind::SaveAs, save_as_start()); return true;
        case Command::SaveAs: return do_save_as(arg, confirmed);
        case Command::SaveImageDialog: dialogs_.show(Dialogs::Kind::SaveImage, default_image_name()); return true;
        case Command::SaveImage: do_save_image(arg); return true;
        case Command::Screenshot: screenshot_request_ = arg; return true;
        case Command::Quit:
            if (ask_first(c)) return true;
            // Quitting is the user's decision about unsaved text: no recovery copy.
            editor_.discard_recovery();
            host_.quit();
            return true;
        case Command::Undo:
        case Command::Redo: return undo_redo(c == Command::Undo, arg.empty() ? 1 : std::atoi(arg.c_str()));
        case Command::EditText:
            panels_.show_tab(Panels::Text);
            editor_.focus();
            return true;
        case Command::ApplyText: editor_.apply(); return true;
        case Command::RevertText: doc.revert_text(); return true;
        case Command::FrameScene:
        case Command::ResetView:
        case Command::SetSceneCamera:
        case Command::CopyCamera:
        case Command::TogglePause:
        case Command::FitWindow:
        case Command::FitPicture: return view_command(c);
        case Command::Help: dialogs_.show(Dialogs::Kind::Help); return true;
        case Command::FormatHelp: dialogs_.show(Dialogs::Kind::Format); return true;
        case Command::AddItem:
        case Command::Duplicate:
        case Command::Delete:
        case Command::SwitchLight:
        case Command::MakeCsg:
        case Command::AddModel: return scene_edit(arg, c);
        case Command::AddModelDialog:
            // The model goes where the menu was opened (or in the middle): kept for the
            // dialog's answer, so a dialog cancelled leaves no point for the next Add.
            model_place_x_ = std::exchange(place_x_, -1);
            model_place_y_ = std::exchange(place_y_, -1);
            dialogs_.show(Dialogs::Kind::AddModel, rt::folder_of(doc.path()));
            return true;
        case Command::TextureDialog: dialogs_.show(Dialogs::Kind::Texture, arg); return true;
        case Command::SetTexture: return panels_.set_texture(arg);
    }
    return false;
}

bool ViewerApp::undo_redo(bool undo, int steps) {
    Document& doc = editor_.doc();
    int done = 0;
    while (done < std::max(steps, 1) && (undo ? doc.undo() : doc.redo())) {
        ++done;
        // A step of several things gives back the selection it had (or made).
        const std::size_t depth = doc.undo_depth();
        if (std::optional<Selection> s = undo ? selection_steps_.undone(depth, doc.last_step_name())
                                               : selection_steps_.redone(depth, doc.last_step_name()))
            panels_.set_selected(*s);
    }
    if (done == 0) return false;
    // Say what was taken back or done again: "Undid: Move sphere 3".
    const std::string& last = doc.last_step_name();
    const std::string what =
        done == 1 ? ": " + last : " " + std::to_string(done) + " steps, " + (undo ? "back to before " : "up to ") + last;
    status_.set_about_step(std::string(undo ? "Undid" : "Redid") + what + (undo ? " (Ctrl+Y redoes)" : " (Ctrl+Z undoes)"),
                           doc.history_changes());
    return true;
}

bool ViewerApp::cancel_load() {
    if (!loader_.active()) return false;
    loader_.cancel();
    Document& doc = editor_.doc();
    if (!doc.has_scene() && doc.editor_text().empty() && doc.path().empty()) {
        // The start-up file was cancelled: there is no old scene to keep showing.
        doc.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
        after_document_replaced();
    }
    status_.set("Cancelled opening; showing " + doc.name());
    return true;
}

bool ViewerApp::view_command(Command c) {
    Document& doc = editor_.doc();
    switch (c) {
        case Command::FrameScene:
            if (render_.world())
                nav_.frame(frame_target(*render_.world()),
                           {layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
            return true;
        case Command::ResetView:
            if (doc.has_scene()) nav_.reset(doc.scene().camera);
            return true;
        case Command::SetSceneCamera:
            if (!doc.has_scene() || !nav_.has_view()) return false;
            if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
                status_.set(blocked, true);
                return false;
            }
            if (doc.set_camera(nav_.camera()))
                status_.set_about_step("The scene camera is now the view (Ctrl+Z undoes)", doc.history_changes());
            return true;
        case Command::CopyCamera:
            ImGui::SetClipboardText(rt::write_camera(nav_.camera()).c_str());
            status_.set("Copied the view's camera block to the clipboard");
            return true;
        case Command::TogglePause:
            render_.set_paused(!render_.paused());
            status_.set(render_.paused() ? "Paused (Space resumes)" : "Resumed");
            return true;
        case Command::FitWindow:
            layout_.fit = FitMode::Window;
            status_.set("Fill the window: the picture's sides may differ from the scene's");
            return true;
        case Command::FitPicture:
            layout_.fit = FitMode::Picture;
            status_.set("Picture frame: exactly the scene's picture");
            return true;
        default: return false;
    }
}

std::string ViewerApp::default_image_name() const {
    const Document& doc = editor_.doc();
    return stem_of(doc.path().empty() ? doc.name() : doc.path()) + ".png";
}

// Before a save: a draft that parses is applied (the file will be the scene shown);
// text that does not parse is saved only once the user has said so (false: asked).
bool ViewerApp::ready_to_save(Command c, const std::string& arg, bool confirmed) {
    Document& doc = editor_.doc();
    doc.commit();
    if (doc.apply_parsing_draft()) status_.set("Applied the scene text");
    if (confirmed) return true;
    if (std::optional<std::string> problem = doc.save_problem()) {
        dialogs_.ask_save_with_errors(*problem, c, arg);
        return false;
    }
    return true;
}

// Where Save As starts: the scene's own file (as an absolute path: its folder is shown,
// whatever the working folder), else its name in the folder of the last scene that had
// one (a model opened as a scene: the model's).
std::string ViewerApp::save_as_start() const {
    const Document& doc = editor_.doc();
    std::error_code ec;
    if (!doc.path().empty()) {
        const std::filesystem::path p = std::filesystem::absolute(doc.path(), ec);
        return ec ? doc.path() : p.lexically_normal().string();
    }
    if (!last_folder_.empty()) return (std::filesystem::path(last_folder_) / doc.name()).string();
    return doc.name();
}

bool ViewerApp::do_save(bool confirmed) {
    Document& doc = editor_.doc();
    if (doc.path().empty()) {
        dialogs_.show(Dialogs::Kind::SaveAs, doc.name());
        return false;
    }
    failure_.clear();
    if (!ready_to_save(Command::Save, {}, confirmed)) return false;
    const rt::Status st = doc.save();
    if (st) editor_.saved();
    if (st) status_.set("Saved " + doc.path());
    else status_.set(failure_ = "Cannot save " + doc.path() + ": " + st.message(), true);
    return st.ok();
}

bool ViewerApp::do_save_as(const std::string& path, bool confirmed) {
    Document& doc = editor_.doc();
    failure_.clear();
    if (!ready_to_save(Command::SaveAs, path, confirmed)) return false;
    if (rt::Status st = doc.save_as(path); !st) {
        status_.set(failure_ = "Cannot save " + path + ": " + st.message(), true);
        return false;
    }
    editor_.saved_as();
    std::error_code ec;
    if (const std::filesystem::path p = std::filesystem::absolute(path, ec); !ec) last_folder_ = p.parent_path().string();
    const rt::Status recent = remember_recent(path);
    status_.set("Saved " + doc.path() + recent_note(recent), !recent);
    return true;
}

rt::Status ViewerApp::remember_recent(const std::string& path) {
    if (!interactive_) return {};
    return editor_.recent().add(path);
}

// The film as rendered so far: in the picture frame the scene's picture at its
// picture_size (zoom and pan only place it on the screen), else the window's.
void ViewerApp::do_save_image(const std::string& path) {
    const rt::RenderProgress p = render_.progress();
    rt::Image img = render_.snapshot();
    if (img.width < 1) {
        status_.set("There is no image to save yet", true);
        return;
    }
    if (rt::format_from_path(path) == rt::ImageFormat::Unknown) {
        status_.set("Image names must end in .png, .ppm, .pfm or .exr", true);
        return;
    }
    const rt::Status st = rt::write_image(path, img);
    if (!st) {
        status_.set("Cannot write " + path + ": " + st.message(), true);
        return;
    }
    std::string what = std::to_string(img.width) + "x" + std::to_string(img.height) + ", " + std::to_string(p.samples) +
                       (p.done ? "" : " of " + std::to_string(render_.max_samples())) + " samples per pixel";
    const Document& doc = editor_.doc();
    if (layout_.fit == FitMode::Window) what += ", the window's picture (View > Picture frame saves picture_size)";
    else if (doc.has_scene() && (img.width != doc.scene().width || img.height != doc.scene().height))
        what += ", smaller than picture_size " + std::to_string(doc.scene().width) + "x" +
                std::to_string(doc.scene().height) + " (Render to file makes it)";
    status_.set("Wrote " + path + " (" + what + ")");
}

}  // namespace rtview
