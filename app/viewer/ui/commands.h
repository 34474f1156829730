// The commands that menus, panels, dialogs and keys ask the app to run (so that no
// part reaches into another's state).
#pragma once

#include <string>

namespace rtview {

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
    TextureDialog,   // ask for a material's texture file (arg: where the browser starts)
    SetTexture,      // arg: the texture file's path, for the material that asked (Panels::set_texture)
};

class Commands {
public:
    virtual ~Commands() = default;
    // Returns false if the command failed (the status line says why). `confirmed`:
    // the user already chose to drop unsaved edits (Quit, Open, OpenDefault, NewScene), or to
    // save text that does not parse (Save, SaveAs).
    virtual bool run(Command c, const std::string& arg = {}, bool confirmed = false) = 0;
    // Why the last run() that returned false failed (the path and the reason), if it
    // failed rather than asked the user something first.
    virtual std::string failure() const { return {}; }
};

}  // namespace rtview
