// Tokens, line ends and numbers of the scene format. The lexer touches each byte once
// and keeps no line count: the parser reads 100+ MB files, and positions are needed
// only for the few tokens a diagnostic or an item's location points at.
#include "scene_lexer.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

namespace rt {
namespace {

enum CharClass : unsigned char { kWord = 0, kSpace = 1, kBrace = 2 };

constexpr std::array<unsigned char, 256> make_classes() {
    std::array<unsigned char, 256> c{};
    for (unsigned char s : {' ', '\t', '\n', '\r', '\v', '\f'}) c[s] = kSpace;
    c['{'] = c['}'] = kBrace;
    return c;
}
constexpr std::array<unsigned char, 256> kClass = make_classes();

inline unsigned char char_class(char c) { return kClass[static_cast<unsigned char>(c)]; }

}  // namespace

SceneLexer::SceneLexer(std::string_view text) : text_(text) {
    if (text_.size() >= 3 && std::memcmp(text_.data(), "\xEF\xBB\xBF", 3) == 0) pos_ = 3;
    advance();
}

void SceneLexer::advance() {
    const char* p = text_.data();
    const std::size_t n = text_.size();
    std::size_t i = pos_;
    for (;;) {
        while (i < n && char_class(p[i]) == kSpace) ++i;
        if (i + 1 < n && p[i] == '/' && p[i + 1] == '/') {
            while (i < n && p[i] != '\n' && p[i] != '\r') ++i;
            continue;
        }
        break;
    }
    const std::size_t start = i;
    if (i < n) {
        if (char_class(p[i]) == kBrace)
            ++i;
        else
            while (i < n && char_class(p[i]) == kWord) ++i;
    }
    pos_ = i;
    cur_ = Token{text_.substr(start, i - start), start};
}

// ---- lines ----------------------------------------------------------------------

LineCol line_col_at(std::string_view text, std::size_t offset) {
    LineMap m(text);
    return m.at(offset);
}

std::size_t offset_at(std::string_view text, int line, int col) {
    std::size_t pos = 0;
    for (int l = 1; l < line; ++l) {
        while (pos < text.size() && !is_line_end(text, pos)) ++pos;
        if (pos == text.size()) return text.size();
        ++pos;
    }
    std::size_t eol = pos;
    while (eol < text.size() && text[eol] != '\n' && text[eol] != '\r') ++eol;
    return std::min(pos + std::size_t(col > 1 ? col - 1 : 0), eol);
}

void LineMap::scan_to(std::size_t offset) {
    const char* p = text_.data();
    const std::size_t n = text_.size();
    std::size_t i = cur_.offset;
    while (i < offset) {
        // Stop at each checkpoint boundary so that backward look-ups restart nearby.
        const std::size_t stop = std::min(offset, (i / kCheckpoint + 1) * kCheckpoint);
        // Count first (a loop the compiler vectorises), then find the last line start.
        int lines = 0;
        for (std::size_t k = i; k < stop; ++k)
            lines += (p[k] == '\n') | ((p[k] == '\r') & (k + 1 == n || p[k + 1] != '\n'));
        if (lines > 0) {
            std::size_t k = stop;
            while (!is_line_end(text_, k - 1)) --k;
            cur_.line_start = k;
            cur_.line += lines;
        }
        i = stop;
        cur_.offset = i;
        if (i % kCheckpoint == 0 && (checkpoints_.empty() || checkpoints_.back().offset < i))
            checkpoints_.push_back(cur_);
    }
}

LineCol LineMap::at(std::size_t offset) {
    offset = std::min(offset, text_.size());
    if (offset < cur_.offset) {
        // Backwards: restart from the last checkpoint at or before the offset.
        auto it = std::upper_bound(checkpoints_.begin(), checkpoints_.end(), offset,
                                   [](std::size_t o, const Mark& m) { return o < m.offset; });
        cur_ = it == checkpoints_.begin() ? Mark{0, 0, 1} : *(it - 1);
    }
    scan_to(offset);
    return {cur_.line, int(offset - cur_.line_start) + 1};
}

// ---- numbers --------------------------------------------------------------------

bool is_number_syntax(std::string_view s) {
    std::size_t i = 0, n = s.size();
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t int_digits = 0, frac_digits = 0;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++int_digits;
    if (i < n && s[i] == '.') {
        ++i;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++frac_digits;
    }
    if (int_digits + frac_digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        std::size_t exp_digits = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++exp_digits;
        if (exp_digits == 0) return false;
    }
    return i == n;
}

bool is_integer_syntax(std::string_view s) {
    std::size_t i = 0;
    if (i < s.size() && s[i] == '+') ++i;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}

namespace {

// Clinger's fast path: a decimal whose digits fit in 53 bits, scaled by at most 10^22,
// is exactly one correctly rounded IEEE multiplication or division of two exact
// doubles, so it equals what from_chars/strtod return. Nearly every number in a scene
// file qualifies; false sends the rest to the library.
bool fast_number(std::string_view s, double& out) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    std::size_t i = 0, n = s.size();
    bool negative = false;
    if (s[0] == '+' || s[0] == '-') negative = s[i++] == '-';
    std::uint64_t m = 0;
    int digits = 0, scale = 0;  // significant digits taken; value = m * 10^scale
    for (; i < n && s[i] >= '0' && s[i] <= '9'; ++i) {
        if (m == 0 && s[i] == '0') continue;
        if (++digits > 19) return false;
        m = m * 10 + std::uint64_t(s[i] - '0');
    }
    if (i < n && s[i] == '.') {
        for (++i; i < n && s[i] >= '0' && s[i] <= '9'; ++i) {
            --scale;
            if (m == 0 && s[i] == '0') continue;
            if (++digits > 19) return false;
            m = m * 10 + std::uint64_t(s[i] - '0');
        }
    }
    if (i < n) {  // an exponent, as the syntax check guarantees
        ++i;
        bool neg_exp = false;
        if (s[i] == '+' || s[i] == '-') neg_exp = s[i++] == '-';
        int e = 0;
        for (; i < n; ++i) {
            if (e > 10000) return false;
            e = e * 10 + (s[i] - '0');
        }
        scale += neg_exp ? -e : e;
    }
    if (m > (std::uint64_t(1) << 53)) return false;
    double v = double(m);
    if (m != 0) {
        if (scale < -22 || scale > 22) return false;
        v = scale < 0 ? v / kPow10[-scale] : v * kPow10[scale];
    }
    out = negative ? -v : v;
    return true;
}

}  // namespace

double number_value(std::string_view s) {
    double d = 0;
    if (fast_number(s, d)) return d;
    // from_chars is locale-independent; it rejects a leading '+', and on overflow or
    // underflow strtod tells which of the two it was.
    std::string_view digits = s[0] == '+' ? s.substr(1) : s;
    auto res = std::from_chars(digits.data(), digits.data() + digits.size(), d);
    if (res.ec != std::errc() || res.ptr != digits.data() + digits.size()) d = std::strtod(std::string(s).c_str(), nullptr);
    return d;
}

}  // namespace rt
