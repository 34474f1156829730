// The open scene as the viewer edits it: editor text, last good Scene, file on disk,
// undo history. The UI changes the document only through these calls, so every rule
// (text never lost, panels written back into the text, atomic saves, reload on
// external change) lives here and is unit-tested without a window.
// Big scenes: the text is held once (a second copy only while an unapplied draft
// exists), a panel edit rewrites only its own block of the text, and undo steps hold
// what an edit changed, within a byte budget.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "file_id.h"
#include "model.h"
#include "scene.h"
#include "scene_delta.h"
#include "scene_parser.h"
#include "doc_step.h"
#include "scene_text.h"
#include "status.h"
#include "undo.h"

namespace rtview {

// The items a held edit has changed so far, with their values now.
struct HeldEdit {
    std::vector<std::size_t> objects, planes, lights;  // indices in the scene
    rt::Scene items;      // their values, in the same order; the scene camera
    bool camera = false;  // the camera is one of them
    bool empty() const { return objects.empty() && planes.empty() && lights.empty() && !camera; }
    bool operator==(const HeldEdit& o) const {
        return objects == o.objects && planes == o.planes && lights == o.lights && camera == o.camera &&
               items == o.items;
    }
};

class Document {
    static std::uint64_t text_key_of(std::uint64_t version, std::uint64_t typed) {
        return version * 0x9E3779B97F4A7C15ull + typed;
    }

public:
    Document();

    // --- opening ---------------------------------------------------------------
    // Replaces everything (history too). `path` empty: an unsaved scene called `name`.
    void load_text(const std::string& text, const std::string& path, const std::string& name);
    // Takes a text parsed elsewhere (a background load): nothing is parsed again and
    // the text is moved in, not copied; `layout`, if given, is scan_layout(text), and
    // `hash` text_hash(text).
    void load_parsed(std::string text, rt::ParseResult parsed, const std::string& path, const std::string& name,
                     std::optional<SceneLayout> layout = std::nullopt, std::optional<std::uint64_t> hash = std::nullopt);
    // An empty document with no scene and no errors: the window's state while its
    // first file loads in the background.
    void load_pending(const std::string& name);
    // Reads and loads a file; on failure says why and leaves the document as it was.
    rt::Status load_file(const std::string& path);

    const std::string& path() const { return path_; }
    const std::string& name() const { return name_; }
    // The editor text differs from the file as last loaded or saved.
    bool modified() const;
    std::string title() const;  // "name* - raytracer-view"

    // --- the scene -------------------------------------------------------------
    const rt::Scene& scene() const { return scene_; }
    bool has_scene() const { return has_scene_; }
    // Increases whenever scene() changes.
    std::uint64_t scene_version() const { return scene_version_; }
    // Increases when anything but the camera changes: the compiled world depends
    // on this only (the renderer takes its camera from the view).
    std::uint64_t content_version() const { return content_version_; }
    // What changed in the scene since content version `version` (everything when that is
    // not known: too long ago, or not a version of this document's): what a compiled
    // world of that version needs to become this one (World::update).
    rt::SceneDelta changes_since(std::uint64_t version) const;

    // --- panel edits -----------------------------------------------------------
    // A continuous edit (a slider drag) changes the scene on every frame and commit()
    // ends it: one undo step, and the text is written once. The item calls remember
    // only that item as it was, and the text is patched in that item's block; edit()
    // may change anything (it keeps a copy of the whole scene until the commit).
    rt::Object& edit_object(std::size_t i);
    rt::Plane& edit_plane(std::size_t i);
    rt::Light& edit_light(std::size_t i);
    rt::Camera& edit_camera();
    rt::Scene& edit();
    bool edit_held() const { return held_; }
    void commit();
    // Drops a held edit, restoring the scene as it was before it.
    void cancel_edit();
    // The named material `k` (scene().materials) takes the values of `m` for every use
    // of it, as a held edit (commit() ends it: one undo step that rewrites the
    // definition in the text; the blocks that name it stay as they are): the items that
    // use it (a CSG's operands too) and named objects whose definitions do. The world
    // hears of the items (changes_since). False, with nothing changed, when `k` is not
    // one of the scene file's own definitions (an included file's cannot be written).
    bool set_named_material(std::size_t k, const rt::Material& m);
    // Why panel and handle edits cannot be made now (empty: they can): the editor
    // holds unapplied changes that do not parse, so an edit could not be written into
    // the text that Save writes. (Parses the draft once per change of the text if it
    // is smaller than kSyncParseBytes. A bigger draft is not parsed here: until a check
    // of it (take_check()) says whether it parses, edits wait, and blocker_pending()
    // says a check is wanted.)
    std::string edit_blocker() const;
    bool blocker_pending() const { return blocker_pending_ && blocker_key_ == text_key(); }
    // Texts up to this size are parsed on the UI thread when needed (a few
    // milliseconds); bigger ones off it.
    static constexpr std::size_t kSyncParseBytes = 1u << 20;
    // Why a commit() just now was not made (an edit that could not be carried into
    // the draft: the scene went back), once; empty if none.
    std::string take_refusal();
    // Makes `camera` the scene camera ("Set scene camera from view"): one undo step
    // that rewrites only the camera block of the text. False if nothing changed.
    bool set_camera(const rt::Camera& camera);

    // --- editor ----------------------------------------------------------------
    // The text for a widget to edit in place: from here on the applied text is kept
    // apart (a draft may begin) and the text counts as typed into (text_key() changes).
    // Only for typing: a reader takes editor_text().
    std::string& typing_text();
    const std::string& editor_text() const { return editor_; }
    // The text the scene was made from.
    const std::string& applied_text() const { return applied_ ? *applied_ : editor_; }
    bool editor_dirty() const { return applied_ && *applied_ != editor_; }
    // What the user is told: the editor holds changes of theirs that are not applied.
    // A file opened with errors (no scene yet) is not that until it is typed into.
    bool unapplied() const { return editor_dirty() && (has_scene_ || modified()); }
    // Panel edits since the draft was typed are not in the editor text.
    bool text_behind() const { return behind_; }
    // Increases when editor_text() is replaced by the document (undo, reload, panel
    // write-back), so an active text widget knows to reload its buffer.
    std::uint64_t text_version() const { return text_version_; }
    // The changes that take the editor text of text version `version` to this one, in
    // order: a widget holding that text applies them instead of taking the whole text
    // again. False when they are not kept (a load, or too many or too large since).
    bool text_changes_since(std::uint64_t version, std::vector<TextReplacement>& out) const;
    // The editor text was typed into (call after a widget changed it).
    void note_typed() { ++typed_; }
    // Changes with every possible change of the editor text (with text_version()).
    std::uint64_t typed() const { return typed_; }
    // One key for the editor text as it is now (text_version() and typed()): a cache of
    // something computed from the text is valid while this stays the same.
    std::uint64_t text_key() const { return text_key_of(text_version_, typed_); }
    // Parses the editor text. Errors: diagnostics() lists them, the scene and the text
    // stay as they are. Success: the scene becomes the text's (one undo step).
    bool apply_text();
    // Editor text back to the text of the current scene, dropping the draft; also
    // how the user resolves text_behind() the other way round (undoable).
    void revert_text();
    // A structural edit of the text (add, duplicate, delete: scene_edits.h): replaces
    // `length` bytes at `pos` with `text` and applies the result, as one undo step
    // (called `name`) that stores the replacement. Only when the editor text is the scene's (no
    // draft), no edit is held (edit_held()) and the result parses; else false and nothing changes.
    // `splice`, if given, says what the replacement does to the scene (one item inserted,
    // removed or replaced: scene_edits.h): then only the new block is parsed, and the
    // scene, the layout and, on undo and redo, both again are changed in place, so the
    // edit costs its block rather than the whole text (the result is the same as a
    // parse of the whole text; where that cannot be known cheaply, it is parsed).
    bool replace_text(std::size_t pos, std::size_t length, const std::string& text,
                      const std::string& name = "Edit the scene text", const ItemSplice* splice = nullptr);
    // Several structural edits as one undo step (a group Delete or Duplicate): each a
    // replacement of the text with the ItemSplice that says what it does to the scene (as
    // replace_text() takes one), made in the order given, each on the text and the scene
    // the ones before it left. They are spliced as replace_text() splices one, all in one
    // pass over the text and the lists, and so are the step's undo and redo: N edits cost
    // about one single splice, not a parse of the whole text. False, with nothing changed,
    // when one of them cannot be spliced (the caller then replaces the text as a whole).
    struct SpliceEdit {
        TextReplacement replacement;
        ItemSplice splice;
    };
    bool splice_texts(const std::vector<SpliceEdit>& edits, const std::string& name);
    // Where the items of the editor text are (scan_layout), kept up to date through the
    // document's own edits: scanned again only after other changes. Null when the text's
    // structure is unclear.
    const SceneLayout* layout();
    // How many edits, undos and redos so far were made by splicing one item (for tests
    // and benchmarks: the rest parsed the whole text).
    std::uint64_t spliced_count() const { return spliced_count_; }
    // How many group steps (splice_texts(), and their undos and redos) were made in one
    // pass over the text and the lists (for tests: the rest went edit by edit).
    std::uint64_t group_passes() const { return group_passes_; }
    // Puts `text` in the editor as an unapplied draft (undoable): crash recovery.
    void restore_draft(const std::string& text);
    // Re-parses the draft to refresh diagnostics() without applying it (live check).
    void check_text();
    // The live check off the UI thread (a big text's parse takes longer than a frame):
    // the text as it is now, the options to parse it with and its key (text_key()).
    // take_check() takes the check's diagnostics if the text is still the one checked
    // (false, nothing changed, if it changed meanwhile: a newer check is due).
    struct TextCheck {
        std::string text;
        rt::ParseOptions options;
        std::uint64_t key = 0;
    };
    TextCheck text_check() const { return {editor_, parse_options(path_), text_key()}; }
    bool take_check(std::uint64_t key, std::vector<rt::Diagnostic> diagnostics);
    // apply_text() with the parse off the UI thread (a big text's takes seconds):
    // begin_apply() ends a held edit and the typing step as apply_text() does and gives
    // the text to parse; finish_apply() takes the parse and applies it as apply_text()
    // would, if the text is still the one parsed (its key); else nothing changes and
    // it returns nothing (the text changed meanwhile: parse it again).
    TextCheck begin_apply();
    std::optional<bool> finish_apply(std::uint64_t key, rt::ParseResult r);
    const std::vector<rt::Diagnostic>& diagnostics() const { return diagnostics_; }
    bool has_errors() const;

    // --- undo ------------------------------------------------------------------
    bool can_undo() const { return history_.can_undo(); }
    bool can_redo() const { return history_.can_redo(); }
    std::size_t undo_depth() const { return history_.undo_size(); }
    // Changes when a step is made, undone or redone, or the history cleared (UndoHistory::changes).
    std::uint64_t history_changes() const { return history_.changes(); }
    std::size_t undo_bytes() const { return history_.bytes(); }
    void set_undo_budget(std::size_t bytes) { history_.set_budget(bytes); }
    bool undo();
    bool redo();
    // Names the held edit for the undo history ("Move sphere 3", "Edit radius of
    // sphere 1"); the first name given to an edit stays. An edit left unnamed is named
    // by what it changed ("Edit object 3", "Edit the scene camera").
    void name_edit(const std::string& name);
    // The names of up to `max` steps that undo() (redo()) would take back (do again) in
    // turn, the next first: a held edit and text typed since the last step count.
    std::vector<std::string> undo_names(std::size_t max) const;
    std::vector<std::string> redo_names(std::size_t max) const;
    // The step the last successful undo() or redo() took back or did again.
    const std::string& last_step_name() const { return last_step_name_; }

    // --- saving ----------------------------------------------------------------
    // Save writes the editor text. A draft that parses is applied first, so that the
    // file and the picture agree (true if it was); one that does not parse makes
    // save_problem() say why to ask the user before saving it.
    bool apply_parsing_draft();
    std::optional<std::string> save_problem() const;
    // Writes the editor text atomically; success, or why not.
    rt::Status save();
    rt::Status save_as(const std::string& path);

    // --- crash recovery --------------------------------------------------------
    // The held edit (a drag): the items it has touched so far, with their values now
    // (what a recovery copy keeps beside the text, which has not got them yet). Empty
    // when no edit is held, or when it is an edit() of the whole scene.
    HeldEdit held_edit() const;
    // text_hash() of the file as last loaded or saved.
    std::uint64_t saved_hash() const { return saved_hash_; }

    // --- the file on disk ------------------------------------------------------
    enum class DiskEvent {
        None, Reloaded, Conflict, Removed, ModelsReloaded, ModelUnreadable, NotText, IncludesReloaded, IncludeUnreadable
    };
    // Call now and then (the viewer: once a second). Reloads by itself when there
    // are no unsaved edits (looking around is not an edit: the view camera lives
    // outside the document); reports a conflict otherwise. A model file a mesh names,
    // or a texture file a material names, that changed is read again (the text stays:
    // ModelsReloaded); if it no longer reads, the scene keeps the model or texture as
    // it was (ModelUnreadable, model_problem()). A file that became no scene text at
    // all (not_scene_text(): a binary written over it) is not read in: the document
    // stays (NotText, disk_problem()). So is a file the scene includes read again
    // (IncludesReloaded; IncludeUnreadable, with model_problem() saying why), whether
    // or not the scene file has unsaved edits or a draft (they are in its own text,
    // which stays), once no gesture is held. When the number of items changed, the
    // undo history is dropped (its steps name items by their place in the scene).
    // The models read for this document's scenes, kept between parses (and shared
    // with the loader, which reads them in the background), and with them the
    // textures: one decoded copy per file (models().textures()).
    rt::ModelStore& models() const { return *models_; }
    // The texture a material of this document names as `file` (as written: relative to
    // the scene file's folder), through the document's store: null, with `error` the
    // texture reader's message, if it cannot be read.
    std::shared_ptr<const rt::Texture> load_texture(const std::string& file, std::string& error) const;
    // Reads models through `store` from now on (one a load begun before the document
    // existed reads into).
    void share_models(std::shared_ptr<rt::ModelStore> store) { models_ = std::move(store); }
    // How the document parses a text that is (to be) the file at `path`.
    rt::ParseOptions parse_options(const std::string& path) const;
    DiskEvent check_disk();
    const std::string& model_problem() const { return model_problem_; }
    const std::string& disk_problem() const { return disk_problem_; }
    bool disk_conflict() const { return conflict_; }
    void resolve_conflict_reload();  // take the disk version (undoable)
    void resolve_conflict_keep();    // keep ours; ask again only on the next change

private:
    struct Saved {  // an item as it was when a held edit first touched it
        std::vector<std::pair<std::size_t, rt::Object>> objects;
        std::vector<std::pair<std::size_t, rt::Plane>> planes;
        std::vector<std::pair<std::size_t, rt::Light>> lights;
        std::optional<rt::Camera> camera;
        std::optional<rt::Scene> whole;  // edit(): everything
        std::vector<std::pair<std::size_t, rt::NamedMaterial>> materials;  // set_named_material()
        std::vector<std::pair<std::size_t, rt::NamedObject>> defined;
    };
    void hold_edit();
    rt::Scene scene_before_edit() const;  // (a copy: only for the slow paths)
    rt::Scene scene_before_edit_from(const DocStep& step) const;
    bool reads_back(const DocStep& step, bool wide) const;
    // Why the step cannot be written into this file's text (it changes an item read from
    // an included file); empty if it can.
    std::string included_edit(const DocStep& step, bool wide) const;
    bool commit_in_place(DocStep& step);
    bool commit_generic(DocStep& step);
    void record(DocStep step);
    // Text typed into the editor since the last step becomes a step of its own
    // (every step's replacements hold for the text exactly as the previous step left it).
    void flush_typing();
    bool apply_parsed(rt::ParseResult r);  // apply_text() once the text is parsed
    // Replaces the texts and scene as one undoable step (apply, revert, reload...).
    // `editor` null: the editor text stays; `scene` empty: the scene stays.
    void replace_state(const std::string* editor, std::optional<std::string> applied, std::optional<rt::Scene> scene,
                       bool behind, std::string name);
    // replace_text() of one item's block without parsing the whole text; false (nothing
    // changed) when it cannot be done that way (document_splice.cpp).
    bool splice_text(std::size_t pos, std::size_t length, const std::string& text, const std::string& name,
                     const ItemSplice& splice);
    // Whether replacing [pos, pos + length) of the editor text by `text` is the item
    // splice `sp`, the layout `l` being the text's; if so `s` says what it does (its new
    // block read), and nothing has changed yet.
    bool plan_splice(std::size_t pos, std::size_t length, const std::string& text, const ItemSplice& sp,
                     const SceneLayout& l, SplicedItem& s) const;
    // The scene and (when `layout_valid`) the layout changed as the splice says, forward
    // (as made) or back: the text's replacement at `pos` of `removed` by `inserted` is made.
    void apply_splice(const SplicedItem& s, bool forward, std::size_t pos, std::string_view removed,
                      std::string_view inserted, bool layout_valid);
    // The edits of a group step (DocStep::spliced_many), made forward or back, as one pass
    // over the text, the scene's lists and (when `layout_valid`) the layout; false, with
    // nothing changed, when they are not in the order that needs (document_splice_group.cpp).
    bool apply_group(const DocStep& s, bool forward, bool layout_valid);
    // splice_texts()'s edits planned, each on the text as it is, into `step`; false if
    // one cannot be spliced.
    bool plan_group(const std::vector<SpliceEdit>& edits, DocStep& step) const;
    // splice_texts()'s edits made one after the other, each planned on what the ones
    // before it left, into `step`; false, with nothing changed, if one cannot be spliced.
    bool splice_each(const std::vector<SpliceEdit>& edits, DocStep& step);
    // The source positions of the scene's own items (and definitions, includes, the
    // camera) and of the diagnostics after the editor text's replacement at `pos` of
    // `removed` by `inserted`, just made, moved as the text did: the scene is the
    // editor text's (no draft). Those inside the replaced text stay. `at`: the line and
    // column of `pos` if known (else the text before it is counted). Returns them.
    rt::SourceLoc follow_positions(std::size_t pos, std::string_view removed, std::string_view inserted,
                                   const rt::SourceLoc* at = nullptr);
    // The layout kept in step with the text through `reps` (made in order), when each
    // replaces one whole block (an undo or redo of a panel edit); else dropped (false).
    bool follow_layout(const std::vector<TextReplacement>& reps);
    // The name of the held edit: as given to name_edit(), else from what it touched.
    std::string held_name() const;
    void apply_step(const DocStep& s, bool forward);
    // undo() (forward false) or redo(): the held edit and typing committed first.
    bool take_step(bool forward);
    // The scene's content changed as `delta` says: a new content version, logged for
    // changes_since().
    void changed(rt::SceneDelta delta);
    void normalize_applied();
    void mark_saved(std::optional<std::uint64_t> hash = std::nullopt);
    void reload_text(const std::string& text);
    // The scene's models and textures read again if one changed on disk; true if the
    // scene changed.
    bool reload_models();
    // The same for the files the scene includes (check_disk()).
    bool reload_includes();
    // check_disk() for the scene file itself.
    DiskEvent check_scene_file();
    std::vector<rt::FileId> include_tried_;  // the included files as a failed reload found them
    void restore_object(std::size_t i, const rt::Object& o);  // an undo step's object, with today's model
    void restore_plane(std::size_t i, const rt::Plane& p);    // and textures
    // The material's texture as it is on disk now, if the file changed since it was read.
    void refresh_texture(rt::Material& m) const;
    // The editor text changed by `s` (forward: as made or redone; else undone): a new
    // text version, whose changes text_changes_since() gives.
    void text_changed(const DocStep& s, bool forward);

    // A cache: reading through it changes no state, and copies of the document share it.
    std::shared_ptr<rt::ModelStore> models_ = std::make_shared<rt::ModelStore>();
    std::string model_problem_;      // why a changed model did not read, once said
    std::string disk_problem_;       // why the file on disk was not read in (NotText)
    // The distinct models scene_ holds, as of scene version scene_models_version_.
    std::vector<std::shared_ptr<const rt::MeshModel>> scene_models_;
    std::vector<std::shared_ptr<const rt::Texture>> scene_textures_;  // and textures (of its materials)
    std::uint64_t scene_models_version_ = 0;
    std::string editor_;
    std::optional<std::string> applied_;  // only while it differs from editor_ (or may)
    std::optional<std::string> typing_base_;  // editor_ as the last step left it, while typed into
    rt::Scene scene_;
    bool has_scene_ = false;
    bool behind_ = false;

    UndoHistory<DocStep> history_;
    std::string path_, name_;
    // The file as last loaded or saved: its hash and size (the text itself is not
    // kept twice); its text only when it does not parse (Revert needs it then).
    std::uint64_t saved_hash_ = 0;
    std::size_t saved_size_ = 0;
    std::string saved_broken_text_;
    mutable std::uint64_t modified_key_ = ~std::uint64_t(0);  // (text_version_, typed_) the cache is for
    mutable bool modified_cache_ = false;
    rt::FileId stamp_;  // the file as last loaded or saved: to notice changes other programs make
    std::vector<rt::Diagnostic> diagnostics_;
    std::uint64_t scene_version_ = 1, content_version_ = 1, text_version_ = 1, typed_ = 0;
    // What changed from content version `from` to `to`, oldest first (changes_since()).
    struct Change {
        std::uint64_t from, to;
        rt::SceneDelta delta;
    };
    std::deque<Change> changes_;
    // Text versions (text_version_ - text_log_.size(), text_version_] as changes of the
    // one before, oldest first, within a budget (text_changes_since()).
    std::deque<std::vector<TextReplacement>> text_log_;
    std::size_t text_log_bytes_ = 0;
    bool held_ = false;
    Saved saved_;
    std::string held_name_;    // name_edit() of the held edit
    std::string last_step_name_;  // of the last undo() or redo()
    std::optional<SceneLayout> layout_;  // of editor_ when layout_key_ matches
    std::uint64_t layout_key_ = 0;
    // What layout_key_ must be for the text as it is (`ahead`: after that many more
    // versions): its version and the keys typed into it.
    std::uint64_t layout_key(std::uint64_t ahead = 0) const {
        return text_key_of(text_version_ + ahead, typed_);
    }
    std::uint64_t spliced_count_ = 0, group_passes_ = 0;
    bool conflict_ = false;
    std::string conflict_text_;
    std::string refusal_;
    mutable std::string blocker_;  // edit_blocker() for blocker_key_
    mutable std::uint64_t blocker_key_ = ~std::uint64_t(0);
    mutable bool blocker_pending_ = false;  // blocker_ waits for a check of the draft
    // edit_blocker()'s answer for the draft at `key` (if it is still the one asked about).
    void take_blocker(std::uint64_t key, bool parses) const;
};

// FNV-1a of a text (the saved file's identity for modified()).
std::uint64_t text_hash(const std::string& text);

}  // namespace rtview
