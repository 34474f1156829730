// The edit fuzzer's scenes (edit_fuzz.h): random scene texts as people write them, with
// definitions, instances and an included file now and then.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "edit_fuzz_choices.h"

namespace rtfuzz {

// Random scenes, laid out as people write them: keys in any order, comments, sections
// split and repeated, CR LF line ends, text after `end`.

class SceneWriter {
public:
    explicit SceneWriter(Choices& c) : c_(c) {}

    std::string scene() {
        std::vector<std::string> sections;
        // Now and then definitions first: a named material and object the things may use.
        std::string define;
        if (c_.one_in(3)) {
            define = "define {\n  material gold " + material("").substr(1) + "\n";
            defined_ = true;
            define += "  object post { " + object(1) + " }\n}\n";
        }
        const int things = c_.between(0, 2);
        for (int k = 0; k < things; ++k) sections.push_back(section("thing", objects()));
        if (c_.below(3)) sections.push_back(section("special_thing", planes()));
        if (c_.below(4)) sections.push_back(section("light", lights()));
        camera_sections(sections);
        if (!c_.one_in(24)) sections.push_back(picture_size());
        // Now and then an include of a file beside it with things and lights of its own
        // (included_file(): the caller writes it as lib.txt).
        if (kIncludes && c_.one_in(3)) {
            sections.push_back(std::string("include ") + (c_.one_in(4) ? "lib.txt" : "\"lib.txt\"") + comment() + "\n");
            // (Its things name none of this scene's definitions: another scene written
            // over this one keeps the library, which must read without them.)
            const bool defined = std::exchange(defined_, false);
            included_ = library();
            defined_ = defined;
        }
        for (std::size_t i = sections.size(); i > 1; --i) std::swap(sections[i - 1], sections[c_.below(unsigned(i))]);
        std::string out = c_.one_in(3) ? "// a scene\n" : "";
        out += define;
        for (const std::string& s : sections) out += s;
        out += "end\n";
        if (c_.one_in(6)) out += c_.one_in(2) ? "after the end { thing {\n" : "camera { }\n";
        if (c_.one_in(8)) out = crlf(out);
        return out;
    }

    // The text of lib.txt when scene() included it, else nothing.
    const std::optional<std::string>& included_file() const { return included_; }
    // A file to include: things and lights (no camera, no picture size, no `end`).
    std::string library() {
        std::string out = c_.one_in(4) ? "// a library\n" : "";
        out += section("thing", objects());
        if (c_.one_in(2)) out += section("light", lights());
        if (c_.one_in(3)) out += section("special_thing", planes());
        return out;
    }

private:
    std::string comment() {
        static const char* const kComments[] = {" // note", " // { brace", " // lamp size 3", " // } end", ""};
        return c_.one_in(5) ? kComments[c_.below(5)] : "";
    }
    std::string sep() { return c_.one_in(4) ? "\n      " : c_.one_in(6) ? "\t" : "  "; }
    std::string num(double v) { return number_text(v, c_); }
    std::string vec(const rt::Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }
    // Keys in a random order, each "key value".
    std::string keys(std::vector<std::string> k) {
        for (std::size_t i = k.size(); i > 1; --i) std::swap(k[i - 1], k[c_.below(unsigned(i))]);
        std::string out;
        for (const std::string& s : k) {
            const std::string note = comment();
            out += sep() + s + note + (note.empty() ? "" : "\n      ");
        }
        return out;
    }
    std::string block(const std::string& name, std::vector<std::string> k) {
        return name + " {" + keys(std::move(k)) + " }";
    }
    std::string section(const std::string& name, const std::vector<std::string>& items) {
        std::string out = name + " {" + comment() + "\n";
        for (const std::string& i : items) out += "  " + i + comment() + "\n";
        return out + "}\n";
    }
    std::string material(const char* name = "material") {
        std::vector<std::string> k;
        if (c_.one_in(2)) k.push_back("reflection " + num(c_.between(0, 10) / 10.0));
        if (c_.one_in(3)) k.push_back("refraction " + num(c_.between(0, 10) / 10.0));
        if (c_.one_in(2)) k.push_back("scattering " + num(c_.between(0, 10) / 10.0));
        if (c_.one_in(3)) k.push_back("translusans " + num(c_.between(-2, 12) / 10.0));
        if (c_.one_in(3)) k.push_back("refractive_index " + num(c_.between(5, 25) / 10.0));
        if (c_.one_in(2)) k.push_back("colour " + vec({c_.between(0, 10) / 10.0, c_.between(0, 10) / 10.0, 1}));
        return block(name, std::move(k));
    }
    void maybe_material(std::vector<std::string>& k) {
        if (defined_ && c_.one_in(4)) k.push_back("material gold");
        else if (c_.below(3)) k.push_back(material());
        // Placement keys now and then (the same call for every object kind).
        if (c_.one_in(5)) k.push_back("rotation " + vec({double(c_.between(-2, 2) * 45), 0, double(c_.between(0, 7) * 15)}));
        if (c_.one_in(6)) k.push_back(c_.one_in(2) ? "scale " + num(c_.between(1, 8) / 4.0)
                                                    : "scale " + vec({1, c_.between(1, 8) / 4.0, 0.5}));
        if (c_.one_in(5)) k.push_back("translate " + vec({0, c_.between(-2, 2) / 2.0, c_.between(0, 2) / 2.0}));
    }
    rt::Vec3 point() { return {double(c_.between(-6, 12)), double(c_.between(-6, 6)), c_.between(0, 8) / 2.0}; }
    std::string object(int depth) {
        std::vector<std::string> k;
        const rt::Vec3 p = point();
        switch (c_.below(depth < 3 ? 7 : 6)) {
            case 0:
                k = {"position " + vec(p), "radius " + num(c_.between(1, 20) / 10.0)};
                maybe_material(k);
                return block("sphere", std::move(k));
            case 1:
                k = {"end_1 " + vec(p), "end_2 " + vec(p + rt::Vec3{0, c_.between(-2, 2) / 2.0, c_.between(1, 4) / 2.0}),
                     "radius " + num(c_.between(1, 10) / 10.0)};
                maybe_material(k);
                return block("cylinder", std::move(k));
            case 2:
                k = {"vect1 " + vec(p), "vect2 " + vec(p + rt::Vec3{1, 0, 0}), "vect3 " + vec(p + rt::Vec3{0, 1, 0}),
                     "vect4 " + vec(p + rt::Vec3{c_.between(0, 2) / 2.0, 0.5, c_.between(1, 4) / 2.0})};
                maybe_material(k);
                return block("tetrahedron", std::move(k));
            case 3:
                k = {"position " + vec(p), "major " + num(c_.between(0, 10) / 10.0),
                     "minor " + num(c_.between(1, 5) / 10.0)};
                if (c_.one_in(2)) k.push_back("direction " + vec({0, double(c_.between(0, 1)), 1}));
                maybe_material(k);
                return block("torus", std::move(k));
            case 4:
                k = {"corner_1 " + vec(p),
                     "corner_2 " + vec(p + rt::Vec3{c_.between(1, 4) / 2.0, -c_.between(1, 4) / 2.0, c_.between(1, 4) / 2.0})};
                maybe_material(k);
                return block("box", std::move(k));
            case 5: {
                double r1 = c_.between(0, 10) / 10.0, r2 = c_.between(1, 10) / 10.0;
                if (c_.one_in(2)) std::swap(r1, r2);  // either end may be the point
                k = {"end_1 " + vec(p), "end_2 " + vec(p + rt::Vec3{0, c_.between(-2, 2) / 2.0, c_.between(1, 4) / 2.0}),
                     "radius_1 " + num(r1), "radius_2 " + num(r2)};
                maybe_material(k);
                return block("cone", std::move(k));
            }
            default:
                k = {"type " + std::string(1, "UIC"[c_.below(3)]), "left { " + object(depth + 1) + " }",
                     "right { " + object(depth + 1) + " }"};
                maybe_material(k);
                return block("constructive_solid_geometry", std::move(k));
        }
    }
    std::vector<std::string> objects() {
        std::vector<std::string> out(std::size_t(c_.between(0, 5)));
        for (std::string& o : out) {
            if (defined_ && c_.one_in(4)) {
                std::vector<std::string> k = {"object post"};
                maybe_material(k);
                o = block("instance", std::move(k));
                continue;
            }
            o = object(0);
        }
        return out;
    }
    std::vector<std::string> planes() {
        std::vector<std::string> out(std::size_t(c_.between(0, 2)));
        for (std::string& o : out) {
            const bool chess = c_.one_in(2);
            const double z = c_.between(-2, 0);
            std::vector<std::string> k = {"point 1 " + vec({0, 0, z}), "point 2 " + vec({1, 0, z}),
                                          "point 3 " + vec({0, double(c_.between(1, 2)), z}),
                                          "point 4 " + vec({0, 0, z + c_.between(-1, 3)})};
            if (c_.below(3)) k.push_back(material(chess ? "material 1" : "material"));
            if (chess && c_.one_in(2)) k.push_back(material("material 2"));
            o = block(chess ? "chess_plane" : "plane", std::move(k));
        }
        return out;
    }
    std::vector<std::string> lights() {
        std::vector<std::string> out(std::size_t(c_.between(0, 3)));
        for (std::string& o : out) {
            const bool lamp = c_.one_in(2);
            std::vector<std::string> k = {"position " + vec({double(c_.between(-3, 6)), double(c_.between(-5, 5)), 6}),
                                          "colour " + vec({double(c_.between(0, 90)), 60, double(c_.between(0, 90))})};
            if (lamp) k.push_back("size " + num(c_.between(-1, 5) / 10.0));
            o = block(lamp ? "lamp" : "spotlight", std::move(k));
        }
        return out;
    }
    void camera_sections(std::vector<std::string>& sections) {
        if (c_.one_in(24)) return;  // (a scene without a camera does not parse)
        const rt::Vec3 pos{double(c_.between(-4, 0)), double(c_.between(-2, 2)), double(c_.between(1, 4))};
        const rt::Vec3 centre{double(c_.between(4, 8)), double(c_.between(-1, 1)), 1};
        std::vector<std::string> k = {"position " + vec(pos), "centre " + vec(centre),
                                      "up " + vec(centre + (c_.one_in(12) ? rt::Vec3{1, 0, 0} : rt::Vec3{0, 0, 1})),
                                      "angle_x " + num(c_.between(20, 90)), "angle_y " + num(c_.between(15, 70))};
        if (c_.one_in(4)) k.push_back(std::string("projection ") + (c_.one_in(2) ? "polar" : "linear"));
        if (c_.one_in(3)) {
            // Split over two sections: keys accumulate, a repeated key keeps its last value.
            const std::size_t cut = c_.below(unsigned(k.size()));
            std::vector<std::string> first(k.begin(), k.begin() + std::ptrdiff_t(cut));
            if (c_.one_in(2)) first.push_back("angle_x 33");
            sections.push_back(block("camera", first) + "\n");
            k.erase(k.begin(), k.begin() + std::ptrdiff_t(cut));
        }
        sections.push_back(block("camera", k) + "\n");
    }
    std::string picture_size() {
        return block("picture_size", {"x_max " + std::to_string(c_.between(1, 64)),
                                      "y_max " + std::to_string(c_.between(1, 48))}) +
               "\n";
    }
    static std::string crlf(const std::string& s) {
        std::string out;
        for (char ch : s) out += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
        return out;
    }

    Choices& c_;
    bool defined_ = false;  // the scene defines material gold and object post
    // Includes: the items they bring are shown read only (their edits refused), and an
    // included file changed on disk is read again.
    static constexpr bool kIncludes = true;
    std::optional<std::string> included_;
};

}  // namespace rtfuzz
