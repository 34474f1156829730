// Scene -> scene-format text, indented two spaces per level, driven by the schema
// (scene_schema.h): every key of every block is written, defaults included, so the
// text does not depend on the parser's defaults; numbers use the shortest digits that
// read back to the same double.
#include "scene_writer.h"

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "scene_schema.h"

namespace rt {

std::string format_number(double v) {
    // The format has no spelling for these; a huge finite value or 0 at least keeps the
    // text well-formed, and the parser's range check then points at the culprit.
    if (std::isnan(v)) v = 0;
    if (std::isinf(v)) v = std::copysign(DBL_MAX, v);
    // to_chars/from_chars are printf("%.*g")/strtod without the locale: a viewer that
    // sets a locale with a decimal comma must not change what gets written.
    char buf[64];
    auto print = [&](int precision) {
        auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, precision);
        return std::string(buf, res.ptr);
    };
    auto exact = [&](const std::string& s) {
        double back = 0;
        std::from_chars(s.data(), s.data() + s.size(), back);
        return back == v;
    };
    int precision = 1;
    while (precision < 17 && !exact(print(precision))) ++precision;
    std::string shortest = print(precision);
    // %g switches to an exponent once the integer part has more digits than the
    // precision, so the shortest text for 60 would be "6e+01". Allow up to six
    // padding zeros to keep round numbers plain. Below 2^53 such a value is exactly
    // that integer, so the padding really is zeros (above, it would be the double's
    // exact binary expansion: 20 digits instead of "8.8134680156415394e+19").
    if (v != 0 && std::fabs(v) < 9007199254740992.0) {
        const int int_digits = int(std::floor(std::log10(std::fabs(v)))) + 1;
        if (int_digits > precision && int_digits <= precision + 6) {
            std::string plain = print(int_digits);
            if (exact(plain)) return plain;
        }
    }
    return shortest;
}

namespace {

namespace sc = schema;

class Writer {
public:
    std::string out;
    // The scene whose named materials are written by name (null, or flattened: every
    // material written out).
    const Scene* scene = nullptr;

    void line(int depth, const std::string& text) {
        out.append(2 * std::size_t(depth), ' ');
        out += text;
        out += '\n';
    }
    static std::string num(double v) { return format_number(v); }
    static std::string vec(const Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }

    // One line: six keys are easier to scan side by side than stacked.
    static std::string material_body(const Material& m) {
        static const Material defaults = sc::material_block().make();
        std::string s = "{";
        for (const sc::Key<Material>& k : sc::material_block().keys)
            if (!(k.optional && at_default(k, m, defaults, 0))) s += " " + simple_value(k, m, 0);
        return s + " }";
    }

    // Whether key k of t holds the value it has in `defaults` (bit for bit for numbers).
    template <class T>
    static bool at_default(const sc::Key<T>& k, const T& t, const T& defaults, int i) {
        auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
        switch (k.kind) {
        case sc::Kind::Number: return same(k.number(t, i), k.number(defaults, i));
        case sc::Kind::Vec3: {
            const Vec3 a = k.vec3(t, i), b = k.vec3(defaults, i);
            return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
        }
        case sc::Kind::File: return k.text(t, i) == k.text(defaults, i);
        case sc::Kind::Integer: return k.integer(t, i) == k.integer(defaults, i);
        case sc::Kind::Choice: return k.access.get_choice(t) == k.access.get_choice(defaults);
        case sc::Kind::Material:
        case sc::Kind::Operand: break;
        }
        return false;
    }

    // `name value` for the keys that fit on one line.
    template <class T>
    static std::string simple_value(const sc::Key<T>& k, const T& t, int i) {
        std::string s(k.name);
        if (k.count > 0) s += " " + std::to_string(i + 1);
        switch (k.kind) {
        case sc::Kind::Number: return s + " " + num(k.number(t, i));
        case sc::Kind::Vec3: {
            const Vec3 v = k.vec3(t, i);
            return s + " " + (k.one_or_three && v.x == v.y && v.y == v.z ? num(v.x) : vec(v));
        }
        case sc::Kind::File: return s + (k.bare ? " " + k.text(t, i) : " \"" + k.text(t, i) + "\"");
        case sc::Kind::Integer: return s + " " + std::to_string(k.integer(t, i));
        case sc::Kind::Choice: return s + " " + std::string(k.choice->word_for(k.access.get_choice(t)));
        case sc::Kind::Material: return s + " " + material_body(k.material(t, i));
        case sc::Kind::Operand: break;
        }
        return s;
    }

    // A block: the lead keys first, then the rest, each in schema order.
    template <class T>
    void item(int depth, const sc::Block<T>& b, const T& t) {
        line(depth, std::string(b.name) + " {");
        // (Made only for blocks with optional keys: writing a big scene makes no copies.)
        const bool optional = std::any_of(b.keys.begin(), b.keys.end(), [](const sc::Key<T>& k) { return k.optional; });
        const std::optional<T> defaults = optional ? std::optional<T>(b.make()) : std::nullopt;
        for (bool lead : {true, false})
            for (const sc::Key<T>& k : b.keys)
                if (k.lead == lead) key(depth + 1, k, t, defaults ? &*defaults : nullptr);
        line(depth, "}");
    }

    template <class T>
    void key(int depth, const sc::Key<T>& k, const T& t, const T* defaults) {
        for (int i = 0; i < std::max(k.count, 1); ++i) {
            if (k.optional && defaults && at_default(k, t, *defaults, i)) continue;
            if (k.kind == sc::Kind::Operand) {
                // Only CSGs have operands.
                if constexpr (std::is_same_v<T, Object>) {
                    const Object* o = k.operand(t, i);
                    if (!o) continue;
                    line(depth, std::string(k.name) + " {");
                    item(depth + 1, sc::object_block(*o), *o);
                    line(depth, "}");
                }
                continue;
            }
            // Only when the file had a block: has_material is part of the scene, and a
            // block-less item's default (translusans 0) differs from a block's (1).
            if (k.kind == sc::Kind::Material && !k.has_material(t, i)) continue;
            if (k.kind == sc::Kind::Material && scene) {
                // By name while it holds the definition's values (an edited use is
                // written out in full: the edit is not lost).
                const Material& m = k.material(t, i);
                const int named = m.named;
                if (named >= 0 && std::size_t(named) < scene->materials.size() &&
                    m.same_bits(scene->materials[std::size_t(named)].material)) {
                    line(depth, std::string(k.name) + (k.count > 0 ? " " + std::to_string(i + 1) : "") + " " +
                                    scene->materials[std::size_t(named)].name);
                    continue;
                }
            }
            line(depth, simple_value(k, t, i));
        }
    }
};

}  // namespace

namespace {

// A block on one line, its keys as the writer orders them: `sphere { position 0 0 0 ... }`.
// Materials and operands are named, not spelled out.
template <class T>
std::string block_line(const sc::Block<T>& b) {
    const T item = b.make();
    std::string s = std::string(b.name) + " {";
    const char* gap = " ";
    for (bool lead : {true, false})
        for (const sc::Key<T>& k : b.keys) {
            if (k.lead != lead || k.default_text) continue;
            for (int i = 0; i < std::max(k.count, 1); ++i, gap = "  ") {
                const std::string index = k.count > 0 ? " " + std::to_string(i + 1) : "";
                s += gap;
                if (k.kind == sc::Kind::Material) s += std::string(k.name) + index + " {...}";
                else if (k.kind == sc::Kind::Operand) s += std::string(k.name) + " { OBJECT }";
                else if (k.kind == sc::Kind::File && k.bare) s += std::string(k.name) + " " + k.placeholder;
                else if (k.kind == sc::Kind::File) s += std::string(k.name) + " \"" + k.placeholder + "\"";
                else s += Writer::simple_value(k, item, i);
            }
        }
    return s + " }";
}

// `list` with `item` after a comma, as the reference lists names.
void add_listed(std::string& list, std::string_view item) {
    if (!list.empty()) list += ", ";
    list += item;
}

// The rules of a block's keys: the keys it must have, choices, ranges (errors and
// clamps); each rule once.
template <class T>
void key_rules(const sc::Block<T>& b, std::vector<std::string>& required, std::vector<std::string>& rules) {
    std::string needed;
    auto add = [&rules](const std::string& r) {
        if (std::find(rules.begin(), rules.end(), r) == rules.end()) rules.push_back(r);
    };
    for (const sc::Key<T>& k : b.keys) {
        const std::string name = std::string(b.name) + " " + std::string(k.name);
        if (k.required) add_listed(needed, k.name);
        if (k.default_text) add(name + ": " + k.default_text + " unless given");
        if (k.choice) {
            std::string words;
            for (const sc::Choice::Word& w : k.choice->words) add_listed(words, w.word);
            add(name + ": one of " + words);
        }
        if (k.range.rule == sc::Range::Rule::Error && k.range.message) add(k.range.message);
        if (k.range.rule == sc::Range::Rule::Clamp)
            add(name + " is clamped to " + format_number(k.range.min) +
                (k.range.max < 1e300 ? ".." + format_number(k.range.max) : " or more"));
    }
    if (!needed.empty()) required.push_back(std::string(b.name) + ": " + needed);
}

}  // namespace

std::string format_reference() {
    std::string optional;
    for (const sc::Section& s : sc::sections())
        if (s.item_noun) add_listed(optional, s.name);
    std::string out = "The scene format: sections in any order, any number of times (" + optional +
                      "\nmay be left out; a name is defined before its first use), `end` closing the file. Every\n"
                      "block with each of its keys at its default, but the keys a block must have (listed\n"
                      "below), which show an example value; `//` starts a comment.\n\n";
    std::vector<std::string> required, rules;
    auto block = [&](const auto& b, const char* indent) {
        out += indent + block_line(b) + "\n";
        key_rules(b, required, rules);
    };
    auto items = [&](const sc::Section& s, const auto& blocks) {
        out += std::string(s.name) + " {\n";
        for (const auto& b : blocks) block(b, "  ");
        out += "}\n";
    };
    for (const sc::Section& s : sc::sections()) {
        switch (s.kind) {
        case sc::SectionKind::Things: items(s, sc::object_blocks()); break;
        case sc::SectionKind::Specials: items(s, sc::plane_blocks()); break;
        case sc::SectionKind::Lights: items(s, sc::light_blocks()); break;
        case sc::SectionKind::Camera: block(sc::camera_block(), ""); break;
        case sc::SectionKind::PictureSize: block(sc::picture_size_block(), ""); break;
        case sc::SectionKind::End: out += std::string(s.name) + "\n"; break;
        case sc::SectionKind::Include: out += std::string(s.name) + " \"FILE.txt\"\n"; break;
        case sc::SectionKind::Define:
            out += std::string(s.name) + " {\n  material NAME {...}\n  object NAME { OBJECT }\n}\n";
            break;
        }
    }
    key_rules(sc::material_block(), required, rules);
    out += "\nmaterial {...} is " + block_line(sc::material_block()) + "\n";
    out += "OBJECT is any one block of `thing` (a mesh excepted)\n";
    out += "material NAME, where a material {...} goes, is the one defined as NAME before it\n";
    out += "include \"FILE.txt\" reads that file's sections (all but camera and picture_size) there\n";
    out += "\nKeys a block must have:\n";
    for (const std::string& r : required) out += "  " + r + "\n";
    out += "Values:\n";
    for (const std::string& r : rules) out += "  " + r + "\n";
    return out;
}

std::string write_material(const Material& m) { return Writer::material_body(m); }

std::string write_camera(const Camera& camera) {
    Writer w;
    w.item(0, sc::camera_block(), camera);
    return w.out;
}

namespace {
// An instance as an object of its own, for a flattened scene: its definition with the
// instance's transform and material; a definition with a transform of its own goes
// inside a CSG that carries the instance's (both operands the definition: the same
// solid), so that the two apply in their order.
Object expanded(const Object& o) {
    const Instance& in = std::get<Instance>(o.shape);
    Object out;
    if (!in.defined->transform.set()) {
        out = *in.defined;
    } else {
        Csg c;
        c.type = CsgType::Intersection;
        c.operands = {*in.defined, *in.defined};
        out.shape = std::move(c);
    }
    out.material = o.material;
    out.has_material = true;
    out.transform = o.transform;
    return out;
}
}  // namespace

namespace {
// The scene file's own named materials [from, to) and named objects [objects_from,
// objects_to) (counted among its own), in a `define` section if there are any.
void write_definitions(Writer& w, const Scene& scene, std::size_t from, std::size_t to, std::size_t objects_from,
                       std::size_t objects_to) {
    std::size_t k = 0;
    bool open = false;
    for (const NamedMaterial& m : scene.materials) {
        if (m.origin != 0) continue;
        if (k >= from && k < to) {
            if (!open) w.line(0, "define {"), open = true;
            w.line(1, "material " + m.name + " " + write_material(m.material));
        }
        ++k;
    }
    k = 0;
    for (const NamedObject& d : scene.defined) {
        if (d.origin != 0 || !d.object) continue;
        if (k >= objects_from && k < objects_to) {
            if (!open) w.line(0, "define {"), open = true;
            w.line(1, "object " + d.name + " {");
            w.item(2, sc::object_block(*d.object), *d.object);
            w.line(1, "}");
        }
        ++k;
    }
    if (open) w.line(0, "}");
}
}  // namespace

std::string write_scene(const Scene& scene, bool flatten) {
    Writer w;
    if (!flatten) w.scene = &scene;
    // Sections of items are left out when empty; camera and picture size always written.
    // Unless flattened, only the scene file's own items are (the included ones are the
    // included files'), split where each include stands among them.
    auto items = [&w](const sc::Section& s, const auto& list, std::size_t from, std::size_t to, auto block_of, bool own) {
        std::size_t k = 0;  // of the items written so far: the own ones, unless all
        bool open = false;
        for (const auto& item : list) {
            if (own && item.origin != 0) continue;
            if (k >= from && k < to) {
                if (!open) w.line(0, std::string(s.name) + " {"), open = true;
                bool done = false;
                if constexpr (std::is_same_v<std::decay_t<decltype(item)>, Object>) {
                    if (!own && std::holds_alternative<Instance>(item.shape) && std::get<Instance>(item.shape).defined) {
                        const Object x = expanded(item);
                        w.item(1, block_of(x), x);
                        done = true;
                    }
                }
                if (!done) w.item(1, block_of(item), item);
            }
            ++k;
        }
        if (open) w.line(0, "}");
    };
    const std::size_t all = std::size_t(-1);
    const std::size_t parts = flatten ? 1 : scene.includes.size() + 1;
    Include before;  // (counts) where the previous include stood
    for (std::size_t p = 0; p < parts; ++p) {
        const bool last = p + 1 == parts;
        const Include& at = last ? Include{} : scene.includes[p];
        const bool own = !flatten;
        if (!flatten)
            write_definitions(w, scene, before.materials, last ? all : at.materials, before.defined, last ? all : at.defined);
        for (const sc::Section& s : sc::sections()) {
            switch (s.kind) {
            case sc::SectionKind::Things:
                items(s, scene.objects, before.objects, last ? all : at.objects,
                      [](const Object& o) -> const auto& { return sc::object_block(o); }, own);
                break;
            case sc::SectionKind::Specials:
                items(s, scene.planes, before.planes, last ? all : at.planes,
                      [](const Plane& pl) -> const auto& { return sc::plane_block(pl); }, own);
                break;
            case sc::SectionKind::Lights:
                items(s, scene.lights, before.lights, last ? all : at.lights,
                      [](const Light& l) -> const auto& { return sc::light_block(l); }, own);
                break;
            default: break;
            }
        }
        if (!last) {
            w.line(0, "include \"" + at.file + "\"");
            before = at;
        }
    }
    for (const sc::Section& s : sc::sections()) {
        switch (s.kind) {
        case sc::SectionKind::Camera: w.item(0, sc::camera_block(), scene.camera); break;
        case sc::SectionKind::PictureSize: w.item(0, sc::picture_size_block(), scene); break;
        case sc::SectionKind::End: w.line(0, std::string(s.name)); break;
        default: break;
        }
    }
    return w.out;
}

}  // namespace rt
