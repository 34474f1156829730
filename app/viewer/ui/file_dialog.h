// A file browser drawn inside a dialog (FileBrowser does the listing): the folder and
// its entries, a name or path field with Tab completion, a filter, and the buttons.
// Open mode wants an existing file; Save mode asks before replacing one.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "file_browser.h"

namespace rtview {

class FileDialog {
public:
    enum class Mode { Open, Save };
    enum class Result { None, Go, Cancel };

    // Starts browsing: `initial` names a file (its folder is shown, its name typed)
    // or a folder; `filter` describes `extensions` ("Scenes (*.txt)").
    void start(Mode mode, std::vector<std::string> extensions, const std::string& filter, const std::string& initial);
    // Inside an open popup. Go: path() is the file chosen; the popup is left open
    // (the caller closes it).
    Result draw(const char* button);
    const std::string& path() const { return chosen_; }
    // The chosen path could not be used (`message` says why): the dialog stays, with
    // the path as typed, and shows the message.
    void refuse(const std::string& message) {
        message_ = message;
        confirm_replace_.clear();
        focus_field_ = true;
    }

private:
    void draw_folder_row();
    void draw_entries(Result& result);
    bool draw_name_field();
    Result choose(const std::string& typed);
    std::string filter_label() const;

    Mode mode_ = Mode::Open;
    std::unique_ptr<FileBrowser> browser_;
    std::string filter_;
    std::string typed_;
    std::string chosen_;
    std::string message_;                // why the last choice was refused
    std::vector<std::string> candidates_;  // of the last Tab, when several
    std::string confirm_replace_;        // Save: the existing file the user must confirm
    bool focus_field_ = false;
};

}  // namespace rtview
