// What the parts of the viewer share: the frame's layout, the status line and
// the commands that menus, panels, dialogs and keys ask the app to run
// (so that no part reaches into another's state).
#pragma once

#include <string>
#include <vector>

#include "options.h"
#include "scene_edits.h"
#include "viewport.h"

namespace rtview {

// Where everything is this frame (ImGui logical coordinates) and the film it implies.
struct Layout {
    float menu_h = 0, status_h = 0, sidebar_w = 0;
    bool sidebar_hidden = false;  // Tab: the picture alone
    float fb_scale = 1;
    Rect area;   // all space for the image
    Rect image;  // where the film is drawn (letterboxed in picture mode; zoomed by the picture tools)
    Rect fit_image;  // where it is drawn unzoomed
    int film_w = 1, film_h = 1;  // the picture rendered: picture_size in the picture frame, else the area's
    FitMode fit = FitMode::Picture;
    // Rectangles of some panels, for --print-layout.
    Rect camera_panel, editor, diagnostics, outline;
};

class StatusLine {
public:
    void set(const std::string& text, bool error = false) {
        text_ = text;
        error_ = error;
    }
    const std::string& text() const { return text_; }
    bool error() const { return error_; }

private:
    std::string text_;
    bool error_ = false;
};

enum class Command {
    OpenDialog,      // ask for a path
    Open,            // arg: path (asks about unsaved edits first)
    OpenDefault,
    NewScene,        // a new unsaved scene (kNewScene; asks about unsaved edits first)
    Save,
    SaveAsDialog,
    SaveAs,          // arg: path
    SaveImageDialog,
    SaveImage,       // arg: path
    Screenshot,      // arg: path
    Quit,            // asks about unsaved edits first
    Undo,            // arg: how many steps (empty: one)
    Redo,            // arg: how many steps (empty: one)
    EditText,        // show and focus the editor
    ApplyText,
    RevertText,
    FrameScene,
    ResetView,       // the view back to the scene camera
    SetSceneCamera,  // the scene camera becomes the view (one undo step)
    CopyCamera,      // the view's camera block to the clipboard
    TogglePause,
    FitWindow,
    FitPicture,
    Help,
    FormatHelp,      // the scene format in brief (rt::format_reference)
    CancelLoad,
    // Structural edits (scene_edits.h), each one undo step written into the text.
    AddItem,         // arg: "sphere", ..., "spotlight"; at the point set by place_at (else the image centre)
    Duplicate,       // the selected object, plane or light
    Delete,
    SwitchLight,     // the selected lamp <-> spotlight
    MakeCsg,         // arg: "U", "I" or "C" and an object number: "U 3" (the selection is left)
    AddModelDialog,  // ask for a model file (.obj, .ply) to add
    AddModel,        // arg: the model file's path; a mesh block where AddItem puts a new object
};

class Commands {
public:
    virtual ~Commands() = default;
    // Returns false if the command failed (the status line says why). `confirmed`:
    // the user already chose to drop unsaved edits (Quit, Open, OpenDefault, NewScene), or to
    // save text that does not parse (Save, SaveAs).
    virtual bool run(Command c, const std::string& arg = {}, bool confirmed = false) = 0;
};

}  // namespace rtview
