// The document's held edit (see document.h): a panel or handle edit changes the scene
// on every frame; its commit writes the text once and makes one undo step.
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

// A delta of item `i` of one of the scene's lists (`list`, `size` long): empty when `i`
// is past the end.
rt::SceneDelta one_item(std::vector<std::uint32_t> rt::SceneDelta::*list, std::size_t i, std::size_t size) {
    rt::SceneDelta d;
    if (i < size) (d.*list).push_back(std::uint32_t(i));
    return d;
}

// `s` with the items as they were before an edit put back, each (index, item).
template <class Objects, class Planes, class Lights, class Materials, class Defined>
rt::Scene put_back(rt::Scene s, const Objects& objects, const Planes& planes, const Lights& lights,
                   const Materials& materials, const Defined& defined, const std::optional<rt::Camera>& camera) {
    auto back = [](auto& items, const auto& before) {
        for (const auto& p : before) items[p.first] = p.second;
    };
    back(s.objects, objects);
    back(s.planes, planes);
    back(s.lights, lights);
    back(s.materials, materials);
    back(s.defined, defined);
    if (camera) s.camera = *camera;
    return s;
}

// Item `i` of `items`, kept in `saved` as it is now the first time the held edit touches
// it (unless the edit keeps the whole scene).
template <class T>
T& keep_first(std::vector<std::pair<std::size_t, T>>& saved, std::vector<T>& items, std::size_t i, bool whole) {
    if (!whole && std::none_of(saved.begin(), saved.end(), [i](const auto& p) { return p.first == i; }))
        saved.push_back({i, items.at(i)});
    return items.at(i);
}

// The layout after [pos, pos + old_len) of the text became new_len bytes long: spans
// after it move, the span that was it (if any) takes the new length.
void shift_layout(SceneLayout& l, std::size_t pos, std::size_t old_len, std::size_t new_len) {
    auto fix = [&](std::size_t& x) {
        if (x >= pos + old_len) x = x - old_len + new_len;
    };
    // A replacement of the same length moves nothing (a group move's numbers of the same
    // width: no pass over a million spans per item).
    if (old_len == new_len) return;
    for (auto* v : {&l.objects, &l.planes, &l.lights, &l.cameras})
        // (Spans are in order and apart: those ending before pos stay.)
        for (auto it = std::partition_point(v->begin(), v->end(), [&](const TextSpan& t) { return t.end < pos; });
             it != v->end(); ++it) {
            TextSpan& t = *it;
            if (t.begin == pos && t.end == pos + old_len) {
                t.end = pos + new_len;
                continue;
            }
            fix(t.begin);
            fix(t.end);
        }
    fix(l.append_at);
}

// The items of a held edit that changed, as (index, value) pairs both ways. An item
// that came back to its value (or to -0 where it had 0: equal, but not what its text
// reads) takes its value from before again, as the text holds it.
template <class T>
void diff_saved(const std::vector<std::pair<std::size_t, T>>& saved, std::vector<T>& now,
                std::vector<std::pair<std::size_t, T>>& before, std::vector<std::pair<std::size_t, T>>& after) {
    for (const auto& p : saved) {
        if (p.second == now[p.first]) {
            now[p.first] = p.second;
            continue;
        }
        before.push_back(p);
        after.push_back({p.first, now[p.first]});
    }
}

// "Edit object 3", "Edit the scene camera": a step named by what it changed.
std::string changed_name(std::size_t objects, std::size_t planes, std::size_t lights, bool camera, bool wide,
                         std::size_t first) {
    const std::size_t items = objects + planes + lights;
    if (wide || items > 1) return "Edit the scene";
    if (items == 0) return camera ? "Edit the scene camera" : "Edit the scene";
    const char* kind = objects ? "object " : planes ? "plane " : "light ";
    return std::string("Edit ") + kind + std::to_string(first + 1);
}

// What an edit held over the whole scene changed, from `b` to `now`, into `step`'s
// items and camera; true (and no items) when it is wide: the lists' lengths, the size,
// the named materials or definitions changed, or too many items did (`step` is
// re-read from the text then).
bool diff_whole(const rt::Scene& b, const rt::Scene& now, DocStep& step) {
    const bool wide =
        b.objects.size() != now.objects.size() || b.planes.size() != now.planes.size() ||
        b.lights.size() != now.lights.size() || b.width != now.width || b.height != now.height ||
        !(b.materials == now.materials) || !(b.defined == now.defined) ||
        !diff_items(b.objects, now.objects, step.objects_before, step.objects_after, kMaxStepItems) ||
        !diff_items(b.planes, now.planes, step.planes_before, step.planes_after, kMaxStepItems) ||
        !diff_items(b.lights, now.lights, step.lights_before, step.lights_after, kMaxStepItems);
    if (!(b.camera == now.camera)) {
        step.camera_before = b.camera;
        step.camera_after = now.camera;
    }
    if (wide) {
        step.reparse = true;
        step.objects_before.clear(), step.objects_after.clear();
        step.planes_before.clear(), step.planes_after.clear();
        step.lights_before.clear(), step.lights_after.clear();
    }
    return wide;
}

}  // namespace

void Document::hold_edit() {
    if (!held_) {
        saved_ = {};
        held_name_.clear();
        held_ = true;
    }
    ++scene_version_;
}

void Document::name_edit(const std::string& name) {
    if (held_ && held_name_.empty()) held_name_ = name;
}

std::string Document::held_name() const {
    if (!held_name_.empty()) return held_name_;
    const std::size_t first = !saved_.objects.empty() ? saved_.objects[0].first
                              : !saved_.planes.empty() ? saved_.planes[0].first
                              : !saved_.lights.empty() ? saved_.lights[0].first
                                                       : 0;
    return changed_name(saved_.objects.size(), saved_.planes.size(), saved_.lights.size(), saved_.camera.has_value(),
                        saved_.whole.has_value(), first);
}

rt::Object& Document::edit_object(std::size_t i) {
    hold_edit();
    changed(one_item(&rt::SceneDelta::objects, i, scene_.objects.size()));
    return keep_first(saved_.objects, scene_.objects, i, saved_.whole.has_value());
}

rt::Plane& Document::edit_plane(std::size_t i) {
    hold_edit();
    changed(one_item(&rt::SceneDelta::planes, i, scene_.planes.size()));
    return keep_first(saved_.planes, scene_.planes, i, saved_.whole.has_value());
}

rt::Light& Document::edit_light(std::size_t i) {
    hold_edit();
    changed(one_item(&rt::SceneDelta::lights, i, scene_.lights.size()));
    return keep_first(saved_.lights, scene_.lights, i, saved_.whole.has_value());
}

rt::Camera& Document::edit_camera() {
    hold_edit();
    if (!saved_.whole && !saved_.camera) saved_.camera = scene_.camera;
    return scene_.camera;
}

rt::Scene& Document::edit() {
    hold_edit();
    changed(rt::SceneDelta::all());
    if (!saved_.whole) saved_.whole = scene_before_edit();
    return scene_;
}

rt::Scene Document::scene_before_edit() const {
    if (saved_.whole) return *saved_.whole;
    return put_back(scene_, saved_.objects, saved_.planes, saved_.lights, saved_.materials, saved_.defined,
                    saved_.camera);
}

void Document::cancel_edit() {
    if (!held_) return;
    held_ = false;
    scene_ = scene_before_edit();
    rt::SceneDelta d = saved_.whole ? rt::SceneDelta::all() : items_of(saved_.objects, saved_.planes, saved_.lights);
    saved_ = {};
    held_name_.clear();
    ++scene_version_;
    changed(std::move(d));
}

bool Document::set_camera(const rt::Camera& camera) {
    if (!has_scene_ || camera == scene_.camera) return false;
    commit();
    edit_camera() = camera;
    name_edit("Set the scene camera from the view");
    commit();
    return true;
}

void Document::commit() {
    if (!held_) return;
    flush_typing();
    held_ = false;
    DocStep step;
    step.name = std::move(held_name_);
    held_name_.clear();
    step.has_scene_before = step.has_scene_after = has_scene_;
    step.behind_before = behind_;
    bool wide = false;
    if (saved_.whole) {
        wide = diff_whole(*saved_.whole, scene_, step);
    } else {
        diff_saved(saved_.objects, scene_.objects, step.objects_before, step.objects_after);
        diff_saved(saved_.planes, scene_.planes, step.planes_before, step.planes_after);
        diff_saved(saved_.lights, scene_.lights, step.lights_before, step.lights_after);
        diff_saved(saved_.materials, scene_.materials, step.materials_before, step.materials_after);
        diff_saved(saved_.defined, scene_.defined, step.defined_before, step.defined_after);
        if (saved_.camera && !(*saved_.camera == scene_.camera)) {
            step.camera_before = saved_.camera;
            step.camera_after = scene_.camera;
        } else if (saved_.camera) {
            scene_.camera = *saved_.camera;
        }
    }
    bool changed = wide || !step.objects_before.empty() || !step.planes_before.empty() || !step.lights_before.empty() ||
                   step.camera_before.has_value() || !step.materials_before.empty();
    if (!changed) {
        saved_ = {};
        return;
    }
    if (step.name.empty()) {
        const std::size_t first = !step.objects_after.empty() ? step.objects_after[0].first
                                  : !step.planes_after.empty() ? step.planes_after[0].first
                                  : !step.lights_after.empty() ? step.lights_after[0].first
                                                               : 0;
        step.name = changed_name(step.objects_after.size(), step.planes_after.size(), step.lights_after.size(),
                                 step.camera_before.has_value(), wide, first);
    }
    // An item an include brought is not in this file's text (Save could not keep the
    // edit); written as it is, the text would not parse: the edit does not happen.
    std::string why = included_edit(step, wide);
    if (why.empty() && !reads_back(step, wide))
        why = "the scene text cannot hold it (a number past the format's limit of 1e15, or a shape the format "
              "refuses)";
    if (!why.empty()) {
        scene_ = scene_before_edit_from(step);
        saved_ = {};
        ++scene_version_;
        this->changed(rt::SceneDelta::all());
        refusal_ = "The edit was undone: " + why;
        return;
    }
    normalize_applied();
    if ((applied_ || wide || !commit_in_place(step)) && !commit_generic(step)) {
        saved_ = {};
        refusal_ = "The edit was undone: it cannot be written into the scene text's unapplied changes "
                   "(apply or revert them first)";
        return;
    }
    saved_ = {};
    step.behind_after = behind_;
    if (!step.editor.empty()) text_changed(step, true);
    record(std::move(step));
}

namespace {

// The items of `v` read from included files, in order.
template <class T>
std::vector<const T*> included_items(const std::vector<T>& v) {
    std::vector<const T*> out;
    for (const T& x : v)
        if (x.origin != 0) out.push_back(&x);
    return out;
}

template <class T>
bool same_included(const std::vector<T>& a, const std::vector<T>& b) {
    const std::vector<const T*> x = included_items(a), y = included_items(b);
    if (x.size() != y.size()) return false;
    for (std::size_t k = 0; k < x.size(); ++k)
        if (!(*x[k] == *y[k]) || x[k]->origin != y[k]->origin) return false;
    return true;
}

}  // namespace

std::string Document::included_edit(const DocStep& step, bool wide) const {
    if (scene_.includes.empty()) return {};
    auto said = [this](const char* what, std::size_t i, ItemList list) {
        const rt::Include* inc = included_file(scene_, list, i);
        return std::string(what) + " " + std::to_string(i + 1) + " comes from the included file \"" +
               (inc ? inc->file : std::string("?")) + "\": open that file to edit it";
    };
    if (wide) {
        const rt::Scene& b = *saved_.whole;
        if (!same_included(b.objects, scene_.objects) || !same_included(b.planes, scene_.planes) ||
            !same_included(b.lights, scene_.lights))
            return "it changes items that come from included files: open those files to edit them";
        return {};
    }
    for (const auto& p : step.objects_before)
        if (p.second.origin != 0) return said("object", p.first, ItemList::Object);
    for (const auto& p : step.planes_before)
        if (p.second.origin != 0) return said("plane", p.first, ItemList::Plane);
    for (const auto& p : step.lights_before)
        if (p.second.origin != 0) return said("light", p.first, ItemList::Light);
    for (const auto& p : step.materials_before)
        if (p.second.origin != 0) return "material " + p.second.name + " comes from an included file: open that file to edit it";
    return {};
}

// Whether the items a step changed, written as the text will hold them, read back as
// they are: every number within the format's range, every shape one the parser takes
// (a drag far out, or a move's rounding of a tiny tetrahedron, could make either
// false). Only the changed items are written and read (all of them for a wide edit).
bool Document::reads_back(const DocStep& step, bool wide) const {
    rt::Scene changed;
    if (wide) {
        changed = scene_;
    } else {
        changed = item_scene(scene_);
        for (const auto& p : step.objects_after) changed.objects.push_back(p.second);
        for (const auto& p : step.planes_after) changed.planes.push_back(p.second);
        for (const auto& p : step.lights_after) changed.lights.push_back(p.second);
    }
    return text_holds(changed);
}

// The fast path: no draft, so the editor text is the scene's text; each changed item's
// block is rewritten where it stands. Nothing else of the text is touched or parsed.
bool Document::commit_in_place(DocStep& step) {
    // A named material's definition is rewritten by patch_scene_text (commit_generic).
    if (!step.materials_before.empty()) return false;
    // The layout of the text is scanned once and then kept up to date through the
    // document's own replacements: an edit costs its block, not a pass over the text.
    const std::uint64_t key = layout_key();
    if (!layout_ || layout_key_ != key) {
        layout_ = scan_layout(editor_, has_scene_ ? scene_.objects.size() : 0);
        layout_key_ = key;
    }
    SceneLayout& l = *layout_;
    // The text's blocks are the scene file's own items (those of included files are not
    // in it): an item's block is found by its place among them.
    if (!layout_matches(l, scene_)) return false;
    auto span_of = [&](ItemList kind, std::size_t i) -> std::optional<TextSpan> {
        const std::optional<std::size_t> own = own_index(scene_, kind, i);
        const std::vector<TextSpan>& v = kind == ItemList::Object ? l.objects : kind == ItemList::Plane ? l.planes : l.lights;
        if (!own || *own >= v.size()) return std::nullopt;
        return v[*own];
    };
    std::vector<TextReplacement> reps;
    std::vector<std::pair<std::size_t, rt::SourceLoc>> at;  // where a block starts: its item's place
    rt::Scene one = item_scene(scene_);  // a valid camera, the named materials: as the text has them
    // An item's block keeps its comments and layout when only its changed values can
    // be replaced (block_patch.h); else the writer's block replaces it.
    auto add = [&](TextSpan span, ItemList kind, std::optional<std::string> patched = std::nullopt,
                   rt::SourceLoc loc = {}) {
        std::string t = patched ? std::move(*patched) : written_item(one, kind, line_indent(editor_, span.begin));
        if (t.empty()) return false;
        reps.push_back({span.begin, span.end - span.begin, std::move(t)});
        at.push_back({span.begin, loc});
        return true;
    };
    auto block = [&](TextSpan span) { return std::string_view(editor_).substr(span.begin, span.end - span.begin); };
    // Each changed item's block, written with `one` holding just that item.
    auto items = [&](const auto& after, const auto& before, auto& list, ItemList kind) {
        for (std::size_t k = 0; k < after.size(); ++k) {
            const auto& p = after[k];
            list = {p.second};
            const std::optional<TextSpan> span = span_of(kind, p.first);
            if (!span ||
                !add(*span, kind, patch_block(block(*span), before[k].second, p.second), before[k].second.loc))
                return false;
        }
        list.clear();
        return true;
    };
    if (!items(step.objects_after, step.objects_before, one.objects, ItemList::Object) ||
        !items(step.planes_after, step.planes_before, one.planes, ItemList::Plane) ||
        !items(step.lights_after, step.lights_before, one.lights, ItemList::Light))
        return false;
    if (step.camera_after) {
        // Camera keys accumulate over all camera sections, so one complete block in
        // place of the last section gives exactly the new camera.
        if (!l.cameras.empty()) {
            if (!add(l.cameras.back(), ItemList::Camera)) return false;
        } else {
            std::string t = written_item(one, ItemList::Camera, "");
            if (t.empty()) return false;
            reps.push_back({l.append_at, 0, t + "\n"});
        }
    }
    // Back to front, so every span still holds where the text was read.
    std::sort(reps.begin(), reps.end(),
              [](const TextReplacement& a, const TextReplacement& b) { return a.offset > b.offset; });
    for (TextReplacement& r : reps) {
        shift_layout(l, r.offset, r.length, r.text.size());
        const std::size_t pos = r.offset;
        step.editor_back.push_back(r.apply(editor_));
        step.editor.push_back(std::move(r));
        const auto a = std::find_if(at.begin(), at.end(), [pos](const auto& x) { return x.first == pos; });
        step.editor_at.push_back(follow_positions(pos, step.editor_back.back().text, step.editor.back().text,
                                                  a == at.end() ? nullptr : &a->second));
    }
    // The text changes its version below: the layout stays valid for the new one.
    layout_key_ = layout_key(1);
    return true;
}

// Drafts and wide edits: the text is synchronised the careful way (this copies the
// scene once; panels do not come here for documents without a draft). False, with
// the edit undone, when there is a draft the edit cannot be written into in full.
bool Document::commit_generic(DocStep& step) {
    rt::Scene before = scene_before_edit_from(step);
    const std::string old_applied = applied_text();
    const rt::ParseOptions options = parse_options(path_);
    std::string new_applied = has_scene_ ? sync_scene_text(old_applied, before, scene_, &options) : rt::write_scene(scene_);
    if (!applied_) {
        // No draft: the editor text is the applied text.
        step.made(diff_texts(editor_, new_applied), editor_);
        editor_ = std::move(new_applied);
        for (std::size_t k = 0; k < step.editor.size(); ++k)
            step.editor_at.push_back(follow_positions(step.editor[k].offset, step.editor_back[k].text, step.editor[k].text));
        return true;
    }
    // The user has an unapplied draft: carry the edit into it only where that is
    // unambiguous (the draft parses and has the same items); never overwrite it. An
    // edit that cannot be carried is not made: the text the user saves and the scene
    // the panels show would disagree.
    rt::ParseResult draft = rt::parse_scene(editor_, parse_options(path_));
    std::optional<std::string> patched;
    if (draft.ok()) {
        bool complete = false;
        rt::Scene target = carry_edit(draft.scene, before, scene_, &complete);
        if (complete) patched = patch_scene_text(editor_, draft.scene, target, &options);
    }
    if (!patched) {
        scene_ = std::move(before);
        ++scene_version_;
        changed(saved_.whole ? rt::SceneDelta::all() : items_of(step.objects_before, step.planes_before, step.lights_before));
        return false;
    }
    step.made(diff_texts(editor_, *patched), editor_);
    editor_ = std::move(*patched);
    step.applied_before = *applied_;
    applied_ = std::move(new_applied);
    normalize_applied();
    step.applied_after = applied_;
    return true;
}

std::string Document::edit_blocker() const {
    if (!applied_ || !has_scene_) return {};
    const std::uint64_t key = text_key();
    if (key != blocker_key_) {
        blocker_key_ = key;
        blocker_.clear();
        blocker_pending_ = false;
        if (*applied_ == editor_) {
            // (No draft: edits go into the text of the scene.)
        } else if (editor_.size() >= kSyncParseBytes) {
            blocker_pending_ = true;
            blocker_ = "The scene text's unapplied changes are being checked: a moment";
        } else {
            take_blocker(key, rt::parse_scene(editor_, parse_options(path_)).ok());
        }
    }
    return blocker_;
}

void Document::take_blocker(std::uint64_t key, bool parses) const {
    if (key != blocker_key_) return;
    blocker_pending_ = false;
    blocker_ = parses ? std::string()
                      : "The scene text has unapplied changes with errors: fix them (Ctrl+Enter applies) "
                        "or revert them before editing here";
}

std::string Document::take_refusal() {
    std::string r = std::move(refusal_);
    refusal_.clear();
    return r;
}

rt::Scene Document::scene_before_edit_from(const DocStep& step) const {
    if (saved_.whole) return *saved_.whole;
    return put_back(scene_, step.objects_before, step.planes_before, step.lights_before, step.materials_before,
                    step.defined_before, step.camera_before);
}

HeldEdit Document::held_edit() const {
    HeldEdit h;
    if (!held_ || saved_.whole || !has_scene_) return h;
    for (const auto& p : saved_.objects) {
        h.objects.push_back(p.first);
        h.items.objects.push_back(scene_.objects[p.first]);
    }
    for (const auto& p : saved_.planes) {
        h.planes.push_back(p.first);
        h.items.planes.push_back(scene_.planes[p.first]);
    }
    for (const auto& p : saved_.lights) {
        h.lights.push_back(p.first);
        h.items.lights.push_back(scene_.lights[p.first]);
    }
    h.camera = saved_.camera.has_value();
    if (h.empty()) return {};
    h.items.camera = scene_.camera;
    return h;
}

}  // namespace rtview
