// Crash recovery for the scene editor: while the document has unsaved text, a copy is
// kept on disk (written atomically, at most every few seconds and only when the text
// changed), and a later start that opens the same file finds it and offers it back.
// Saving or closing cleanly removes it. The viewer calls update() off the UI thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "status.h"

namespace rtview {

class Recovery {
public:
    // `dir` empty: $XDG_STATE_HOME/raytracer-view/recovery, or ~/.local/state/...
    explicit Recovery(std::string dir = {});

    // The recovery file for a document path ("" for the unsaved default scene).
    std::string file_for(const std::string& doc_path) const;

    // Call often (each idle tick). Writes when the text changed since the last write
    // and at least `interval` seconds have passed; removes the file when the document
    // is no longer modified. Fails, saying why, if a write failed.
    rt::Status update(const std::string& doc_path, const std::string& text, bool modified, double now,
                      double interval = 3.0);
    // Text left by an earlier session for this document, if any.
    std::optional<std::string> find(const std::string& doc_path) const;
    void discard(const std::string& doc_path);

    const std::string& dir() const { return dir_; }

private:
    std::string dir_;
    std::string last_path_;
    std::uint64_t last_hash_ = 0;  // of the text last written (not a second copy of it)
    double last_write_ = -1e300;
    bool written_ = false;
};

}  // namespace rtview
