// docs/scene-format.md: every example in it is checked, so the reference cannot
// drift from the parser. Fenced code blocks are tagged by their info string:
//
//   ```scene NAME        a complete scene: parses with no errors and no warnings, and
//                        its thumbnail docs/img/NAME.png exists and is shown in the file
//                        (docs/make-gallery.sh renders it from this very block)
//   ```scene-check NAME  a scene with mistakes; the next block is a ```text block
//                        starting with `$ raytracer --check NAME.txt` and holding exactly
//                        what that prints (the diagnostics, then the `ok` summary line
//                        when there are no errors)
//   ```fragment          objects, planes or lights without their section: wrapped in
//                        thing { }, special_thing { } or light { } (chosen by the first
//                        word) plus a camera, a picture_size and `end`; must parse cleanly
//   ```defaults          a fragment holding one item with its keys written out at their
//                        defaults: must also equal the same item written as `NAME { }`
//   ```text, ```sh       output, commands and schematic text; never a scene
//
// Each block's key table lists exactly the keys of the schema (scene_schema.h), and
// where a row gives one key a single default, it is the schema's default.
//
// Any other tag, or an untagged fence, fails the test, so nothing slips through unchecked.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scene_parser.h"
#include "scene_schema.h"
#include "scene_writer.h"
#include "test_util.h"

using namespace rt;

namespace {

const std::string kDocs = RT_SOURCE_DIR "/docs/scene-format.md";

struct Block {
    std::string tag, name;  // info string: first word, second word
    std::string text;
    int line = 0;  // of the opening fence
};

std::string read_text(const std::string& path) { return rt_test::slurp(path); }

bool file_exists(const std::string& path) { return std::ifstream(path).good(); }

std::vector<std::string> split_words(const std::string& s) {
    std::istringstream in(s);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

// Fences are lines starting with ``` at column 1 (the document never indents them).
std::vector<Block> extract_blocks(const std::string& md, std::vector<std::string>& problems) {
    std::vector<Block> blocks;
    std::istringstream in(md);
    std::string line;
    int n = 0;
    Block* open = nullptr;
    while (std::getline(in, line)) {
        ++n;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.rfind("```", 0) != 0) {
            if (open) open->text += line + "\n";
            continue;
        }
        if (open) {
            if (line.find_first_not_of('`') != std::string::npos)
                problems.push_back("line " + std::to_string(n) + ": a closing fence must be only ```");
            open = nullptr;
            continue;
        }
        Block b;
        b.line = n;
        auto words = split_words(line.substr(3));
        if (!words.empty()) b.tag = words[0];
        if (words.size() > 1) b.name = words[1];
        if (words.size() > 2) problems.push_back("line " + std::to_string(n) + ": too many words after ```");
        blocks.push_back(b);
        open = &blocks.back();
    }
    if (open) problems.push_back("line " + std::to_string(open->line) + ": code block never closed");
    return blocks;
}

std::string where(const Block& b) { return "scene-format.md:" + std::to_string(b.line) + " (```" + b.tag + " " + b.name + ")"; }

std::string first_word(const std::string& text) {
    // Skip // comments, as the parser does.
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        auto words = split_words(line);
        for (const auto& w : words) {
            if (w.rfind("//", 0) == 0) break;
            std::string word = w.substr(0, w.find('{'));
            if (!word.empty()) return word;
        }
    }
    return {};
}

// The section an item's block belongs in, from the schema.
const char* section_for(const std::string& item) {
    if (schema::object_block(item)) return "thing";
    for (const auto& b : schema::plane_blocks())
        if (b.name == item) return "special_thing";
    for (const auto& b : schema::light_blocks())
        if (b.name == item) return "light";
    return nullptr;
}

std::string wrap(const char* section, const std::string& body) {
    return std::string(section) + " {\n" + body +
           "}\n"
           "camera { position -5 0 0 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
           "picture_size { x_max 8 y_max 6 }\n"
           "end\n";
}

// The examples' models are named as from scenes/ (docs/make-gallery.sh runs them so).
ParseOptions scene_folder() {
    ParseOptions o;
    o.base_dir = RT_SOURCE_DIR "/scenes";
    return o;
}

std::string diagnostics_text(const std::string& file, const ParseResult& r) {
    std::string out;
    for (const auto& d : r.diagnostics) out += format_diagnostic(file, d) + "\n";
    return out;
}

}  // namespace

TEST_CASE("docs/scene-format.md: every example is checked") {
    const std::string md = read_text(kDocs);
    REQUIRE_MESSAGE(!md.empty(), "cannot read " << kDocs);
    std::vector<std::string> problems;
    const std::vector<Block> blocks = extract_blocks(md, problems);
    for (const auto& p : problems) FAIL_CHECK(p);

    std::set<std::string> names;
    int scenes = 0, checks = 0, defaults = 0;
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        const Block& b = blocks[i];
        INFO(where(b));
        if (b.tag == "text" || b.tag == "sh") continue;

        if (b.tag == "scene" || b.tag == "scene-check") {
            REQUIRE_MESSAGE(!b.name.empty(), "a ```" << b.tag << " block needs a name");
            CHECK_MESSAGE(names.insert(b.name).second, "example name used twice: " << b.name);
            CHECK_MESSAGE(b.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") == std::string::npos,
                          "example names use a-z, 0-9 and '-': " << b.name);
        }

        if (b.tag == "scene") {
            ++scenes;
            ParseResult r = parse_scene(b.text, scene_folder());
            CHECK_MESSAGE(r.diagnostics.empty(), "the example should parse cleanly:\n"
                                                     << diagnostics_text(b.name + ".txt", r));
            const std::string img = "img/" + b.name + ".png";
            CHECK_MESSAGE(md.find("](" + img + ")") != std::string::npos,
                          "the document should show its thumbnail " << img);
            CHECK_MESSAGE(file_exists(RT_SOURCE_DIR "/docs/" + img),
                          "docs/" << img << " is missing: run docs/make-gallery.sh");
        } else if (b.tag == "scene-check") {
            ++checks;
            REQUIRE_MESSAGE(i + 1 < blocks.size(), "a ```scene-check block must be followed by its output");
            const Block& out = blocks[i + 1];
            REQUIRE_MESSAGE(out.tag == "text", "the block after ```scene-check must be ```text");
            const std::string file = b.name + ".txt";
            const std::string command = "$ raytracer --check " + file + "\n";
            REQUIRE_MESSAGE(out.text.rfind(command, 0) == 0, "the output block should start with " << command);
            ParseResult r = parse_scene(b.text, scene_folder());
            CHECK_MESSAGE(!r.diagnostics.empty(), "a ```scene-check example should have errors or warnings");
            std::string expected = diagnostics_text(file, r);
            if (r.ok()) {
                // --check then prints a summary line; only its start is checked here
                // (docs/make-gallery.sh compares the whole output of the real program).
                std::string shown = out.text.substr(command.size());
                std::size_t cut = shown.rfind(file + ": ok: ");
                REQUIRE_MESSAGE(cut != std::string::npos, "a scene without errors ends with the 'ok' line");
                CHECK(shown.substr(0, cut) == expected);
            } else {
                CHECK(out.text.substr(command.size()) == expected);
            }
        } else if (b.tag == "fragment" || b.tag == "defaults") {
            if (b.tag == "defaults") ++defaults;
            const std::string item = first_word(b.text);
            const char* section = section_for(item);
            REQUIRE_MESSAGE(section, "a fragment starts with an object, plane or light, not '" << item << "'");
            ParseResult r = parse_scene(wrap(section, b.text));
            CHECK_MESSAGE(r.diagnostics.empty(), "the fragment should parse cleanly:\n" << diagnostics_text("fragment", r));
            if (b.tag == "defaults" && r.ok()) {
                ParseResult e = parse_scene(wrap(section, item + " { }\n"));
                REQUIRE(e.ok());
                const Material in_block;  // the defaults inside a material block
                if (std::string(section) == "thing") {
                    REQUIRE(r.scene.objects.size() == 1);
                    const Object& o = r.scene.objects[0];
                    CHECK_MESSAGE(o.shape == e.scene.objects[0].shape, "the written-out keys are not the defaults");
                    if (o.has_material) CHECK_MESSAGE(o.material == in_block, "the material is not the default");
                } else if (std::string(section) == "special_thing") {
                    REQUIRE(r.scene.planes.size() == 1);
                    const Plane& p = r.scene.planes[0];
                    for (int k = 0; k < 4; ++k) CHECK(p.point[k] == e.scene.planes[0].point[k]);
                    if (p.has_material) CHECK(p.material == in_block);
                    if (p.has_material2) CHECK(p.material2 == in_block);
                } else {
                    REQUIRE(r.scene.lights.size() == 1);
                    CHECK_MESSAGE(r.scene.lights[0] == e.scene.lights[0], "the written-out keys are not the defaults");
                }
            }
        } else {
            FAIL_CHECK("unknown code block tag '" << b.tag
                                                      << "' (use scene NAME, scene-check NAME, fragment, defaults, "
                                                         "text or sh)");
        }
    }
    // Guards against the extraction silently finding nothing.
    CHECK(scenes >= 15);
    CHECK(checks >= 3);
    CHECK(defaults >= 5);
}

TEST_CASE("docs/gallery.md shows every scene in scenes/") {
    const std::string md = read_text(RT_SOURCE_DIR "/docs/gallery.md");
    REQUIRE_MESSAGE(!md.empty(), "docs/gallery.md is missing: run docs/make-gallery.sh");
    int n = 0;
    for (const auto& entry : std::filesystem::directory_iterator(RT_SOURCE_DIR "/scenes")) {
        if (entry.path().extension() != ".txt") continue;
        ++n;
        const std::string img = "gallery/" + entry.path().stem().string() + ".png";
        INFO(img);
        CHECK_MESSAGE(md.find("](" + img + ")") != std::string::npos,
                      "docs/gallery.md does not show " << img << ": run docs/make-gallery.sh");
        CHECK_MESSAGE(file_exists(RT_SOURCE_DIR "/docs/" + img), "docs/" << img << " is missing: run docs/make-gallery.sh");
    }
    CHECK(n > 0);
}

namespace {

// The key table after a heading: rows of `| key | value | default | meaning |`.
struct Row {
    std::vector<std::string> keys;  // first words of the first cell's `code` spans
    std::vector<int> indices;       // "point 2": 2, else 0
    std::string default_cell;
};

std::vector<std::string> code_spans(const std::string& cell) {
    std::vector<std::string> spans;
    for (std::size_t a = cell.find('`'); a != std::string::npos; a = cell.find('`', a)) {
        const std::size_t b = cell.find('`', a + 1);
        if (b == std::string::npos) break;
        spans.push_back(cell.substr(a + 1, b - a - 1));
        a = b + 1;
    }
    return spans;
}

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::size_t a = line.find('|');
    while (a != std::string::npos) {
        const std::size_t b = line.find('|', a + 1);
        if (b == std::string::npos) break;
        out.push_back(line.substr(a + 1, b - a - 1));
        a = b;
    }
    return out;
}

std::vector<Row> key_table(const std::string& md, const std::string& heading) {
    std::vector<Row> rows;
    std::size_t at = md.find("\n" + heading + "\n");
    if (at == std::string::npos) return rows;
    std::istringstream in(md.substr(at + heading.size() + 2));
    bool in_table = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| `", 0) != 0) {
            if (in_table) break;
            continue;
        }
        in_table = true;
        const auto c = cells(line);
        if (c.size() < 3) continue;
        Row row;
        row.default_cell = c[2];
        const auto spans = code_spans(c[0]);
        for (const std::string& sp : spans) {
            const auto w = split_words(sp);
            row.keys.push_back(w.empty() ? "" : w[0]);
            row.indices.push_back(w.size() > 1 ? std::atoi(w[1].c_str()) : 0);
        }
        // `vect1` … `vect4`: the keys in between too.
        if (c[0].find("\u2026") != std::string::npos && spans.size() == 2) {
            const std::string a = row.keys[0];
            const std::string b = row.keys[1];
            if (a != b && !a.empty() && a.substr(0, a.size() - 1) == b.substr(0, b.size() - 1))
                for (char d = char(a.back() + 1); d < b.back(); ++d) row.keys.push_back(a.substr(0, a.size() - 1) + d);
        }
        rows.push_back(row);
    }
    return rows;
}

template <class T>
std::string default_text(const schema::Key<T>& k, const T& item, int i) {
    switch (k.kind) {
    case schema::Kind::Number: return format_number(k.number(item, i));
    case schema::Kind::Vec3: {
        const Vec3 v = k.vec3(item, i);
        return format_number(v.x) + " " + format_number(v.y) + " " + format_number(v.z);
    }
    case schema::Kind::Choice: return std::string(k.choice->word_for(k.access.get_choice(item)));
    default: return {};
    }
}

template <class T>
void check_table(const std::string& md, const std::string& heading, const schema::Block<T>& b) {
    INFO("the key table under '" << heading << "' and the schema's block " << std::string(b.name));
    const auto rows = key_table(md, heading);
    REQUIRE_MESSAGE(!rows.empty(), "no key table found");
    std::set<std::string> documented, schema_keys;
    for (const auto& k : b.keys) schema_keys.insert(std::string(k.name));
    const T item = b.make();
    for (const Row& row : rows) {
        documented.insert(row.keys.begin(), row.keys.end());
        // One key with one default value written as code: it must be the schema's.
        const auto defaults = code_spans(row.default_cell);
        if (row.keys.size() != 1 || defaults.size() != 1 || row.default_cell.find("each") != std::string::npos) continue;
        const schema::Key<T>* k = b.find(row.keys[0]);
        if (!k) continue;
        const int i = row.indices[0] > 0 ? row.indices[0] - 1 : 0;
        const std::string want = default_text(*k, item, i);
        if (!want.empty()) CHECK_MESSAGE(defaults[0] == want, "default of " << row.keys[0]);
    }
    CHECK(documented == schema_keys);
}

}  // namespace

TEST_CASE("docs/scene-format.md: each block's key table lists the schema's keys and defaults") {
    const std::string md = read_text(kDocs);
    REQUIRE(!md.empty());
    int blocks = 0;
    for (const auto& b : schema::object_blocks()) check_table(md, "### " + std::string(b.name), b), ++blocks;
    for (const auto& b : schema::plane_blocks()) check_table(md, "### " + std::string(b.name), b), ++blocks;
    for (const auto& b : schema::light_blocks()) check_table(md, "### " + std::string(b.name), b), ++blocks;
    check_table(md, "## Materials", schema::material_block());
    check_table(md, "## Camera", schema::camera_block());
    check_table(md, "## Picture size", schema::picture_size_block());
    CHECK(blocks == 13);
    // The layout table names every section.
    for (const auto& s : schema::sections())
        if (s.kind != schema::SectionKind::End)
            CHECK_MESSAGE(md.find("| `" + std::string(s.name) +
                                  (s.kind == schema::SectionKind::Include ? " \"FILE\"` |" : " { ... }` |")) != std::string::npos,
                          "section " << std::string(s.name) << " missing from the layout table");
}
