// The edit fuzzer's choices (edit_fuzz.h): what the input's bytes decide, and the
// numbers a user types or drags to, plain or at the edges of what the format takes.
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "scene_writer.h"
#include "math.h"

namespace rtfuzz {

// The choices of one run, read from the input's bytes; zeros once they run out, so
// that every input is a complete run.
class Choices {
public:
    Choices(const std::uint8_t* data, std::size_t size) : p_(data), n_(size) {}
    bool more() const { return i_ < n_; }
    unsigned byte() { return i_ < n_ ? p_[i_++] : 0u; }
    // 0 .. n - 1.
    unsigned below(unsigned n) {
        if (n <= 1) return 0;
        unsigned v = byte();
        if (n > 256) v = v << 8 | byte();
        return v % n;
    }
    bool one_in(unsigned n) { return below(n) == 0; }
    int between(int lo, int hi) { return lo + int(below(unsigned(hi - lo + 1))); }

private:
    const std::uint8_t* p_;
    std::size_t n_, i_ = 0;
};

// ---------------------------------------------------------------------------------
// Numbers

// Values a user types or drags to, and the edges of what the format takes.
inline double edge_number(Choices& c) {
    static const double kEdges[] = {0.0,
                                    -0.0,
                                    1e15,
                                    -1e15,
                                    1e16,
                                    -1e16,
                                    999999999999999.9,
                                    1e-300,
                                    4.9e-324,
                                    1e308,
                                    std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(),
                                    std::numeric_limits<double>::quiet_NaN(),
                                    0.1 + 0.2,
                                    1.0 / 3,
                                    2.07 - 2.5,
                                    123456789.123456789,
                                    1e-7,
                                    0.5,
                                    180,
                                    179.5,
                                    16384,
                                    16385};
    return kEdges[c.below(sizeof kEdges / sizeof kEdges[0])];
}

// A number as scenes have them: small, with few digits.
inline double plain_number(Choices& c) {
    switch (c.below(4)) {
        case 0: return c.between(-10, 10);
        case 1: return c.between(-1000, 1000) / 100.0;
        case 2: return c.between(0, 100) / 100.0;
        default: return c.between(-30, 30) / 4.0;
    }
}

inline double any_number(Choices& c) { return c.one_in(6) ? edge_number(c) : plain_number(c); }

// `v` written as a user might: the writer's form, or "+2", "2.", ".5", "5e-1".
inline std::string number_text(double v, Choices& c) {
    std::string s = rt::format_number(v);
    switch (c.below(8)) {
        case 0:
            if (v >= 0) s = "+" + s;
            break;
        case 1:
            if (s.find_first_of(".e") == std::string::npos) s += ".";
            break;
        case 2:
            if (s.rfind("0.", 0) == 0) s.erase(0, 1);
            break;
        case 3:
            if (s.find('e') == std::string::npos) s += "e0";
            break;
        default: break;
    }
    return s;
}

// Text typed into a number field: numbers, numbers with spaces around, and junk.
inline std::string typed_text(Choices& c, double current) {
    static const char* const kJunk[] = {"",     " ",      "1e16",   "-1e16", "0x10", "inf",    "nan",   "--1",
                                        "1.5cm", "1,5",   "\x01",   "\xc3\xa9", "\xff\xfe", "1e-400", "1e400", "+",
                                        ".",    "e5",     "5e",     "1 2",   "\t7\t", " 3 ",    "\n4",   "0.1\r"};
    switch (c.below(4)) {
        case 0: return kJunk[c.below(sizeof kJunk / sizeof kJunk[0])];
        case 1: return std::string(c.between(250, 300), '1');
        case 2: return number_text(current + plain_number(c), c);
        default: return number_text(any_number(c), c);
    }
}

inline rt::Vec3 any_vec(Choices& c) { return {any_number(c), any_number(c), any_number(c)}; }
inline rt::Vec3 plain_vec(Choices& c) { return {plain_number(c), plain_number(c), plain_number(c)}; }

}  // namespace rtfuzz
