// The scene language, defined once: its sections, the blocks they hold and each block's
// keys (kind, index, range or clamp, the messages for bad values, where the value lives
// in the structs of scene.h). The parser checks keys from it, the writer writes them
// from it, and tools (docs test, editing panels) can iterate it:
//   for (const auto& k : schema::camera_block().keys)  // name, kind, range, ...
//       if (k.kind == schema::Kind::Number) edit(k.name, k.access.number(camera, 0));
// A key's default is its value in the block's make() item (scene.h's initialisers).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "scene.h"

namespace rt::schema {

enum class Kind {
    Number,    // one number
    Vec3,      // three numbers
    Integer,   // a whole number
    Choice,    // one word from a list
    Material,  // a `{ ... }` block of material keys
    Operand,   // a `{ ... }` holding exactly one object (CSG left/right)
    File,      // a file name in double quotes (a mesh's model)
};

// What happens to a Number outside [min, max] (`min_open`: min itself is outside too).
// Integer keys and key indices are always checked, with `message`, at the value.
struct Range {
    enum class Rule { None, Clamp, Error } rule = Rule::None;
    double min = -1e300, max = 1e300;
    bool min_open = false;
    const char* message = nullptr;  // Rule::Error: at the key's last value, or at the item
                                    // name when the key was not given
    bool contains(double v) const { return (min_open ? v > min : v >= min) && v <= max; }
};

// The words a Choice key accepts, each with the value stored.
struct Choice {
    struct Word {
        std::string_view word;
        int value;
    };
    std::vector<Word> words;  // the first word of each value is the one written
    int any_single_char = -1; // the value any other one-character word means; -1: none
    const char* eof_expects;  // "unexpected end of file: expected <this> after '<key>'"
    const char* wrong;        // "<wrong>got '<word>'" for a word not in the list
    const char* brace;        // the same for a `{` or `}` in its place (null: `wrong`)
    bool drops_item;          // a wrong word makes the item unusable (else: the value stays)
    std::string_view word_for(int value) const;
    bool find(std::string_view word, int& value) const;
};

// Where a key's value lives in an item of type T; `i` is the key's index - 1 (0 for
// keys without one). Exactly the accessor matching the key's kind is set.
template <class T>
struct Access {
    double& (*number)(T&, int i) = nullptr;
    Vec3& (*vec3)(T&, int i) = nullptr;
    // Reading without writing, where `vec3` would change the item to give a reference
    // (an object's transform is made on the first write); null: `vec3` reads too.
    const Vec3& (*vec3_read)(const T&, int i) = nullptr;
    int& (*integer)(T&, int i) = nullptr;
    int (*get_choice)(const T&) = nullptr;
    void (*set_choice)(T&, int) = nullptr;
    Material& (*material)(T&, int i) = nullptr;
    bool& (*has_material)(T&, int i) = nullptr;  // a Material key given in the file
    Object* (*operand)(T&, int i) = nullptr;  // null: the item has no such operand
    std::string& (*text)(T&, int i) = nullptr;
};

template <class T>
struct Key {
    std::string_view name;
    Kind kind;
    Access<T> access;
    int count = 0;                  // > 0: the key takes an index 1..count first ("point 2 ...")
    const char* count_error = nullptr;
    Range range{};                  // Number: a clamp or a rule; Integer: its bounds; Vec3: a
                                    // rule (Error) for each of the three numbers
    const Choice* choice = nullptr;  // Kind::Choice
    bool required = false;          // must be given (somewhere in the file)
    bool lead = false;              // the writer puts it before the other keys
    bool one_or_three = false;      // Vec3: one number may stand for three equal ones
    bool optional = false;          // New: written only where it differs from its default, so
                                    // that a 2013 scene is written as it always was
    const char* placeholder = nullptr;  // File: the name the format reference shows
    bool bare = false;              // File: a name, written without quotes
    const char* default_text = nullptr;  // a default that no value spells (the reference says it)

    // Read access for const items (the accessors are shared with writing).
    double number(const T& t, int i = 0) const { return access.number(const_cast<T&>(t), i); }
    Vec3 vec3(const T& t, int i = 0) const {
        return access.vec3_read ? access.vec3_read(t, i) : access.vec3(const_cast<T&>(t), i);
    }
    int integer(const T& t, int i = 0) const { return access.integer(const_cast<T&>(t), i); }
    const Material& material(const T& t, int i = 0) const { return access.material(const_cast<T&>(t), i); }
    bool has_material(const T& t, int i = 0) const { return access.has_material(const_cast<T&>(t), i); }
    const Object* operand(const T& t, int i = 0) const { return access.operand(const_cast<T&>(t), i); }
    const std::string& text(const T& t, int i = 0) const { return access.text(const_cast<T&>(t), i); }
};

// A rule across keys, checked once the block is read. Reported at the item's name.
struct Problem {
    enum class Severity { None, Error, Warning } severity = Severity::None;
    std::string message;
    explicit operator bool() const { return severity != Severity::None; }
};

// a == b for the short words of the format, without a library call per comparison
// (the parser compares every key it reads with its block's keys). Words of 4 to 16
// bytes compare as two overlapping loads from each end, which stay inside both words.
inline bool same_word(std::string_view a, std::string_view b) {
    const std::size_t n = a.size();
    if (n != b.size() || n == 0 || a[0] != b[0]) return n == b.size() && n == 0;
    auto same = [&](auto word) {
        decltype(word) x, y, u, v;
        std::memcpy(&x, a.data(), sizeof word);
        std::memcpy(&y, b.data(), sizeof word);
        std::memcpy(&u, a.data() + n - sizeof word, sizeof word);
        std::memcpy(&v, b.data() + n - sizeof word, sizeof word);
        return ((x ^ y) | (u ^ v)) == 0;
    };
    if (n >= 8 && n <= 16) return same(std::uint64_t());
    if (n >= 4 && n < 8) return same(std::uint32_t());
    for (std::size_t i = 1; i < n; ++i)
        if (a[i] != b[i]) return false;
    return true;
}

template <class T>
struct Block {
    std::string_view name;
    std::vector<Key<T>> keys;  // in the order error messages list them
    T (*make)();               // a new item holding the format's defaults
    Problem (*check)(const T&) = nullptr;

    const Key<T>* find(std::string_view key) const {
        for (const Key<T>& k : keys)
            if (same_word(k.name, key)) return &k;
        return nullptr;
    }
    // "a, b, c": the keys as error messages list them.
    std::string key_list() const;
};

// ---- the blocks -----------------------------------------------------------------
// Objects (thing), in the order messages list them. The Object's shape holds the
// alternative of the block's name.
const std::vector<Block<Object>>& object_blocks();
const Block<Object>* object_block(std::string_view name);
const Block<Object>& object_block(const Object& o);  // the block an object is written as

// special_thing: plane, chess_plane.
const std::vector<Block<Plane>>& plane_blocks();
const Block<Plane>& plane_block(const Plane& p);
// light: lamp, spotlight.
const std::vector<Block<Light>>& light_blocks();
const Block<Light>& light_block(const Light& l);

const Block<Material>& material_block();  // defaults are those inside a `material { }`
const Block<Camera>& camera_block();      // keys accumulate over all camera sections
const Block<Scene>& picture_size_block();

// ---- the sections ---------------------------------------------------------------
enum class SectionKind { Things, Specials, Lights, Camera, PictureSize, End, Include, Define };
struct Section {
    std::string_view name;
    SectionKind kind;
    const char* item_noun;  // in "unknown <noun> 'x'" (sections of items only)
};
const std::vector<Section>& sections();  // in file order of a written scene
const Section* find_section(std::string_view name);
// "include, define, thing, special_thing, light, camera, picture_size or end"
std::string section_list();

// Names of a block list: "sphere, tetrahedron, ...".
template <class T>
std::string names_of(const std::vector<Block<T>>& blocks) {
    std::string out;
    for (const Block<T>& b : blocks) {
        if (!out.empty()) out += ", ";
        out += b.name;
    }
    return out;
}

template <class T>
std::string Block<T>::key_list() const {
    std::string out;
    for (const Key<T>& k : keys) {
        if (!out.empty()) out += ", ";
        out += k.name;
    }
    return out;
}

}  // namespace rt::schema
