// The modal dialogs: unsaved changes, open, save as, save image, help. Other parts
// ask for one with show(); a dialog's answer goes back as a Command, so no part
// talks to another through flags.
#pragma once

#include <string>

#include "file_dialog.h"
#include "recent_files.h"
#include "commands.h"

namespace rtview {

class Dialogs {
public:
    enum class Kind { None, Unsaved, SaveErrors, Open, SaveAs, SaveImage, AddModel, Texture, Help, Format };

    Dialogs(Commands& commands, const RecentFiles& recent) : commands_(commands), recent_(recent) {}

    // Opens a dialog on the next frame; `path` pre-fills its path field.
    void show(Kind k, const std::string& path = {}) {
        request_ = k;
        path_ = path;
    }
    // The document has unsaved edits: ask before running `pending` (with `arg`).
    void ask_unsaved(Command pending, const std::string& arg) {
        pending_ = pending;
        pending_arg_ = arg;
        has_pending_ = true;
        show(Kind::Unsaved);
    }
    // The text to save does not parse (`problem` says where): ask before running
    // `save` (Save or SaveAs, with `arg`) confirmed.
    void ask_save_with_errors(const std::string& problem, Command save, const std::string& arg) {
        save_problem_ = problem;
        save_command_ = save;
        save_arg_ = arg;
        show(Kind::SaveErrors, path_);
    }
    // `doc_name`: for the unsaved-changes question; `image_mode`: the Save Image hint.
    void draw(const std::string& doc_name, bool has_path, const char* image_mode);
    bool wants_frames() const { return request_ != Kind::None; }

private:
    void run_pending();
    // Inside a dialog: centred modal `k` is open (then EndPopup after drawing it).
    bool begin(Kind k);
    void draw_unsaved(const std::string& doc_name, bool has_path);
    void draw_save_errors();
    // A dialog that chooses a file (Add model, a texture): `c` runs with its path.
    void draw_chooser(Kind k, const char* button, Command c);
    void draw_save_as();
    // Open, Save As and Save Image browse for their file: the browser starts when
    // one of them is asked for.
    void start_browser();

    Commands& commands_;
    const RecentFiles& recent_;
    Kind request_ = Kind::None;
    std::string path_;
    FileDialog file_;
    bool has_pending_ = false;
    Command pending_ = Command::Quit;
    std::string pending_arg_;
    std::string save_problem_, save_arg_;
    Command save_command_ = Command::Save;
    std::string refusal_;  // shown in the Save As dialog shown again after a failed save
};

}  // namespace rtview
