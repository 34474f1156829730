// Structural scene edits as text edits: add an item, duplicate or delete one, make a
// CSG of two objects, switch a lamp to a spotlight and back. Each edit is one minimal
// replacement of the scene text (offset, length, new text), so undo can store the
// replacement instead of a copy of the document, and the user's comments and layout
// outside the touched blocks survive. No GL: unit-tested in tests/viewer.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model.h"
#include "placement.h"
#include "scene.h"
#include "scene_text.h"
#include "text_replacement.h"
#include "triangles.h"
#include "world.h"

namespace rtview {

// A top-level item of a scene: scene.objects[index], planes[index] or lights[index].
struct SceneItem {
    enum class Kind { Object, Plane, Light } kind = Kind::Object;
    int index = -1;
    bool operator==(const SceneItem& o) const { return kind == o.kind && index == o.index; }
};

// A top-level item, or a CSG operand below an object (path: 0 = left, 1 = right); none
// when item.index < 0. The viewer's selection is one.
struct ItemRef {
    SceneItem item;
    std::vector<int> path;
    bool none() const { return item.index < 0; }
    // Whether it names an item of kind k (or an operand below one).
    bool is(SceneItem::Kind k) const { return !none() && item.kind == k; }
    bool operator==(const ItemRef& o) const {
        return none() ? o.none() : !o.none() && item == o.item && path == o.path;
    }
};

struct SceneEdit {
    TextReplacement replacement;
    SceneItem select;  // what to select afterwards: the new item, or -1 when none
    // What the replacement does to the scene's lists, when it is one item inserted,
    // removed or replaced: the document then parses only the new block.
    std::optional<ItemSplice> splice;
};

// (The objects first, up to Torus.)
enum class NewItem { Sphere, Cylinder, Tetrahedron, Torus, Box, Cone, Plane, ChessPlane, Lamp, Spotlight };
const char* new_item_name(NewItem k);  // "sphere", ..., as in the format
// Every kind, in the Add menus' order.
inline constexpr NewItem kNewItems[] = {NewItem::Sphere,     NewItem::Cylinder, NewItem::Tetrahedron, NewItem::Torus,
                                        NewItem::Box,        NewItem::Cone,     NewItem::Plane,       NewItem::ChessPlane,
                                        NewItem::Lamp,       NewItem::Spotlight};
// The kind `name` names (new_item_name's words), if any.
std::optional<NewItem> new_item_kind(std::string_view name);
// Whether the kind is a thing (an object), not a plane or a light.
inline bool new_item_is_object(NewItem k) { return k <= NewItem::Cone; }

// All edits take the scene text and the scene it parses to (its items must match
// the text's blocks one for one), and return nothing when the text's structure is
// unclear or the item does not exist. The result is a plain block of the format, so
// applying it and parsing gives the scene with the edit made. `layout`, if given, is
// scan_layout(text) (Document::layout()): the text is then not scanned again.

// A new item with a size from typical_object_size: objects after the last object (or in a
// new `thing` section), planes after the last plane, lights after the last light.
// Objects and lights rest on the surface; a plane stands upright on it (it contains
// the surface's normal) and faces the viewer: a plane through the point with the
// surface's own orientation would lie in a floor it was added to, and show nothing.
// `world`, if given, is the scene's compiled world: its bounds give the scene's size
// without a pass over the objects.
std::optional<SceneEdit> add_item(const std::string& text, const rt::Scene& scene, NewItem kind, const Placement& at,
                                  const SceneLayout* layout = nullptr, const rt::World* world = nullptr);
// A mesh of the model read from `file` (as the block names it): its size typical_object_size,
// its box resting on the surface at the point (centred on a point in space), turned
// so that the model's y axis (OBJ's and PLY's usual up) is the scene's up when that
// is z.
std::optional<SceneEdit> add_model(const std::string& text, const rt::Scene& scene, const std::string& file,
                                   const rt::MeshModel& model, const Placement& at, const SceneLayout* layout = nullptr);
// A new scene that shows the model read from `file` (written as it is, best
// absolute): the model as the file has it (y up, its own materials where it has them,
// else one colour), on a chess floor under its lowest point, lit by a lamp and framed
// by the camera.
std::string model_scene(const std::string& file, const rt::MeshModel& model);

// A copy right after the original. With a zero offset the original's text is copied
// as it is (comments included); otherwise the copy is written moved by `offset`.
std::optional<SceneEdit> duplicate_item(const std::string& text, const rt::Scene& scene, SceneItem item,
                                        rt::Vec3 offset = {0, 0, 0}, const SceneLayout* layout = nullptr);
// Removes the item's block, with its line when the line holds nothing else.
std::optional<SceneEdit> delete_item(const std::string& text, const rt::Scene& scene, SceneItem item,
                                     const SceneLayout* layout = nullptr);
// Removes the CSG operand `path` names below object `index`: its CSG becomes the other
// operand (a whole CSG when that is one). When the CSG was the object itself, the
// object keeps its material, the one that was rendered; the object stays selected.
std::optional<SceneEdit> delete_operand(const std::string& text, const rt::Scene& scene, int index,
                                        const std::vector<int>& path, const SceneLayout* layout = nullptr);
// Objects a and b (top level, a != b) become one CSG `left a, right b` at a's place,
// with a's material (only the CSG's own material is rendered). Nothing for a mesh or an
// instance (the format refuses them as operands).
std::optional<SceneEdit> make_csg(const std::string& text, const rt::Scene& scene, int a, int b, rt::CsgType type);
// lamp <-> spotlight. A spotlight has no size, so the lamp's size is kept in the
// block as a comment (`// lamp size S`) from which switching back restores it.
std::optional<SceneEdit> switch_light_kind(const std::string& text, const rt::Scene& scene, int light,
                                           const SceneLayout* layout = nullptr);

// Moves every point of an item (for duplicate with an offset, and the move tool),
// rounding each coordinate to 12 significant digits so that float noise of the sum
// (2.07 - 2.5 = -0.43000000000000016) does not reach the text. `d` is in the frame the
// object is written in (the world for a top-level one). An object with a transform
// (`rotation`, `scale` or `translate`; an instance always) moves by its `translate`,
// which applies last: moving its shape's own points would move it by the transform
// of `d`. Others move their points, so a user's numbers stay theirs.
void translate(rt::Object& o, rt::Vec3 d);
void translate(rt::Plane& p, rt::Vec3 d);
void translate(rt::Light& l, rt::Vec3 d);

// The CSG operand `path` names below `top` (0 = left, 1 = right at each level; top
// itself for an empty path), or null when there is none.
const rt::Object* operand_of(const rt::Object& top, const std::vector<int>& path);
rt::Object* operand_of(rt::Object& top, const std::vector<int>& path);
// Moves only that operand (the rest of the CSG stays) by `d` in the world, whatever the
// transforms of the CSGs above it; false if there is none.
bool translate_operand(rt::Object& top, const std::vector<int>& path, rt::Vec3 d);

// New: an object's own transform as a map from the frame its shape is written in to the
// one the object is written in (the identity when it has none, and for a mesh, whose
// keys place it).
rt::MeshInstance own_placement(const rt::Object& o);
// The map from the frame the operand `path` names below `top` is written in to the
// world: the transforms of the CSGs above it, composed (the identity for `top` itself).
rt::MeshInstance parent_placement(const rt::Object& top, const std::vector<int>& path);

}  // namespace rtview
