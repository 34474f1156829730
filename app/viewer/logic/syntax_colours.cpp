// The colouring of one line of scene text (see syntax_colours.h).
#include "syntax_colours.h"

#include <algorithm>
#include <cctype>

namespace rtview {

bool is_scene_number(std::string_view s) {
    std::size_t i = 0, n = s.size();
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t digits = 0;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++digits;
    if (i < n && s[i] == '.') {
        ++i;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        std::size_t exp = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++exp;
        if (exp == 0) return false;
    }
    return i == n;
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\n'; }

TokenKind word_kind(std::string_view w) {
    static const std::string_view sections[] = {"thing", "special_thing", "light", "camera", "picture_size", "end"};
    static const std::string_view objects[] = {"sphere", "tetrahedron", "cylinder",  "torus",    "constructive_solid_geometry",
                                               "plane",  "chess_plane", "lamp",      "spotlight"};
    static const std::string_view keys[] = {
        "position", "radius",      "vect1",      "vect2",       "vect3",       "vect4",      "end_1",
        "end_2",    "direction",   "major",      "minor",       "type",        "left",       "right",
        "material", "point",       "reflection", "refraction",  "scattering",  "translusans", "refractive_index",
        "colour",   "size",        "centre",     "up",          "projection",  "angle_x",    "angle_y",
        "x_max",    "y_max"};
    for (auto s : sections)
        if (w == s) return TokenKind::Section;
    for (auto s : objects)
        if (w == s) return TokenKind::Object;
    for (auto s : keys)
        if (w == s) return TokenKind::Key;
    if (is_scene_number(w)) return TokenKind::Number;
    return TokenKind::Text;
}

}  // namespace

// The parser's lexical rules: tokens are runs of non-space bytes, braces stand alone,
// `//` at a token's start comments out the rest of the line.
void tokenise_scene_line(std::string_view line, std::vector<TokenSpan>& out) {
    out.clear();
    std::size_t i = 0, n = line.size();
    while (i < n) {
        while (i < n && is_space(line[i])) ++i;
        if (i >= n) break;
        if (line[i] == '/' && i + 1 < n && line[i + 1] == '/') {
            out.push_back({int(i), int(n), TokenKind::Comment});
            break;
        }
        if (line[i] == '{' || line[i] == '}') {
            out.push_back({int(i), int(i + 1), TokenKind::Brace});
            ++i;
            continue;
        }
        std::size_t b = i;
        while (i < n && !is_space(line[i]) && line[i] != '{' && line[i] != '}') ++i;
        TokenKind k = word_kind(line.substr(b, i - b));
        if (k != TokenKind::Text) out.push_back({int(b), int(i), k});
    }
}


}  // namespace rtview
