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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
// Bytes 9..13 and ' ' of a 16-byte load.
inline __m128i spaces(__m128i c) {
    const __m128i x = _mm_sub_epi8(c, _mm_set1_epi8(9));
    const __m128i control = _mm_cmpeq_epi8(_mm_min_epu8(x, _mm_set1_epi8(4)), x);  // 9..13
    return _mm_or_si128(control, _mm_cmpeq_epi8(c, _mm_set1_epi8(' ')));
}
inline __m128i braces(__m128i c) {
    return _mm_or_si128(_mm_cmpeq_epi8(c, _mm_set1_epi8('{')), _mm_cmpeq_epi8(c, _mm_set1_epi8('}')));
}
inline __m128i load16(const char* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
// Bit i set if p[i] ends a word: a space (9..13 or ' ') or a brace.
inline unsigned word_ends(const char* p) {
    const __m128i c = load16(p);
    return unsigned(_mm_movemask_epi8(_mm_or_si128(spaces(c), braces(c))));
}
#endif

}  // namespace

SceneLexer::SceneLexer(std::string_view text) : text_(text) {
    if (text_.size() >= 3 && std::memcmp(text_.data(), "\xEF\xBB\xBF", 3) == 0) pos_ = 3;
    advance();
}

void SceneLexer::fill_window() {
#if defined(__SSE2__)
    const char* p = text_.data() + pos_;
    std::uint64_t space = 0, brace = 0;
    for (int k = 0; k < 4; ++k) {
        const __m128i c = load16(p + 16 * k);
        space |= std::uint64_t(unsigned(_mm_movemask_epi8(spaces(c)))) << (16 * k);
        brace |= std::uint64_t(unsigned(_mm_movemask_epi8(braces(c)))) << (16 * k);
    }
    win_ = pos_;
    space_ = space;
    brace_ = brace;
    ends_ = space | brace;
#endif
}

// The next token if it lies (with the spaces before it) in the window, and does not
// start with '/' (a comment, maybe); else false, and nothing has changed.
inline bool SceneLexer::advance_in_window() {
    const std::size_t rel = pos_ - win_;  // pos_ >= win_ while a window is in use
    if (rel >= 64) return false;
    const std::uint64_t word = ~space_ >> rel;
    if (word == 0) return false;
    const unsigned s = unsigned(rel) + unsigned(__builtin_ctzll(word));
    const char* const start = text_.data() + win_ + s;
    if (*start == '/') return false;
    unsigned len = 1;
    if (!(brace_ >> s & 1)) {
        if (s == 63) return false;
        const std::uint64_t after = ends_ >> (s + 1);
        if (after == 0) return false;  // it may go on past the window
        len = 1 + unsigned(__builtin_ctzll(after));
    }
    pos_ = win_ + s + len;
    cur_.text = std::string_view(start, len);
    cur_.offset = win_ + s;
    return true;
}

void SceneLexer::advance() {
    const char* const begin = text_.data();
    const char* const end = begin + text_.size();
    const char* p = begin + pos_;
#if defined(__SSE2__)
    // The usual token is found in the window of 64 bytes classified at once; a token
    // past it starts a new window where the last one ended. Anything else (comments,
    // long words or runs of spaces, the last bytes of the text) takes the general way.
    if (advance_in_window()) return;
    if (end - p >= 64) {
        fill_window();
        if (advance_in_window()) return;
    }
#endif
    for (;;) {
        while (p != end && char_class(*p) == kSpace) ++p;
        if (end - p >= 2 && p[0] == '/' && p[1] == '/') {
            while (p != end && *p != '\n' && *p != '\r') ++p;
            continue;
        }
        break;
    }
    const char* const start = p;
    if (p != end) {
        if (char_class(*p) == kBrace) {
            ++p;
        } else {
            ++p;
#if defined(__SSE2__)
            for (; end - p >= 16; p += 16)
                if (const unsigned m = word_ends(p)) {
                    p += __builtin_ctz(m);
                    goto done;
                }
#endif
            while (p != end && char_class(*p) == kWord) ++p;
        }
    }
#if defined(__SSE2__)
done:
#endif
    pos_ = std::size_t(p - begin);
    cur_.text = std::string_view(start, std::size_t(p - start));
    cur_.offset = std::size_t(start - begin);
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
    std::size_t k = cur_.offset;
    while (k < offset) {
        // Stop at each checkpoint boundary so that backward look-ups restart nearby.
        const std::size_t stop = std::min(offset, (k / kCheckpoint + 1) * kCheckpoint);
#if defined(__SSE2__)
        const __m128i lf = _mm_set1_epi8('\n'), cr = _mm_set1_epi8('\r');
        // Whole 16-byte blocks without a CR (the usual text): their LFs only counted,
        // in byte counters summed every 255 blocks, and the last line's start found by
        // looking back from the end. A CR anywhere sends the span to the exact way below.
        if (const std::size_t blocks = (stop - k) / 16; blocks >= 4) {
            const std::size_t to = k + blocks * 16;
            std::size_t lines = 0;
            __m128i crs = _mm_setzero_si128();
            for (std::size_t at = k; at < to;) {
                const std::size_t run_end = std::min(to, at + 255 * 16);
                __m128i counts = _mm_setzero_si128();
                for (; at < run_end; at += 16) {
                    const __m128i here = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + at));
                    counts = _mm_sub_epi8(counts, _mm_cmpeq_epi8(here, lf));
                    crs = _mm_or_si128(crs, _mm_cmpeq_epi8(here, cr));
                }
                const __m128i sums = _mm_sad_epu8(counts, _mm_setzero_si128());
                lines += std::size_t(_mm_cvtsi128_si32(sums)) + std::size_t(_mm_cvtsi128_si32(_mm_srli_si128(sums, 8)));
            }
            if (_mm_movemask_epi8(crs) == 0) {
                if (lines > 0) {
                    // The last LF: in the last block that has one, found a block at a time.
                    std::size_t at = to - 16;
                    unsigned lfs;
                    while ((lfs = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(
                                    _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + at)), lf)))) == 0)
                        at -= 16;
                    cur_.line += int(lines);
                    cur_.line_start = at + std::size_t(32 - __builtin_clz(lfs));
                }
                k = to;
            }
        }
        // 16 bytes at a time; the look-ahead load at k + 1 needs k + 17 <= n. The last
        // partial block before `stop` is masked rather than read byte by byte.
        auto block = [&](std::size_t at, unsigned mask) {
            const __m128i here = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + at));
            unsigned ends = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(here, lf)));
            if (const unsigned crs = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(here, cr)))) {
                // CR LF ends at its LF: a CR counts only if no LF follows it.
                const __m128i next = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + at + 1));
                ends |= crs & ~unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(next, lf)));
            }
            ends &= mask;
            if (ends == 0) return;
            cur_.line_start = at + std::size_t(32 - __builtin_clz(ends));  // after the last one
            for (; ends != 0; ends &= ends - 1) ++cur_.line;                 // line ends are sparse
        };
        for (; k + 16 <= stop && k + 17 <= n; k += 16) block(k, 0xFFFFu);
        if (k < stop && k + 17 <= n) {
            block(k, (1u << (stop - k)) - 1);
            k = stop;
        }
#endif
        for (; k < stop; ++k)
            if (is_line_end(text_, k)) {
                ++cur_.line;
                cur_.line_start = k + 1;
            }
        cur_.offset = k;
        if (k % kCheckpoint == 0 && (checkpoints_.empty() || checkpoints_.back().offset < k))
            checkpoints_.push_back(cur_);
    }
}

LineMap::LineMap(std::string_view text, std::size_t start) : text_(text) {
    start = std::min(start, text.size());
    std::size_t line_start = start;
    while (line_start > 0 && !is_line_end(text, line_start - 1)) --line_start;
    cur_ = {start, line_start, 1};
}

void LineMap::rebase(LineMap&& later, int first_line) {
    const int shift = first_line - 1;
    for (Mark m : later.checkpoints_) {
        m.line += shift;
        if (checkpoints_.empty() || checkpoints_.back().offset < m.offset) checkpoints_.push_back(m);
    }
    cur_ = later.cur_;
    cur_.line += shift;
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

NumberScan scan_number(std::string_view s, double& value) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* p = s.data();
    const char* const e = p + s.size();
    bool negative = false;
    if (p != e && (*p == '+' || *p == '-')) negative = *p++ == '-';
    // All digits go into m (value = m * 10^scale); past 19 significant digits m has
    // wrapped, and the library reads the token instead.
    std::uint64_t m = 0;
    const char* const mantissa = p;
    for (; p != e && unsigned(*p - '0') < 10; ++p) m = m * 10 + unsigned(*p - '0');
    std::ptrdiff_t digits = p - mantissa, frac_digits = 0;
    if (p != e && *p == '.') {
        const char* const frac = ++p;
        for (; p != e && unsigned(*p - '0') < 10; ++p) m = m * 10 + unsigned(*p - '0');
        frac_digits = p - frac;
        digits += frac_digits;
    }
    if (digits == 0) return NumberScan::NotNumber;
    if (p == e && digits <= 15) {
        // The usual case, and the fast path below at its simplest: m < 10^15 < 2^53
        // (signed, the conversion is one instruction).
        double v = double(std::int64_t(m));
        if (frac_digits > 0) v /= kPow10[frac_digits];
        value = negative ? -v : v;
        return NumberScan::Exact;
    }
    bool exact = true;
    std::ptrdiff_t scale = -frac_digits;
    if (p != e && (*p == 'e' || *p == 'E')) {
        ++p;
        bool neg_exp = false;
        if (p != e && (*p == '+' || *p == '-')) neg_exp = *p++ == '-';
        const char* const exp_start = p;
        std::ptrdiff_t x = 0;
        for (; p != e && unsigned(*p - '0') < 10; ++p) {
            if (x > 100000) exact = false;
            else x = x * 10 + (*p - '0');
        }
        if (p == exp_start) return NumberScan::NotNumber;
        scale += neg_exp ? -x : x;
    }
    if (p != e) return NumberScan::NotNumber;
    if (digits > 19) {
        // Leading zeros add nothing to m; more than 19 other digits do not fit.
        std::ptrdiff_t zeros = 0;
        for (const char* q = mantissa; q != e && (*q == '0' || *q == '.'); ++q) zeros += *q == '0';
        exact = exact && digits - zeros <= 19;
    }
    // Clinger's fast path: digits that fit in 53 bits, scaled by at most 10^22, give
    // exactly one correctly rounded IEEE multiplication or division of two exact
    // doubles, so the result equals what from_chars/strtod return.
    if (!exact || m > (std::uint64_t(1) << 53) || (m != 0 && (scale < -22 || scale > 22))) return NumberScan::Library;
    double v = double(m);
    if (m != 0) v = scale < 0 ? v / kPow10[-scale] : v * kPow10[scale];
    value = negative ? -v : v;
    return NumberScan::Exact;
}

bool is_number_syntax(std::string_view s) {
    double unused = 0;
    return scan_number(s, unused) != NumberScan::NotNumber;
}

bool is_integer_syntax(std::string_view s) {
    std::size_t i = 0;
    if (i < s.size() && s[i] == '+') ++i;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}

double library_number_value(std::string_view s) {
    // from_chars is locale-independent; it rejects a leading '+', and on overflow or
    // underflow strtod tells which of the two it was.
    double d = 0;
    std::string_view digits = s[0] == '+' ? s.substr(1) : s;
    auto res = std::from_chars(digits.data(), digits.data() + digits.size(), d);
    if (res.ec != std::errc() || res.ptr != digits.data() + digits.size()) d = std::strtod(std::string(s).c_str(), nullptr);
    return d;
}

double number_value(std::string_view s) {
    double d = 0;
    return scan_number(s, d) == NumberScan::Exact ? d : library_number_value(s);
}

}  // namespace rt
