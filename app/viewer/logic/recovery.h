// Crash recovery for the scene editor: while the document has unsaved work, a copy is
// kept on disk, and a later start that opens the same file finds it and offers it back.
// Saving or closing cleanly removes it. The viewer calls update() off the UI thread.
// Two files per document: the text, written whole (atomically) when it changed, and
// beside it what a held edit (a slider or move drag, not in the text until it ends) has
// changed so far: only those items, so that a drag in a scene of a million objects never
// copies the text. Reading the copy back writes them into the text.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "document.h"
#include "recent_files.h"  // absolute_path: "" stays "" (the unsaved default scene)
#include "scene.h"
#include "status.h"

namespace rtview {

// `text` with the held edit's items written into it (their blocks rewritten), as the
// commit would have; `text` as it is when they do not fit it (it does not parse, or has
// other items).
std::string with_held_edit(const std::string& text, const HeldEdit& held);

class Recovery {
public:
    // `dir` empty: $XDG_STATE_HOME/raytracer-view/recovery, or ~/.local/state/...
    explicit Recovery(std::string dir = {});
    ~Recovery();  // release()
    Recovery(const Recovery&) = delete;
    Recovery& operator=(const Recovery&) = delete;

    // --- which viewer has a document open ------------------------------------------
    // Takes the lock of `doc_path`'s copy for this viewer, letting go of the one held
    // before: an flock on a file beside the copy (its name with ".lock"), which the
    // system lets go of when the process ends, however it ends. Returns 0 when taken
    // (or already held); else the pid of the live viewer holding it (-1: it does not
    // say). While another viewer holds it, this object never writes, removes or finds
    // that document's copy: it is the other viewer's, not an earlier session's.
    long claim(const std::string& doc_path);
    // Lets go of the lock held (its file is removed): the document is closed cleanly.
    void release();
    // The document whose lock another live viewer holds (claim() failed), and its pid.
    bool blocked(const std::string& doc_path) const { return blocked_pid_ != 0 && doc_path == blocked_path_; }
    long blocked_pid() const { return blocked_pid_; }

    // A copy left by a session that ended without closing: no live viewer holds its lock.
    struct Orphan {
        std::string doc_path;  // as the copy names it (absolute; "" for the default scene)
        std::string file;      // the copy
        std::int64_t mtime = 0;  // seconds since the epoch, when it was last written
        std::uint64_t bytes = 0; // the text's size
    };
    // Every such copy in the folder, newest first, but the one of `except` (the
    // document this viewer has open: its copy is offered on its own).
    std::vector<Orphan> orphans(const std::string& except = {}) const;
    // Removes an orphan's files, unless a viewer has taken its lock since (false).
    bool discard_orphan(const Orphan& o);
    // An orphan's text (a copy of another slot's default scene, which find() does not
    // read): nothing if it is gone or not a copy.
    std::optional<std::string> read_orphan(const Orphan& o) const;
    // How many viewers may keep copies of an unsaved default scene side by side.
    static constexpr int kDefaultSceneSlots = 16;

    // The recovery file for a document path ("" for the unsaved default scene), and the
    // held edit's file beside it.
    std::string file_for(const std::string& doc_path) const;
    std::string held_file_for(const std::string& doc_path) const;

    // Call often (each idle tick). Writes when the text changed since the last write;
    // removes the file when the document is no longer modified. Fails, saying why, if
    // a write failed.
    rt::Status update(const std::string& doc_path, const std::string& text, bool modified);
    // Writes the held edit's file for the text whose text_hash() is `base_hash` (the
    // copy update() wrote, or the document's file when the text is as saved); an empty
    // edit removes it.
    rt::Status update_held(const std::string& doc_path, const HeldEdit& held, std::uint64_t base_hash);
    // text_hash() of the text update() wrote last (0: none).
    std::uint64_t written_hash() const { return written_ ? last_hash_ : 0; }
    // Text left by an earlier session for this document, if any, with its held edit.
    std::optional<std::string> find(const std::string& doc_path) const;
    // Removes both files.
    void discard(const std::string& doc_path);

    const std::string& dir() const { return dir_; }

private:
    std::string lock_file_for(const std::string& doc_path) const;
    std::string dir_;
    int lock_fd_ = -1;          // the lock held, on lock_path_'s copy
    int slot_ = 0;              // the default scene's slot claimed (its copy's name)
    std::string lock_path_;
    std::string blocked_path_;  // claim() found this document's lock held...
    long blocked_pid_ = 0;      // ...by this process
    std::string last_path_;
    std::uint64_t last_hash_ = 0;  // of the text last written (not a second copy of it)
    bool written_ = false;
    bool held_written_ = false;
};

}  // namespace rtview
