// The viewer's selection when it holds several things (Shift+click, box select), and
// what is done to all of them at once: a move as one held edit of the document (one
// undo step), delete and duplicate as one undo step (spliced item by item), the
// things a box in the picture sees, their joint outline, and the selection before and
// after such a step, which undo and redo give back. No GL, no ImGui: unit-tested.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "document.h"
#include "object_ids.h"
#include "scene_edits.h"
#include "viewport.h"

namespace rtview {

struct Selection {
    // What the panels edit: the one selected item (a CSG operand too), or of several the
    // last one added. None when nothing is selected.
    ItemRef one;
    // Every selected thing when there are two or more (top-level items, in the order they
    // were added; `one` names the last); else empty.
    std::vector<SceneItem> many;
    bool operator==(const Selection& o) const { return one == o.one && many == o.many; }
    bool operator!=(const Selection& o) const { return !(*this == o); }
};

// Every selected top-level item: the many, else the one (a CSG operand: its object).
std::vector<SceneItem> selected_items(const Selection& s);
bool is_selected(const Selection& s, const SceneItem& item);
// A plain click: this alone (none: nothing).
void select_one(Selection& s, const ItemRef& r);
// Shift+click: adds the item (it becomes `one`), or takes it out when it is in already;
// of two, the one left is selected alone.
void toggle(Selection& s, const SceneItem& item);
// Box select: adds each of `items` not yet selected (the last becomes `one`).
void add_all(Selection& s, const std::vector<SceneItem>& items);
// Items the scene no longer has (a shorter list after an undo or a reload) leave the
// selection.
void keep_existing(Selection& s, const rt::Scene& scene);
// "3 things selected: 2 objects, 1 light"
std::string selection_summary(const Selection& s);

// Whether the item was read from a file the scene includes (it has no block here).
bool item_included(const rt::Scene& scene, const SceneItem& item);

// The move handle's point for several items: the centre of the box around their
// anchors (move_handle.h's item_anchor), or nothing when none has one.
std::optional<rt::Vec3> group_anchor(const rt::Scene& scene, const std::vector<SceneItem>& items);

// A drag of the move handle of several items: each moves by the same amount from where
// it was when the drag began, in one held edit of the document (Document::commit()
// then makes one undo step that rewrites each item's block). Items read from an
// included file are left out (their text is not this file's).
class GroupMove {
public:
    GroupMove(const rt::Scene& scene, const std::vector<SceneItem>& items);
    // The items at their first places moved by `d` (world units).
    void apply(Document& doc, const rt::Vec3& d) const;
    std::size_t size() const { return objects_.size() + planes_.size() + lights_.size(); }
    std::size_t left_out() const { return left_out_; }

private:
    std::vector<std::pair<std::size_t, rt::Object>> objects_;
    std::vector<std::pair<std::size_t, rt::Plane>> planes_;
    std::vector<std::pair<std::size_t, rt::Light>> lights_;
    std::size_t left_out_ = 0;
};

// The objects among `items` (those of this file, not an included one's) take the
// material `m` (a named material's use stays a use of it), as one held edit of the
// document (commit() makes it one undo step). Returns how many changed.
std::size_t give_material(Document& doc, const std::vector<SceneItem>& items, const rt::Material& m);

// Delete or duplicate several items as one step: `splices`, each item's edit (its
// replacement of the text and what it does to the scene) in the order to make them
// (the last in the text first, so each one's place and index hold when it is made),
// for Document::splice_texts(); when that cannot be (a scene with includes),
// whole_replacement(), all of them as one replacement of the text, which the document
// parses whole. `select`: what is selected afterwards (the copies; none after a
// delete). Items whose block is not in the text (an included file's) are left out and
// counted in `skipped`; nothing when no item is left, or when two items' replacements
// overlap.
struct GroupEdit {
    std::vector<Document::SpliceEdit> splices;  // empty when some edit is not a splice
    std::vector<TextReplacement> parts;         // each item's replacement of the text
    std::vector<SceneItem> select;
    std::size_t done = 0, skipped = 0;
};
std::optional<GroupEdit> delete_items(const std::string& text, const rt::Scene& scene,
                                      const std::vector<SceneItem>& items, const SceneLayout* layout = nullptr);
// Each copy right after its original, moved by `offset` (duplicate_item).
std::optional<GroupEdit> duplicate_items(const std::string& text, const rt::Scene& scene,
                                         const std::vector<SceneItem>& items, const rt::Vec3& offset,
                                         const SceneLayout* layout = nullptr);
// The group's edits as one replacement of `text` (the text they were planned on): a
// copy of all the text between the first and the last (only when it cannot be spliced).
TextReplacement whole_replacement(const std::string& text, const GroupEdit& g);
// Several replacements of one text that do not overlap, as one (the span from the first
// to the last, the text between them kept); nothing if two overlap.
std::optional<TextReplacement> merge_replacements(const std::string& text, std::vector<TextReplacement> reps);

// The things seen in the window rectangle between (x0, y0) and (x1, y1) (any corners):
// the primary hit of each of its film pixels (what a click there would select), on a
// grid of at most about `max_rays` rays (coarser in a big box). Objects first, then
// planes, then lights (lamp glows), each by index. It is called on the UI thread: an
// eighth of the grid's rows (evenly spread) is traced first, the rest while `seconds`
// last (a slow scene sees the box at a coarser grid, not for longer).
std::vector<SceneItem> items_in_box(const rt::World& world, const rt::Camera& view_camera, const Rect& image,
                                    int film_w, int film_h, double x0, double y0, double x1, double y1,
                                    std::size_t max_rays = 40000, double seconds = 0.03);

// The texel window (at `block`) that can see any of `items`: the union of their
// item_window()s (object_ids.h), or the whole film for very many.
void items_window(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                  const std::vector<SceneItem>& items, int& x0, int& y0, int& x1, int& y1);

// The borders between the texels that hold one of `codes` (object_ids.h's id_code) and
// any other texel, joined into runs: the outline of several items at once (two
// selected items that touch keep the line between them).
std::vector<Edge> outline_edges_of(const IdBuffer& ids, std::vector<std::uint32_t> codes);

// The selection before and after the steps that changed several items, so that undo
// and redo give it back (a plain item's step keeps the selection as it is). A step is
// known by the undo depth it left and its name; steps the history has since dropped or
// replaced are simply not found.
class SelectionSteps {
public:
    void made(std::size_t depth_after, const std::string& name, const Selection& before, const Selection& after);
    // After an undo that left `depth` steps and took back the step called `name`.
    std::optional<Selection> undone(std::size_t depth, const std::string& name) const;
    // After a redo that left `depth` steps, the last one called `name`.
    std::optional<Selection> redone(std::size_t depth, const std::string& name) const;
    void clear() { steps_.clear(); }

private:
    struct Step {
        std::size_t depth;
        std::string name;
        Selection before, after;
    };
    std::deque<Step> steps_;
};

}  // namespace rtview
