// Builds the fuzzers' seed corpus:
//   fuzz_seed_corpus OUTDIR [FILE...]
// Scene files are copied as they are. From C++ files (the parser tests) every run of
// adjacent string literals is taken as a snippet, alone and followed by a camera,
// picture size and `end` (the tests' parse_with_camera). Built-in snippets cover every
// object, light and key, and every kind of error. File names are content hashes, so
// running it again adds nothing twice.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

const char* const kTail =
    "\ncamera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
    "picture_size { x_max 32 y_max 24 }\nend\n";

// Bodies that are completed with kTail.
const char* const kBodies[] = {
    // every object, with and without keys
    "thing { sphere { } }",
    "thing { sphere { position 1 -2 3.5 radius 0.25 material { reflection 0.2 refraction 0.3 scattering 0.5 "
    "translusans 0.9 refractive_index 1.5 colour 0.1 0.2 0.3 } } }",
    "thing { tetrahedron { vect1 0 0 0 vect2 1 0 0 vect3 0 1 0 vect4 0 0 1 } }",
    "thing { cylinder { end_1 0 0 0 end_2 0 0 2 radius 0.5 material { colour 1 0 0 } } }",
    "thing { torus { position 0 0 0 direction 0 0 1 major 2 minor 0.5 } }",
    "thing { constructive_solid_geometry { type C left { sphere { } } right { cylinder { } } "
    "material { reflection 1 } } }",
    "thing { constructive_solid_geometry { type I left { constructive_solid_geometry { type U "
    "left { sphere { radius 2 } } right { torus { } } } } right { tetrahedron { vect1 0 0 0 vect2 1 0 0 "
    "vect3 0 1 0 vect4 0 0 1 } } } }",
    "special_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 material { colour 1 1 1 } } }",
    "special_thing { chess_plane { material 1 { colour 1 1 1 } material 2 { colour 0 0 0 } point 4 0 0 5 } }",
    "light { lamp { position 1 2 3 colour 10 10 10 size 0.5 } spotlight { position 0 0 5 colour 5 5 5 } }",
    "thing { mesh { file \"models/cube.obj\" position 1 2 3 scale 2 rotation 0 90 45 smooth 1 "
    "material { colour 1 0 0 } } mesh { file plain.ply scale 1 2 0.5 } }",
    "thing { constructive_solid_geometry { left { mesh { file \"a b.obj\" } } right { sphere { } } } }",
    "thing { box { corner_1 0 0 0 corner_2 1 2 3 material { colour 0 1 0 } } cone { end_1 0 0 0 end_2 0 0 2 "
    "radius_1 1 radius_2 0.25 } }",
    "thing { constructive_solid_geometry { type C left { box { corner_1 -1 -1 -1 corner_2 1 1 1 rotation 0 0 45 } } "
    "right { cone { radius_1 0 radius_2 0.5 scale 2 1 1 } } rotation 10 20 30 scale 1.5 translate 1 2 3 } "
    "sphere { scale 1 2 3 } mesh { file a.obj translate 1 0 0 } }",
    "// comment\nthing { // after brace\n sphere { radius 1 } // trailing\n}",
    "thing{sphere{radius 1}}",
    // warnings
    "thing { sphere { material { reflection 0 refraction 0 scattering 0 } } }",
    "special_thing { plane { point 4 0.5 0.5 0 } }",
    // every error kind
    "thing sphere { }",
    "thing { cube { } }",
    "thing { sphere { positio 1 2 3 } }",
    "thing { sphere { position 1 2 } }",
    "thing { sphere { radius x } }",
    "thing { sphere { radius 1e999 } }",
    "thing { sphere { radius 1e16 } }",
    "thing { sphere { radius -1 } }",
    "thing { sphere { radius 0 } }",
    "thing { sphere { material { colour 1 1 } } }",
    "thing { sphere { material { shiny 1 } } }",
    "thing { cylinder { end_1 1 1 1 end_2 1 1 1 } }",
    "thing { cylinder { radius 0 } }",
    "thing { torus { minor 0 } }",
    "thing { torus { major -1 } }",
    "thing { torus { direction 0 0 0 } }",
    "thing { tetrahedron { } }",
    "define { material gold { colour 1 0.8 0 } object post { cylinder { end_1 0 0 0 end_2 0 0 1 radius 0.1 } } }\n"
    "thing { instance { object post material gold rotation 0 0 45 translate 1 2 0 } sphere { material gold } }",
    "thing { sphere { material gold } }",
    "define { material a { } material a { } }",
    "define { object a { sphere { } } }\nthing { instance { object b } instance { } }",
    "define { material gold { } }\nthing { instance { object gold } }",
    "include \"nothing.txt\"\n",
    "include \"/dev/zero\"\n",
    "thing { box { corner_1 1 1 1 corner_2 1 1 1 } }",
    "thing { box { corner_1 0 0 0 corner_2 1 1 0 } }",
    "thing { cone { radius_1 0 radius_2 0 } }",
    "thing { cone { end_1 1 1 1 end_2 1 1 1 } }",
    "thing { cone { radius_1 -1 } }",
    "thing { sphere { scale 0 } }",
    "thing { sphere { scale 1 -1 1 } }",
    "thing { torus { rotation nan 0 0 } }",
    "thing { torus { translate 1 2 } }",
    "thing { constructive_solid_geometry { type X left { sphere { } } right { sphere { } } } }",
    "thing { constructive_solid_geometry { left { sphere { } } } }",
    "thing { constructive_solid_geometry { right { sphere { } } } }",
    "thing { constructive_solid_geometry { left { } right { sphere { } } } }",
    "thing { constructive_solid_geometry { left { sphere { } sphere { } } right { sphere { } } } }",
    "thing { constructive_solid_geometry { left { plane { } } right { sphere { } } } }",
    "special_thing { plane { point 5 1 2 3 } }",
    "special_thing { plane { point 1.5 2 3 4 } }",
    "special_thing { chess_plane { material 3 { } } }",
    "special_thing { plane { point 1 0 0 0 point 2 1 0 0 point 3 2 0 0 } }",
    "special_thing { cube { } }",
    "light { torch { } }",
    "light { spotlight { size 1 } }",
    "bogus { }",
    "thing { sphere { end } }",
    "thing { { } }",
    "thing { } }",
    "thing { sphere { radius 1 }",
};

// Whole files, with no tail added.
const char* const kWhole[] = {
    "",
    "end",
    "end\ntext after end { is ignored",
    "thing {\n  sphere {\n    radius 1\n",
    "camera { position 0 0 0 centre 1 0 0 }\npicture_size { x_max 4 y_max 4 }\nend",
    "camera { position 1 1 1 centre 1 1 1 up 1 1 2 angle_x 60 angle_y 45 }\npicture_size { x_max 4 y_max 4 }\nend",
    "camera { position 0 0 0 centre 1 0 0 up 2 0 0 angle_x 60 angle_y 45 }\npicture_size { x_max 4 y_max 4 }\nend",
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 180 angle_y 45 }\npicture_size { x_max 4 y_max 4 }\nend",
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 projection polar }\n"
    "picture_size { x_max 16384 y_max 1 }\nend",
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 projection 12 }\n"
    "picture_size { x_max 16385 y_max 0 }\nend",
    "\xEF\xBB\xBF" "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\r\n"
    "picture_size { x_max 4 y_max 4 }\r\nend\r\n",
    "thing { sph\0ere { } }\nend",
    "thing { sph\xC3\xA8re { } }\nend",
    "{{{{{{{{{{{{{{{{{{{{}}}}}}}}}}}}}}}}}}}}",
};

std::uint64_t fnv1a(const std::string& s) {
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

int written = 0;

void emit(const std::string& dir, const std::string& prefix, const std::string& data) {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(fnv1a(data)));
    std::ofstream out(dir + "/" + prefix + "-" + name, std::ios::binary);
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) {
        std::cerr << "fuzz_seed_corpus: cannot write into " << dir << "\n";
        std::exit(2);
    }
    ++written;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int hex(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// Every run of adjacent string literals in C++ source, unescaped. Comments and
// character literals are skipped; raw strings are taken as they are.
std::vector<std::string> string_literals(const std::string& src) {
    std::vector<std::string> groups;
    std::string cur;
    bool in_group = false;
    auto flush = [&] {
        if (in_group) groups.push_back(cur);
        cur.clear();
        in_group = false;
    };
    std::size_t i = 0, n = src.size();
    while (i < n) {
        char c = src[i];
        if (c == '/' && i + 1 < n && src[i + 1] == '/') {
            while (i < n && src[i] != '\n') ++i;
        } else if (c == '/' && i + 1 < n && src[i + 1] == '*') {
            std::size_t e = src.find("*/", i + 2);
            i = e == std::string::npos ? n : e + 2;
        } else if (c == '\'') {
            ++i;
            while (i < n && src[i] != '\'') i += src[i] == '\\' ? 2 : 1;
            ++i;
            flush();
        } else if (c == 'R' && i + 1 < n && src[i + 1] == '"') {
            std::size_t open = src.find('(', i + 2);
            if (open == std::string::npos) break;
            std::string close = ")" + src.substr(i + 2, open - i - 2) + "\"";
            std::size_t e = src.find(close, open + 1);
            if (e == std::string::npos) break;
            cur += src.substr(open + 1, e - open - 1);
            in_group = true;
            i = e + close.size();
        } else if (c == '"') {
            ++i;
            while (i < n && src[i] != '"') {
                if (src[i] != '\\' || i + 1 >= n) {
                    cur += src[i++];
                    continue;
                }
                char e = src[i + 1];
                i += 2;
                switch (e) {
                    case 'n': cur += '\n'; break;
                    case 't': cur += '\t'; break;
                    case 'r': cur += '\r'; break;
                    case 'v': cur += '\v'; break;
                    case 'f': cur += '\f'; break;
                    case 'x': {
                        int v = 0;
                        while (i < n && hex(src[i]) >= 0) v = v * 16 + hex(src[i++]);
                        cur += char(v);
                        break;
                    }
                    default:
                        if (e >= '0' && e <= '7') {
                            int v = e - '0';
                            for (int k = 0; k < 2 && i < n && src[i] >= '0' && src[i] <= '7'; ++k)
                                v = v * 8 + (src[i++] - '0');
                            cur += char(v);
                        } else {
                            cur += e;  // \\ \" \' \?
                        }
                }
            }
            ++i;
            in_group = true;
        } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            ++i;
        } else {
            ++i;
            flush();
        }
    }
    flush();
    return groups;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: fuzz_seed_corpus OUTDIR [SCENE.txt | TESTS.cpp ...]\n";
        return 2;
    }
    const std::string dir = argv[1];
    for (const char* b : kBodies) emit(dir, "snippet", std::string(b) + kTail);
    for (const char* w : kWhole) emit(dir, "snippet", w);
    emit(dir, "snippet", std::string("thing { sph\0ere { } }", 21) + kTail);
    for (int i = 2; i < argc; ++i) {
        const std::string path = argv[i];
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            std::cerr << "fuzz_seed_corpus: cannot read " << path << "\n";
            return 2;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        const std::string text = ss.str();
        if (ends_with(path, ".cpp") || ends_with(path, ".h")) {
            for (const std::string& lit : string_literals(text)) {
                if (lit.size() < 3) continue;
                emit(dir, "test", lit);
                emit(dir, "test", lit + kTail);
            }
        } else {
            emit(dir, "file", text);
        }
    }
    std::cout << "fuzz_seed_corpus: " << written << " inputs written to " << dir << "\n";
    return 0;
}
