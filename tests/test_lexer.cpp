// The lexer: token offsets, line:column from offsets with LF, CR LF and CR alone as
// line ends, and the fast number path against the C library's correctly rounded
// conversion.
#include <doctest/doctest.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scene_lexer.h"
#include "scene_parser.h"
#include "scene_schema.h"
#include "test_random.h"

using namespace rt;

namespace {

// Independent reference: walk the text byte by byte.
LineCol walk(const std::string& text, std::size_t offset) {
    LineCol lc;
    for (std::size_t i = 0; i < offset; ++i) {
        const bool crlf = text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n';
        if ((text[i] == '\n' || text[i] == '\r') && !crlf) {
            ++lc.line;
            lc.col = 1;
        } else {
            ++lc.col;
        }
    }
    return lc;
}

std::vector<Token> all_tokens(std::string_view text) {
    SceneLexer lex(text);
    std::vector<Token> out;
    while (!lex.peek().eof()) out.push_back(lex.next());
    return out;
}

// strtod on a NUL-terminated copy: the C library's correctly rounded reading.
double libc_value(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("lexer: tokens carry their byte offsets; braces stand alone; // comments to the line end") {
    const std::string text = "\xEF\xBB\xBF" "thing{sphere {radius 1}}// c } {\r  end\n";
    const auto toks = all_tokens(text);
    const std::vector<std::pair<std::string, std::size_t>> want = {
        {"thing", 3}, {"{", 8}, {"sphere", 9}, {"{", 16}, {"radius", 17}, {"1", 24}, {"}", 25}, {"}", 26}, {"end", 38}};
    REQUIRE(toks.size() == want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
        CHECK(toks[i].text == want[i].first);
        CHECK(toks[i].offset == want[i].second);
        CHECK(text.substr(toks[i].offset, toks[i].text.size()) == want[i].first);
    }
    SceneLexer lex(text);
    while (!lex.peek().eof()) lex.next();
    CHECK(lex.peek().offset == text.size());
}

TEST_CASE("lexer: line and column of every offset, for LF, CR LF, CR alone and mixes") {
    rt_test::Rng rng(7);
    const char* pieces[] = {"a", "bc", " ", "\t", "\n", "\r\n", "\r", "\r\r\n", "\n\r", "{", "}", "//x", "\xC3\xA8"};
    for (int round = 0; round < 200; ++round) {
        std::string text;
        const std::size_t n = rng.index(60);
        for (std::size_t i = 0; i < n; ++i) text += pieces[rng.index(std::size(pieces))];
        CAPTURE(text);
        LineMap forward(text);
        for (std::size_t off = 0; off <= text.size(); ++off) {
            const LineCol want = walk(text, off);
            const LineCol got = line_col_at(text, off);
            CHECK(got.line == want.line);
            CHECK(got.col == want.col);
            const LineCol f = forward.at(off);
            CHECK(f.line == want.line);
            CHECK(f.col == want.col);
            // offset_at inverts it, except on the bytes that end a line.
            if (off < text.size() && text[off] != '\n' && text[off] != '\r')
                CHECK(offset_at(text, want.line, want.col) == off);
        }
    }
}

TEST_CASE("lexer: the line map answers look-ups in any order, across its checkpoints") {
    std::string text;
    rt_test::Rng rng(11);
    const char* ends[] = {"\n", "\r", "\r\n"};
    while (text.size() < 300000) {
        text.append(rng.index(90), 'x');
        text += ends[rng.index(3)];
    }
    LineMap map(text);
    for (int i = 0; i < 300; ++i) {
        const std::size_t off = rng.index(text.size() + 1);
        const LineCol want = walk(text, off), got = map.at(off);
        CHECK(got.line == want.line);
        CHECK(got.col == want.col);
    }
}

TEST_CASE("lexer: the line map's counting of long LF-only spans, with a rare CR among them") {
    // Spans of whole 16-byte blocks without a CR are counted apart from the exact way;
    // the CRs (alone, or before an LF, at any place in a block) send a span to it.
    rt_test::Rng rng(17);
    for (int round = 0; round < 40; ++round) {
        std::string text;
        const std::size_t size = 200 + rng.index(3000);
        while (text.size() < size) {
            text.append(rng.index(round % 4 == 0 ? 400 : 40), 'x');
            const std::size_t r = rng.index(100);
            text += r == 0 ? "\r" : r == 1 ? "\r\n" : r == 2 ? "\n\n\n" : "\n";
        }
        CAPTURE(round);
        LineMap forward(text), backward(text);
        for (std::size_t off = 0; off <= text.size(); off += rng.index(300)) {
            const LineCol want = walk(text, off), got = forward.at(off);
            REQUIRE(got.line == want.line);
            REQUIRE(got.col == want.col);
        }
        for (std::size_t k = 0; k < 200; ++k) {
            const std::size_t off = rng.index(text.size() + 1);
            const LineCol want = walk(text, off), got = backward.at(off);
            REQUIRE(got.line == want.line);
            REQUIRE(got.col == want.col);
        }
        // Jumps over long spans at once, from the start each time.
        for (std::size_t off = text.size(); off > 0; off = off * 3 / 4) {
            const LineCol want = walk(text, off), got = line_col_at(text, off);
            REQUIRE(got.line == want.line);
            REQUIRE(got.col == want.col);
        }
    }
}

TEST_CASE("lexer: a line map started mid-text counts from its first line; rebased, it gives true lines") {
    rt_test::Rng rng(13);
    const char* pieces[] = {"a", "bc", " ", "\n", "\r\n", "\r", "\r\r\n", "\n\r", "{", "}"};
    for (int round = 0; round < 300; ++round) {
        std::string text;
        const std::size_t n = rng.index(80);
        for (std::size_t i = 0; i < n; ++i) text += pieces[rng.index(std::size(pieces))];
        const std::size_t start = rng.index(text.size() + 1);
        CAPTURE(text);
        CAPTURE(start);
        const LineCol first = walk(text, start);
        LineMap later(text, start), later_copy(text, start);
        for (std::size_t off = start; off <= text.size(); ++off) {
            const LineCol want = walk(text, off), got = later.at(off);
            CHECK(got.line == want.line - first.line + 1);
            CHECK(got.col == want.col);
        }
        // A reader that went as far as `start`, then takes over the other's map (which
        // scanned part of the rest): true lines everywhere, in any order.
        LineMap map(text);
        map.at(start);
        later_copy.at(start + rng.index(text.size() - start + 1));
        map.rebase(std::move(later_copy), first.line);
        for (int i = 0; i < 40; ++i) {
            const std::size_t off = rng.index(text.size() + 1);
            const LineCol want = walk(text, off), got = map.at(off);
            CHECK(got.line == want.line);
            CHECK(got.col == want.col);
        }
    }
}

TEST_CASE("numbers: the fast path gives the library's double, bit for bit") {
    rt_test::Rng rng(3);
    const char* fixed[] = {"0",      "-0",     "+0",     "0.0",     "-0.0",    ".5",      "5.",        "1e22",
                           "1e23",   "1e-22",  "1e-23",  "9007199254740992",    "9007199254740993",   "0.1",
                           "0.3",    "-2.675", "1.0000000000000002",    "123456789012345678", "1234567890123456789",
                           "12345678901234567890", "0.000000000000000000000000000001", "4.9e-324", "2.2250738585072014e-308",
                           "1.7976931348623157e308", "00000000000000000000000001.5", "1E5", "7e+0", "3.14159265358979323846"};
    std::vector<std::string> cases(std::begin(fixed), std::end(fixed));
    const char digits[] = "0123456789";
    for (int i = 0; i < 20000; ++i) {
        std::string s;
        if (rng.uni() < 0.3) s += rng.uni() < 0.5 ? "-" : "+";
        const std::size_t int_digits = rng.index(12), frac_digits = rng.index(12);
        for (std::size_t k = 0; k < int_digits; ++k) s += digits[rng.index(10)];
        if (frac_digits > 0 || int_digits == 0) {
            s += '.';
            for (std::size_t k = 0; k < std::max<std::size_t>(frac_digits, int_digits == 0); ++k) s += digits[rng.index(10)];
        }
        if (rng.uni() < 0.3) s += "e" + std::to_string(int(rng.index(60)) - 30);
        cases.push_back(s);
    }
    int fast = 0;
    for (const std::string& s : cases) {
        CAPTURE(s);
        REQUIRE(is_number_syntax(s));
        double v = 0;
        const NumberScan scan = scan_number(s, v);
        REQUIRE(scan != NumberScan::NotNumber);
        fast += scan == NumberScan::Exact;
        if (scan == NumberScan::Exact) CHECK(same_bits(v, libc_value(s)));
        CHECK(same_bits(number_value(s), libc_value(s)));
    }
    CHECK(fast > int(cases.size()) / 2);  // the fast path is the common one
}

TEST_CASE("numbers: short_decimal takes exactly the short decimals, with the library's double") {
    // Tokens from the characters of numbers, so that most are near misses: signs and
    // points in odd places, exponents, 15 and 16 digits, empty digit runs.
    rt_test::Rng rng(29);
    const char alphabet[] = "0123456789000000000.-+eE";
    int taken = 0;
    for (int i = 0; i < 300000; ++i) {
        std::string s;
        const std::size_t n = rng.index(20);
        if (i % 2 == 0) {
            for (std::size_t k = 0; k < n; ++k) s += alphabet[rng.index(sizeof alphabet - 1)];
        } else {  // well-formed decimals of 0 to 19 digits
            if (rng.uni() < 0.4) s += "-+"[rng.index(2)];
            const std::size_t point = rng.index(n + 1);
            for (std::size_t k = 0; k < n; ++k) {
                if (k == point) s += '.';
                s += "0123456789"[rng.index(10)];
            }
        }
        CAPTURE(s);
        double fast = 0, scanned = 0;
        const bool short_one = short_decimal(s, fast);
        const NumberScan scan = scan_number(s, scanned);
        std::size_t digits = 0;
        bool plain = !s.empty();
        for (std::size_t k = 0; k < s.size(); ++k) {
            digits += s[k] >= '0' && s[k] <= '9';
            plain = plain && (std::strchr("0123456789.", s[k]) || (k == 0 && (s[k] == '-' || s[k] == '+')));
        }
        // Its own definition, from the text: a sign, digits with at most one point.
        const bool want = plain && std::count(s.begin(), s.end(), '.') <= 1 && digits >= 1 && digits <= 15;
        REQUIRE(short_one == want);
        if (!short_one) continue;
        ++taken;
        REQUIRE(scan == NumberScan::Exact);
        REQUIRE(same_bits(fast, scanned));
        REQUIRE(same_bits(fast, libc_value(s)));
    }
    CHECK(taken > 50000);
}

TEST_CASE("numbers: the syntax, whole tokens only") {
    for (const char* s : {"1", "-1", "+1", "1.", ".1", "1e5", "1E-5", "+.5e+3"}) CHECK(is_number_syntax(s));
    for (const char* s : {"", "+", "-", ".", "e5", "1e", "1e+", "1.2.3", "0x10", "inf", "nan", "1,5", "1e5x", "--1", " 1"})
        CHECK_FALSE(is_number_syntax(s));
}

TEST_CASE("CR-only line ends: comments stop at CR and errors get their own lines") {
    const std::string tail = "camera {\r position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\r"
                             "picture_size { x_max 4 y_max 4 }\r";
    // A comment on line 1 must not swallow the rest of the file.
    ParseResult ok = parse_scene("// a scene\rthing {\r  sphere { radius 2 }\r}\r" + tail + "end\r");
    CHECK(ok.ok());
    REQUIRE(ok.scene.objects.size() == 1);
    CHECK(ok.scene.objects[0].loc.line == 3);
    CHECK(ok.scene.objects[0].loc.col == 3);
    ParseResult bad = parse_scene("// a scene\rthing {\r  sphere {\r    radios 1\r  }\r}\r" + tail + "end\r");
    REQUIRE(!bad.diagnostics.empty());
    CHECK(bad.diagnostics[0].line == 4);
    CHECK(bad.diagnostics[0].col == 5);
    CHECK(bad.diagnostics[0].message.find("'radios'") != std::string::npos);
    // The same file with CR LF and with LF gives the same positions.
    for (const char* eol : {"\r\n", "\n"}) {
        std::string text = "// a scene\rthing {\r  sphere {\r    radios 1\r  }\r}\r" + tail + "end\r";
        std::string converted;
        for (char c : text) c == '\r' ? converted += eol : converted += c;
        ParseResult r = parse_scene(converted);
        REQUIRE(!r.diagnostics.empty());
        CHECK(r.diagnostics[0].line == 4);
        CHECK(r.diagnostics[0].col == 5);
    }
    // A missing end is reported past the last line.
    ParseResult noend = parse_scene("thing {\r}\r" + tail);
    REQUIRE(!noend.diagnostics.empty());
    CHECK(noend.diagnostics.back().line == 6);
    CHECK(noend.diagnostics.back().col == 1);
}

TEST_CASE("schema: same_word agrees with string comparison for words of every length") {
    // Words from a two-letter alphabet, so that equal sizes and first bytes are common
    // and a difference may sit at any place, both ends included.
    rt_test::Rng rng(23);
    for (int round = 0; round < 20000; ++round) {
        const std::size_t n = rng.index(21);
        std::string a, b;
        for (std::size_t i = 0; i < n; ++i) a += "ab"[rng.index(2)];
        b = a;
        if (rng.index(2) == 0 && n > 0) b[rng.index(n)] = "ab"[rng.index(2)];
        if (rng.index(8) == 0) b += 'a';
        CAPTURE(a);
        CAPTURE(b);
        REQUIRE(schema::same_word(a, b) == (a == b));
        REQUIRE(schema::same_word(b, a) == (a == b));
    }
}

TEST_CASE("schema: no object name is a section name (the parser takes an object name as an item at once)") {
    for (const schema::Block<Object>& b : schema::object_blocks()) {
        CAPTURE(b.name);
        CHECK(schema::find_section(b.name) == nullptr);
        CHECK(schema::object_block(b.name) == &b);
    }
}
