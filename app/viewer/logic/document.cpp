// The viewer's document (see document.h): opening, the scene's versions, the editor
// text, applying and reverting it. The held edit: document_edit.cpp; undo:
// document_history.cpp; saving and the file on disk: document_disk.cpp.
#include "document.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "block_patch.h"
#include "image_io.h"
#include "paths.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "snapshots.h"

namespace rtview {

std::uint64_t text_hash(const std::string& text) {
    // FNV-1a over 8-byte words (then the tail): fast enough for 100 MB scenes.
    std::uint64_t h = 1469598103934665603ull ^ text.size();
    std::size_t i = 0, n = text.size();
    for (; i + 8 <= n; i += 8) {
        std::uint64_t w;
        std::memcpy(&w, text.data() + i, 8);
        h = (h ^ w) * 1099511628211ull;
        h ^= h >> 29;
    }
    for (; i < n; ++i) h = (h ^ std::uint8_t(text[i])) * 1099511628211ull;
    return h;
}

namespace {

// The changes kept for changes_since(): a consumer further behind compiles anew.
constexpr std::size_t kMaxChanges = 256;

}  // namespace

Document::Document() { load_text("", "", "untitled"); }

void Document::load_text(const std::string& text, const std::string& path, const std::string& name) {
    load_parsed(text, rt::parse_scene(text, parse_options(path)), path, name);
}

void Document::load_parsed(std::string text, rt::ParseResult parsed, const std::string& path,
                           const std::string& name, std::optional<SceneLayout> layout,
                           std::optional<std::uint64_t> hash) {
    history_.clear();
    held_ = false;
    saved_ = {};
    held_name_.clear();
    last_step_name_.clear();
    typing_base_.reset();
    layout_.reset();
    conflict_ = false;
    conflict_text_.clear();
    path_ = path;
    name_ = name;
    bool ok = parsed.ok();
    diagnostics_ = std::move(parsed.diagnostics);
    editor_ = std::move(text);
    behind_ = false;
    if (ok) {
        scene_ = std::move(parsed.scene);
        has_scene_ = true;
        applied_.reset();
    } else {
        scene_ = rt::Scene{};
        has_scene_ = false;
        applied_ = std::string();  // nothing applied yet
    }
    ++scene_version_;
    changes_.clear();
    changed(rt::SceneDelta::all());
    ++text_version_;
    text_log_.clear();
    text_log_bytes_ = 0;
    mark_saved(hash);
    if (layout) {
        layout_ = std::move(layout);
        layout_key_ = layout_key();
    }
}

void Document::load_pending(const std::string& name) {
    load_parsed("", rt::ParseResult{}, "", name);
    has_scene_ = false;
    scene_ = rt::Scene{};
    applied_ = std::string();
}

rt::Status Document::load_file(const std::string& path) {
    std::string text;
    if (rt::Status st = rt::read_file(path, text, rt::Limits::max_file_size); !st) return st;
    load_text(text, path, base_name(path));
    return {};
}

void Document::changed(rt::SceneDelta delta) {
    const std::uint64_t from = content_version_++;
    // A held edit changes its item every frame: one entry for all of them.
    if (!changes_.empty() && changes_.back().to == from && delta.in_place() && changes_.back().delta.in_place() &&
        changes_.back().delta.objects == delta.objects && changes_.back().delta.planes == delta.planes &&
        changes_.back().delta.lights == delta.lights) {
        changes_.back().to = content_version_;
        return;
    }
    changes_.push_back({from, content_version_, std::move(delta)});
    if (changes_.size() > kMaxChanges) changes_.pop_front();
}

rt::SceneDelta Document::changes_since(std::uint64_t version) const {
    rt::SceneDelta d;
    if (version == content_version_) return d;
    if (version > content_version_ || changes_.empty() || version < changes_.front().from) return rt::SceneDelta::all();
    for (const Change& c : changes_)
        if (c.to > version) d.merge(c.delta);
    return d;
}

bool Document::modified() const {
    // Hashing a big text is not free: once per change of the text, not per frame.
    std::uint64_t key = text_key();
    if (key != modified_key_) {
        modified_cache_ = editor_.size() != saved_size_ || text_hash(editor_) != saved_hash_;
        modified_key_ = key;
    }
    return modified_cache_;
}

std::string Document::title() const { return name_ + (modified() ? "*" : "") + " - raytracer-view"; }

std::string& Document::typing_text() {
    // The caller may type into it: from now on the applied text needs its own copy,
    // and the text as it is now is where the typing starts.
    if (!applied_) applied_ = editor_;
    if (!typing_base_) typing_base_ = editor_;
    ++typed_;
    return editor_;
}

void Document::flush_typing() {
    if (!typing_base_) return;
    std::string base;
    base.swap(*typing_base_);
    typing_base_.reset();
    if (base == editor_) return;
    DocStep step;
    step.name = kTypingName;
    step.made(diff_texts(base, editor_), base);
    step.keep_applied = true;
    step.has_scene_before = step.has_scene_after = has_scene_;
    step.behind_before = step.behind_after = behind_;
    record(std::move(step));
}

void Document::normalize_applied() {
    if (applied_ && has_scene_ && *applied_ == editor_) applied_.reset();
}

bool Document::has_errors() const {
    for (const auto& d : diagnostics_)
        if (d.is_error()) return true;
    return false;
}

bool Document::apply_text() {
    commit();
    flush_typing();
    return apply_parsed(rt::parse_scene(editor_, parse_options(path_)));
}

Document::TextCheck Document::begin_apply() {
    commit();
    flush_typing();
    return text_check();
}

std::optional<bool> Document::finish_apply(std::uint64_t key, rt::ParseResult r) {
    if (key != text_key()) return std::nullopt;
    return apply_parsed(std::move(r));
}

bool Document::apply_parsed(rt::ParseResult r) {
    diagnostics_ = r.diagnostics;
    if (!r.ok()) return false;
    normalize_applied();
    if (has_scene_ && !applied_ && !behind_ && r.scene == scene_) return true;
    replace_state(nullptr, std::nullopt, std::move(r.scene), false, "Apply the scene text");
    return true;
}

bool Document::replace_text(std::size_t pos, std::size_t length, const std::string& text, const std::string& name,
                            const ItemSplice* splice) {
    // The replacement was planned on the text and the scene as they are now; a held
    // edit (a drag) would rewrite the text when committed, and the replacement would
    // land on the wrong bytes.
    if (held_) return false;
    flush_typing();  // text typed since the last step is a step of its own, first
    normalize_applied();
    if (applied_ || behind_ || pos > editor_.size() || length > editor_.size() - pos) return false;
    if (splice && splice_text(pos, length, text, name, *splice)) return true;
    std::string edited = editor_;
    edited.replace(pos, length, text);
    rt::ParseResult r = rt::parse_scene(edited, parse_options(path_));
    if (!r.ok()) return false;
    diagnostics_ = r.diagnostics;
    replace_state(&edited, std::nullopt, std::move(r.scene), false, name);
    return true;
}

void Document::check_text() {
    diagnostics_ = rt::parse_scene(editor_, parse_options(path_)).diagnostics;
    take_blocker(text_key(), !has_errors());
}

bool Document::take_check(std::uint64_t key, std::vector<rt::Diagnostic> diagnostics) {
    if (key != text_key()) return false;
    diagnostics_ = std::move(diagnostics);
    take_blocker(key, !has_errors());
    return true;
}

void Document::revert_text() {
    commit();
    flush_typing();
    // Without a scene the text goes back to the file as last loaded or saved, which is
    // kept only when it does not parse; one that parses (an undo went back past its
    // reload) is not known here, and the text stays.
    if (!has_scene_ && (saved_broken_text_.size() != saved_size_ || text_hash(saved_broken_text_) != saved_hash_))
        return;
    std::string target = has_scene_ ? applied_text() : saved_broken_text_;
    if (editor_ == target && !behind_) return;
    replace_state(&target, has_scene_ ? std::nullopt : std::optional<std::string>(std::string()), std::nullopt, false,
                  "Revert the scene text");
    diagnostics_.clear();
}

void Document::restore_draft(const std::string& text) {
    commit();
    flush_typing();
    if (editor_ == text) return;
    std::string applied = applied_text();
    replace_state(&text, std::move(applied), std::nullopt, behind_, "Restore the recovered text");
    check_text();
}

}  // namespace rtview
