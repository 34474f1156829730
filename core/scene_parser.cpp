// Recursive-descent reader for the scene format. It collects diagnostics instead of
// stopping at the first problem: after an error it skips to the next key it knows in
// the same block (or the block's closing brace), so one typo gives one message.
#include "scene_parser.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

#include "camera.h"

namespace rt {
namespace {

struct Token {
    std::string_view text;
    int line = 0, col = 0;
    bool eof() const { return text.empty(); }
    bool is(std::string_view s) const { return text == s; }
};

// Splits text into tokens: runs of non-space characters, with `{` and `}` always
// tokens of their own and `//` at the start of a token commenting out the line.
class Lexer {
public:
    explicit Lexer(std::string_view text) : text_(text) {
        // A UTF-8 byte-order mark is not part of the scene.
        if (text_.size() >= 3 && std::memcmp(text_.data(), "\xEF\xBB\xBF", 3) == 0) pos_ = 3, col_ = 4;
        advance();
    }
    const Token& peek() const { return cur_; }
    Token next() {
        Token t = cur_;
        advance();
        return t;
    }
    // Position just past the last character, for end-of-file diagnostics.
    Token end_token() const { return Token{{}, line_, col_}; }

private:
    static bool space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
    void bump() {
        if (text_[pos_] == '\n') {
            ++line_;
            col_ = 1;
        } else {
            ++col_;
        }
        ++pos_;
    }
    void advance() {
        for (;;) {
            while (pos_ < text_.size() && space(text_[pos_])) bump();
            if (pos_ + 1 < text_.size() && text_[pos_] == '/' && text_[pos_ + 1] == '/') {
                while (pos_ < text_.size() && text_[pos_] != '\n') bump();
                continue;
            }
            break;
        }
        if (pos_ >= text_.size()) {
            cur_ = Token{{}, line_, col_};
            return;
        }
        std::size_t start = pos_;
        int line = line_, col = col_;
        if (text_[pos_] == '{' || text_[pos_] == '}') {
            bump();
        } else {
            while (pos_ < text_.size() && !space(text_[pos_]) && text_[pos_] != '{' && text_[pos_] != '}') bump();
        }
        cur_ = Token{text_.substr(start, pos_ - start), line, col};
    }

    std::string_view text_;
    std::size_t pos_ = 0;
    int line_ = 1, col_ = 1;
    Token cur_;
};

// Raised to abandon parsing (too many errors, or the end of the file inside a block).
struct Stop {};

std::string quote(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 40)) {
        unsigned char u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    if (s.size() > 40) out += "...";
    return out + "'";
}

std::string join_keys(std::initializer_list<const char*> keys) {
    std::string out;
    for (const char* k : keys) {
        if (!out.empty()) out += ", ";
        out += k;
    }
    return out;
}

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

// Every number must stay well inside double range so that squares and products in
// the tracer stay finite.
constexpr double kMaxMagnitude = 1e15;

class Parser {
public:
    Parser(std::string_view text, const ParseOptions& opt, ParseResult& out)
        : lex_(text), opt_(opt), out_(out) {}

    void run() {
        try {
            parse_top();
            if (errors_ == 0) validate();
        } catch (const Stop&) {
            // Too many errors: what was collected is the result.
        }
        std::stable_sort(out_.diagnostics.begin(), out_.diagnostics.end(), [](const Diagnostic& a, const Diagnostic& b) {
            return a.line != b.line ? a.line < b.line : a.col < b.col;
        });
    }

private:
    // ---- diagnostics -------------------------------------------------------------
    void error_at(int line, int col, std::string msg) {
        out_.diagnostics.push_back({Diagnostic::Severity::Error, line, col, std::move(msg)});
        if (++errors_ >= opt_.max_errors) throw Stop{};
    }
    void error(const Token& t, std::string msg) { error_at(t.line, t.col, std::move(msg)); }
    void warning(SourceLoc loc, std::string msg) {
        out_.diagnostics.push_back({Diagnostic::Severity::Warning, loc.line, loc.col, std::move(msg)});
    }
    static std::string got(const Token& t) { return t.eof() ? "end of file" : quote(t.text); }

    // ---- token helpers -----------------------------------------------------------
    static bool is_section(const Token& t) {
        return t.is("thing") || t.is("special_thing") || t.is("light") || t.is("camera") || t.is("picture_size") ||
               t.is("end");
    }
    // A section name inside a block almost always means a '}' is missing before it.
    // Report that once and let the caller close the block, so the rest still parses.
    bool section_inside(const Token& t, std::string_view what) {
        if (!is_section(t)) return false;
        error(t, quote(t.text) + " inside " + quote(what) + ": is a '}' missing before it?");
        return true;
    }

    // Consumes '{' after a block name; false (with an error) if it is not there.
    bool open(const Token& name) {
        const Token& t = lex_.peek();
        if (t.is("{")) {
            lex_.next();
            return true;
        }
        if (t.eof()) {
            error(t, "unexpected end of file: expected '{' after " + quote(name.text));
            throw Stop{};
        }
        error(t, "expected '{' after " + quote(name.text) + ", got " + got(t));
        return false;
    }

    // Skips a balanced { ... } block whose '{' is the next token; iterative so that
    // absurd nesting cannot exhaust the stack.
    void skip_block() {
        if (!lex_.peek().is("{")) return;
        std::size_t depth = 0;
        do {
            Token t = lex_.next();
            if (t.eof()) {
                error(t, "unexpected end of file: unbalanced '{'");
                throw Stop{};
            }
            if (t.is("{")) ++depth;
            if (t.is("}")) --depth;
        } while (depth > 0);
    }

    // After an error inside a block: skip to the next known key, a nested block, or
    // the closing brace.
    void recover(std::initializer_list<const char*> keys) {
        for (;;) {
            const Token& t = lex_.peek();
            if (t.eof() || t.is("}")) return;
            if (t.is("{")) {
                skip_block();
                continue;
            }
            for (const char* k : keys)
                if (t.text == k) return;
            lex_.next();
        }
    }

    // Reads the body of a block up to and including its '}'. `key` handles one key and
    // returns false if it reported an error.
    template <class KeyFn>
    void block(std::string_view what, std::initializer_list<const char*> keys, KeyFn key) {
        for (;;) {
            Token t = lex_.peek();
            if (t.eof()) {
                error(t, "unexpected end of file inside " + quote(what) + ": expected '}'");
                throw Stop{};
            }
            if (t.is("}")) {
                lex_.next();
                return;
            }
            if (section_inside(t, what)) return;
            lex_.next();
            bool known = false;
            for (const char* k : keys) known = known || t.text == k;
            if (!known) {
                if (t.is("{"))
                    error(t, "unexpected '{' in " + quote(what));
                else
                    error(t, "unknown key " + quote(t.text) + " in " + std::string(what) + " (expected " +
                                 join_keys(keys) + ")");
                if (t.is("{")) {
                    // Treat the brace as an unnamed block and skip it whole.
                    std::size_t depth = 1;
                    while (depth > 0) {
                        Token u = lex_.next();
                        if (u.eof()) {
                            error(u, "unexpected end of file: unbalanced '{'");
                            throw Stop{};
                        }
                        depth += u.is("{") ? 1 : u.is("}") ? -1 : 0;
                    }
                }
                recover(keys);
                continue;
            }
            if (!key(t)) recover(keys);
        }
    }

    bool number(const Token& key, double& v) {
        Token t = lex_.peek();
        if (t.eof() || t.is("{") || t.is("}") || !is_number_syntax(t.text)) {
            if (t.eof()) {
                error(t, "unexpected end of file: expected a number after " + quote(key.text));
                throw Stop{};
            }
            error(t, "expected a number after " + quote(key.text) + ", got " + got(t));
            return false;
        }
        lex_.next();
        last_number_ = {t.line, t.col};
        if (t.text.size() > Limits::max_token_length) {
            error(t, "number too long (" + std::to_string(t.text.size()) + " characters, limit " +
                         std::to_string(Limits::max_token_length) + ")");
            return false;
        }
        // from_chars is locale-independent and fast; it rejects a leading '+', and on
        // overflow or underflow strtod tells which of the two it was.
        std::string_view digits = t.text[0] == '+' ? t.text.substr(1) : t.text;
        double d = 0;
        auto res = std::from_chars(digits.data(), digits.data() + digits.size(), d);
        if (res.ec != std::errc() || res.ptr != digits.data() + digits.size()) {
            char buf[Limits::max_token_length + 1];
            std::memcpy(buf, t.text.data(), t.text.size());
            buf[t.text.size()] = 0;
            d = std::strtod(buf, nullptr);
        }
        if (!std::isfinite(d) || std::fabs(d) > kMaxMagnitude) {
            error(t, "number " + quote(t.text) + " is out of range (magnitude at most 1e15)");
            return false;
        }
        v = d;
        return true;
    }

    bool vec3(const Token& key, Vec3& v) {
        Vec3 r;
        for (int i = 0; i < 3; ++i) {
            const Token& t = lex_.peek();
            if (!t.eof() && !is_number_syntax(t.text)) {
                error(t, "expected 3 numbers after " + quote(key.text) + ", got " + got(t));
                return false;
            }
            if (!number(key, r[i])) return false;
        }
        v = r;
        return true;
    }

    // Unsigned integer slot; `lo..hi` inclusive.
    bool integer(const Token& key, long lo, long hi, long& v, const char* range_msg) {
        Token t = lex_.peek();
        if (t.eof()) {
            error(t, "unexpected end of file: expected an integer after " + quote(key.text));
            throw Stop{};
        }
        if (!is_integer_syntax(t.text)) {
            error(t, "expected an integer after " + quote(key.text) + ", got " + got(t));
            if (!t.is("{") && !t.is("}")) lex_.next();
            return false;
        }
        lex_.next();
        std::string_view digits = t.text[0] == '+' ? t.text.substr(1) : t.text;
        while (digits.size() > 1 && digits[0] == '0') digits.remove_prefix(1);
        long value = 0;
        if (digits.size() > 9) {
            value = hi + 1;
        } else {
            for (char c : digits) value = value * 10 + (c - '0');
        }
        if (value < lo || value > hi) {
            error(t, range_msg);
            return false;
        }
        v = value;
        return true;
    }

    // ---- sections ----------------------------------------------------------------
    void parse_top() {
        for (;;) {
            Token t = lex_.next();
            if (t.eof()) {
                error(t, "missing 'end' at the end of the scene");
                return;
            }
            if (t.is("end")) return;
            if (t.is("thing")) {
                if (open(t)) things(t);
            } else if (t.is("special_thing")) {
                if (open(t)) specials();
            } else if (t.is("light")) {
                if (open(t)) lights();
            } else if (t.is("camera")) {
                if (open(t)) camera(t);
            } else if (t.is("picture_size")) {
                if (!size_seen_) size_loc_ = {t.line, t.col};
                size_seen_ = true;
                if (open(t)) picture_size();
            } else {
                error(t, "unknown section " + quote(t.text) +
                             " (expected thing, special_thing, light, camera, picture_size or end)");
                if (lex_.peek().is("{")) skip_block();
                // Resynchronise on the next section name.
                for (;;) {
                    const Token& u = lex_.peek();
                    if (u.eof() || u.is("thing") || u.is("special_thing") || u.is("light") || u.is("camera") ||
                        u.is("picture_size") || u.is("end"))
                        break;
                    if (u.is("{"))
                        skip_block();
                    else
                        lex_.next();
                }
            }
        }
    }

    void count_object(const Token& t) {
        if (++objects_ > Limits::max_objects) {
            error(t, "too many objects (limit " + std::to_string(Limits::max_objects) + ")");
            throw Stop{};
        }
    }

    void things(const Token&) {
        for (;;) {
            Token t = lex_.peek();
            if (t.eof()) {
                error(t, "unexpected end of file inside 'thing': expected '}'");
                throw Stop{};
            }
            if (t.is("}")) {
                lex_.next();
                return;
            }
            if (section_inside(t, "thing")) return;
            Object obj;
            if (object(obj, 0)) out_.scene.objects.push_back(std::move(obj));
        }
    }

    static constexpr std::initializer_list<const char*> kObjectNames = {"sphere", "tetrahedron", "cylinder", "torus",
                                                                        "constructive_solid_geometry"};

    // Reads one object (its name is the next token). False if it was unusable.
    bool object(Object& obj, int depth) {
        Token t = lex_.next();
        obj.loc = {t.line, t.col};
        if (t.is("sphere")) {
            count_object(t);
            Sphere s;
            SourceLoc radius_at{t.line, t.col};
            if (!open(t)) return false;
            block("sphere", {"position", "radius", "material"}, [&](const Token& k) {
                if (k.is("position")) return vec3(k, s.position);
                if (k.is("radius")) return number(k, s.radius) && (radius_at = last_number_, true);
                return material(k, obj);
            });
            if (!(s.radius > 0)) error_at(radius_at.line, radius_at.col, "sphere radius must be greater than 0");
            obj.shape = s;
            return true;
        }
        if (t.is("tetrahedron")) {
            count_object(t);
            Tetrahedron s;
            if (!open(t)) return false;
            block("tetrahedron", {"vect1", "vect2", "vect3", "vect4", "material"}, [&](const Token& k) {
                if (k.is("vect1")) return vec3(k, s.v[0]);
                if (k.is("vect2")) return vec3(k, s.v[1]);
                if (k.is("vect3")) return vec3(k, s.v[2]);
                if (k.is("vect4")) return vec3(k, s.v[3]);
                return material(k, obj);
            });
            Vec3 e1 = s.v[1] - s.v[0], e2 = s.v[2] - s.v[0], e3 = s.v[3] - s.v[0];
            double vol = std::fabs(dot(cross(e1, e2), e3));
            double scale = std::max({length2(e1), length2(e2), length2(e3)});
            if (!(vol > 1e-12 * scale * std::sqrt(scale)) || scale == 0)
                error_at(t.line, t.col, "tetrahedron is flat: its four corners lie in one plane");
            obj.shape = s;
            return true;
        }
        if (t.is("cylinder")) {
            count_object(t);
            Cylinder s;
            SourceLoc radius_at{t.line, t.col};
            if (!open(t)) return false;
            block("cylinder", {"end_1", "end_2", "radius", "material"}, [&](const Token& k) {
                if (k.is("end_1")) return vec3(k, s.end1);
                if (k.is("end_2")) return vec3(k, s.end2);
                if (k.is("radius")) return number(k, s.radius) && (radius_at = last_number_, true);
                return material(k, obj);
            });
            if (!(s.radius > 0)) error_at(radius_at.line, radius_at.col, "cylinder radius must be greater than 0");
            if (s.end1 == s.end2) error_at(t.line, t.col, "cylinder end_1 and end_2 are the same point");
            obj.shape = s;
            return true;
        }
        if (t.is("torus")) {
            count_object(t);
            Torus s;
            SourceLoc major_at{t.line, t.col}, minor_at{t.line, t.col};
            if (!open(t)) return false;
            block("torus", {"position", "direction", "major", "minor", "material"}, [&](const Token& k) {
                if (k.is("position")) return vec3(k, s.position);
                if (k.is("direction")) return vec3(k, s.direction);
                if (k.is("major")) return number(k, s.major) && (major_at = last_number_, true);
                if (k.is("minor")) return number(k, s.minor) && (minor_at = last_number_, true);
                return material(k, obj);
            });
            if (!(s.minor > 0)) error_at(minor_at.line, minor_at.col, "torus minor radius must be greater than 0");
            if (s.major < 0) error_at(major_at.line, major_at.col, "torus major radius must not be negative");
            if (length2(s.direction) == 0) error_at(t.line, t.col, "torus direction must not be 0 0 0");
            obj.shape = s;
            return true;
        }
        if (t.is("constructive_solid_geometry")) {
            count_object(t);
            if (depth >= Limits::max_csg_depth) {
                error(t, "CSG nested too deeply (limit " + std::to_string(Limits::max_csg_depth) + " levels)");
                skip_block();
                return false;
            }
            Csg s;
            s.operands.resize(2);
            bool have[2] = {false, false};
            bool bad = false;
            if (!open(t)) return false;
            block("constructive_solid_geometry", {"left", "right", "type", "material"}, [&](const Token& k) {
                if (k.is("left") || k.is("right")) {
                    int side = k.is("left") ? 0 : 1;
                    if (!open(k)) return false;
                    const Token& first = lex_.peek();
                    if (first.is("}")) {
                        error(first, "CSG " + std::string(k.text) + " operand is empty: expected one object");
                        lex_.next();
                        bad = true;
                        return true;
                    }
                    if (!is_object_name(first)) {
                        error(first, "unknown object " + got(first) + " in CSG " + std::string(k.text) +
                                         " operand (expected " + join_keys(kObjectNames) + ")");
                        skip_rest_of_block();
                        bad = true;
                        return true;
                    }
                    Object operand;
                    if (!object(operand, depth + 1)) bad = true;
                    s.operands[side] = std::move(operand);
                    have[side] = true;
                    const Token& close = lex_.peek();
                    if (!close.is("}")) {
                        error(close, "expected '}' after the CSG " + std::string(k.text) +
                                         " operand (it holds exactly one object), got " + got(close));
                        skip_rest_of_block();
                        bad = true;
                        return true;
                    }
                    lex_.next();
                    return true;
                }
                if (k.is("type")) {
                    Token v = lex_.peek();
                    if (v.eof()) {
                        error(v, "unexpected end of file: expected U, I or C after 'type'");
                        throw Stop{};
                    }
                    if (v.is("U") || v.is("I") || v.is("C")) {
                        lex_.next();
                        s.type = static_cast<CsgType>(v.text[0]);
                        return true;
                    }
                    error(v, "CSG type must be U, I or C, got " + got(v));
                    if (!v.is("{") && !v.is("}")) lex_.next();
                    bad = true;
                    return true;
                }
                return material(k, obj);
            });
            if (!have[0]) error_at(t.line, t.col, "CSG is missing its 'left' operand"), bad = true;
            if (!have[1]) error_at(t.line, t.col, "CSG is missing its 'right' operand"), bad = true;
            obj.shape = std::move(s);
            return !bad;
        }
        if (t.is("{") || t.is("}")) {
            error(t, "expected an object name (" + join_keys(kObjectNames) + "), got " + got(t));
            if (t.is("{")) {
                // Skip the anonymous block: we already consumed its '{'.
                std::size_t d = 1;
                while (d > 0) {
                    Token u = lex_.next();
                    if (u.eof()) {
                        error(u, "unexpected end of file: unbalanced '{'");
                        throw Stop{};
                    }
                    d += u.is("{") ? 1 : u.is("}") ? -1 : 0;
                }
            }
            return false;
        }
        error(t, "unknown object " + quote(t.text) + " (expected " + join_keys(kObjectNames) + ")");
        if (lex_.peek().is("{")) skip_block();
        return false;
    }

    static bool is_object_name(const Token& t) {
        for (const char* k : kObjectNames)
            if (t.text == k) return true;
        return false;
    }

    // Skips tokens (and nested blocks) up to and including the '}' closing the block
    // we are in.
    void skip_rest_of_block() {
        for (;;) {
            Token t = lex_.peek();
            if (t.eof()) {
                error(t, "unexpected end of file: expected '}'");
                throw Stop{};
            }
            if (t.is("}")) {
                lex_.next();
                return;
            }
            if (t.is("{"))
                skip_block();
            else
                lex_.next();
        }
    }

    bool material(const Token& k, Object& obj) {
        Material m;
        if (!material_block(k, m)) return false;
        obj.material = m;
        obj.has_material = true;
        return true;
    }

    bool material_block(const Token& k, Material& out) {
        if (!open(k)) return false;
        Material m;  // in-block defaults
        Token start = k;
        block("material", {"reflection", "refraction", "scattering", "translusans", "refractive_index", "colour"},
              [&](const Token& key) {
                  if (key.is("reflection")) return number(key, m.reflection);
                  if (key.is("refraction")) return number(key, m.refraction);
                  if (key.is("scattering")) return number(key, m.scattering);
                  if (key.is("translusans")) return number(key, m.translusans);
                  if (key.is("refractive_index")) return number(key, m.refractive_index);
                  return vec3(key, m.colour);
              });
        m.translusans = std::clamp(m.translusans, 0.0, 1.0);
        if (m.refractive_index < 1) m.refractive_index = 1;
        if (m.reflection + m.refraction + m.scattering == 0)
            warning({start.line, start.col},
                    m.reflection == 0 && m.refraction == 0
                        ? "material weights reflection, refraction and scattering are all 0: the surface renders black"
                        : "material weights reflection, refraction and scattering add up to 0: the surface renders black");
        out = m;
        return true;
    }

    void specials() {
        for (;;) {
            Token t = lex_.peek();
            if (t.eof()) {
                error(t, "unexpected end of file inside 'special_thing': expected '}'");
                throw Stop{};
            }
            if (t.is("}")) {
                lex_.next();
                return;
            }
            if (section_inside(t, "special_thing")) return;
            lex_.next();
            if (!t.is("plane") && !t.is("chess_plane")) {
                error(t, "unknown special thing " + quote(t.text) + " (expected plane, chess_plane)");
                if (lex_.peek().is("{")) skip_block();
                continue;
            }
            count_object(t);  // planes cost memory like objects
            Plane p;
            p.chess = t.is("chess_plane");
            p.loc = {t.line, t.col};
            if (!open(t)) continue;
            block(t.text, {"point", "material"}, [&](const Token& k) {
                if (k.is("point")) {
                    long n = 0;
                    if (!integer(k, 1, 4, n, "point number must be 1..4")) return false;
                    return vec3(k, p.point[n - 1]);
                }
                if (p.chess) {
                    long n = 0;
                    if (!integer(k, 1, 2, n, "material number must be 1 or 2")) return false;
                    Material m;
                    if (!material_block(k, m)) return false;
                    (n == 1 ? p.material : p.material2) = m;
                    (n == 1 ? p.has_material : p.has_material2) = true;
                    return true;
                }
                Material m;
                if (!material_block(k, m)) return false;
                p.material = m;
                p.has_material = true;
                return true;
            });
            Vec3 e1 = p.point[1] - p.point[0], e2 = p.point[2] - p.point[0];
            Vec3 n = cross(e1, e2);
            if (!(length2(n) > 1e-24 * length2(e1) * length2(e2)) || length2(n) == 0) {
                error_at(t.line, t.col, std::string(t.text) + ": points 1, 2 and 3 lie on one line");
            } else if (std::fabs(dot(normalize(n), p.point[3] - p.point[0])) <= 1.5e-5) {
                warning(p.loc, std::string(t.text) + ": point 4 lies in the plane, so the lit side is arbitrary" +
                                   (p.chess ? " and every cell gets material 1" : ""));
            }
            out_.scene.planes.push_back(p);
        }
    }

    void lights() {
        for (;;) {
            Token t = lex_.peek();
            if (t.eof()) {
                error(t, "unexpected end of file inside 'light': expected '}'");
                throw Stop{};
            }
            if (t.is("}")) {
                lex_.next();
                return;
            }
            if (section_inside(t, "light")) return;
            lex_.next();
            if (!t.is("lamp") && !t.is("spotlight")) {
                error(t, "unknown light " + quote(t.text) + " (expected lamp, spotlight)");
                if (lex_.peek().is("{")) skip_block();
                continue;
            }
            count_object(t);
            Light l;
            l.lamp = t.is("lamp");
            l.loc = {t.line, t.col};
            if (!open(t)) continue;
            auto key = [&](const Token& k) {
                if (k.is("position")) return vec3(k, l.position);
                if (k.is("colour")) return vec3(k, l.colour);
                return number(k, l.size);
            };
            if (l.lamp)
                block(t.text, {"position", "colour", "size"}, key);
            else
                block(t.text, {"position", "colour"}, key);
            out_.scene.lights.push_back(l);
        }
    }

    void camera(const Token& name) {
        if (!camera_seen_) camera_loc_ = {name.line, name.col};
        camera_seen_ = true;
        Camera& c = out_.scene.camera;
        block("camera", {"position", "centre", "up", "projection", "angle_x", "angle_y"}, [&](const Token& k) {
            if (k.is("position")) return cam_set(0), vec3(k, c.position);
            if (k.is("centre")) return cam_set(1), vec3(k, c.centre);
            if (k.is("up")) return cam_set(2), vec3(k, c.up);
            if (k.is("angle_x")) return cam_set(3), number(k, c.angle_x);
            if (k.is("angle_y")) return cam_set(4), number(k, c.angle_y);
            Token v = lex_.peek();
            if (v.eof()) {
                error(v, "unexpected end of file: expected a projection after 'projection'");
                throw Stop{};
            }
            if (v.is("{") || v.is("}")) {
                error(v, "expected a projection (linear, polar or a single character) after 'projection', got " +
                             got(v));
                return false;
            }
            lex_.next();
            if (v.is("1") || v.is("polar") || v.is("angular")) {
                c.projection = Projection::Polar;
            } else if (v.text.size() == 1 || v.is("linear")) {
                c.projection = Projection::Linear;
            } else {
                error(v, "projection must be 'linear', 'polar' (or 1), or a single character for linear; got " +
                             got(v));
                return false;
            }
            return true;
        });
    }
    void cam_set(int i) { camera_keys_ |= 1u << i; }

    void picture_size() {
        block("picture_size", {"x_max", "y_max"}, [&](const Token& k) {
            long v = 0;
            if (!integer(k, 1, Limits::max_picture_side, v,
                         "picture size must be 1..16384 pixels on each side"))
                return false;
            (k.is("x_max") ? out_.scene.width : out_.scene.height) = int(v);
            size_keys_ |= k.is("x_max") ? 1u : 2u;
            return true;
        });
    }

    // Whole-scene checks that need every section read.
    void validate() {
        Token eof = lex_.end_token();
        if (!camera_seen_) {
            error_at(eof.line, eof.col, "the scene has no 'camera' section");
        } else {
            static const char* names[] = {"position", "centre", "up", "angle_x", "angle_y"};
            for (int i = 0; i < 5; ++i)
                if (!(camera_keys_ & (1u << i)))
                    error_at(camera_loc_.line, camera_loc_.col, std::string("camera: missing '") + names[i] + "'");
            if (camera_keys_ == 31u) {
                if (const char* why = camera_problem(out_.scene.camera))
                    error_at(camera_loc_.line, camera_loc_.col, std::string("camera: ") + why);
            }
        }
        SourceLoc size_at = size_seen_ ? size_loc_ : SourceLoc{eof.line, eof.col};
        if (!size_seen_) error_at(eof.line, eof.col, "the scene has no 'picture_size' section");
        else if (!(size_keys_ & 1u)) error_at(size_at.line, size_at.col, "picture_size: missing 'x_max'");
        if (size_seen_ && !(size_keys_ & 2u)) error_at(size_at.line, size_at.col, "picture_size: missing 'y_max'");
        out_.scene.camera_loc = camera_loc_;
    }

    Lexer lex_;
    const ParseOptions& opt_;
    ParseResult& out_;
    int errors_ = 0;
    std::size_t objects_ = 0;
    bool camera_seen_ = false, size_seen_ = false;
    unsigned camera_keys_ = 0, size_keys_ = 0;
    SourceLoc camera_loc_;
    SourceLoc last_number_;
    SourceLoc size_loc_;
};

}  // namespace

ParseResult parse_scene(std::string_view text, const ParseOptions& options) {
    ParseResult result;
    if (text.size() > Limits::max_file_size) {
        result.diagnostics.push_back({Diagnostic::Severity::Error, 1, 1,
                                      "scene file too large (" + std::to_string(text.size()) +
                                          " bytes, limit " + std::to_string(Limits::max_file_size) + ")"});
        return result;
    }
    Parser p(text, options, result);
    p.run();
    return result;
}

std::string format_diagnostic(const std::string& file, const Diagnostic& d) {
    return file + ":" + std::to_string(d.line) + ":" + std::to_string(d.col) + ": " +
           (d.is_error() ? "error: " : "warning: ") + d.message;
}

}  // namespace rt
