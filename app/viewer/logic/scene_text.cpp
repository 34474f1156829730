// Scene text <-> Scene agreement for the editor (see scene_text.h): where the items'
// blocks are, which items are the file's own, what the text can hold. Items are found
// with the parser's own lexer (scene_lexer.h), so the two cannot disagree about tokens,
// comments or line ends. Changed items written into the text: scene_text_patch.cpp.
#include "scene_text.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "huge_pages.h"
#include "scene_lexer.h"
#include "scene_parser.h"
#include "scene_schema.h"
#include "scene_writer.h"

namespace rtview {

namespace {

// The parser's lexer, plus skipping a block to its matching brace.
class Scanner {
public:
    explicit Scanner(std::string_view t) : lex_(t) {}
    rt::Token next() { return lex_.next(); }
    // Past a file name in double quotes (spaces allowed in it, as the parser reads it)
    // that starts at token `t`; false if it has no closing quote on its line.
    bool skip_quoted(const rt::Token& t) {
        const std::string_view text = lex_.text();
        if (t.text.empty() || t.text[0] != '"') return false;
        std::size_t end = t.offset + 1;
        while (end < text.size() && text[end] != '"' && text[end] != '\n' && text[end] != '\r') ++end;
        if (end >= text.size() || text[end] != '"') return false;
        lex_.seek(end + 1);
        return true;
    }
    // After a `{` has been read: consumes up to and including its matching `}`.
    // Returns the offset just past it, or npos at end of text.
    std::size_t skip_block() {
        int depth = 1;
        for (;;) {
            rt::Token k = next();
            if (k.eof()) return std::string_view::npos;
            if (k.is('{')) ++depth;
            if (k.is('}') && --depth == 0) return k.end();
        }
    }

private:
    rt::SceneLexer lex_;
};

// Re-indents the continuation lines of `block` (written at `from_indent`) to `to_indent`.
std::string reindent(std::string_view block, std::size_t from_indent, const std::string& to_indent) {
    std::string out;
    std::size_t i = 0;
    bool first = true;
    while (i <= block.size()) {
        std::size_t nl = block.find('\n', i);
        std::string_view line = block.substr(i, nl == std::string_view::npos ? std::string_view::npos : nl - i);
        if (!first) {
            std::size_t strip = 0;
            while (strip < from_indent && strip < line.size() && line[strip] == ' ') ++strip;
            out += to_indent;
            line.remove_prefix(strip);
        }
        out += line;
        if (nl == std::string_view::npos) break;
        out += '\n';
        i = nl + 1;
        first = false;
    }
    return out;
}

}  // namespace

std::string line_indent(std::string_view text, std::size_t offset) {
    std::size_t ls = text.find_last_of("\r\n", offset == 0 ? 0 : offset - 1);  // CR alone ends lines too
    ls = (ls == std::string_view::npos || offset == 0) ? 0 : ls + 1;
    std::size_t e = ls;
    while (e < text.size() && (text[e] == ' ' || text[e] == '\t')) ++e;
    return std::string(text.substr(ls, e - ls));
}

std::string written_item(const rt::Scene& one, ItemList list, const std::string& indent) {
    const std::string all = list == ItemList::Camera ? rt::write_camera(one.camera) : rt::write_scene(one);
    const SceneLayout l = scan_layout(all);
    const std::vector<TextSpan>& v = list == ItemList::Object  ? l.objects
                                     : list == ItemList::Plane ? l.planes
                                     : list == ItemList::Light ? l.lights
                                                               : l.cameras;
    if (!l.ok || v.size() != 1) return {};
    return reindent(std::string_view(all).substr(v[0].begin, v[0].end - v[0].begin), line_indent(all, v[0].begin).size(),
                    indent);
}

rt::Scene item_scene(const rt::Scene& s) {
    rt::Scene one;
    one.camera = s.camera;
    one.materials = s.materials;
    for (rt::NamedMaterial& m : one.materials) m.origin = 0;
    one.defined = s.defined;
    for (rt::NamedObject& d : one.defined) d.origin = 0;
    return one;
}

SceneLayout scan_layout(std::string_view text, std::size_t objects) {
    SceneLayout l;
    if (objects > 0) {
        l.objects.reserve(objects);
        rt::advise_huge_pages(l.objects.data(), objects * sizeof(TextSpan));
    }
    Scanner sc(text);
    l.append_at = text.size();
    for (;;) {
        rt::Token k = sc.next();
        if (k.eof()) break;
        if (k.text == "end") {
            l.append_at = k.offset;
            break;
        }
        const rt::schema::Section* section = rt::schema::find_section(k.text);
        if (!section) return l;  // not a section: unclear
        if (section->kind == rt::schema::SectionKind::Include) {
            // `include "FILE"`: its items are the other file's, with no block here.
            const rt::Token name = sc.next();
            if (name.eof() || name.is('{') || name.is('}')) return l;
            if (name.text[0] == '"' && !sc.skip_quoted(name)) return l;
            continue;
        }
        std::vector<TextSpan>* items = nullptr;
        if (section->kind == rt::schema::SectionKind::Things) items = &l.objects;
        else if (section->kind == rt::schema::SectionKind::Specials) items = &l.planes;
        else if (section->kind == rt::schema::SectionKind::Lights) items = &l.lights;
        if (sc.next().text != "{") return l;
        if (!items) {
            std::size_t e = sc.skip_block();
            if (e == std::string_view::npos) return l;
            if (section->kind == rt::schema::SectionKind::Camera) l.cameras.push_back({k.offset, e});
            continue;
        }
        for (;;) {
            rt::Token item = sc.next();
            if (item.eof()) return l;
            if (item.is('}')) break;
            if (sc.next().text != "{") return l;
            std::size_t e = sc.skip_block();
            if (e == std::string_view::npos) return l;
            items->push_back({item.offset, e});
        }
    }
    l.ok = true;
    return l;
}

std::vector<std::pair<std::string, TextSpan>> material_definitions(std::string_view text) {
    std::vector<std::pair<std::string, TextSpan>> out;
    Scanner sc(text);
    for (;;) {
        const rt::Token k = sc.next();
        if (k.eof() || k.text == "end") return out;
        const rt::schema::Section* section = rt::schema::find_section(k.text);
        if (!section) return {};
        if (section->kind == rt::schema::SectionKind::Include) {
            const rt::Token name = sc.next();
            if (name.eof() || name.is('{') || name.is('}')) return {};
            if (name.text[0] == '"' && !sc.skip_quoted(name)) return {};
            continue;
        }
        if (!sc.next().is('{')) return {};
        if (section->kind != rt::schema::SectionKind::Define) {
            if (sc.skip_block() == std::string_view::npos) return {};
            continue;
        }
        for (;;) {
            const rt::Token what = sc.next();
            if (what.is('}')) break;
            const rt::Token name = sc.next();
            const rt::Token open = sc.next();
            if (what.eof() || name.eof() || !open.is('{')) return {};
            const std::size_t e = sc.skip_block();
            if (e == std::string_view::npos) return {};
            if (what.text == "material") out.push_back({std::string(name.text), {open.offset, e}});
        }
    }
}

namespace {

template <class T>
std::optional<std::size_t> own_index_in(const std::vector<T>& v, std::size_t i) {
    if (i >= v.size() || v[i].origin != 0) return std::nullopt;
    std::size_t n = 0;
    for (std::size_t k = 0; k < i; ++k) n += v[k].origin == 0;
    return n;
}

template <class T>
std::size_t own_count_in(const std::vector<T>& v) {
    std::size_t n = 0;
    for (const T& x : v) n += x.origin == 0;
    return n;
}

}  // namespace

std::optional<std::size_t> own_index(const rt::Scene& s, ItemList list, std::size_t i) {
    const std::size_t size = list == ItemList::Object  ? s.objects.size()
                             : list == ItemList::Plane ? s.planes.size()
                             : list == ItemList::Light ? s.lights.size()
                                                       : 0;
    if (i >= size) return std::nullopt;
    if (s.includes.empty()) return i;  // every item is the file's own
    switch (list) {
        case ItemList::Object: return own_index_in(s.objects, i);
        case ItemList::Plane: return own_index_in(s.planes, i);
        case ItemList::Light: return own_index_in(s.lights, i);
        case ItemList::Camera: break;
    }
    return std::nullopt;
}

std::size_t own_count(const rt::Scene& s, ItemList list) {
    const bool all = s.includes.empty();
    switch (list) {
        case ItemList::Object: return all ? s.objects.size() : own_count_in(s.objects);
        case ItemList::Plane: return all ? s.planes.size() : own_count_in(s.planes);
        case ItemList::Light: return all ? s.lights.size() : own_count_in(s.lights);
        case ItemList::Camera: break;
    }
    return 0;
}

const rt::Include* included_file(const rt::Scene& s, ItemList list, std::size_t i) {
    std::uint16_t origin = 0;
    if (list == ItemList::Object && i < s.objects.size()) origin = s.objects[i].origin;
    if (list == ItemList::Plane && i < s.planes.size()) origin = s.planes[i].origin;
    if (list == ItemList::Light && i < s.lights.size()) origin = s.lights[i].origin;
    if (origin == 0 || origin > s.includes.size()) return nullptr;
    return &s.includes[origin - 1u];
}

bool layout_matches(const SceneLayout& l, const rt::Scene& s) {
    return l.ok && l.objects.size() == own_count(s, ItemList::Object) &&
           l.planes.size() == own_count(s, ItemList::Plane) && l.lights.size() == own_count(s, ItemList::Light);
}

namespace {

// What the text holds of an object: its blocks, without what the files they name gave
// (a mesh's model, a material's texture: the stores' business, and no part of the text).
// False if there was nothing to take away.
bool strip_files(rt::Object& o);

bool strip_files(rt::Material& m) {
    if (!m.texture_image) return false;
    m.texture_image = nullptr;
    return true;
}

bool strip_files(rt::Object& o) {
    bool any = strip_files(o.material);
    if (rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape); m && m->model) {
        m->model = nullptr;
        any = true;
    } else if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape)) {
        for (rt::Object& k : g->operands) any = strip_files(k) || any;
    } else if (rt::Instance* in = std::get_if<rt::Instance>(&o.shape); in && in->defined) {
        rt::Object copy = *in->defined;
        if (strip_files(copy)) {
            in->defined = std::make_shared<const rt::Object>(std::move(copy));
            any = true;
        }
    }
    return any;
}

// False if the scene holds nothing read from other files.
bool strip_files(rt::Scene& s) {
    bool any = false;
    for (rt::NamedMaterial& m : s.materials) any = strip_files(m.material) || any;
    for (rt::NamedObject& d : s.defined) {
        if (!d.object) continue;
        rt::Object copy = *d.object;
        if (strip_files(copy)) {
            d.object = std::make_shared<const rt::Object>(std::move(copy));
            any = true;
        }
    }
    for (rt::Object& o : s.objects) any = strip_files(o) || any;
    for (rt::Plane& p : s.planes) {
        any = strip_files(p.material) || any;
        any = strip_files(p.material2) || any;
    }
    return any;
}

// Whether the scene holds anything read from other files (without copying it).
bool holds_files(const rt::Object& o) {
    if (o.material.texture_image) return true;
    if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape)) return m->model != nullptr;
    if (const rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
        return std::any_of(g->operands.begin(), g->operands.end(), [](const rt::Object& k) { return holds_files(k); });
    if (const rt::Instance* in = std::get_if<rt::Instance>(&o.shape)) return in->defined && holds_files(*in->defined);
    return false;
}

bool holds_files(const rt::Scene& s) {
    for (const rt::NamedMaterial& m : s.materials)
        if (m.material.texture_image) return true;
    for (const rt::NamedObject& d : s.defined)
        if (d.object && holds_files(*d.object)) return true;
    for (const rt::Object& o : s.objects)
        if (holds_files(o)) return true;
    for (const rt::Plane& p : s.planes)
        if (p.material.texture_image || p.material2.texture_image) return true;
    return false;
}

}  // namespace

bool text_holds(const rt::Scene& s) {
    // Mesh and texture files are not read: what the text holds of a mesh is its block
    // (which model the file gives is the model store's business, and no part of the
    // text), of a texture its name.
    rt::ParseOptions o;
    o.read_models = false;
    const rt::ParseResult r = rt::parse_scene(rt::write_scene(s), o);
    if (!r.ok()) return false;
    if (!holds_files(s)) return r.scene == s;
    rt::Scene without = s;
    strip_files(without);
    return r.scene == without;
}

rt::Scene carry_edit(const rt::Scene& base, const rt::Scene& old_scene, const rt::Scene& new_scene,
                     bool* complete) {
    rt::Scene r = base;
    bool all = true;
    if (!(old_scene.camera == new_scene.camera)) r.camera = new_scene.camera;
    if (old_scene.width != new_scene.width || old_scene.height != new_scene.height) {
        r.width = new_scene.width;
        r.height = new_scene.height;
    }
    // A named material the edit changed (the same name in the same place in all three)
    // changes in `base` too, for every use of it there (as the panels change it); an
    // item whose only change was that is then no change to carry, so the draft's own
    // changes to it stay.
    std::optional<rt::Scene> renamed;
    if (!(old_scene.materials == new_scene.materials)) {
        const std::size_t n = new_scene.materials.size();
        if (base.materials.size() != n || old_scene.materials.size() != n) all = false;
        else renamed = old_scene;
        for (std::size_t k = 0; renamed && k < n; ++k) {
            const rt::NamedMaterial &a = old_scene.materials[k], &b = new_scene.materials[k];
            if (a == b) continue;
            if (a.name != b.name || base.materials[k].name != b.name || base.materials[k].origin != b.origin) {
                all = false;
                continue;
            }
            use_named_material(r, k, b.material);
            use_named_material(*renamed, k, b.material);
        }
    }
    const rt::Scene& was_scene = renamed ? *renamed : old_scene;
    auto carry = [&all](auto& dst, const auto& was, const auto& now) {
        bool same_count = dst.size() == was.size() && was.size() == now.size();
        for (std::size_t k = 0; k < now.size() && k < was.size(); ++k) {
            if (was[k] == now[k]) continue;
            if (same_count) dst[k] = now[k];
            else all = false;
        }
        if (was.size() != now.size()) all = false;
    };
    carry(r.objects, was_scene.objects, new_scene.objects);
    carry(r.planes, was_scene.planes, new_scene.planes);
    carry(r.lights, was_scene.lights, new_scene.lights);
    if (complete) *complete = all;
    return r;
}

std::size_t offset_of(std::string_view text, int line, int col) { return rt::offset_at(text, line, col); }

namespace {

// The length of the UTF-8 sequence at text[i] (a lead byte and its continuation
// bytes, no overlong forms, no surrogates, at most U+10FFFF), or 0 if it is none.
std::size_t utf8_length(std::string_view text, std::size_t i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // the second byte's range
    if (c >= 0xC2 && c <= 0xDF) n = 2;
    else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
    else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
    else return 0;
    if (i + n > text.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        const unsigned char b = static_cast<unsigned char>(text[i + k]);
        if (k == 1 ? (b < lo || b > hi) : (b < 0x80 || b > 0xBF)) return 0;
    }
    return n;
}

}  // namespace

std::string not_scene_text(std::string_view text) {
    if (const void* nul = std::memchr(text.data(), 0, text.size()))
        return "not a scene text: a NUL byte at byte " +
               std::to_string(static_cast<const char*>(nul) - text.data() + 1) + " (a binary file?)";
    std::size_t foreign = 0, first = 0;
    const std::size_t n = text.size();
    for (std::size_t i = 0; i < n;) {
        // Eight ASCII bytes at a time (most of any scene).
        if (i + 8 <= n) {
            std::uint64_t w;
            std::memcpy(&w, text.data() + i, 8);
            if (!(w & 0x8080808080808080ull)) {
                i += 8;
                continue;
            }
        }
        if (static_cast<unsigned char>(text[i]) < 0x80) {
            ++i;
            continue;
        }
        if (const std::size_t len = utf8_length(text, i)) {
            i += len;
            continue;
        }
        if (foreign++ == 0) first = i;
        ++i;
    }
    if (foreign > kMaxForeignBytes && foreign * 100 > n)
        return "not a scene text: " + std::to_string(foreign) + " of its " + std::to_string(n) +
               " bytes are not UTF-8 text, the first at byte " + std::to_string(first + 1) + " (a binary file?)";
    return {};
}

}  // namespace rtview
