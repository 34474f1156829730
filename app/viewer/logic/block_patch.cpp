// Value-level rewrites of one block (see block_patch.h). The block's tokens are read
// with the parser's lexer and its keys with the schema, so a key is found exactly where
// the parser took its value from (the last time it was given).
#include "block_patch.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <type_traits>
#include <utility>
#include <vector>

#include "scene_lexer.h"
#include "scene_parser.h"
#include "scene_schema.h"
#include "scene_writer.h"
#include "text_replacement.h"

namespace rtview {

namespace {

namespace sc = rt::schema;

std::string vec_text(const rt::Vec3& v) {
    return rt::format_number(v.x) + " " + rt::format_number(v.y) + " " + rt::format_number(v.z);
}

// `{ reflection ... colour r g b }`, as the writer prints a material.
std::string material_text(const rt::Material& m) { return rt::write_material(m); }

// A number is rewritten when its text would change: -0 and 0 are equal as numbers, but
// the text must read back as the very value the scene holds.
bool same(double a, double b) { return a == b && std::signbit(a) == std::signbit(b); }
bool same(const rt::Vec3& a, const rt::Vec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }
bool same(const rt::Material& a, const rt::Material& b) { return material_text(a) == material_text(b); }

class Patcher {
public:
    explicit Patcher(std::string_view text) : text_(text) {
        rt::SceneLexer lex(text);
        for (;;) {
            rt::Token t = lex.next();
            if (t.eof()) break;
            toks_.push_back(t);
        }
    }

    // The item's name at token 0, its body after it.
    template <class T>
    bool item(const sc::Block<T>& b, const T& before, const T& after) {
        if (toks_.size() < 2 || !toks_[0].is(b.name)) return false;
        std::size_t i = 1;
        return body(b, i, before, after) && i == toks_.size();
    }

    // A block's body on its own, its `{` at token 0 (a material's).
    template <class T>
    bool bare(const sc::Block<T>& b, const T& before, const T& after) {
        std::size_t i = 0;
        return body(b, i, before, after) && i == toks_.size();
    }

    std::string result() const {
        std::vector<TextReplacement> reps = reps_;
        // Insertions at one place keep the order they were made in.
        std::stable_sort(reps.begin(), reps.end(), [](const TextReplacement& a, const TextReplacement& b) { return a.offset < b.offset; });
        std::string out;
        std::size_t pos = 0;
        for (const TextReplacement& r : reps) {
            out.append(text_.substr(pos, r.offset - pos));
            out += r.text;
            pos = r.offset + r.length;
        }
        out.append(text_.substr(pos));
        return out;
    }

private:
    bool is_brace(std::size_t i, char c) const { return i < toks_.size() && toks_[i].is(c); }
    // Whether the value at token i is three numbers (else one stands for three).
    bool three_numbers(std::size_t i) const {
        return i + 2 < toks_.size() && rt::is_number_syntax(toks_[i + 1].text) && rt::is_number_syntax(toks_[i + 2].text);
    }

    // Past the balanced `{ ... }` starting at token i.
    bool skip_braces(std::size_t& i) const {
        if (!is_brace(i, '{')) return false;
        int depth = 0;
        for (; i < toks_.size(); ++i) {
            depth += toks_[i].is('{') ? 1 : toks_[i].is('}') ? -1 : 0;
            if (depth == 0) {
                ++i;
                return true;
            }
        }
        return false;
    }

    void replace_token(std::size_t i, std::string text) { reps_.push_back({toks_[i].offset, toks_[i].text.size(), std::move(text)}); }

    // `key value` for a key the block did not give, before its closing brace (token
    // `close`): on a line of its own when the brace starts its line.
    void insert_key(std::size_t close, const std::string& kv) {
        const std::size_t c = toks_[close].offset;
        std::size_t ls = c;
        while (ls > 0 && (text_[ls - 1] == ' ' || text_[ls - 1] == '\t')) --ls;
        if (ls == 0 || text_[ls - 1] == '\n' || text_[ls - 1] == '\r') {
            reps_.push_back({c, 0, "  " + kv + "\n" + std::string(text_.substr(ls, c - ls))});
        } else {
            reps_.push_back({c, 0, (ls == c ? " " : "") + kv + " "});
        }
    }

    // The block body whose `{` is token i; i ends past its `}`.
    template <class T>
    bool body(const sc::Block<T>& b, std::size_t& i, const T& before, const T& after) {
        if (!is_brace(i, '{')) return false;
        ++i;
        std::map<std::pair<std::size_t, int>, std::size_t> value_at;  // (key, index) -> its last value's token
        std::size_t close = 0;
        for (;;) {
            if (i >= toks_.size()) return false;
            if (toks_[i].is('}')) {
                close = i++;
                break;
            }
            const sc::Key<T>* k = b.find(toks_[i].text);
            if (!k) return false;
            ++i;
            int index = 0;
            if (k->count > 0) {
                if (i >= toks_.size()) return false;
                const std::string_view n = toks_[i].text;
                if (n.size() != 1 || n[0] < '1' || n[0] > '0' + std::min(k->count, 9)) return false;
                index = n[0] - '1';
                ++i;
            }
            value_at[{std::size_t(k - b.keys.data()), index}] = i;
            switch (k->kind) {
                case sc::Kind::Number:
                case sc::Kind::Choice:
                case sc::Kind::Integer: i += 1; break;
                case sc::Kind::Vec3: i += k->one_or_three && !three_numbers(i) ? 1 : 3; break;
                case sc::Kind::File: {
                    // A quoted name with spaces is several tokens, up to the one ending the quote.
                    const std::string_view first = i < toks_.size() ? toks_[i].text : std::string_view();
                    if (!first.empty() && first.front() == '"' && (first.size() < 2 || first.back() != '"'))
                        while (++i < toks_.size() && toks_[i].text.back() != '"') {
                        }
                    i += 1;
                    break;
                }
                case sc::Kind::Material:
                case sc::Kind::Operand:
                    if (!skip_braces(i)) return false;
                    break;
            }
        }
        for (std::size_t ki = 0; ki < b.keys.size(); ++ki) {
            const sc::Key<T>& k = b.keys[ki];
            for (int index = 0; index < std::max(k.count, 1); ++index) {
                auto it = value_at.find({ki, index});
                const std::size_t at = it == value_at.end() ? 0 : it->second;
                if (!key(k, index, at, close, before, after)) return false;
            }
        }
        return true;
    }

    // One key: rewritten where its value is (token `at`; 0: not given) if it changed.
    template <class T>
    bool key(const sc::Key<T>& k, int i, std::size_t at, std::size_t close, const T& before, const T& after) {
        std::string name(k.name);
        if (k.count > 0) name += " " + std::to_string(i + 1);
        switch (k.kind) {
            case sc::Kind::Number: {
                const double a = k.number(before, i), b = k.number(after, i);
                if (same(a, b)) return true;
                if (at) replace_token(at, rt::format_number(b));
                else insert_key(close, name + " " + rt::format_number(b));
                return true;
            }
            case sc::Kind::Vec3: {
                const rt::Vec3 a = k.vec3(before, i), b = k.vec3(after, i);
                if (same(a, b)) return true;
                if (!at) {
                    insert_key(close, name + " " + vec_text(b));
                    return true;
                }
                if (k.one_or_three && !three_numbers(at)) {  // `scale 2`: one number for all three
                    replace_token(at, b.x == b.y && b.y == b.z ? rt::format_number(b.x) : vec_text(b));
                    return true;
                }
                for (int c = 0; c < 3; ++c)
                    if (!same(a[c], b[c])) replace_token(at + std::size_t(c), rt::format_number(b[c]));
                return true;
            }
            case sc::Kind::Integer: {
                const int a = k.integer(before, i), b = k.integer(after, i);
                if (a == b) return true;
                if (at) replace_token(at, std::to_string(b));
                else insert_key(close, name + " " + std::to_string(b));
                return true;
            }
            case sc::Kind::Choice: {
                const int a = k.access.get_choice(before), b = k.access.get_choice(after);
                if (a == b) return true;
                const std::string word(k.choice->word_for(b));
                if (at) replace_token(at, word);
                else insert_key(close, name + " " + word);
                return true;
            }
            case sc::Kind::Material: {
                const bool had = k.has_material(before, i), has = k.has_material(after, i);
                if (had == has && same(k.material(before, i), k.material(after, i))) return true;
                if (!has) return false;  // a block cannot be taken out here
                if (!at) {
                    insert_key(close, name + " " + material_text(k.material(after, i)));
                    return true;
                }
                std::size_t j = at;
                return body(sc::material_block(), j, k.material(before, i), k.material(after, i));
            }
            case sc::Kind::File:
                return k.text(before, i) == k.text(after, i);  // a new name: the block is written anew
            case sc::Kind::Operand:
                if constexpr (std::is_same_v<T, rt::Object>) {
                    const rt::Object* a = k.operand(before, i);
                    const rt::Object* b = k.operand(after, i);
                    if (!a || !b) return a == b;
                    // `{ OBJECT }`: the object's name, then its body.
                    const sc::Block<rt::Object>& ob = sc::object_block(*b);
                    if (!at || &sc::object_block(*a) != &ob || !toks_[at + 1].is(ob.name)) return false;
                    std::size_t j = at + 2;
                    return body(ob, j, *a, *b) && is_brace(j, '}');
                }
                return false;
        }
        return false;
    }

    std::string_view text_;
    std::vector<rt::Token> toks_;
    std::vector<TextReplacement> reps_;
};

// The patched block parses to `after` (read as the only item of a small scene).
template <class T>
bool reads_back(const std::string& block, const char* section, const T& after) {
    std::string scene = std::string(section) + " {\n" + block + "\n}\n" + rt::write_camera(rt::Camera{}) +
                        "picture_size { x_max 1 y_max 1 }\nend\n";
    rt::ParseOptions o;
    o.read_models = false;  // the block's text is what is checked; its model stays as read
    rt::ParseResult r = rt::parse_scene(scene, o);
    if (!r.ok()) return false;
    if constexpr (std::is_same_v<T, rt::Object>) {
        if (r.scene.objects.size() != 1) return false;
        if (const rt::Mesh* m = std::get_if<rt::Mesh>(&after.shape)) {
            rt::Object& read = r.scene.objects[0];
            if (rt::Mesh* back = std::get_if<rt::Mesh>(&read.shape)) back->model = m->model;
        }
        return r.scene.objects[0] == after;
    }
    if constexpr (std::is_same_v<T, rt::Plane>) return r.scene.planes.size() == 1 && r.scene.planes[0] == after;
    if constexpr (std::is_same_v<T, rt::Light>) return r.scene.lights.size() == 1 && r.scene.lights[0] == after;
    return false;
}

template <class T>
std::optional<std::string> patch(std::string_view block, const sc::Block<T>& b_before, const sc::Block<T>& b_after,
                                 const T& before, const T& after, const char* section) {
    if (&b_before != &b_after) return std::nullopt;  // another kind of block: written anew
    Patcher p(block);
    if (!p.item(b_after, before, after)) return std::nullopt;
    std::string out = p.result();
    if (!reads_back(out, section, after)) return std::nullopt;
    return out;
}

}  // namespace

std::optional<std::string> patch_material(std::string_view braces, const rt::Material& before,
                                          const rt::Material& after) {
    Patcher p(braces);
    if (!p.bare(sc::material_block(), before, after)) return std::nullopt;
    std::string out = p.result();
    // Read back as the definition of a small scene: the values of `after` (its file as
    // named; the texture itself is not read here).
    const std::string scene = "define { material m " + out + "\n}\n" + rt::write_camera(rt::Camera{}) +
                              "picture_size { x_max 1 y_max 1 }\nend\n";
    rt::ParseOptions o;
    o.read_models = false;
    const rt::ParseResult r = rt::parse_scene(scene, o);
    if (!r.ok() || r.scene.materials.size() != 1) return std::nullopt;
    rt::Material want = after;
    want.texture_image.reset();
    want.named = r.scene.materials[0].material.named;
    rt::Material got = r.scene.materials[0].material;
    got.texture_image.reset();
    if (!(got == want)) return std::nullopt;
    return out;
}

std::optional<std::string> patch_block(std::string_view block, const rt::Object& before, const rt::Object& after) {
    return patch(block, sc::object_block(before), sc::object_block(after), before, after, "thing");
}

std::optional<std::string> patch_block(std::string_view block, const rt::Plane& before, const rt::Plane& after) {
    return patch(block, sc::plane_block(before), sc::plane_block(after), before, after, "special_thing");
}

std::optional<std::string> patch_block(std::string_view block, const rt::Light& before, const rt::Light& after) {
    return patch(block, sc::light_block(before), sc::light_block(after), before, after, "light");
}

}  // namespace rtview
