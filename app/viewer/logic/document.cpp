// The viewer's document model (see document.h): undoable edits stored as what they
// changed, text write-back into single blocks, atomic saves and external changes.
#include "document.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include "block_patch.h"
#include "image_io.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "snapshots.h"

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

std::string base_name(const std::string& path) {
    std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

bool same_except_camera(const rt::Scene& a, const rt::Scene& b) {
    return a.objects == b.objects && a.planes == b.planes && a.lights == b.lights && a.width == b.width &&
           a.height == b.height;
}

// The one replacement that turns `a` into `b` (common prefix and suffix left out).
UndoableReplacement diff_texts(const std::string& a, const std::string& b) {
    std::size_t p = 0, n = std::min(a.size(), b.size());
    while (p < n && a[p] == b[p]) ++p;
    std::size_t s = 0;
    while (s < n - p && a[a.size() - 1 - s] == b[b.size() - 1 - s]) ++s;
    return {p, a.substr(p, a.size() - p - s), b.substr(p, b.size() - p - s)};
}

// Changed items of two equally long lists, as (index, value) pairs both ways.
template <class T>
bool diff_items(const std::vector<T>& a, const std::vector<T>& b, std::vector<std::pair<std::size_t, T>>& before,
                std::vector<std::pair<std::size_t, T>>& after, std::size_t limit) {
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i] == b[i]) continue;
        if (before.size() >= limit) return false;
        before.push_back({i, a[i]});
        after.push_back({i, b[i]});
    }
    return true;
}

// The layout after [pos, pos + old_len) of the text became new_len bytes long: spans
// after it move, the span that was it (if any) takes the new length.
void shift_layout(SceneLayout& l, std::size_t pos, std::size_t old_len, std::size_t new_len) {
    auto fix = [&](std::size_t& x) {
        if (x >= pos + old_len) x = x - old_len + new_len;
    };
    for (auto* v : {&l.objects, &l.planes, &l.lights, &l.cameras})
        for (TextSpan& t : *v) {
            if (t.begin == pos && t.end == pos + old_len) {
                t.end = pos + new_len;
                continue;
            }
            fix(t.begin);
            fix(t.end);
        }
    fix(l.append_at);
}

// The items of a pending edit that changed, as (index, value) pairs both ways. An item
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

// The items of (index, value) lists, as a delta.
template <class O, class P, class L>
rt::SceneDelta items_of(const O& objects, const P& planes, const L& lights) {
    rt::SceneDelta d;
    for (const auto& p : objects) d.objects.push_back(std::uint32_t(p.first));
    for (const auto& p : planes) d.planes.push_back(std::uint32_t(p.first));
    for (const auto& p : lights) d.lights.push_back(std::uint32_t(p.first));
    d.normalize();
    return d;
}

// The changes kept for changes_since(): a consumer further behind compiles anew.
constexpr std::size_t kMaxChanges = 256;

// Beyond this many changed items an undo step parses the text again instead.
constexpr std::size_t kMaxStepItems = 4096;

constexpr const char* kTypingName = "Typing in the scene text";

// "Edit object 3", "Edit the scene camera": a step named by what it changed.
std::string changed_name(std::size_t objects, std::size_t planes, std::size_t lights, bool camera, bool wide,
                         std::size_t first) {
    const std::size_t items = objects + planes + lights;
    if (wide || items > 1) return "Edit the scene";
    if (items == 0) return camera ? "Edit the scene camera" : "Edit the scene";
    const char* kind = objects ? "object " : planes ? "plane " : "light ";
    return std::string("Edit ") + kind + std::to_string(first + 1);
}

}  // namespace

std::size_t DocStep::bytes() const {
    std::size_t b = sizeof(DocStep) + name.size();
    for (const UndoableReplacement& s : editor) b += sizeof(UndoableReplacement) + s.before.size() + s.after.size();
    if (applied_before) b += applied_before->size();
    if (applied_after) b += applied_after->size();
    for (const auto& o : objects_before) b += object_bytes(o.second) + sizeof(std::size_t);
    for (const auto& o : objects_after) b += object_bytes(o.second) + sizeof(std::size_t);
    b += (planes_before.size() + planes_after.size()) * (sizeof(rt::Plane) + sizeof(std::size_t));
    b += (lights_before.size() + lights_after.size()) * (sizeof(rt::Light) + sizeof(std::size_t));
    return b;
}

Document::Document() { load_text("", "", "untitled"); }

void Document::load_text(const std::string& text, const std::string& path, const std::string& name) {
    load_parsed(text, rt::parse_scene(text, parse_options(path)), path, name);
}

void Document::load_parsed(std::string text, rt::ParseResult parsed, const std::string& path,
                           const std::string& name, std::optional<SceneLayout> layout,
                           std::optional<std::uint64_t> hash) {
    history_.clear();
    pending_ = false;
    saved_ = {};
    pending_name_.clear();
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
    if (has_scene_) file_camera_ = scene_.camera;
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
    // A pending edit changes its item every frame: one entry for all of them.
    if (!changes_.empty() && changes_.back().to == from && !delta.everything && !changes_.back().delta.everything &&
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
    std::uint64_t key = text_version_ * 0x9E3779B97F4A7C15ull + typed_;
    if (key != modified_key_) {
        modified_cache_ = editor_.size() != saved_size_ || text_hash(editor_) != saved_hash_;
        modified_key_ = key;
    }
    return modified_cache_;
}

std::string Document::title() const { return name_ + (modified() ? "*" : "") + " - raytracer-view"; }

std::string& Document::editor_text() {
    // The caller may type into it: from now on the applied text needs its own copy,
    // and the text as it is now is where the typing starts.
    if (!applied_) applied_ = editor_;
    if (!typing_base_) typing_base_ = editor_;
    ++typed_;
    return editor_;
}

void Document::flush_typing() {
    if (!typing_base_) return;
    std::string base = std::move(*typing_base_);
    typing_base_.reset();
    if (base == editor_) return;
    DocStep step;
    step.name = kTypingName;
    step.editor.push_back(diff_texts(base, editor_));
    step.keep_applied = true;
    step.has_scene_before = step.has_scene_after = has_scene_;
    step.behind_before = step.behind_after = behind_;
    record(std::move(step));
}

void Document::normalize_applied() {
    if (applied_ && has_scene_ && *applied_ == editor_) applied_.reset();
}

// ---------------------------------------------------------------------------------
// Panel edits

void Document::open_edit() {
    if (!pending_) {
        saved_ = {};
        pending_name_.clear();
        pending_ = true;
    }
    ++scene_version_;
}

void Document::name_edit(const std::string& name) {
    if (pending_ && pending_name_.empty()) pending_name_ = name;
}

std::string Document::pending_name() const {
    if (!pending_name_.empty()) return pending_name_;
    const std::size_t first = !saved_.objects.empty() ? saved_.objects[0].first
                              : !saved_.planes.empty() ? saved_.planes[0].first
                              : !saved_.lights.empty() ? saved_.lights[0].first
                                                       : 0;
    return changed_name(saved_.objects.size(), saved_.planes.size(), saved_.lights.size(), saved_.camera.has_value(),
                        saved_.whole.has_value(), first);
}

rt::Object& Document::edit_object(std::size_t i) {
    open_edit();
    rt::SceneDelta d;
    if (i < scene_.objects.size()) d.objects.push_back(std::uint32_t(i));
    changed(std::move(d));
    auto& v = saved_.objects;
    if (!saved_.whole && std::none_of(v.begin(), v.end(), [i](const auto& p) { return p.first == i; }))
        v.push_back({i, scene_.objects.at(i)});
    return scene_.objects.at(i);
}

rt::Plane& Document::edit_plane(std::size_t i) {
    open_edit();
    rt::SceneDelta d;
    if (i < scene_.planes.size()) d.planes.push_back(std::uint32_t(i));
    changed(std::move(d));
    auto& v = saved_.planes;
    if (!saved_.whole && std::none_of(v.begin(), v.end(), [i](const auto& p) { return p.first == i; }))
        v.push_back({i, scene_.planes.at(i)});
    return scene_.planes.at(i);
}

rt::Light& Document::edit_light(std::size_t i) {
    open_edit();
    rt::SceneDelta d;
    if (i < scene_.lights.size()) d.lights.push_back(std::uint32_t(i));
    changed(std::move(d));
    auto& v = saved_.lights;
    if (!saved_.whole && std::none_of(v.begin(), v.end(), [i](const auto& p) { return p.first == i; }))
        v.push_back({i, scene_.lights.at(i)});
    return scene_.lights.at(i);
}

rt::Camera& Document::edit_camera() {
    open_edit();
    if (!saved_.whole && !saved_.camera) saved_.camera = scene_.camera;
    return scene_.camera;
}

rt::Scene& Document::edit() {
    open_edit();
    changed(rt::SceneDelta::all());
    if (!saved_.whole) saved_.whole = scene_before_edit();
    return scene_;
}

rt::Scene Document::scene_before_edit() const {
    if (saved_.whole) return *saved_.whole;
    rt::Scene s = scene_;
    for (const auto& p : saved_.objects) s.objects[p.first] = p.second;
    for (const auto& p : saved_.planes) s.planes[p.first] = p.second;
    for (const auto& p : saved_.lights) s.lights[p.first] = p.second;
    if (saved_.camera) s.camera = *saved_.camera;
    return s;
}

void Document::cancel_edit() {
    if (!pending_) return;
    pending_ = false;
    scene_ = scene_before_edit();
    rt::SceneDelta d = saved_.whole ? rt::SceneDelta::all() : items_of(saved_.objects, saved_.planes, saved_.lights);
    saved_ = {};
    pending_name_.clear();
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
    if (!pending_) return;
    flush_typing();
    pending_ = false;
    DocStep step;
    step.name = std::move(pending_name_);
    pending_name_.clear();
    step.has_scene_before = step.has_scene_after = has_scene_;
    step.behind_before = behind_;
    bool wide = false;
    if (saved_.whole) {
        const rt::Scene& b = *saved_.whole;
        if (b.objects.size() != scene_.objects.size() || b.planes.size() != scene_.planes.size() ||
            b.lights.size() != scene_.lights.size() || b.width != scene_.width || b.height != scene_.height ||
            !diff_items(b.objects, scene_.objects, step.objects_before, step.objects_after, kMaxStepItems) ||
            !diff_items(b.planes, scene_.planes, step.planes_before, step.planes_after, kMaxStepItems) ||
            !diff_items(b.lights, scene_.lights, step.lights_before, step.lights_after, kMaxStepItems)) {
            wide = true;
        }
        if (!(b.camera == scene_.camera)) {
            step.camera_before = b.camera;
            step.camera_after = scene_.camera;
        }
        if (wide) {
            step.reparse = true;
            step.objects_before.clear(), step.objects_after.clear();
            step.planes_before.clear(), step.planes_after.clear();
            step.lights_before.clear(), step.lights_after.clear();
        }
    } else {
        diff_saved(saved_.objects, scene_.objects, step.objects_before, step.objects_after);
        diff_saved(saved_.planes, scene_.planes, step.planes_before, step.planes_after);
        diff_saved(saved_.lights, scene_.lights, step.lights_before, step.lights_after);
        if (saved_.camera && !(*saved_.camera == scene_.camera)) {
            step.camera_before = saved_.camera;
            step.camera_after = scene_.camera;
        } else if (saved_.camera) {
            scene_.camera = *saved_.camera;
        }
    }
    bool changed = wide || !step.objects_before.empty() || !step.planes_before.empty() || !step.lights_before.empty() ||
                   step.camera_before.has_value();
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
    if (!reads_back(step, wide)) {
        // Written as it is, the text would not parse: the edit does not happen.
        scene_ = scene_before_edit_from(step);
        saved_ = {};
        ++scene_version_;
        this->changed(rt::SceneDelta::all());
        refusal_ = "The edit was undone: the scene text cannot hold it (a number past the format's limit of "
                   "1e15, or a shape the format refuses)";
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

// Whether the items a step changed, written as the text will hold them, read back as
// they are: every number within the format's range, every shape one the parser takes
// (a drag far out, or a move's rounding of a tiny tetrahedron, could make either
// false). Only the changed items are written and read (all of them for a wide edit).
bool Document::reads_back(const DocStep& step, bool wide) const {
    rt::Scene changed;
    if (wide) {
        changed = scene_;
    } else {
        changed.camera = scene_.camera;
        for (const auto& p : step.objects_after) changed.objects.push_back(p.second);
        for (const auto& p : step.planes_after) changed.planes.push_back(p.second);
        for (const auto& p : step.lights_after) changed.lights.push_back(p.second);
    }
    return text_holds(changed);
}

// The fast path: no draft, so the editor text is the scene's text; each changed item's
// block is rewritten where it stands. Nothing else of the text is touched or parsed.
bool Document::commit_in_place(DocStep& step) {
    // The layout of the text is scanned once and then kept up to date through the
    // document's own replacements: an edit costs its block, not a pass over the text.
    const std::uint64_t key = layout_key();
    if (!layout_ || layout_key_ != key) {
        layout_ = scan_layout(editor_, has_scene_ ? scene_.objects.size() : 0);
        layout_key_ = key;
    }
    SceneLayout& l = *layout_;
    if (!l.ok || l.objects.size() != scene_.objects.size() || l.planes.size() != scene_.planes.size() ||
        l.lights.size() != scene_.lights.size())
        return false;
    struct Rep {
        TextSpan span;
        std::string text;
    };
    std::vector<Rep> reps;
    rt::Scene one;  // carries a valid camera so the writer prints a normal scene
    one.camera = scene_.camera;
    // An item's block keeps its comments and layout when only its changed values can
    // be replaced (block_patch.h); else the writer's block replaces it.
    auto add = [&](TextSpan span, ItemList kind, std::optional<std::string> patched = std::nullopt) {
        std::string t = patched ? std::move(*patched) : written_item(one, kind, line_indent(editor_, span.begin));
        if (t.empty()) return false;
        reps.push_back({span, std::move(t)});
        return true;
    };
    auto block = [&](TextSpan span) { return std::string_view(editor_).substr(span.begin, span.end - span.begin); };
    for (std::size_t k = 0; k < step.objects_after.size(); ++k) {
        const auto& p = step.objects_after[k];
        one.objects = {p.second};
        if (!add(l.objects[p.first], ItemList::Object, patch_block(block(l.objects[p.first]), step.objects_before[k].second, p.second)))
            return false;
    }
    one.objects.clear();
    for (std::size_t k = 0; k < step.planes_after.size(); ++k) {
        const auto& p = step.planes_after[k];
        one.planes = {p.second};
        if (!add(l.planes[p.first], ItemList::Plane, patch_block(block(l.planes[p.first]), step.planes_before[k].second, p.second)))
            return false;
    }
    one.planes.clear();
    for (std::size_t k = 0; k < step.lights_after.size(); ++k) {
        const auto& p = step.lights_after[k];
        one.lights = {p.second};
        if (!add(l.lights[p.first], ItemList::Light, patch_block(block(l.lights[p.first]), step.lights_before[k].second, p.second)))
            return false;
    }
    one.lights.clear();
    if (step.camera_after) {
        // Camera keys accumulate over all camera sections, so one complete block in
        // place of the last section gives exactly the new camera.
        if (!l.cameras.empty()) {
            if (!add(l.cameras.back(), ItemList::Camera)) return false;
        } else {
            std::string t = written_item(one, ItemList::Camera, "");
            if (t.empty()) return false;
            reps.push_back({{l.append_at, l.append_at}, t + "\n"});
        }
    }
    // Back to front, so every span still holds where the text was read.
    std::sort(reps.begin(), reps.end(), [](const Rep& a, const Rep& b) { return a.span.begin > b.span.begin; });
    for (Rep& r : reps) {
        UndoableReplacement s{r.span.begin, editor_.substr(r.span.begin, r.span.end - r.span.begin), std::move(r.text)};
        editor_.replace(s.pos, s.before.size(), s.after);
        shift_layout(l, s.pos, s.before.size(), s.after.size());
        step.editor.push_back(std::move(s));
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
    std::string new_applied = has_scene_ ? sync_scene_text(old_applied, before, scene_) : rt::write_scene(scene_);
    if (!applied_) {
        // No draft: the editor text is the applied text.
        UndoableReplacement s = diff_texts(editor_, new_applied);
        editor_ = std::move(new_applied);
        if (!s.before.empty() || !s.after.empty()) step.editor.push_back(std::move(s));
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
        if (complete) patched = patch_scene_text(editor_, draft.scene, target);
    }
    if (!patched) {
        scene_ = std::move(before);
        ++scene_version_;
        changed(saved_.whole ? rt::SceneDelta::all() : items_of(step.objects_before, step.planes_before, step.lights_before));
        return false;
    }
    UndoableReplacement s = diff_texts(editor_, *patched);
    editor_ = std::move(*patched);
    if (!s.before.empty() || !s.after.empty()) step.editor.push_back(std::move(s));
    step.applied_before = *applied_;
    applied_ = std::move(new_applied);
    normalize_applied();
    step.applied_after = applied_;
    return true;
}

std::string Document::edit_blocker() const {
    if (!applied_ || !has_scene_) return {};
    const std::uint64_t key = text_version_ * 0x9E3779B97F4A7C15ull + typed_;
    if (key != blocker_key_) {
        blocker_key_ = key;
        blocker_.clear();
        if (*applied_ != editor_) {
            const rt::ParseResult draft = rt::parse_scene(editor_, parse_options(path_));
            if (!draft.ok())
                blocker_ = "The scene text has unapplied changes with errors: fix them (Ctrl+Enter applies) "
                           "or revert them before editing here";
        }
    }
    return blocker_;
}

std::optional<std::string> Document::save_problem() const {
    if (has_scene_ && !applied_ && !behind_) return std::nullopt;  // the text is the scene's own
    if (has_scene_ && applied_ && *applied_ == editor_ && !behind_) return std::nullopt;
    const rt::ParseResult r = rt::parse_scene(editor_, parse_options(path_));
    for (const rt::Diagnostic& d : r.diagnostics)
        if (d.is_error())
            return "line " + std::to_string(d.line) + ":" + std::to_string(d.col) + ": " + d.message;
    return std::nullopt;
}

bool Document::apply_parsing_draft() {
    if (!applied_ || *applied_ == editor_ || !rt::parse_scene(editor_, parse_options(path_)).ok()) return false;
    return apply_text();
}

std::string Document::take_refusal() {
    std::string r = std::move(refusal_);
    refusal_.clear();
    return r;
}

rt::Scene Document::scene_before_edit_from(const DocStep& step) const {
    if (saved_.whole) return *saved_.whole;
    rt::Scene s = scene_;
    for (const auto& p : step.objects_before) s.objects[p.first] = p.second;
    for (const auto& p : step.planes_before) s.planes[p.first] = p.second;
    for (const auto& p : step.lights_before) s.lights[p.first] = p.second;
    if (step.camera_before) s.camera = *step.camera_before;
    return s;
}

void Document::text_changed(const DocStep& s, bool forward) {
    ++text_version_;
    std::vector<TextChange> changes;
    if (forward) {
        for (const UndoableReplacement& t : s.editor) changes.push_back({t.pos, t.before.size(), t.after});
    } else {
        for (auto it = s.editor.rbegin(); it != s.editor.rend(); ++it)
            changes.push_back({it->pos, it->after.size(), it->before});
    }
    // What a version's changes hold, as the log counts it in and out.
    auto bytes_of = [](const std::vector<TextChange>& v) {
        std::size_t n = 0;
        for (const TextChange& c : v) n += c.inserted.size() + sizeof(TextChange);
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

bool Document::text_changes_since(std::uint64_t version, std::vector<TextChange>& out) const {
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

// ---------------------------------------------------------------------------------
// Whole-text changes

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
        step.editor.push_back(diff_texts(editor_, *editor));
        editor_ = *editor;
    }
    step.has_scene_before = has_scene_;
    step.behind_before = behind_;
    bool content_changed = false, scene_changed = false;
    if (scene) {
        bool same_counts = has_scene_ && scene->objects.size() == scene_.objects.size() &&
                           scene->planes.size() == scene_.planes.size() &&
                           scene->lights.size() == scene_.lights.size() && scene->width == scene_.width &&
                           scene->height == scene_.height;
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
    // A typing step leaves the applied text alone: it is the editor text as it is
    // before the step when they are one and the same now.
    if (s.keep_applied && !applied_) applied_ = editor_;
    if (forward) {
        for (const UndoableReplacement& t : s.editor) editor_.replace(t.pos, t.before.size(), t.after);
    } else {
        for (auto it = s.editor.rbegin(); it != s.editor.rend(); ++it) editor_.replace(it->pos, it->after.size(), it->before);
    }
    if (!s.keep_applied) applied_ = forward ? s.applied_after : s.applied_before;
    else normalize_applied();
    has_scene_ = forward ? s.has_scene_after : s.has_scene_before;
    if (s.reparse) {
        if (has_scene_) {
            rt::ParseResult r = rt::parse_scene(applied_text(), parse_options(path_));
            scene_ = std::move(r.scene);
        }
    } else {
        for (const auto& p : forward ? s.objects_after : s.objects_before) restore_object(p.first, p.second);
        for (const auto& p : forward ? s.planes_after : s.planes_before) scene_.planes[p.first] = p.second;
        for (const auto& p : forward ? s.lights_after : s.lights_before) scene_.lights[p.first] = p.second;
    }
    if (s.camera_before) scene_.camera = forward ? *s.camera_after : *s.camera_before;
    behind_ = forward ? s.behind_after : s.behind_before;
    ++scene_version_;
    if (s.reparse || s.has_scene_before != s.has_scene_after)
        changed(rt::SceneDelta::all());
    else if (!s.objects_before.empty() || !s.planes_before.empty() || !s.lights_before.empty())
        changed(items_of(s.objects_before, s.planes_before, s.lights_before));
    if (!s.editor.empty() || s.applied_before != s.applied_after) text_changed(s, forward);
    typing_base_.reset();
    diagnostics_ = editor_dirty() ? rt::parse_scene(editor_, parse_options(path_)).diagnostics : std::vector<rt::Diagnostic>{};
}

void Document::restore_object(std::size_t i, const rt::Object& o) {
    rt::Object& slot = scene_.objects[i];
    slot = o;
    // The step holds the model as it was when the step was made; a file read again
    // since (it changed on disk) is shown as it is now, as everywhere else.
    if (rt::Mesh* m = std::get_if<rt::Mesh>(&slot.shape); m && m->model && !m->model->unchanged_on_disk())
        if (rt::ModelStore::Loaded l = models_->load(m->model->path()); l.model) m->model = std::move(l.model);
}

bool Document::has_errors() const {
    for (const auto& d : diagnostics_)
        if (d.is_error()) return true;
    return false;
}

bool Document::apply_text() {
    commit();
    flush_typing();
    rt::ParseResult r = rt::parse_scene(editor_, parse_options(path_));
    diagnostics_ = r.diagnostics;
    if (!r.ok()) return false;
    normalize_applied();
    if (has_scene_ && !applied_ && !behind_ && r.scene == scene_) return true;
    replace_state(nullptr, std::nullopt, std::move(r.scene), false, "Apply the scene text");
    return true;
}

bool Document::replace_text(std::size_t pos, std::size_t length, const std::string& text, const std::string& name) {
    // The replacement was planned on the text and the scene as they are now; a held
    // edit (a drag) would rewrite the text when committed, and the replacement would
    // land on the wrong bytes.
    if (pending_) return false;
    flush_typing();  // text typed since the last step is a step of its own, first
    normalize_applied();
    if (applied_ || behind_ || pos > editor_.size() || length > editor_.size() - pos) return false;
    std::string edited = editor_;
    edited.replace(pos, length, text);
    rt::ParseResult r = rt::parse_scene(edited, parse_options(path_));
    if (!r.ok()) return false;
    diagnostics_ = r.diagnostics;
    replace_state(&edited, std::nullopt, std::move(r.scene), false, name);
    return true;
}

void Document::check_text() { diagnostics_ = rt::parse_scene(editor_, parse_options(path_)).diagnostics; }

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

bool Document::undo() {
    commit();
    flush_typing();
    const DocStep* s = history_.undo();
    if (!s) return false;
    apply_step(*s, false);
    last_step_name_ = s->name;
    return true;
}

bool Document::redo() {
    commit();
    flush_typing();
    const DocStep* s = history_.redo();
    if (!s) return false;
    apply_step(*s, true);
    last_step_name_ = s->name;
    return true;
}

std::vector<std::string> Document::undo_names(std::size_t max) const {
    std::vector<std::string> out;
    // As undo() goes: a pending edit is committed first (after the typing before it).
    if (pending_ && out.size() < max) out.push_back(pending_name());
    if (typing_base_ && *typing_base_ != editor_ && out.size() < max) out.push_back(kTypingName);
    for (std::size_t k = 0; out.size() < max; ++k) {
        const DocStep* s = history_.peek_undo(k);
        if (!s) break;
        out.push_back(s->name);
    }
    return out;
}

std::vector<std::string> Document::redo_names(std::size_t max) const {
    // A pending edit or typing becomes a step of its own, which ends the redo branch.
    if (pending_ || (typing_base_ && *typing_base_ != editor_)) return {};
    std::vector<std::string> out;
    for (std::size_t k = 0; k < max; ++k) {
        const DocStep* s = history_.peek_redo(k);
        if (!s) break;
        out.push_back(s->name);
    }
    return out;
}

Document::HeldItems Document::held_items() const {
    HeldItems h;
    if (!pending_) return h;
    h.whole = saved_.whole.has_value();
    for (const auto& p : saved_.objects) h.objects.push_back(p.first);
    for (const auto& p : saved_.planes) h.planes.push_back(p.first);
    for (const auto& p : saved_.lights) h.lights.push_back(p.first);
    h.camera = saved_.camera.has_value();
    return h;
}

// ---------------------------------------------------------------------------------
// Saving and the file on disk

void Document::mark_saved(std::optional<std::uint64_t> hash) {
    saved_hash_ = hash ? *hash : text_hash(editor_);
    saved_size_ = editor_.size();
    // The text is the saved one now: no need to hash it again to know that.
    modified_key_ = text_version_ * 0x9E3779B97F4A7C15ull + typed_;
    modified_cache_ = false;
    // Revert of a text that never parsed goes back to the file: keep it (such files
    // are small; a scene that parses is not kept twice).
    saved_broken_text_ = has_scene_ ? std::string() : editor_;
    // No second parse of the saved text: it is the text of the current scene whenever
    // that has no unapplied draft.
    if (has_scene_ && !editor_dirty()) file_camera_ = scene_.camera;
    stamp_ = FileStamp::of(path_);
    conflict_ = false;
}

rt::Status Document::save() {
    commit();
    if (path_.empty()) return rt::Status::error("the scene has no file name yet: use Save As", rt::kExitUsage);
    // No name until the file is complete: a viewer killed while saving (SIGKILL: no
    // handler runs) leaves no partial file behind.
    if (rt::Status st = rt::write_file_atomic(path_, editor_, rt::WhileWriting::NoName); !st) return st;
    mark_saved();
    return {};
}

rt::Status Document::save_as(const std::string& path) {
    commit();
    if (path.empty()) return rt::Status::error("no file name given", rt::kExitUsage);
    if (rt::Status st = rt::write_file_atomic(path, editor_, rt::WhileWriting::NoName); !st) return st;
    path_ = path;
    name_ = base_name(path);
    mark_saved();
    return {};
}

void Document::reload_text(const std::string& text) {
    flush_typing();
    rt::ParseResult r = rt::parse_scene(text, parse_options(path_));
    diagnostics_ = r.diagnostics;
    if (r.ok()) {
        replace_state(&text, std::nullopt, std::move(r.scene), false, "Reload from disk");
    } else {
        // Show the new text with its errors; the last good scene keeps rendering.
        std::string applied = has_scene_ ? applied_text() : std::string();
        replace_state(&text, std::move(applied), std::nullopt, behind_, "Reload from disk");
    }
    mark_saved();
}

rt::ParseOptions Document::parse_options(const std::string& path) const {
    rt::ParseOptions o;
    o.base_dir = rt::folder_of(path);  // mesh files are named from the scene's folder
    o.models = models_.get();
    return o;
}

bool Document::reload_models() {
    if (!has_scene_ || pending_ || editor_dirty() || behind_) return false;
    // The scene's models, looked for once per scene version (a pass over every object:
    // 9 ms in a 1M-object scene, too much for every second).
    if (scene_models_version_ != scene_version_) {
        scene_models_.clear();
        for (const rt::Object& o : scene_.objects)
            if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape); m && m->model)
                if (std::find(scene_models_.begin(), scene_models_.end(), m->model) == scene_models_.end())
                    scene_models_.push_back(m->model);
        scene_models_version_ = scene_version_;
    }
    bool changed = false;
    for (const auto& m : scene_models_) changed = changed || !m->unchanged_on_disk();
    if (!changed) return false;
    // The text is the same: only the scene's models are new (no undo step). A model
    // that no longer reads leaves the scene as it was, and is said once.
    rt::ParseResult r = rt::parse_scene(editor_, parse_options(path_));
    if (!r.ok()) {
        std::string why;
        for (const rt::Diagnostic& d : r.diagnostics)
            if (d.is_error() && why.empty()) why = "line " + std::to_string(d.line) + ": " + d.message;
        if (why == model_problem_) return false;
        model_problem_ = why;
        return true;
    }
    model_problem_.clear();
    scene_.objects = std::move(r.scene.objects);
    ++scene_version_;
    this->changed(rt::SceneDelta::all());  // a model's triangles: the world is compiled anew
    return true;
}

Document::DiskEvent Document::check_disk() {
    if (reload_models()) return model_problem_.empty() ? DiskEvent::ModelsReloaded : DiskEvent::ModelUnreadable;
    if (path_.empty() || pending_) return DiskEvent::None;  // not in the middle of a gesture
    FileStamp st = FileStamp::of(path_);
    if (st == stamp_) return DiskEvent::None;
    stamp_ = st;
    if (!st.exists) return DiskEvent::Removed;
    std::string text;
    if (!rt::read_file(path_, text, rt::Limits::max_file_size).ok()) return DiskEvent::None;
    if (text.size() == saved_size_ && text_hash(text) == saved_hash_) return DiskEvent::None;  // touched, or our own save
    if (!modified()) {
        reload_text(text);
        return DiskEvent::Reloaded;
    }
    conflict_ = true;
    conflict_text_ = std::move(text);
    return DiskEvent::Conflict;
}

void Document::resolve_conflict_reload() {
    if (!conflict_) return;
    conflict_ = false;
    std::string text = std::move(conflict_text_);
    conflict_text_.clear();
    reload_text(text);
}

void Document::resolve_conflict_keep() {
    conflict_ = false;
    conflict_text_.clear();
}

}  // namespace rtview
