// The document and its editor widget (see editor.h).
#include "editor.h"

#include <imgui.h>

#include <algorithm>
#include <ctime>
#include <utility>
#include <vector>

#include "imgui_common.h"
#include "panel_widgets.h"
#include "probe.h"
#include "scene_text.h"

namespace rtview {

namespace {
// Bigger texts are not edited in the widget: it holds a second copy of the text, as
// lines (the document's copy is the first).
constexpr std::size_t kMaxEditableBytes = 64u << 20;
}  // namespace

DocumentEditor::~DocumentEditor() {
    if (recovery_write_.valid()) recovery_write_.wait();
}

bool DocumentEditor::recovery_busy() {
    if (!recovery_write_.valid()) return false;
    if (!recovery_write_.ready()) return true;
    if (const rt::Status st = recovery_write_.get(); !st)
        status_.set("cannot keep a recovery copy: " + st.message(), true);
    return false;
}

bool DocumentEditor::recovery_finding() {
    if (!recovery_find_.valid()) return false;
    if (!recovery_find_.ready()) return true;
    settle_recovery_find();
    return false;
}

void DocumentEditor::settle_recovery_find() {
    if (!recovery_find_.valid()) return;
    std::optional<std::string> text = recovery_find_.get();
    if (text && *text != doc_.editor_text()) {
        recovered_text_ = std::move(*text);
        recovery_offer_ = true;
    }
}

void DocumentEditor::forget_earlier_copy() {
    // The copy of a document this editor held before (under another name, or another
    // file): its unsaved text was saved or let go by the user.
    if (const rt::Status st = recovery_.update(doc_.path(), {}, false); !st)
        status_.set("cannot keep a recovery copy: " + st.message(), true);
}

void DocumentEditor::replaced() {
    seen_version_ = 0;
    recovery_key_ = ~std::uint64_t(0);
    recovery_held_ = {};
    const bool offered = recovery_offer_;
    recovery_offer_ = false;
    if (interactive_) {
        // Text a crashed or killed session had not saved, for this same file.
        if (recovery_busy()) recovery_write_.wait();
        recovery_busy();
        if (recovery_find_.valid()) recovery_find_.wait();  // an earlier document's: no longer wanted
        if (!offered) forget_earlier_copy();
        recovered_text_.clear();
        // The copy now on offer (this document's, or the one chosen) leaves the list.
        const std::string chosen = pending_orphan_ ? pending_orphan_->file : std::string();
        claim_document();
        if (!orphans_looked_) {
            // At start: what sessions that did not close left of other documents.
            orphans_looked_ = true;
            orphans_ = recovery_.orphans(doc_.path());
        } else {
            const std::string own = recovery_.file_for(doc_.path());
            orphans_.erase(std::remove_if(orphans_.begin(), orphans_.end(),
                                          [&](const Recovery::Orphan& o) { return o.file == own || o.file == chosen; }),
                           orphans_.end());
        }
    }
    if (!doc_.has_scene() || doc_.has_errors()) want_tab_ = true;  // show the errors
}

// The document's lock: while another live viewer holds it, that viewer's copy is
// neither offered nor touched here (and this one keeps none); else an earlier
// session's copy is looked for (off the UI thread).
void DocumentEditor::claim_document() {
    const long pid = recovery_.claim(doc_.path());
    held_elsewhere_ = pid;
    if (pid != 0) {
        status_.set("Another viewer (pid " + std::to_string(pid) + ") has " + doc_.name() +
                        " open: its unsaved text stays its own, and no recovery copy is kept here until it closes",
                    true);
        return;
    }
    recovery_key_ = ~std::uint64_t(0);  // (nothing of this one's is on disk yet)
    offered_orphan_.reset();
    if (pending_orphan_ && pending_orphan_->doc_path == absolute_path(doc_.path()) &&
        pending_orphan_->file != recovery_.file_for(doc_.path())) {
        // The default scene another viewer (ended) kept under a slot of its own.
        offered_orphan_ = pending_orphan_;
        recovery_find_ = rt::process_pool().aside([this, o = *pending_orphan_] { return recovery_.read_orphan(o); });
    } else {
        recovery_find_ = rt::process_pool().aside([this, path = doc_.path()] { return recovery_.find(path); });
    }
    pending_orphan_.reset();
}

// The live check of the draft once typing pauses: a small text parsed at once, a big
// one (a parse of more than a frame) off the UI thread, its result taken if the text
// is still the one checked (else checked again).
void DocumentEditor::live_check(double now) {
    if (check_.valid() && check_.ready()) {
        auto [key, diagnostics] = check_.get();
        if (!doc_.take_check(key, std::move(diagnostics)) && check_due_ < 0) check_due_ = now;
    }
    // Panel edits wait for a check of a big draft (Document::edit_blocker): one now.
    if (check_due_ < 0 && !check_.valid() && doc_.blocker_pending()) check_due_ = now;
    if (check_due_ < 0 || now < check_due_ || check_.valid()) return;
    check_due_ = -1;
    if (doc_.editor_text().size() < Document::kSyncParseBytes) {
        doc_.check_text();
        return;
    }
    check_ = rt::process_pool().aside([c = doc_.text_check()] {
        return std::pair{c.key, rt::parse_scene(c.text, c.options).diagnostics};
    });
}

void DocumentEditor::tick(double now) {
    recovery_finding();
    finish_apply();
    // "The scene text has errors" once it has none (fixed, reverted, undone).
    if (status_.cause() == StatusLine::Cause::TextErrors && !doc_.has_errors()) status_.clear_if(StatusLine::Cause::TextErrors);
    // "... (Ctrl+Z undoes)" once Ctrl+Z would take back another step.
    status_.clear_if_history_moved(doc_.history_changes());
    live_check(now);
}

bool DocumentEditor::idle_tick() {
    // While an offer is pending (or being looked for) the old copy stays on disk untouched.
    const bool finding = recovery_find_.valid();
    // The other viewer closed (or died): the document is this one's now, and what that
    // one left is offered.
    if (held_elsewhere_ != 0 && !recovery_finding() && !recovery_busy() && recovery_.claim(doc_.path()) == 0) {
        claim_document();  // (the lock is held now: this looks for the copy)
        status_.set("The other viewer closed " + doc_.name() + ": its recovery copy is kept here now");
        return true;
    }
    if (!recovery_finding() && !recovery_offer_ && !recovery_busy()) keep_recovery_copy();
    if (finding && recovery_offer_) return true;  // the banner shows it
    switch (doc_.check_disk()) {
        case Document::DiskEvent::None: return false;
        case Document::DiskEvent::Reloaded: reloaded_status("Reloaded " + doc_.name() + " (changed on disk)"); break;
        case Document::DiskEvent::Conflict: status_.set(doc_.name() + " changed on disk; you have unsaved edits"); break;
        case Document::DiskEvent::Removed:
            status_.set(doc_.name() + " was removed on disk; Save writes it again", true);
            break;
        case Document::DiskEvent::ModelsReloaded: status_.set("Read the scene's models and textures again (changed on disk)"); break;
        case Document::DiskEvent::NotText:
            status_.set(doc_.path() + " changed on disk and is " + doc_.disk_problem() + "; the scene and its text stay", true);
            break;
        case Document::DiskEvent::ModelUnreadable:
            status_.set("A model or texture changed on disk and no longer reads (" + doc_.model_problem() +
                            "); the scene keeps it as it was",
                        true);
            break;
        case Document::DiskEvent::IncludesReloaded:
            status_.set("Read the included files again (changed on disk)");
            break;
        case Document::DiskEvent::IncludeUnreadable:
            status_.set("An included file changed on disk and no longer reads (" + doc_.model_problem() +
                            "); the scene keeps it as it was",
                        true);
            break;
    }
    return true;
}

// Read again from disk: `ok` says so, or, when the new text has errors (a scene written
// in another editor, saved half done), the first one says where; the picture stays.
void DocumentEditor::reloaded_status(const std::string& ok) {
    const auto& diags = doc_.diagnostics();
    const auto first = std::find_if(diags.begin(), diags.end(), [](const rt::Diagnostic& d) { return d.is_error(); });
    if (first == diags.end()) {
        status_.set(ok);
        return;
    }
    status_.set(rt::format_diagnostic(doc_.name(), *first) +
                    " (read again from disk; the last good scene stays; Ctrl+Z undoes the reload)",
                true);
}

// A tick comes about once a second, so at most the last second of work is not on disk.
// The text is copied (on this thread) and written (on another) only when it changed:
// never during a drag, which changes no text until it ends. A held edit is written as
// the few items it changed, against the text last written (or the file as saved).
void DocumentEditor::keep_recovery_copy() {
    const Document& doc = doc_;
    const std::uint64_t key = doc.text_key();
    const bool modified = doc.modified();
    HeldEdit held = doc.held_edit();
    const bool text_due = modified && key != recovery_key_;
    if (!text_due && held == recovery_held_ && (modified || recovery_key_ == ~std::uint64_t(0))) return;
    std::optional<std::string> text;
    if (text_due) text = doc.editor_text();
    recovery_key_ = modified ? key : ~std::uint64_t(0);
    recovery_held_ = held;
    recovery_write_ = rt::process_pool().aside([this, path = doc.path(), text = std::move(text), modified,
                                                 held = std::move(held), file_hash = doc.saved_hash()] {
        rt::Status st;
        if (text) st = recovery_.update(path, *text, true);
        else if (!modified) st = recovery_.update(path, {}, false);  // removes the copy
        // The held edit belongs to the text just written, the one written before (the
        // text has not changed since), or the file (the text is as saved).
        const std::uint64_t base = text ? text_hash(*text) : modified ? recovery_.written_hash() : file_hash;
        const rt::Status held_st = recovery_.update_held(path, held, base);
        return st ? held_st : st;
    });
}

void DocumentEditor::saved() {
    settle_recovery_find();
    if (recovery_write_.valid()) recovery_write_.wait();
    recovery_busy();
    if (recovery_offer_) return;
    recovery_.discard(doc_.path());
    recovery_key_ = ~std::uint64_t(0);
    recovery_held_ = {};
}

void DocumentEditor::discard_recovery() {
    settle_recovery_find();
    if (recovery_write_.valid()) recovery_write_.wait();
    recovery_busy();
    if (recovery_offer_) return;  // the earlier session's text stays on offer
    forget_earlier_copy();
    recovery_.discard(doc_.path());
    recovery_.release();
}

void DocumentEditor::saved_as() {
    settle_recovery_find();
    if (recovery_write_.valid()) recovery_write_.wait();
    recovery_busy();
    if (!recovery_offer_) forget_earlier_copy();
    // The lock goes with the name (a copy another session left under it is not this
    // document's text: it stays for that file's next opening... unless it is this one's).
    if (!recovery_offer_) {
        const long pid = recovery_.claim(doc_.path());
        held_elsewhere_ = pid;
        if (pid != 0)
            status_.set("Saved; another viewer (pid " + std::to_string(pid) + ") has " + doc_.name() + " open", true);
    }
}

void DocumentEditor::focus(int cursor) {
    want_tab_ = true;
    focus_ = true;
    if (cursor >= 0) pending_cursor_ = cursor;
}

void DocumentEditor::apply() {
    if (apply_.valid()) return;  // (under way: it applies the text as it is when it ends)
    if (doc_.editor_text().size() < Document::kSyncParseBytes) {
        applied(doc_.apply_text());
        return;
    }
    // A big text's parse takes longer than a frame: off the UI thread, the window
    // answering meanwhile.
    apply_path_ = doc_.path();
    apply_ = rt::process_pool().aside([c = doc_.begin_apply()] {
        return std::pair{c.key, rt::parse_scene(c.text, c.options)};
    });
    status_.set("Applying the scene text (reading " + std::to_string(doc_.editor_text().size() >> 20) + " MB)...");
}

// A parse of apply() that ended: applied if the text is still the one parsed, else the
// text as it is now is parsed again (what was typed meanwhile is applied too); dropped if
// another document was opened meanwhile.
void DocumentEditor::finish_apply() {
    if (!apply_.valid() || !apply_.ready()) return;
    auto [key, parsed] = apply_.get();
    if (doc_.path() != apply_path_) return;
    if (std::optional<bool> ok = doc_.finish_apply(key, std::move(parsed))) applied(*ok);
    else apply();
}

void DocumentEditor::applied(bool ok) {
    if (ok) status_.set("Applied the scene text");
    else status_.set("The scene text has errors; still showing the last good scene", true, StatusLine::Cause::TextErrors);
}

// The copies of other documents that sessions which did not close left behind: each
// with its file, time and size, to open (its copy is then offered) or to discard.
void DocumentEditor::draw_orphans() {
    std::string shown;
    for (const Recovery::Orphan& o : orphans_)
        shown += (shown.empty() ? "" : "|") + (o.doc_path.empty() ? std::string("(default scene)") : o.doc_path);
    probe("orphans", shown.empty() ? "none" : shown);
    if (orphans_.empty()) return;
    ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
    ImGui::TextWrapped("Unsaved text from %s that did not close normally was kept:",
                       orphans_.size() == 1 ? "an earlier session" : "earlier sessions");
    ImGui::PopStyleColor();
    for (std::size_t k = 0; k < orphans_.size() && k < 8; ++k) {
        const Recovery::Orphan& o = orphans_[k];
        ImGui::PushID(int(k));
        char when[32] = "";
        const std::time_t t = std::time_t(o.mtime);
        if (std::tm tm {}; localtime_r(&t, &tm)) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M", &tm);
        const std::string name = o.doc_path.empty() ? "the default scene" : o.doc_path;
        const std::string size = o.bytes < 10240 ? std::to_string(o.bytes) + " bytes"
                                                 : std::to_string((o.bytes + 512) / 1024) + " KB";
        ImGui::TextWrapped("%s, %s, %s", name.c_str(), when, size.c_str());
        const bool open = ImGui::SmallButton("Open it");
        probe_item("button_open_orphan_" + std::to_string(k + 1));
        same_line_if_fits("Discard");
        const bool drop = ImGui::SmallButton("Discard");
        probe_item("button_discard_orphan_" + std::to_string(k + 1));
        ImGui::PopID();
        if (open) {
            open_request_ = o.doc_path;
            pending_orphan_ = o;
            break;
        }
        if (drop) {
            if (!recovery_.discard_orphan(o)) status_.set(name + ": another viewer has it open now", true);
            orphans_.erase(orphans_.begin() + std::ptrdiff_t(k));
            break;
        }
    }
    if (orphans_.size() > 8) ImGui::TextDisabled("and %zu more", orphans_.size() - 8);
    if (ImGui::SmallButton("Not now")) orphans_.clear();
    ImGui::Separator();
}

void DocumentEditor::draw_banners() {
    draw_orphans();
    probe("held_elsewhere", std::to_string(held_elsewhere_));
    if (held_elsewhere_ != 0) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("Another viewer (pid %ld) has this file open: no recovery copy is kept here until it closes.",
                           held_elsewhere_);
        ImGui::PopStyleColor();
        ImGui::Separator();
    }
    probe("banner", recovery_offer_ ? "recovery" : doc_.disk_conflict() ? "conflict" : "none");
    if (recovery_offer_) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("Unsaved text of %s from an earlier session (the viewer did not close normally) was kept.",
                           doc_.name().c_str());
        ImGui::PopStyleColor();
        const bool restore = ImGui::Button("Restore it");
        probe_item("button_restore_recovered");
        if (restore) {
            doc_.restore_draft(recovered_text_);
            recovered_text_.clear();
            recovery_offer_ = false;
            // (Another slot's copy: its text is this viewer's now, kept in its own copy.)
            if (offered_orphan_) recovery_.discard_orphan(*offered_orphan_);
            offered_orphan_.reset();
            want_tab_ = true;
            status_.set_about_step("Restored the unsaved text into the editor (Ctrl+Enter applies it, Ctrl+Z undoes)",
                                   doc_.history_changes());
        }
        same_line_if_fits("Discard it");
        if (ImGui::Button("Discard it")) {
            if (recovery_write_.valid()) recovery_write_.wait();
            recovery_busy();
            if (offered_orphan_) recovery_.discard_orphan(*offered_orphan_);
            else recovery_.discard(doc_.path());
            offered_orphan_.reset();
            recovered_text_.clear();
            recovery_offer_ = false;
        }
        ImGui::Separator();
    }
    if (doc_.disk_conflict()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("%s changed on disk, and you have unsaved edits here.", doc_.name().c_str());
        ImGui::PopStyleColor();
        const bool reload = ImGui::Button("Reload from disk");
        probe_item("button_disk_reload");
        if (reload) {
            doc_.resolve_conflict_reload();
            reloaded_status("Reloaded " + doc_.name() + " (Ctrl+Z brings your edits back)");
        }
        same_line_if_fits("Keep mine");
        const bool keep = ImGui::Button("Keep mine");
        probe_item("button_disk_keep");
        if (keep) doc_.resolve_conflict_keep();
        ImGui::Separator();
    }
}

// The widget keeps the text as lines; the document keeps it as one string. The
// document's changes (undo, a panel edit) are made in the widget too, and a new text
// (a load, or changes the document no longer keeps) replaces the widget's; typing is
// carried the other way as the widget's edit log, one small replacement per edit.
void DocumentEditor::sync_widget() {
    if (doc_.text_version() != seen_version_) {
        std::vector<TextReplacement> changes;
        if (seen_version_ != 0 && doc_.text_changes_since(seen_version_, changes)) {
            for (const TextReplacement& c : changes) widget_.buffer().follow_replacement(c.offset, c.length, c.text);
        } else if (seen_version_ == 0) {
            widget_.start_over(doc_.editor_text());  // another document
        } else {
            widget_.set_text(doc_.editor_text());
        }
        widget_.buffer().set_logging(true);
        seen_version_ = doc_.text_version();
    }
    const auto& diags = doc_.diagnostics();
    bool same = diags.size() == marked_.size();
    for (std::size_t k = 0; same && k < diags.size(); ++k)
        same = diags[k].line == marked_[k].line && diags[k].message == marked_[k].message;
    if (!same) {
        std::vector<LineMark> marks;
        for (const rt::Diagnostic& d : diags) marks.push_back({d.line, d.is_error(), d.message});
        widget_.set_marks(std::move(marks));
        marked_ = diags;
    }
    if (focus_) {
        widget_.focus();
        focus_ = false;
    }
    if (pending_cursor_ >= 0) {
        widget_.show(widget_.buffer().pos_of(std::size_t(pending_cursor_)));
        pending_cursor_ = -1;
    }
}

void DocumentEditor::draw_text_tab(Layout& layout) {
    // The editor's own shortcuts work whenever its tab is in front, clicked into or not
    // (the pointer may rest anywhere); with the text clicked into, the widget has them.
    const ImGuiIO& io = ImGui::GetIO();
    if (!widget_.focused() && io.KeyCtrl && !io.KeyAlt && !io.WantTextInput &&
        !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) {
        if (key_pressed(keys::kF)) widget_.open_find();
        else if (key_pressed(keys::kG)) widget_.open_goto();
    }
    draw_text_toolbar();
    float diag_h = 0;
    const std::vector<std::string> diag_text = diagnostic_lines(diag_h);
    float line = ImGui::GetTextLineHeightWithSpacing();
    float editor_h = std::max(line * 4, ImGui::GetContentRegionAvail().y - diag_h - ImGui::GetStyle().ItemSpacing.y);

    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    const bool changed = draw_text_widget(editor_h);
    id_ = 0;  // the widget holds no ImGui active id while typing
    layout.editor = {top.x, top.y, width, editor_h};
    if (changed) check_due_ = ImGui::GetTime() + 0.3;  // live check once typing pauses

    layout.diagnostics = {ImGui::GetCursorScreenPos().x, ImGui::GetCursorScreenPos().y, width, diag_h};
    draw_diagnostics(diag_text, diag_h);
}

// Apply, Revert, whether the text is the scene, wrap; and a warning while panel edits
// cannot reach the text.
void DocumentEditor::draw_text_toolbar() {
    bool can_apply = doc_.editor_dirty() || doc_.has_errors();
    ImGui::BeginDisabled(!can_apply);
    if (ImGui::Button("Apply (Ctrl+Enter)")) apply();
    ImGui::EndDisabled();
    same_line_if_fits("Revert");
    ImGui::BeginDisabled(!doc_.unapplied() && !doc_.text_behind());
    const bool revert = ImGui::Button("Revert");
    probe_item("button_revert");
    if (revert) doc_.revert_text();
    ImGui::EndDisabled();
    // (A file opened with errors is the file as it is, not changes of the user's.)
    const bool unapplied = doc_.unapplied();
    const char* state = unapplied ? "unapplied changes" : doc_.has_scene() ? "text = scene" : "no scene yet: fix the errors";
    same_line_if_fits(state);
    ImGui::TextColored(unapplied || !doc_.has_scene() ? kWarnColour : kOkColour, "%s", state);
    same_line_if_fits("wrap", ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x);
    bool wrap = widget_.wrap();
    if (ImGui::Checkbox("wrap", &wrap)) widget_.set_wrap(wrap);
    if (doc_.text_behind()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kWarnColour);
        ImGui::TextWrapped("Panel edits are not in this text: it has unapplied changes that do not parse. "
                           "Apply uses the text; Revert drops the text changes.");
        ImGui::PopStyleColor();
    }
}

// The diagnostics as the list shows them ("LINE:COL: error: ..."), and in `list_h` the
// list's height. Messages wrap at the list's edge (long ones would be cut off at a
// large UI scale): the list is as tall as its first six lines of wrapped text.
std::vector<std::string> DocumentEditor::diagnostic_lines(float& list_h) const {
    const auto& diags = doc_.diagnostics();
    float line = ImGui::GetTextLineHeightWithSpacing();
    const ImGuiStyle& style = ImGui::GetStyle();
    const float wrap_w = std::max(ImGui::GetContentRegionAvail().x - 2 * style.WindowPadding.x - style.ScrollbarSize,
                                  ImGui::GetFontSize() * 4);
    std::vector<std::string> diag_text;
    float diag_lines_h = 0;
    for (const rt::Diagnostic& d : diags) {
        diag_text.push_back(std::to_string(d.line) + ":" + std::to_string(d.col) + ": " +
                            (d.is_error() ? "error: " : "warning: ") + d.message);
        if (diag_lines_h < line * 6)
            diag_lines_h += ImGui::CalcTextSize(diag_text.back().c_str(), nullptr, false, wrap_w).y + style.ItemSpacing.y;
    }
    list_h = std::clamp(diag_lines_h, line, line * 6) + style.WindowPadding.y * 2;
    return diag_text;
}

// The text widget, `height` tall (or a note, for a text too large to edit here); true
// if typing changed the text, which then goes into the document's draft.
bool DocumentEditor::draw_text_widget(float height) {
    bool changed = false;
    if (doc_.editor_text().size() > kMaxEditableBytes) {
        ImGui::BeginChild("##too_big", ImVec2(-1, height), true);
        ImGui::TextWrapped("This scene text is %.0f MB: too large to edit here. The panels still edit it "
                           "(each change rewrites only its own block), and changes made to the file in "
                           "another editor are reloaded by themselves.",
                           double(doc_.editor_text().size()) / (1 << 20));
        ImGui::EndChild();
        active_ = false;
    } else {
        sync_widget();
        changed = widget_.draw("scene_text", ImVec2(-1, height));
        active_ = widget_.focused();
        if (changed) {
            std::string& text = doc_.typing_text();
            for (const BufferEdit& e : widget_.buffer().take_edits()) text.replace(e.offset, e.removed.size(), e.inserted);
            doc_.note_typed();
        }
    }
    return changed;
}

// The list of diagnostics: clicking one puts the cursor where it is.
void DocumentEditor::draw_diagnostics(const std::vector<std::string>& diag_text, float height) {
    const auto& diags = doc_.diagnostics();
    if (ImGui::BeginChild("diagnostics", ImVec2(0, height), true)) {
        if (diags.empty()) ImGui::TextDisabled(doc_.editor_dirty() ? "No errors (Ctrl+Enter applies)." : "No errors.");
        for (std::size_t k = 0; k < diags.size(); ++k) {
            const rt::Diagnostic& d = diags[k];
            const std::string& text = diag_text[k];
            // A selectable as tall as the wrapped message, the message drawn over it.
            const float w = std::max(ImGui::GetContentRegionAvail().x, ImGui::GetFontSize() * 4);
            const ImVec2 size(w, ImGui::CalcTextSize(text.c_str(), nullptr, false, w).y);
            const ImVec2 at = ImGui::GetCursorScreenPos();
            ImGui::PushID(int(k));
            if (ImGui::Selectable("##diagnostic", false, 0, size)) widget_.show({d.line - 1, d.col - 1});
            ImGui::GetWindowDrawList()->AddText(ImGui::GetFont(), ImGui::GetFontSize(), at,
                                                ImGui::GetColorU32(d.is_error() ? kErrorColour : kWarnColour),
                                                text.c_str(), nullptr, w);
            ImGui::PopID();
        }
    }
    ImGui::EndChild();
}

}  // namespace rtview
