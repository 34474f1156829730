// The scene text's syntax colours, one line at a time: which spans of a line are a
// section, an object, a key, a number, a comment or a brace.
#pragma once

#include <string_view>
#include <vector>

namespace rtview {

enum class TokenKind : unsigned char { Text, Section, Object, Key, Number, Comment, Brace };
struct TokenSpan {
    int begin = 0, end = 0;  // byte columns in the line, end exclusive
    TokenKind kind = TokenKind::Text;
};
// Splits one line into coloured spans (spans may leave gaps: plain text). The
// format's tokens never span lines (`//` ends at the line's end), so a line can be
// coloured without looking at its neighbours, and only the visible lines need it.
// The scene format's words, by kind; numbers as the parser reads them (whole tokens).
void tokenise_scene_line(std::string_view line, std::vector<TokenSpan>& out);
// Whether `token` is a whole number in the scene format ([+-]digits[.digits][e[+-]digits]).
bool is_scene_number(std::string_view token);

}  // namespace rtview
