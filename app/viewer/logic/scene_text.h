// Keeps the scene text and the edited Scene in agreement. A panel edit replaces only
// the text of the items it changed (one object, one light, the camera block), so the
// user's comments and layout elsewhere survive; the result is checked by parsing it
// back, and if that ever disagrees the whole text is rewritten with write_scene.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene.h"
#include "scene_parser.h"

namespace rtview {

// The list of a scene an item is in (the camera: its one block).
enum class ItemList { Object, Plane, Light, Camera };

struct TextSpan {
    std::size_t begin = 0, end = 0;  // byte offsets, end exclusive
};

// Where the items of a scene text are: the structure the parser sees, found with the
// format's lexical rules only (tokens, self-delimiting braces, // comments).
struct SceneLayout {
    bool ok = false;                // braces balanced and every item complete
    std::vector<TextSpan> objects;  // top-level objects of all `thing` sections, in order
    std::vector<TextSpan> planes;   // items of `special_thing` sections
    std::vector<TextSpan> lights;   // items of `light` sections
    std::vector<TextSpan> cameras;  // whole `camera { ... }` sections
    std::size_t append_at = 0;      // where a new section goes: before `end`, or the text's end
};
// `objects`: how many objects the text is known to hold (a parse's count), room for
// whose spans is made at once (in huge pages when big) instead of by doubling.
SceneLayout scan_layout(std::string_view text, std::size_t objects = 0);

// `text` must parse to `from`. Returns `text` with the items that differ between
// `from` and `to` rewritten, or nothing if the edit cannot be done in place (the
// number of items changed, the layout is unclear, or the check parse disagrees).
// Items read from included files are not in the text: an edit that changes one cannot
// be done (nothing). `options`: how to parse the result for its check (base_dir for the
// includes); null: as text of no file.
std::optional<std::string> patch_scene_text(const std::string& text, const rt::Scene& from, const rt::Scene& to,
                                            const rt::ParseOptions* options = nullptr);

// Positions in a scene's item lists, and whether the camera is meant.
struct ItemIndices {
    std::vector<std::size_t> objects, planes, lights;
    bool camera = false;
};

// patch_scene_text for an edit of a few items: those at `at` (indices into `from`'s
// lists) become `values`' items, in the same order, and the camera `values.camera`
// when `at.camera`. Only those items are compared, written and checked (text_holds),
// so the cost is a layout scan of `text` and the items, whatever the scene's size.
// Nothing when an index is out of range, the counts disagree or an item cannot be
// written so that it reads back.
std::optional<std::string> patch_scene_items(const std::string& text, const rt::Scene& from, const ItemIndices& at,
                                             const rt::Scene& values);

// Whether the text of `s` (write_scene) reads back as `s`: every number within the
// format's range, every shape one the parser takes. An edit may make either false (a
// drag far out; rounding that flattens a tiny tetrahedron); such an edit is not made.
bool text_holds(const rt::Scene& s);

// The `{ ... }` of each `material NAME { ... }` of the text's define sections (the scene
// file's own named materials, in order), with its name; empty if the text's sections
// are unclear.
std::vector<std::pair<std::string, TextSpan>> material_definitions(std::string_view text);

// patch_scene_text, falling back to write_scene(to). Returns text parsing to `to` for
// every `to` that text_holds().
// An edit of an item read from an included file cannot be written into the text: the
// caller refuses those first (Document::commit).
std::string sync_scene_text(const std::string& text, const rt::Scene& from, const rt::Scene& to,
                            const rt::ParseOptions* options = nullptr);

// `base` with the items that differ between `old_scene` and `new_scene` taken from
// `new_scene`. Item lists carry over only where all three have the same length;
// `complete` says whether every difference could be carried. Used to carry a panel
// edit into a draft text that parses to `base`.
rt::Scene carry_edit(const rt::Scene& base, const rt::Scene& old_scene, const rt::Scene& new_scene,
                     bool* complete = nullptr);

// The named material `k` of `s` takes the values of `m` (the definition's `named` kept)
// for every use of it: each material slot that names it with the definition's values (a
// CSG's operands too; a use the text spells out differs and stays), and the named objects
// whose definitions use it, their instances given the renewed definition. Before an item
// changes, `touch(list, i)` is called with it (ItemList::Object or Plane, in order), and
// before a definition does, `touch_defined(d)`: a caller may keep them as they were.
void use_named_material(rt::Scene& s, std::size_t k, const rt::Material& m,
                        const std::function<void(ItemList, std::size_t)>& touch = {},
                        const std::function<void(std::size_t)>& touch_defined = {});

// The whitespace that starts the line holding `offset` (LF, CR LF and a lone CR end
// lines, as the parser counts them).
std::string line_indent(std::string_view text, std::size_t offset);

// The only item of `one` in `list` as the writer prints it, its lines after the first
// indented for a line that starts with `indent`; empty if the writer's text is unclear.
std::string written_item(const rt::Scene& one, ItemList list, const std::string& indent);
// An empty scene for writing items of `s` on their own (written_item, text_holds): `s`'s
// camera, so that the writer prints a normal scene, and its named materials and objects
// (an included file's too, as if the scene's own, so that each keeps its place), so
// that a use of one is written by its name as the scene's text has it, not spelled out,
// and an instance reads back.
rt::Scene item_scene(const rt::Scene& s);

// What a structural edit's replacement does to the scene's lists, as the edit that
// planned it knows (scene_edits.h): the document then parses only the block it
// brings (Document::replace_text) instead of the whole text. Insert: the replacement
// inserts one item's block that becomes item `index` of `list`; inside a section
// right after the block of item index - 1 of that list, or (`section`) as a section
// of its own at SceneLayout::append_at. Remove: it removes item `index`'s block (with
// blanks, its line, a comment after it). Replace: it replaces that block by another.
struct ItemSplice {
    enum class Op { Insert, Remove, Replace };
    Op op = Op::Insert;
    ItemList list = ItemList::Object;
    std::size_t index = 0;
    bool section = false;
};

// The scene file's own items are those of origin 0; items read from an included file
// have no block in the scene's text. own_index: an item's place among its list's own
// items (the index of its block in scan_layout's list), or nothing for an included one
// or one out of range. own_count: how many own items the list has. included_file: the
// file (as the scene's `include` line names it) an item was read from, or null for an
// own item. Scenes without includes cost nothing more here.
std::optional<std::size_t> own_index(const rt::Scene& s, ItemList list, std::size_t i);
std::size_t own_count(const rt::Scene& s, ItemList list);
const rt::Include* included_file(const rt::Scene& s, ItemList list, std::size_t i);
// Whether the layout has one block for each own item of `s`.
bool layout_matches(const SceneLayout& l, const rt::Scene& s);

// A 1-based line/column as a byte offset, as the parser counts them (columns count
// bytes; LF, CR LF and a lone CR each end a line).
std::size_t offset_of(std::string_view text, int line, int col);

// Why `text` is not a scene text at all (empty: it may be one, errors or not): a NUL
// byte, or bytes that are not UTF-8 in more than kMaxForeignBytes places and in more
// than one byte in 100 (a comment in Latin-1 passes; a binary file does not). Such a
// file is refused at Open: it would fill the editor with noise and replace the scene.
constexpr std::size_t kMaxForeignBytes = 16;
std::string not_scene_text(std::string_view text);

}  // namespace rtview
