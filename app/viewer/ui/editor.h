// The document and its editor: the open scene (Document), the scene text widget with
// its cursor and focus requests, the live syntax check, the recent-files list and
// crash recovery, plus the banners that offer recovered text or resolve a conflict
// with the file on disk.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "document.h"
#include "parallel.h"
#include "recent_files.h"
#include "recovery.h"
#include "layout.h"
#include "status_line.h"
#include "text_editor.h"

namespace rtview {

class DocumentEditor {
public:
    DocumentEditor(bool interactive, StatusLine& status) : interactive_(interactive), status_(status) {}
    ~DocumentEditor();

    Document& doc() { return doc_; }
    const Document& doc() const { return doc_; }
    RecentFiles& recent() { return recent_; }

    // After the document was replaced by a load: drop widget state, look for recovery.
    void replaced();
    // Once a frame: the live check when typing paused.
    void tick(double now);
    // Once a second (idle or not): the recovery copy and the file on disk. True if the
    // document changed (a reload) or a message appeared.
    bool idle_tick();
    // Quitting cleanly: the unsaved text is the user's decision, no recovery copy.
    void discard_recovery();
    // After Save As: no copy stays under the old name.
    void saved_as();
    // After a save: no copy stays (one written before the save would be older than the
    // file, and offered as unsaved text after a crash).
    void saved();

    // An earlier session's unsaved text for this document is on offer (the banner), and
    // that text. Looked for after replaced() off the UI thread: a later tick shows it.
    bool recovery_offered() const { return recovery_offer_; }
    const std::string& recovered_text() const { return recovered_text_; }
    // A document the user chose to open from the list of earlier sessions' copies (its
    // path; "" for the default scene), once.
    std::optional<std::string> take_open_request() {
        std::optional<std::string> r = std::move(open_request_);
        open_request_.reset();
        return r;
    }

    // The editor: show it focused, with the cursor at a byte offset (or where it was).
    void focus(int cursor = -1);
    void apply();
    bool active() const { return active_; }
    // ImGui's id of the text widget (a slider drag holds an edit open, the editor not).
    unsigned widget_id() const { return id_; }
    bool wants_frames() const {
        return focus_ || pending_cursor_ >= 0 || check_due_ >= 0 || check_.valid() || apply_.valid();
    }

    // Drawing (inside the sidebar window).
    void draw_banners();   // recovery offer, disk conflict
    void draw_text_tab(Layout& layout);
    bool wants_text_tab() { bool w = want_tab_; want_tab_ = false; return w; }
    // Ctrl+Z (+1) or Ctrl+Y (-1) typed in the text with nothing of its own to take back:
    // the document's undo is the user's next step back (a panel edit, a move).
    int take_passed_undo() { return widget_.take_passed_undo(); }

private:
    void sync_widget();
    void reloaded_status(const std::string& ok);  // the status line after the file was read again
    // draw_text_tab() in steps, top to bottom.
    void draw_text_toolbar();
    std::vector<std::string> diagnostic_lines(float& list_h) const;
    bool draw_text_widget(float height);
    void draw_diagnostics(const std::vector<std::string>& diag_text, float height);

    bool interactive_;
    StatusLine& status_;
    Document doc_;
    RecentFiles recent_;
    Recovery recovery_;            // touched by one thread at a time: see recovery_busy()
    rt::Job<rt::Status> recovery_write_;  // a copy being written off the UI thread
    std::uint64_t recovery_key_ = ~std::uint64_t(0);  // text state last handed to it
    HeldEdit recovery_held_;       // the held edit last handed to it
    bool recovery_busy();          // a write is under way (collects a finished one)
    void keep_recovery_copy();     // hands what changed since the last tick to a writer
    void forget_earlier_copy();    // removes a copy kept under an earlier name
    // An earlier session's copy being read (and a held edit written into it: a pass
    // over a big scene's text) off the UI thread; recovery_ is left alone until then.
    rt::Job<std::optional<std::string>> recovery_find_;
    bool recovery_finding();       // the read is under way (takes in a finished one)
    void settle_recovery_find();   // waits for the read and takes it in
    bool recovery_offer_ = false;  // a previous session's unsaved text is waiting
    std::string recovered_text_;
    // Another live viewer has this document open (its pid; 0: none): its copy is its own.
    long held_elsewhere_ = 0;
    void claim_document();         // takes the document's lock, then looks for a copy
    // Copies of other documents left by sessions that ended without closing, found at
    // start (the list offers to open them), and the one chosen.
    std::vector<Recovery::Orphan> orphans_;
    bool orphans_looked_ = false;
    std::optional<std::string> open_request_;
    // The copy chosen with "Open it", until its document is open, and then while it is
    // on offer when it is not the one find() reads (another viewer's default scene).
    std::optional<Recovery::Orphan> pending_orphan_, offered_orphan_;
    void draw_orphans();

    TextEditor widget_;
    std::vector<rt::Diagnostic> marked_;  // the diagnostics the widget's gutter shows
    std::uint64_t seen_version_ = 0;
    unsigned id_ = 0;
    bool active_ = false;
    bool focus_ = false;
    bool want_tab_ = false;
    int pending_cursor_ = -1;
    int cursor_ = 0;
    double check_due_ = -1;  // live syntax check of the draft after typing stops
    // A big draft's live check, parsed off the UI thread: its text's key and diagnostics.
    rt::Job<std::pair<std::uint64_t, std::vector<rt::Diagnostic>>> check_;
    void live_check(double now);
    // A big text's Apply, parsed off the UI thread: the parsed text's key and the parse
    // (and the document it was for).
    rt::Job<std::pair<std::uint64_t, rt::ParseResult>> apply_;
    std::string apply_path_;
    void finish_apply();
    void applied(bool ok);  // the status line after an Apply
};

}  // namespace rtview
