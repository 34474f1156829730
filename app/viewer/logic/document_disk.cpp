// The document and its file (see document.h): saving, noticing changes other
// programs make, reloading the text or the models it names.
#include "document.h"

#include <algorithm>
#include <array>
#include <unordered_set>
#include <utility>

#include "block_patch.h"
#include "image_io.h"
#include "paths.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "snapshots.h"

namespace rtview {

namespace {

// The distinct models and textures a scene holds (textures of the models' own MTL
// materials are the models' to watch).
class SceneFiles {
public:
    void material(const rt::Material& m) {
        if (m.texture_image && textures_seen_.insert(m.texture_image.get()).second) textures.push_back(m.texture_image);
    }
    void object(const rt::Object& o) {
        material(o.material);
        if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape); m && m->model)
            if (models_seen_.insert(m->model.get()).second) models.push_back(m->model);
        if (const rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
            for (const rt::Object& k : g->operands) object(k);
    }
    void scene(const rt::Scene& s) {
        for (const rt::NamedMaterial& m : s.materials) material(m.material);
        for (const rt::NamedObject& d : s.defined)
            if (d.object) object(*d.object);
        for (const rt::Object& o : s.objects) object(o);
        for (const rt::Plane& p : s.planes) {
            material(p.material);
            material(p.material2);
        }
    }
    std::vector<std::shared_ptr<const rt::MeshModel>> models;
    std::vector<std::shared_ptr<const rt::Texture>> textures;

private:
    std::unordered_set<const void*> models_seen_, textures_seen_;
};

}  // namespace

std::shared_ptr<const rt::Texture> Document::load_texture(const std::string& file, std::string& error) const {
    if (file.empty()) {
        error = "no file name given";
        return nullptr;
    }
    rt::TextureStore::Loaded l = models_->textures().load(rt::resolve_model_path(rt::folder_of(path_), file));
    error = l.error;
    return l.texture;
}

void Document::refresh_texture(rt::Material& m) const {
    if (!m.texture_image || m.texture_image->unchanged_on_disk()) return;
    if (rt::TextureStore::Loaded l = models_->textures().load(m.texture_image->path()); l.texture)
        m.texture_image = std::move(l.texture);
}

std::optional<std::string> Document::save_problem() const {
    if (has_scene_ && !applied_ && !behind_) return std::nullopt;  // the text is the scene's own
    if (has_scene_ && applied_ && *applied_ == editor_ && !behind_) return std::nullopt;
    const rt::ParseResult r = rt::parse_scene(editor_, parse_options(path_));
    for (const rt::Diagnostic& d : r.diagnostics)
        if (d.is_error())
            return rt::format_diagnostic(name_, d);
    return std::nullopt;
}

bool Document::apply_parsing_draft() {
    if (!applied_ || *applied_ == editor_ || !rt::parse_scene(editor_, parse_options(path_)).ok()) return false;
    return apply_text();
}

void Document::mark_saved(std::optional<std::uint64_t> hash) {
    saved_hash_ = hash ? *hash : text_hash(editor_);
    saved_size_ = editor_.size();
    // The text is the saved one now: no need to hash it again to know that.
    modified_key_ = text_key();
    modified_cache_ = false;
    // Revert of a text that never parsed goes back to the file: keep it (such files
    // are small; a scene that parses is not kept twice).
    saved_broken_text_ = has_scene_ ? std::string() : editor_;
    // No second parse of the saved text: it is the text of the current scene whenever
    // that has no unapplied draft.
    stamp_ = rt::FileId::of(path_);
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

namespace {

// How many items of each list included files brought.
std::array<std::size_t, 3> included_count(const rt::Scene& s) {
    auto count = [](const auto& v) {
        return std::size_t(std::count_if(v.begin(), v.end(), [](const auto& x) { return x.origin != 0; }));
    };
    return {count(s.objects), count(s.planes), count(s.lights)};
}

}  // namespace

void Document::reload_text(const std::string& text) {
    flush_typing();
    rt::ParseResult r = rt::parse_scene(text, parse_options(path_));
    diagnostics_ = r.diagnostics;
    if (r.ok()) {
        // Read with its includes as they are now: when those bring another number of
        // items, the history's steps would name the wrong ones (as in reload_includes()).
        if (has_scene_ && included_count(scene_) != included_count(r.scene)) history_.clear();
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
    if (!has_scene_ || held_ || editor_dirty() || behind_) return false;
    // The scene's models, looked for once per scene version (a pass over every object:
    // 9 ms in a 1M-object scene, too much for every second).
    if (scene_models_version_ != scene_version_) {
        SceneFiles files;
        files.scene(scene_);
        scene_models_ = std::move(files.models);
        scene_textures_ = std::move(files.textures);
        scene_models_version_ = scene_version_;
    }
    bool changed = false;
    for (const auto& m : scene_models_) changed = changed || !m->unchanged_on_disk();
    for (const auto& t : scene_textures_) changed = changed || !t->unchanged_on_disk();
    if (!changed) return false;
    // The text is the same: only the scene's models and textures are new (no undo
    // step). A file that no longer reads leaves the scene as it was, and is said once.
    rt::ParseResult r = rt::parse_scene(editor_, parse_options(path_));
    if (!r.ok()) {
        std::string why;
        for (const rt::Diagnostic& d : r.diagnostics)
            if (d.is_error() && why.empty()) why = rt::format_diagnostic(name_, d);
        if (why == model_problem_) return false;
        model_problem_ = why;
        return true;
    }
    model_problem_.clear();
    scene_.materials = std::move(r.scene.materials);
    scene_.defined = std::move(r.scene.defined);
    scene_.objects = std::move(r.scene.objects);
    scene_.planes = std::move(r.scene.planes);
    ++scene_version_;
    this->changed(rt::SceneDelta::all());  // a model's triangles: the world is compiled anew
    return true;
}

bool Document::reload_includes() {
    if (!has_scene_ || held_ || scene_.files_read.empty()) return false;
    std::vector<rt::FileId> now;
    bool changed = false;
    for (const rt::FileRead& f : scene_.files_read) {
        now.push_back(rt::FileId::of(f.path));
        changed = changed || now.back() != f.id;  // (a file gone is unknown: changed too)
    }
    if (!changed || now == include_tried_) return false;
    // The scene's own text (a draft stays a draft), read with the files as they are now.
    rt::ParseResult r = rt::parse_scene(applied_text(), parse_options(path_));
    if (!r.ok()) {
        include_tried_ = std::move(now);
        model_problem_.clear();
        for (const rt::Diagnostic& d : r.diagnostics)
            if (d.is_error() && model_problem_.empty()) model_problem_ = rt::format_diagnostic(name_, d);
        if (model_problem_.empty()) model_problem_ = "the reading was cancelled";
        return true;
    }
    include_tried_.clear();
    model_problem_.clear();
    // The steps of the undo history name items by their place in the scene: with items
    // come or gone before the scene file's own, they would name the wrong ones.
    if (r.scene.objects.size() != scene_.objects.size() || r.scene.planes.size() != scene_.planes.size() ||
        r.scene.lights.size() != scene_.lights.size()) {
        flush_typing();  // (typing since the last step is a step too: gone with the rest)
        history_.clear();
    }
    scene_ = std::move(r.scene);
    layout_.reset();
    ++scene_version_;
    this->changed(rt::SceneDelta::all());
    return true;
}

Document::DiskEvent Document::check_disk() {
    if (reload_models()) return model_problem_.empty() ? DiskEvent::ModelsReloaded : DiskEvent::ModelUnreadable;
    // The scene file first: reloaded, it reads its includes as they are anyway.
    if (const DiskEvent e = check_scene_file(); e != DiskEvent::None) return e;
    if (reload_includes()) return model_problem_.empty() ? DiskEvent::IncludesReloaded : DiskEvent::IncludeUnreadable;
    return DiskEvent::None;
}

Document::DiskEvent Document::check_scene_file() {
    if (path_.empty() || held_) return DiskEvent::None;  // not in the middle of a gesture
    const rt::FileId st = rt::FileId::of(path_);
    if (st == stamp_) return DiskEvent::None;
    stamp_ = st;
    if (!st.known()) return DiskEvent::Removed;
    std::string text;
    if (!rt::read_file(path_, text, rt::Limits::max_file_size).ok()) return DiskEvent::None;
    if (text.size() == saved_size_ && text_hash(text) == saved_hash_) return DiskEvent::None;  // touched, or our own save
    if (std::string why = not_scene_text(text); !why.empty()) {
        disk_problem_ = std::move(why);
        return DiskEvent::NotText;
    }
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
