// The scene format's lexical rules, in one place for the parser and the viewer's text
// tools: tokens with their byte offsets, the number syntax, and line:column found from
// an offset only when someone asks (a diagnostic, an item's location).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace rt {

// A run of non-space bytes; `{` and `}` are always tokens of their own; `//` at the
// start of a token comments out the rest of the line.
struct Token {
    std::string_view text;   // empty at the end of the text
    std::size_t offset = 0;  // of the first byte; the text's size at its end
    bool eof() const { return text.empty(); }
    bool is(std::string_view s) const { return text == s; }
    bool is(char c) const { return text.size() == 1 && text[0] == c; }
    std::size_t end() const { return offset + text.size(); }
};

class SceneLexer {
public:
    // A UTF-8 byte-order mark at the start is not part of the scene.
    explicit SceneLexer(std::string_view text);
    // Lexing from `offset` on, as if the text began there (no byte-order mark).
    SceneLexer(std::string_view text, std::size_t offset) : text_(text), pos_(offset) { advance(); }
    const Token& peek() const { return cur_; }
    Token next() {
        Token t = cur_;
        advance();
        return t;
    }
    void skip() { advance(); }  // next() without the copy
    // Continues at `offset`. At a token's offset this gives the very tokens that lexing
    // on from before it would (a token is a maximal run, and a comment cannot start
    // inside one).
    void seek(std::size_t offset) {
        pos_ = offset;
        space_ = ~std::uint64_t(0);
        advance();
    }
    std::string_view text() const { return text_; }

private:
    void advance();
    bool advance_in_window();
    void fill_window();
    std::string_view text_;
    std::size_t pos_ = 0;
    Token cur_;
    // The classes of the 64 bytes from win_ on, one bit a byte: spaces, braces, and
    // either (where a word ends). Most tokens, with the spaces before them, are found
    // within one window; all spaces means none has been filled.
    std::size_t win_ = 0;
    std::uint64_t space_ = ~std::uint64_t(0), brace_ = 0, ends_ = 0;
};

// Whether a byte ends a line: LF, CR LF (one end, at the LF) and a CR alone all do.
inline bool is_line_end(std::string_view text, std::size_t i) {
    return text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n'));
}

// 1-based line and column (columns count bytes) of a byte offset.
struct LineCol {
    int line = 1;
    int col = 1;
};
LineCol line_col_at(std::string_view text, std::size_t offset);
// Offset of the 1-based line and column, clamped to the line's end and the text's end.
std::size_t offset_at(std::string_view text, int line, int col);

// line_col_at for many offsets in mostly increasing order: each look-up scans only
// from the previous one (or from a checkpoint before it), so looking up every item's
// start costs one pass over the text.
class LineMap {
public:
    explicit LineMap(std::string_view text) : text_(text) {}
    // Counting lines from the one holding `start` as line 1 (columns stay true): for
    // a reader that starts in the middle and learns the true line later (rebase).
    LineMap(std::string_view text, std::size_t start);
    LineCol at(std::size_t offset);
    // Continues with `later`, a map started further on (at or after everything this
    // one has scanned) whose line 1 is this text's line first_line.
    void rebase(LineMap&& later, int first_line);

private:
    struct Mark {
        std::size_t offset, line_start;
        int line;
    };
    void scan_to(std::size_t offset);
    std::string_view text_;
    Mark cur_{0, 0, 1};
    std::vector<Mark> checkpoints_;  // every kCheckpoint bytes of what was scanned
    static constexpr std::size_t kCheckpoint = 1 << 16;
};

// ---- numbers --------------------------------------------------------------------
// A number is a whole token: [+-] digits [. digits] [(e|E) [+-] digits], with at least
// one digit before or after the point. Integer slots take [+] digits.
bool is_number_syntax(std::string_view s);
bool is_integer_syntax(std::string_view s);

// Checks the syntax and, for the common short decimals, computes the value in the same
// pass. Library: the syntax is right, but the value needs library_number_value.
enum class NumberScan { NotNumber, Exact, Library };
NumberScan scan_number(std::string_view s, double& value);
// The double a token of number syntax stands for, correctly rounded (as strtod);
// infinite or 0 when out of double range. Precondition: is_number_syntax(s).
double library_number_value(std::string_view s);
double number_value(std::string_view s);  // either of the two ways

// The usual numbers of big files, inline in the parser's loop: [+-] digits [. digits]
// with at most 15 digits, no exponent. True with the value scan_number gives, computed
// the same way (exact digits, one correctly rounded division); false for anything
// else, which scan_number then reads.
inline bool short_decimal(std::string_view s, double& value) {
    static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
    const char* const p = s.data();
    const std::size_t n = s.size();
    if (n == 0 || n > 17) return false;
    const std::size_t first = p[0] == '-' || p[0] == '+' ? 1 : 0;
    std::uint64_t m = 0;
    std::size_t after_point = 0;  // the index after the '.', if there is one
    for (std::size_t i = first; i < n; ++i) {
        const unsigned d = unsigned(p[i] - '0');
        if (d < 10)
            m = m * 10 + d;
        else if (p[i] == '.' && after_point == 0)
            after_point = i + 1;
        else
            return false;
    }
    const std::size_t digits = n - first - (after_point != 0);
    if (digits == 0 || digits > 15) return false;
    double v = double(std::int64_t(m));  // m < 10^15 < 2^53: exact
    if (after_point != 0 && n > after_point) v /= kPow10[n - after_point];
    value = p[0] == '-' ? -v : v;
    return true;
}

}  // namespace rt
