// The open scene as the viewer edits it: editor text, last good Scene, file on disk,
// undo history. The UI changes the document only through these calls, so every rule
// (text never lost, panels written back into the text, atomic saves, reload on
// external change) lives here and is unit-tested without a window.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"
#include "scene_parser.h"
#include "undo.h"

namespace rtview {

// What the undo history stores: everything an edit can change.
struct DocState {
    rt::Scene scene;            // last good scene: what renders
    bool has_scene = false;     // false until some text has parsed
    std::string applied_text;   // text that parses to `scene`
    std::string editor_text;    // what the editor shows (may be an unapplied draft)
    bool text_behind = false;   // panel edits could not be written into the draft
};

// Identity of a file version on disk, to notice changes made by other programs.
struct FileStamp {
    bool exists = false;
    std::int64_t mtime_ns = 0;
    std::int64_t size = 0;
    std::uint64_t inode = 0;
    bool operator==(const FileStamp& o) const {
        return exists == o.exists && mtime_ns == o.mtime_ns && size == o.size && inode == o.inode;
    }
    bool operator!=(const FileStamp& o) const { return !(*this == o); }
    static FileStamp of(const std::string& path);
};

class Document {
public:
    Document();

    // --- opening ---------------------------------------------------------------
    // Replaces everything (history too). `path` empty: an unsaved scene called `name`.
    void load_text(const std::string& text, const std::string& path, const std::string& name);
    // Takes a text parsed elsewhere (a background load): nothing is parsed again and
    // the text is moved in, not copied.
    void load_parsed(std::string text, rt::ParseResult parsed, const std::string& path, const std::string& name);
    // Reads and loads a file; on failure returns why and leaves the document as it was.
    std::string load_file(const std::string& path);

    const std::string& path() const { return path_; }
    const std::string& name() const { return name_; }
    bool modified() const { return s_.editor_text != saved_text_; }
    std::string title() const;  // "name* - raytracer-view"

    // --- the scene -------------------------------------------------------------
    const rt::Scene& scene() const { return s_.scene; }
    bool has_scene() const { return s_.has_scene; }
    // Increases whenever scene() changes.
    std::uint64_t scene_version() const { return scene_version_; }
    // Increases when anything but the camera changes: the compiled world depends
    // on this only (the renderer takes its camera from the view).
    std::uint64_t content_version() const { return content_version_; }
    // The camera of the file as last loaded or saved ("R" goes back to it).
    const rt::Camera& file_camera() const { return file_camera_; }

    // --- panel edits -----------------------------------------------------------
    // A continuous edit (a slider drag, a mouse orbit) calls edit() on every change
    // and commit() when the gesture ends: one undo step, and the text is written once.
    rt::Scene& edit();  // marks the scene changed; opens a pending edit
    rt::Camera& edit_camera();  // the same for the camera alone (no world to recompile)
    bool editing() const { return pending_; }
    void commit();
    // Drops a pending edit, restoring the scene as it was before it.
    void cancel_edit();
    // Makes `camera` the scene camera ("Set scene camera from view"): one undo step
    // that rewrites only the camera block of the text. False if nothing changed.
    bool set_camera(const rt::Camera& camera);

    // --- editor ----------------------------------------------------------------
    std::string& editor_text() { return s_.editor_text; }
    const std::string& editor_text() const { return s_.editor_text; }
    bool editor_dirty() const { return s_.editor_text != s_.applied_text; }
    // Panel edits since the draft was typed are not in the editor text.
    bool text_behind() const { return s_.text_behind; }
    // Increases when editor_text() is replaced by the document (undo, reload, panel
    // write-back), so an active text widget knows to reload its buffer.
    std::uint64_t text_version() const { return text_version_; }
    // Parses the editor text. Errors: diagnostics() lists them, the scene and the text
    // stay as they are. Success: the scene becomes the text's (one undo step).
    bool apply_text();
    // Editor text back to the text of the current scene, dropping the draft; also
    // how the user resolves text_behind() the other way round (undoable).
    void revert_text();
    // Puts `text` in the editor as an unapplied draft (undoable): crash recovery.
    void restore_draft(const std::string& text);
    // Re-parses the draft to refresh diagnostics() without applying it (live check).
    void check_text();
    const std::vector<rt::Diagnostic>& diagnostics() const { return diagnostics_; }
    bool has_errors() const;

    // --- undo ------------------------------------------------------------------
    bool can_undo() const { return history_.can_undo(); }
    bool can_redo() const { return history_.can_redo(); }
    std::size_t undo_depth() const { return history_.undo_size(); }
    bool undo();
    bool redo();

    // --- saving ----------------------------------------------------------------
    // Writes the editor text atomically. Empty string on success, else why not.
    std::string save();
    std::string save_as(const std::string& path);

    // --- the file on disk ------------------------------------------------------
    enum class DiskEvent { None, Reloaded, Conflict, Removed };
    // Call now and then (the viewer: once a second). Reloads by itself when there
    // are no unsaved edits (looking around is not an edit: the view camera lives
    // outside the document); reports a conflict otherwise.
    DiskEvent check_disk();
    bool disk_conflict() const { return conflict_; }
    void resolve_conflict_reload();  // take the disk version (undoable)
    void resolve_conflict_keep();    // keep ours; ask again only on the next change

private:
    void set_state(DocState s, bool push_history);
    void mark_saved(const std::string& text);
    void reload_text(const std::string& text);

    DocState s_;
    UndoHistory<DocState> history_;
    std::string path_, name_;
    std::string saved_text_;
    rt::Camera file_camera_;
    FileStamp stamp_;
    std::vector<rt::Diagnostic> diagnostics_;
    std::uint64_t scene_version_ = 1, content_version_ = 1, text_version_ = 1;
    bool pending_ = false;
    DocState before_;  // state at the start of the pending edit
    bool conflict_ = false;
    std::string conflict_text_;
};

}  // namespace rtview
