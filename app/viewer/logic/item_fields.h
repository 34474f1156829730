// The keys of a scene item as editable fields, generated from the schema
// (scene_schema.h): which keys the selected object, CSG operand, plane or light has,
// their current values, and setting one with the parser's ranges, clamps and
// messages. The panels draw a widget per field; no GL, unit-tested in tests/viewer.
//   for (const Field& f : item_fields(scene, ref))
//       if (f.kind == rt::schema::Kind::Number) edit(f.label, field_value(scene, ref, f)->number);
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene.h"
#include "scene_edits.h"
#include "scene_schema.h"
#include "status.h"

namespace rtview {

class Document;

// One key of the item's block (one per index for keys with an index: "point 2").
struct Field {
    std::string label;       // "radius", "point 2", "material 1"
    std::string_view key;    // the key's name in the format
    rt::schema::Kind kind = rt::schema::Kind::Number;
    int index = 0;           // the key's index - 1 (0 for keys without one)
    int key_number = 0;      // the key's place in its block's key list
    const rt::schema::Range* range = nullptr;   // Number keys
    const rt::schema::Choice* choice = nullptr;  // Choice keys
};

// A field's value; the member of the field's kind is the one that counts.
struct FieldValue {
    double number = 0;
    rt::Vec3 vec;
    int choice = 0;
    rt::Material material;
    bool has_material = false;  // Material: the block gives one (else the default is shown)
    const rt::Object* operand = nullptr;  // Operand: the object inside it
    std::string text;                     // File: the name as written
};

// The block the item is written as ("sphere", "chess_plane", "lamp"), or null if `ref`
// names nothing in `scene`.
const char* item_block_name(const rt::Scene& scene, const ItemRef& ref);
// The item as the undo history names it: its block and its number in the outline
// ("sphere 3", "lamp 1"; an operand: "left sphere of object 4"), "" for nothing.
std::string item_label(const rt::Scene& scene, const ItemRef& ref);
// The item's keys: lead keys (a CSG's `type`), the others in schema order, materials
// last. A CSG operand has no material field: only the whole CSG's material is
// rendered, so one there would change the text and nothing in the picture. Empty if
// `ref` names nothing.
std::vector<Field> item_fields(const rt::Scene& scene, const ItemRef& ref);
std::optional<FieldValue> field_value(const rt::Scene& scene, const ItemRef& ref, const Field& f);

struct FieldResult {
    rt::Status status;    // refused: the message the parser gives for such a value
    std::string warning;  // applied; the parser warns about the item as it is now
    bool applied() const { return status.ok(); }
};

// Sets one field of a scene item after the parser's checks: numbers finite and of
// magnitude at most 1e15, the key's range (an error refuses the value, a clamp clamps
// it), then the block's rule across its keys (a flat tetrahedron, a cylinder with equal
// ends, plane points on one line ... refuse it; a warning lets it through).
FieldResult set_field(rt::Scene& scene, const ItemRef& ref, const Field& f, const FieldValue& v);
// The same, as a pending edit of the document (Document::commit ends it: a whole slider
// drag is one undo step and one rewrite of the item's block), named "Edit radius of
// sphere 1". Nothing is touched when the value is refused or unchanged. A material's
// texture given a new name is read (Document::load_texture): refused, with the
// reader's message, if it cannot be.
// A material field whose value uses a named material (`material gold`) edits the
// definition, for every use of it (Document::set_named_material, named "Edit material
// gold"); one given with FieldValue::material.named -1 makes the item's own copy (as
// make_material_local does).
FieldResult set_field(Document& doc, const ItemRef& ref, const Field& f, const FieldValue& v);

// The named material (an index into scene.materials) the material field `f` of `ref`
// uses, or -1 when it is written out in place.
int named_material_of(const rt::Scene& scene, const ItemRef& ref, const Field& f);
// How many things use named material `k`: objects (for a use anywhere in them, a CSG's
// operands and named objects' definitions included) and planes, each counted once.
std::size_t material_users(const rt::Scene& scene, std::size_t k);
// "Make local": the material field `f` of `ref` gets its own copy of the named material
// it uses (the same values, written out in its block), as one undo step; the other
// users keep the name.
FieldResult make_material_local(Document& doc, const ItemRef& ref, const Field& f);

// A file name the format can hold (a texture's, a mesh's), with the parser's message
// for one it cannot: empty, too long, or holding a double quote or control character.
rt::Status check_file_name(std::string_view name);
// A number outside the format's range fails, with the parser's message for it.
rt::Status check_number(double v);
// A number typed into a field, read as the parser reads a number token (spaces
// around it allowed): the whole text or nothing, with the parser's message.
rt::Status parse_typed_number(std::string_view text, double& v);

}  // namespace rtview
