// Fields of scene items from the schema (see item_fields.h). Every check here is one
// the parser makes, with its message: what the panel refuses the text would refuse.
#include "item_fields.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "scene_lexer.h"
#include "document.h"
#include "scene_writer.h"

namespace rtview {

namespace {

namespace sc = rt::schema;

// The object `ref` names inside `top` (top itself for an empty path), or null.
rt::Object* operand_at(rt::Object& top, const std::vector<int>& path) {
    rt::Object* o = &top;
    for (int k : path) {
        auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || k >= int(g->operands.size())) return nullptr;
        o = &g->operands[std::size_t(k)];
    }
    return o;
}

bool in_range(const rt::Scene& s, const SceneItem& it) {
    if (it.index < 0) return false;
    const std::size_t i = std::size_t(it.index);
    switch (it.kind) {
        case SceneItem::Kind::Object: return i < s.objects.size();
        case SceneItem::Kind::Plane: return i < s.planes.size();
        case SceneItem::Kind::Light: return i < s.lights.size();
    }
    return false;
}

// Calls f(block, item) with the item `ref` names in `scene` (non-const: the set_field
// paths write through it). False if there is none.
template <class F>
bool visit_item(rt::Scene& scene, const ItemRef& ref, F&& f) {
    if (!in_range(scene, ref.item)) return false;
    const std::size_t i = std::size_t(ref.item.index);
    switch (ref.item.kind) {
        case SceneItem::Kind::Object: {
            rt::Object* o = operand_at(scene.objects[i], ref.path);
            if (!o) return false;
            f(sc::object_block(*o), *o);
            return true;
        }
        case SceneItem::Kind::Plane:
            if (!ref.path.empty()) return false;
            f(sc::plane_block(scene.planes[i]), scene.planes[i]);
            return true;
        case SceneItem::Kind::Light:
            if (!ref.path.empty()) return false;
            f(sc::light_block(scene.lights[i]), scene.lights[i]);
            return true;
    }
    return false;
}

template <class T>
std::vector<Field> fields_of(const sc::Block<T>& b) {
    std::vector<Field> out;
    // Lead keys, the rest, then materials: what an item is and where it is matters
    // first in a panel (the writer leads with the material instead).
    auto rank = [](const sc::Key<T>& k) { return k.kind == sc::Kind::Material ? 2 : k.lead ? 0 : 1; };
    for (int r = 0; r < 3; ++r)
        for (std::size_t n = 0; n < b.keys.size(); ++n) {
            const sc::Key<T>& k = b.keys[n];
            if (rank(k) != r) continue;
            for (int i = 0; i < std::max(k.count, 1); ++i) {
                Field f;
                f.label = std::string(k.name) + (k.count > 0 ? " " + std::to_string(i + 1) : "");
                f.key = k.name;
                f.kind = k.kind;
                f.index = i;
                f.key_number = int(n);
                f.range = &k.range;
                f.choice = k.choice;
                out.push_back(std::move(f));
            }
        }
    return out;
}

template <class T>
FieldValue value_of(const sc::Block<T>& b, const T& item, const Field& f) {
    const sc::Key<T>& k = b.keys[std::size_t(f.key_number)];
    FieldValue v;
    switch (k.kind) {
        case sc::Kind::Number: v.number = k.number(item, f.index); break;
        case sc::Kind::Vec3: v.vec = k.vec3(item, f.index); break;
        case sc::Kind::Integer: v.number = k.integer(item, f.index); break;
        case sc::Kind::Choice: v.choice = k.access.get_choice(item); break;
        case sc::Kind::Material:
            v.material = k.material(item, f.index);
            v.has_material = k.has_material(item, f.index);
            break;
        case sc::Kind::Operand: v.operand = k.operand(item, f.index); break;
        case sc::Kind::File: v.text = k.text(item, f.index); break;
    }
    return v;
}

// A value the parser would refuse, with its message.
rt::Status refused(std::string message) { return rt::Status::error(std::move(message), rt::kExitScene); }

rt::Status check_vec(const rt::Vec3& v) {
    for (int c = 0; c < 3; ++c)
        if (rt::Status st = check_number(v[c]); !st) return st;
    return {};
}

// A material as the parser leaves it: numbers checked, clamps applied.
rt::Status check_material(rt::Material& m) {
    for (const sc::Key<rt::Material>& k : sc::material_block().keys) {
        if (k.kind == sc::Kind::Vec3) {
            if (rt::Status st = check_vec(k.vec3(m)); !st) return st;
            continue;
        }
        if (k.kind != sc::Kind::Number) continue;  // a texture's name: read when the text is parsed
        double& x = k.access.number(m, 0);
        if (rt::Status st = check_number(x); !st) return st;
        if (k.range.rule == sc::Range::Rule::Clamp && !k.range.contains(x)) x = std::clamp(x, k.range.min, k.range.max);
        if (k.range.rule == sc::Range::Rule::Error && !k.range.contains(x)) return refused(k.range.message);
    }
    return {};
}

// Sets the field on a copy of `item`; the copy replaces it only if every check passes.
template <class T>
FieldResult assign(const sc::Block<T>& b, T& item, const Field& f, const FieldValue& v) {
    FieldResult r;
    if (f.key_number < 0 || std::size_t(f.key_number) >= b.keys.size() || b.keys[std::size_t(f.key_number)].name != f.key ||
        f.index < 0 || f.index >= std::max(b.keys[std::size_t(f.key_number)].count, 1)) {
        r.status = refused("the item has no key '" + std::string(f.key) + "'");
        return r;
    }
    const sc::Key<T>& k = b.keys[std::size_t(f.key_number)];
    T copy = item;
    switch (k.kind) {
        case sc::Kind::Number: {
            double x = v.number;
            if (r.status = check_number(x); !r.status) return r;
            if (!k.range.contains(x)) {
                if (k.range.rule == sc::Range::Rule::Error) {
                    r.status = refused(k.range.message);
                    return r;
                }
                if (k.range.rule == sc::Range::Rule::Clamp) x = std::clamp(x, k.range.min, k.range.max);
            }
            k.access.number(copy, f.index) = x;
            break;
        }
        case sc::Kind::Vec3:
            if (r.status = check_vec(v.vec); !r.status) return r;
            k.access.vec3(copy, f.index) = v.vec;
            break;
        case sc::Kind::Integer: {
            const double x = std::round(v.number);
            if (!(x >= k.range.min && x <= k.range.max)) {
                r.status = refused(k.range.message ? k.range.message : "number out of range");
                return r;
            }
            k.access.integer(copy, f.index) = int(x);
            break;
        }
        case sc::Kind::Choice:
            if (k.choice->word_for(v.choice).empty()) {
                r.status = refused(std::string(k.choice->wrong) + "'" + std::to_string(v.choice) + "'");
                return r;
            }
            k.access.set_choice(copy, v.choice);
            break;
        case sc::Kind::Material: {
            rt::Material m = v.material;
            if (r.status = check_material(m); !r.status) return r;
            k.access.material(copy, f.index) = m;
            k.access.has_material(copy, f.index) = true;
            if (sc::Problem p = sc::material_block().check(m)) r.warning = p.message;
            break;
        }
        case sc::Kind::Operand:
            r.status = refused("select the " + std::string(k.name) + " operand to edit it");
            return r;
        case sc::Kind::File:
            // The model is read when the text is parsed: a field could not read it.
            r.status = refused("change the " + std::string(k.name) + " in the scene text (Ctrl+E)");
            return r;
    }
    if (b.check) {
        if (sc::Problem p = b.check(copy)) {
            if (p.severity == sc::Problem::Severity::Error) {
                r.status = refused(p.message);
                r.warning.clear();
                return r;
            }
            if (r.warning.empty()) r.warning = p.message;
        }
    }
    item = std::move(copy);
    return r;
}

// The material field `f` of the item `ref` names, or null.
rt::Material* material_at(rt::Scene& scene, const ItemRef& ref, const Field& f) {
    rt::Material* m = nullptr;
    if (f.kind != sc::Kind::Material || f.key_number < 0) return nullptr;
    visit_item(scene, ref, [&](const auto& b, auto& item) {
        if (std::size_t(f.key_number) >= b.keys.size()) return;
        const auto& k = b.keys[std::size_t(f.key_number)];
        if (k.name == f.key && k.kind == sc::Kind::Material && f.index >= 0 && f.index < std::max(k.count, 1))
            m = &k.access.material(item, f.index);
    });
    return m;
}

}  // namespace

rt::Status check_file_name(std::string_view name) {
    // As the parser words it (file_name in scene_parser.cpp).
    if (name.empty()) return refused("the file name is empty");
    if (name.size() > 4096) return refused("file name too long (" + std::to_string(name.size()) + " characters, limit 4096)");
    for (char c : name)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '"')
            return refused("the file name '" + std::string(name) + "'" +
                           (c == '"' ? " holds a double quote" : " holds a control character"));
    return {};
}

rt::Status parse_typed_number(std::string_view text, double& v) {
    const std::size_t b = text.find_first_not_of(" \t"), e = text.find_last_not_of(" \t");
    const std::string_view t = b == std::string_view::npos ? std::string_view() : text.substr(b, e - b + 1);
    if (t.empty()) return refused("expected a number, got nothing");
    auto quoted = [](std::string_view s) {
        // A typed text may be anything: shown short, and printable.
        std::string q;
        for (char c : s.substr(0, 40)) q += (c >= 32 && c < 127) ? c : '?';
        return "'" + q + (s.size() > 40 ? "...'" : "'");
    };
    if (t.size() > rt::Limits::max_token_length || !rt::is_number_syntax(t))
        return refused("expected a number, got " + quoted(t));
    const double d = rt::number_value(t);
    if (!std::isfinite(d) || std::fabs(d) > 1e15)
        return refused("number " + quoted(t) + " is out of range (magnitude at most 1e15)");
    v = d;
    return {};
}

rt::Status check_number(double v) {
    // As the parser words it for a token it cannot take as a number.
    constexpr double kMaxMagnitude = 1e15;
    if (std::isnan(v)) return refused("number 'nan' is out of range (magnitude at most 1e15)");
    if (std::isinf(v))
        return refused(std::string("number '") + (v < 0 ? "-inf" : "inf") + "' is out of range (magnitude at most 1e15)");
    if (std::fabs(v) > kMaxMagnitude)
        return refused("number '" + rt::format_number(v) + "' is out of range (magnitude at most 1e15)");
    return {};
}

const char* item_block_name(const rt::Scene& scene, const ItemRef& ref) {
    const char* name = nullptr;
    visit_item(const_cast<rt::Scene&>(scene), ref, [&](const auto& b, const auto&) { name = b.name.data(); });
    return name;
}

std::string item_label(const rt::Scene& scene, const ItemRef& ref) {
    const char* block = item_block_name(scene, ref);
    if (!block) return {};
    std::string where;
    for (int k : ref.path) where += k == 0 ? "left " : "right ";
    if (!ref.path.empty()) return where + block + " of object " + std::to_string(ref.item.index + 1);
    return std::string(block) + " " + std::to_string(ref.item.index + 1);
}

std::vector<Field> item_fields(const rt::Scene& scene, const ItemRef& ref) {
    std::vector<Field> out;
    visit_item(const_cast<rt::Scene&>(scene), ref, [&](const auto& b, const auto&) { out = fields_of(b); });
    if (!ref.path.empty())
        out.erase(std::remove_if(out.begin(), out.end(), [](const Field& f) { return f.kind == sc::Kind::Material; }),
                  out.end());
    return out;
}

std::optional<FieldValue> field_value(const rt::Scene& scene, const ItemRef& ref, const Field& f) {
    std::optional<FieldValue> v;
    visit_item(const_cast<rt::Scene&>(scene), ref, [&](const auto& b, const auto& item) {
        if (f.key_number >= 0 && std::size_t(f.key_number) < b.keys.size() && b.keys[std::size_t(f.key_number)].name == f.key)
            v = value_of(b, item, f);
    });
    return v;
}

FieldResult set_field(rt::Scene& scene, const ItemRef& ref, const Field& f, const FieldValue& v) {
    FieldResult r;
    if (!visit_item(scene, ref, [&](const auto& b, auto& item) { r = assign(b, item, f, v); }))
        r.status = refused("the selected item no longer exists");
    return r;
}

FieldResult set_field(Document& doc, const ItemRef& ref, const Field& f, const FieldValue& v) {
    FieldResult r;
    if (!doc.has_scene() || !in_range(doc.scene(), ref.item)) {
        r.status = refused("the selected item no longer exists");
        return r;
    }
    // Checked on a copy of the one top-level item; the document sees only a real change.
    const std::size_t i = std::size_t(ref.item.index);
    rt::Scene one;
    switch (ref.item.kind) {
        case SceneItem::Kind::Object: one.objects.push_back(doc.scene().objects[i]); break;
        case SceneItem::Kind::Plane: one.planes.push_back(doc.scene().planes[i]); break;
        case SceneItem::Kind::Light: one.lights.push_back(doc.scene().lights[i]); break;
    }
    ItemRef local = ref;
    local.item.index = 0;
    r = set_field(one, local, f, v);
    if (!r.applied()) return r;
    // A material's texture named anew is read now, through the document's store: a file
    // that does not read is refused with the reader's message, as the parser words it.
    if (rt::Material* now = material_at(one, local, f)) {
        const rt::Material* before = material_at(const_cast<rt::Scene&>(doc.scene()), ref, f);
        if (before && before->texture != now->texture) {
            if (now->texture.empty()) {
                now->texture_image.reset();
            } else {
                if (r.status = check_file_name(now->texture); !r.status) return r;
                std::string error;
                now->texture_image = doc.load_texture(now->texture, error);
                if (!now->texture_image) {
                    r.status = refused(now->texture + ": " + error);
                    r.warning.clear();
                    return r;
                }
            }
        }
    }
    // An edit of a use of a named material is an edit of its definition, for all users.
    if (const rt::Material* now = material_at(one, local, f)) {
        const int k = named_material_of(doc.scene(), ref, f);
        if (k >= 0 && now->named == k) {
            if (!doc.set_named_material(std::size_t(k), *now)) {
                r.status = refused("material " + doc.scene().materials[std::size_t(k)].name +
                                   " comes from an included file: open that file to edit it");
                r.warning.clear();
                return r;
            }
            if (doc.edit_held()) doc.name_edit("Edit material " + doc.scene().materials[std::size_t(k)].name);
            return r;
        }
    }
    switch (ref.item.kind) {
        case SceneItem::Kind::Object:
            if (!(one.objects[0] == doc.scene().objects[i])) doc.edit_object(i) = std::move(one.objects[0]);
            break;
        case SceneItem::Kind::Plane:
            if (!(one.planes[0] == doc.scene().planes[i])) doc.edit_plane(i) = std::move(one.planes[0]);
            break;
        case SceneItem::Kind::Light:
            if (!(one.lights[0] == doc.scene().lights[i])) doc.edit_light(i) = std::move(one.lights[0]);
            break;
    }
    if (doc.edit_held()) doc.name_edit("Edit " + f.label + " of " + item_label(doc.scene(), ref));
    return r;
}

int named_material_of(const rt::Scene& scene, const ItemRef& ref, const Field& f) {
    const rt::Material* m = material_at(const_cast<rt::Scene&>(scene), ref, f);
    if (!m || m->named < 0 || std::size_t(m->named) >= scene.materials.size()) return -1;
    return m->same_bits(scene.materials[std::size_t(m->named)].material) ? m->named : -1;
}

namespace {

bool uses(const rt::Material& m, const rt::Scene& scene, std::size_t k) {
    return m.named == int(k) && m.same_bits(scene.materials[k].material);
}

bool uses(const rt::Object& o, const rt::Scene& scene, std::size_t k) {
    if (uses(o.material, scene, k)) return true;
    if (const rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
        return std::any_of(g->operands.begin(), g->operands.end(), [&](const rt::Object& x) { return uses(x, scene, k); });
    if (const rt::Instance* in = std::get_if<rt::Instance>(&o.shape)) return in->defined && uses(*in->defined, scene, k);
    return false;
}

}  // namespace

std::size_t material_users(const rt::Scene& scene, std::size_t k) {
    if (k >= scene.materials.size()) return 0;
    std::size_t n = 0;
    for (const rt::Object& o : scene.objects) n += uses(o, scene, k);
    for (const rt::Plane& p : scene.planes) n += uses(p.material, scene, k) || uses(p.material2, scene, k);
    return n;
}

FieldResult make_material_local(Document& doc, const ItemRef& ref, const Field& f) {
    FieldResult r;
    std::optional<FieldValue> v = doc.has_scene() ? field_value(doc.scene(), ref, f) : std::nullopt;
    if (!v || named_material_of(doc.scene(), ref, f) < 0) {
        r.status = refused("the material is not a named one");
        return r;
    }
    const std::string name = doc.scene().materials[std::size_t(v->material.named)].name;
    v->material.named = -1;
    doc.commit();
    r = set_field(doc, ref, f, *v);
    if (doc.edit_held()) doc.name_edit("Make " + item_label(doc.scene(), ref) + "'s material local (was " + name + ")");
    doc.commit();
    return r;
}

}  // namespace rtview
