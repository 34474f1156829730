// The document's undo history (see document.h): steps recorded, undone and redone,
// whole-text changes as steps, and the log of text changes a text widget follows.
#include "document.h"

#include <algorithm>
#include <utility>

#include "block_patch.h"
#include "image_io.h"
#include "paths.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "snapshots.h"

namespace rtview {

namespace {

bool same_except_camera(const rt::Scene& a, const rt::Scene& b) {
    return a.objects == b.objects && a.planes == b.planes && a.lights == b.lights && a.width == b.width &&
           a.height == b.height;
}

// The items of list `a` read from included files are those of `b`, in order.
template <class T>
bool same_included_items(const std::vector<T>& a, const std::vector<T>& b) {
    auto next = [](const std::vector<T>& v, std::size_t& k) {
        while (k < v.size() && v[k].origin == 0) ++k;
        return k < v.size() ? &v[k++] : nullptr;
    };
    std::size_t i = 0, j = 0;
    for (;;) {
        const T *x = next(a, i), *y = next(b, j);
        if (!x || !y) return x == y;
        if (!(*x == *y) || x->origin != y->origin) return false;
    }
}

// What a step that keeps only the items it changed cannot give back: the named
// materials and objects, the includes, and the items read from included files (an undo
// would bring those back as they were, not as the files are now). A change of any of
// these makes a step that parses the text again.
bool same_definitions(const rt::Scene& a, const rt::Scene& b) {
    if (!(a.materials == b.materials && a.defined == b.defined && a.includes == b.includes)) return false;
    if (a.includes.empty()) return true;
    return same_included_items(a.objects, b.objects) && same_included_items(a.planes, b.planes) &&
           same_included_items(a.lights, b.lights);
}

}  // namespace

std::size_t DocStep::bytes() const {
    std::size_t b = sizeof(DocStep) + name.size();
    for (const auto* v : {&editor, &editor_back})
        for (const TextReplacement& r : *v) b += sizeof(TextReplacement) + r.text.size();
    if (applied_before) b += applied_before->size();
    auto spliced_bytes = [&b](const SplicedItem& s) {
        b += sizeof(SplicedItem);
        for (const rt::Scene* sc : {&s.before, &s.after})
            for (const rt::Object& o : sc->objects) b += object_bytes(o);
    };
    if (spliced) spliced_bytes(*spliced);
    for (const SplicedItem& s : spliced_many) spliced_bytes(s);
    if (applied_after) b += applied_after->size();
    for (const auto& o : objects_before) b += object_bytes(o.second) + sizeof(std::size_t);
    for (const auto& o : objects_after) b += object_bytes(o.second) + sizeof(std::size_t);
    b += (planes_before.size() + planes_after.size()) * (sizeof(rt::Plane) + sizeof(std::size_t));
    b += (lights_before.size() + lights_after.size()) * (sizeof(rt::Light) + sizeof(std::size_t));
    b += (materials_before.size() + materials_after.size()) * (sizeof(rt::NamedMaterial) + sizeof(std::size_t));
    for (const auto* v : {&defined_before, &defined_after})
        for (const auto& d : *v) b += sizeof(rt::NamedObject) + (d.second.object ? object_bytes(*d.second.object) : 0);
    return b;
}

void Document::text_changed(const DocStep& s, bool forward) {
    ++text_version_;
    std::vector<TextReplacement> changes =
        forward ? s.editor : std::vector<TextReplacement>(s.editor_back.rbegin(), s.editor_back.rend());
    // What a version's changes hold, as the log counts it in and out.
    auto bytes_of = [](const std::vector<TextReplacement>& v) {
        std::size_t n = 0;
        for (const TextReplacement& c : v) n += c.text.size() + sizeof(TextReplacement);
        return n;
    };
    // A widget that has not looked for this long takes the whole text again.
    constexpr std::size_t kMaxVersions = 256, kMaxBytes = std::size_t(4) << 20;
    text_log_bytes_ += bytes_of(changes);
    text_log_.push_back(std::move(changes));
    while (text_log_.size() > kMaxVersions || (text_log_bytes_ > kMaxBytes && !text_log_.empty())) {
        text_log_bytes_ -= bytes_of(text_log_.front());
        text_log_.pop_front();
    }
}

bool Document::text_changes_since(std::uint64_t version, std::vector<TextReplacement>& out) const {
    out.clear();
    if (version > text_version_ || text_version_ - version > text_log_.size()) return false;
    for (std::size_t k = text_log_.size() - std::size_t(text_version_ - version); k < text_log_.size(); ++k)
        out.insert(out.end(), text_log_[k].begin(), text_log_[k].end());
    return true;
}

void Document::record(DocStep step) {
    typing_base_.reset();
    std::size_t bytes = step.bytes();
    history_.push(std::move(step), bytes);
}

// --- Whole-text changes

void Document::replace_state(const std::string* editor, std::optional<std::string> applied,
                             std::optional<rt::Scene> scene, bool behind, std::string name) {
    DocStep step;
    step.name = std::move(name);
    // The state before, as it was: the applied text is "the editor text" only if it
    // was equal to the editor text before that changes.
    normalize_applied();
    step.applied_before = applied_;
    if (!applied_) applied_ = editor_;  // (replaced below; keeps the old text meanwhile)
    if (editor && *editor != editor_) {
        step.made(diff_texts(editor_, *editor), editor_);
        editor_ = *editor;
    }
    step.has_scene_before = has_scene_;
    step.behind_before = behind_;
    bool content_changed = false, scene_changed = false;
    if (scene) {
        bool same_counts = has_scene_ && scene->objects.size() == scene_.objects.size() &&
                           scene->planes.size() == scene_.planes.size() &&
                           scene->lights.size() == scene_.lights.size() && scene->width == scene_.width &&
                           scene->height == scene_.height && same_definitions(*scene, scene_);
        bool small = same_counts &&
                     diff_items(scene_.objects, scene->objects, step.objects_before, step.objects_after, kMaxStepItems) &&
                     diff_items(scene_.planes, scene->planes, step.planes_before, step.planes_after, kMaxStepItems) &&
                     diff_items(scene_.lights, scene->lights, step.lights_before, step.lights_after, kMaxStepItems);
        if (!small) {
            step.reparse = true;
            step.objects_before.clear(), step.objects_after.clear();
            step.planes_before.clear(), step.planes_after.clear();
            step.lights_before.clear(), step.lights_after.clear();
        }
        if (!has_scene_ || !(scene->camera == scene_.camera)) {
            step.camera_before = scene_.camera;
            step.camera_after = scene->camera;
        }
        scene_changed = !has_scene_ || !(*scene == scene_);
        content_changed = !has_scene_ || !same_except_camera(*scene, scene_);
        scene_ = std::move(*scene);
        has_scene_ = true;
    }
    applied_ = std::move(applied);
    normalize_applied();
    behind_ = behind;
    step.applied_after = applied_;
    step.has_scene_after = has_scene_;
    step.behind_after = behind_;
    if (scene_changed) ++scene_version_;
    if (content_changed)
        changed(step.reparse ? rt::SceneDelta::all() : items_of(step.objects_after, step.planes_after, step.lights_after));
    if (!step.editor.empty()) text_changed(step, true);
    record(std::move(step));
}

void Document::apply_step(const DocStep& s, bool forward) {
    // (A spliced step keeps the layout in step with the text, as it was made.)
    const bool layout_valid = layout_ && layout_key_ == layout_key();
    // A typing step leaves the applied text alone: it is the editor text as it is
    // before the step when they are one and the same now.
    if (s.keep_applied && !applied_) applied_ = editor_;
    // A panel edit's step (the text is the scene's): the positions after each
    // replacement move with the text.
    const bool follow = !s.spliced && s.spliced_many.empty() && !s.reparse && !s.keep_applied && !s.applied_before && !s.applied_after;
    std::vector<rt::Diagnostic> reparsed;
    const std::vector<TextReplacement>& made = forward ? s.editor : s.editor_back;
    const std::vector<TextReplacement>& undone = forward ? s.editor_back : s.editor;
    // A group's edits: the text, the scene and the layout in one pass where they allow it.
    const bool grouped = !s.spliced_many.empty() && apply_group(s, forward, layout_valid);
    for (std::size_t k = 0; k < made.size() && !grouped; ++k) {
        const TextReplacement& r = made[forward ? k : made.size() - 1 - k];
        editor_.replace(r.offset, r.length, r.text);
        const std::size_t i = forward ? k : made.size() - 1 - k;
        if (follow) follow_positions(r.offset, undone[i].text, r.text, s.editor_at.size() == made.size() ? &s.editor_at[i] : nullptr);
    }
    if (!s.keep_applied) applied_ = forward ? s.applied_after : s.applied_before;
    else normalize_applied();
    has_scene_ = forward ? s.has_scene_after : s.has_scene_before;
    if (s.spliced && s.editor.size() == 1 && s.editor_back.size() == 1) {
        const TextReplacement& r = s.editor[0];
        const TextReplacement& back = s.editor_back[0];
        apply_splice(*s.spliced, forward, r.offset, forward ? back.text : r.text, forward ? r.text : back.text,
                     layout_valid);
    } else if (grouped) {
        // (Made above.)
    } else if (!s.spliced_many.empty() && s.editor.size() == s.spliced_many.size() &&
               s.editor_back.size() == s.spliced_many.size()) {
        // (The text is replaced above; each splice follows it in turn, the last first
        // going back.)
        const std::size_t n = s.spliced_many.size();
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = forward ? k : n - 1 - k;
            const TextReplacement& r = s.editor[i];
            const TextReplacement& back = s.editor_back[i];
            apply_splice(s.spliced_many[i], forward, r.offset, forward ? back.text : r.text,
                         forward ? r.text : back.text, layout_valid);
        }
    } else if (s.reparse) {
        if (has_scene_) {
            rt::ParseResult r = rt::parse_scene(applied_text(), parse_options(path_));
            scene_ = std::move(r.scene);
            reparsed = std::move(r.diagnostics);
        }
    } else {
        if (layout_valid && !s.keep_applied && !s.applied_before && !s.applied_after && !s.editor.empty())
            follow_layout(forward ? s.editor
                                  : std::vector<TextReplacement>(s.editor_back.rbegin(), s.editor_back.rend()));
        for (const auto& p : forward ? s.materials_after : s.materials_before) scene_.materials[p.first] = p.second;
        for (const auto& p : forward ? s.defined_after : s.defined_before) scene_.defined[p.first] = p.second;
        for (const auto& p : forward ? s.objects_after : s.objects_before) restore_object(p.first, p.second);
        for (const auto& p : forward ? s.planes_after : s.planes_before) restore_plane(p.first, p.second);
        for (const auto& p : forward ? s.lights_after : s.lights_before) scene_.lights[p.first] = p.second;
    }
    if (s.camera_before) scene_.camera = forward ? *s.camera_after : *s.camera_before;
    behind_ = forward ? s.behind_after : s.behind_before;
    ++scene_version_;
    if (s.reparse || s.has_scene_before != s.has_scene_after)
        changed(rt::SceneDelta::all());
    else if (s.spliced)
        changed(splice_delta(*s.spliced, forward));
    else if (!s.spliced_many.empty()) {
        rt::SceneDelta d;
        const std::size_t n = s.spliced_many.size();
        for (std::size_t k = 0; k < n; ++k) d.merge(splice_delta(s.spliced_many[forward ? k : n - 1 - k], forward));
        changed(std::move(d));
    }
    else if (!s.objects_before.empty() || !s.planes_before.empty() || !s.lights_before.empty())
        changed(items_of(s.objects_before, s.planes_before, s.lights_before));
    if (!s.editor.empty() || s.applied_before != s.applied_after) text_changed(s, forward);
    typing_base_.reset();
    // The text's warnings: kept (moved with it) through a panel edit's step.
    if (editor_dirty()) diagnostics_ = rt::parse_scene(editor_, parse_options(path_)).diagnostics;
    else if (!follow) diagnostics_ = std::move(reparsed);
}

void Document::restore_object(std::size_t i, const rt::Object& o) {
    rt::Object& slot = scene_.objects[i];
    slot = o;
    // The step holds the model as it was when the step was made; a file read again
    // since (it changed on disk) is shown as it is now, as everywhere else.
    if (rt::Mesh* m = std::get_if<rt::Mesh>(&slot.shape); m && m->model && !m->model->unchanged_on_disk())
        if (rt::ModelStore::Loaded l = models_->load(m->model->path()); l.model) m->model = std::move(l.model);
    refresh_texture(slot.material);
}

void Document::restore_plane(std::size_t i, const rt::Plane& p) {
    rt::Plane& slot = scene_.planes[i];
    slot = p;
    refresh_texture(slot.material);
    refresh_texture(slot.material2);
}

bool Document::undo() { return take_step(false); }

bool Document::redo() { return take_step(true); }

bool Document::take_step(bool forward) {
    commit();
    flush_typing();
    const DocStep* s = forward ? history_.redo() : history_.undo();
    if (!s) return false;
    apply_step(*s, forward);
    last_step_name_ = s->name;
    return true;
}

std::vector<std::string> Document::undo_names(std::size_t max) const {
    std::vector<std::string> out;
    // As undo() goes: a held edit is committed first (after the typing before it).
    if (held_ && out.size() < max) out.push_back(held_name());
    if (typing_base_ && *typing_base_ != editor_ && out.size() < max) out.push_back(kTypingName);
    for (std::size_t k = 0; out.size() < max; ++k) {
        const DocStep* s = history_.peek_undo(k);
        if (!s) break;
        out.push_back(s->name);
    }
    return out;
}

std::vector<std::string> Document::redo_names(std::size_t max) const {
    // A held edit or typing becomes a step of its own, which ends the redo branch.
    if (held_ || (typing_base_ && *typing_base_ != editor_)) return {};
    std::vector<std::string> out;
    for (std::size_t k = 0; k < max; ++k) {
        const DocStep* s = history_.peek_redo(k);
        if (!s) break;
        out.push_back(s->name);
    }
    return out;
}

}  // namespace rtview
