// The viewer's document model (see document.h): undoable edits, text write-back,
// atomic saves and external-change handling.
#include "document.h"

#include <sys/stat.h>

#include "image_io.h"
#include "scene_text.h"
#include "scene_writer.h"

namespace rtview {

FileStamp FileStamp::of(const std::string& path) {
    FileStamp s;
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0) return s;
    s.exists = true;
    s.mtime_ns = std::int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
    s.size = std::int64_t(st.st_size);
    // Editors that save by rename give a new inode even within one mtime tick.
    s.inode = std::uint64_t(st.st_ino);
    return s;
}

namespace {

std::string base_name(const std::string& path) {
    std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool same_except_camera(const rt::Scene& a, const rt::Scene& b) {
    return a.objects == b.objects && a.planes == b.planes && a.lights == b.lights && a.width == b.width &&
           a.height == b.height;
}

}  // namespace

Document::Document() { load_text("", "", "untitled"); }

void Document::load_text(const std::string& text, const std::string& path, const std::string& name) {
    load_parsed(text, rt::parse_scene(text), path, name);
}

void Document::load_parsed(std::string text, rt::ParseResult parsed, const std::string& path,
                           const std::string& name) {
    history_.clear();
    pending_ = false;
    conflict_ = false;
    path_ = path;
    name_ = name;
    DocState s;
    bool ok = parsed.ok();
    diagnostics_ = std::move(parsed.diagnostics);
    if (ok) {
        s.scene = std::move(parsed.scene);
        s.has_scene = true;
        s.applied_text = text;
    }
    s.editor_text = std::move(text);
    s_ = std::move(s);
    ++scene_version_;
    ++content_version_;
    ++text_version_;
    mark_saved(s_.editor_text);
    if (s_.has_scene) file_camera_ = s_.scene.camera;
}

std::string Document::load_file(const std::string& path) {
    std::string text;
    std::string err = rt::read_file(path, text, rt::Limits::max_file_size);
    if (!err.empty()) return err;
    load_text(text, path, base_name(path));
    return {};
}

std::string Document::title() const { return name_ + (modified() ? "*" : "") + " - raytracer-view"; }

rt::Scene& Document::edit() {
    if (!pending_) {
        before_ = s_;
        pending_ = true;
    }
    ++scene_version_;
    ++content_version_;
    return s_.scene;
}

rt::Camera& Document::edit_camera() {
    if (!pending_) {
        before_ = s_;
        pending_ = true;
    }
    ++scene_version_;
    return s_.scene.camera;
}

void Document::cancel_edit() {
    if (!pending_) return;
    pending_ = false;
    s_ = before_;
    ++scene_version_;
    ++content_version_;
}

bool Document::set_camera(const rt::Camera& camera) {
    if (!s_.has_scene || camera == s_.scene.camera) return false;
    commit();
    edit_camera() = camera;
    commit();
    return true;
}

void Document::commit() {
    if (!pending_) return;
    pending_ = false;
    if (s_.scene == before_.scene) return;
    DocState next = s_;
    next.applied_text = before_.has_scene ? sync_scene_text(before_.applied_text, before_.scene, s_.scene)
                                          : rt::write_scene(s_.scene);
    if (before_.editor_text == before_.applied_text) {
        next.editor_text = next.applied_text;
    } else {
        // The user has an unapplied draft: carry the edit into it only where that is
        // unambiguous (the draft parses and has the same items); never overwrite it.
        rt::ParseResult draft = rt::parse_scene(before_.editor_text);
        bool carried = false;
        if (draft.ok()) {
            bool complete = false;
            rt::Scene target = carry_edit(draft.scene, before_.scene, s_.scene, &complete);
            if (auto patched = patch_scene_text(before_.editor_text, draft.scene, target)) {
                next.editor_text = *patched;
                carried = complete;
            }
        }
        next.text_behind = before_.text_behind || !carried;
    }
    DocState prev = std::move(before_);
    before_ = DocState{};
    bool text_changed = next.editor_text != prev.editor_text;
    history_.push(std::move(prev));
    s_ = std::move(next);
    if (text_changed) ++text_version_;
}

void Document::set_state(DocState s, bool push_history) {
    bool scene_changed = s.has_scene != s_.has_scene || s.scene != s_.scene;
    bool content_changed = scene_changed && (s.has_scene != s_.has_scene || !same_except_camera(s.scene, s_.scene));
    bool text_changed = s.editor_text != s_.editor_text;
    if (push_history) history_.push(s_);
    s_ = std::move(s);
    if (scene_changed) ++scene_version_;
    if (content_changed) ++content_version_;
    if (text_changed) ++text_version_;
}

bool Document::has_errors() const {
    for (const auto& d : diagnostics_)
        if (d.is_error()) return true;
    return false;
}

bool Document::apply_text() {
    commit();
    rt::ParseResult r = rt::parse_scene(s_.editor_text);
    diagnostics_ = r.diagnostics;
    if (!r.ok()) return false;
    if (s_.has_scene && r.scene == s_.scene && s_.applied_text == s_.editor_text && !s_.text_behind) return true;
    DocState next = s_;
    next.scene = std::move(r.scene);
    next.has_scene = true;
    next.applied_text = next.editor_text;
    next.text_behind = false;
    set_state(std::move(next), true);
    return true;
}

void Document::check_text() { diagnostics_ = rt::parse_scene(s_.editor_text).diagnostics; }

void Document::revert_text() {
    commit();
    const std::string& target = s_.has_scene ? s_.applied_text : saved_text_;
    if (s_.editor_text == target && !s_.text_behind) return;
    DocState next = s_;
    next.editor_text = target;
    next.text_behind = false;
    set_state(std::move(next), true);
    diagnostics_.clear();
}

void Document::restore_draft(const std::string& text) {
    commit();
    if (s_.editor_text == text) return;
    DocState next = s_;
    next.editor_text = text;
    set_state(std::move(next), true);
    check_text();
}

bool Document::undo() {
    commit();
    auto prev = history_.undo(s_);
    if (!prev) return false;
    set_state(std::move(*prev), false);
    diagnostics_ = editor_dirty() ? rt::parse_scene(s_.editor_text).diagnostics : std::vector<rt::Diagnostic>{};
    return true;
}

bool Document::redo() {
    commit();
    auto next = history_.redo(s_);
    if (!next) return false;
    set_state(std::move(*next), false);
    diagnostics_ = editor_dirty() ? rt::parse_scene(s_.editor_text).diagnostics : std::vector<rt::Diagnostic>{};
    return true;
}

void Document::mark_saved(const std::string& text) {
    saved_text_ = text;
    // No second parse of the saved text: it is the text of the current scene whenever
    // that has no unapplied draft.
    if (s_.has_scene && s_.applied_text == text) file_camera_ = s_.scene.camera;
    stamp_ = FileStamp::of(path_);
    conflict_ = false;
}

std::string Document::save() {
    commit();
    if (path_.empty()) return "the scene has no file name yet: use Save As";
    std::string err = rt::write_file_atomic(path_, s_.editor_text);
    if (!err.empty()) return err;
    mark_saved(s_.editor_text);
    return {};
}

std::string Document::save_as(const std::string& path) {
    commit();
    if (path.empty()) return "no file name given";
    std::string err = rt::write_file_atomic(path, s_.editor_text);
    if (!err.empty()) return err;
    path_ = path;
    name_ = base_name(path);
    mark_saved(s_.editor_text);
    return {};
}

void Document::reload_text(const std::string& text) {
    rt::ParseResult r = rt::parse_scene(text);
    DocState next = s_;
    diagnostics_ = r.diagnostics;
    if (r.ok()) {
        next.scene = std::move(r.scene);
        next.has_scene = true;
        next.applied_text = text;
        next.editor_text = text;
        next.text_behind = false;
    } else {
        // Show the new text with its errors; the last good scene keeps rendering.
        next.editor_text = text;
    }
    set_state(std::move(next), true);
    mark_saved(text);
}

Document::DiskEvent Document::check_disk() {
    if (path_.empty() || pending_) return DiskEvent::None;  // not in the middle of a gesture
    FileStamp st = FileStamp::of(path_);
    if (st == stamp_) return DiskEvent::None;
    stamp_ = st;
    if (!st.exists) return DiskEvent::Removed;
    std::string text;
    if (!rt::read_file(path_, text, rt::Limits::max_file_size).empty()) return DiskEvent::None;
    if (text == saved_text_) return DiskEvent::None;  // touched, or our own save
    if (!modified()) {
        reload_text(text);
        return DiskEvent::Reloaded;
    }
    conflict_ = true;
    conflict_text_ = text;
    return DiskEvent::Conflict;
}

void Document::resolve_conflict_reload() {
    if (!conflict_) return;
    conflict_ = false;
    reload_text(conflict_text_);
}

void Document::resolve_conflict_keep() { conflict_ = false; }

}  // namespace rtview
