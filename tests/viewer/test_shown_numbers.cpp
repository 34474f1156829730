// Numbers the panels compute go into the scene as their fields show them: the text
// gets the decimal a person would type, and reading the text back gives exactly the
// scene's value (text and picture agree).
#include <doctest/doctest.h>

#include <charconv>
#include <cmath>
#include <random>
#include <string>

#include "scene_writer.h"
#include "shown_numbers.h"

using namespace rtview;

namespace {

double read_back(const std::string& s) {
    double v = 0;
    std::from_chars(s.data(), s.data() + s.size(), v);
    return v;
}

int decimals_of(const std::string& s) {
    std::size_t dot = s.find('.');
    return dot == std::string::npos ? 0 : int(s.size() - dot - 1);
}

}  // namespace

TEST_CASE("shown numbers: a light's colour from a tint and an intensity is written as the field shows it") {
    // A lamp of colour 120 110 100 set to intensity 40: the tint times 40 is
    // 40 36.666666666666664 33.333333333333336 in doubles.
    const double tint_y = 110.0 / 120, tint_z = 100.0 / 120;
    CHECK(rt::format_number(tint_y * 40) == "36.666666666666664");
    CHECK(rt::format_number(as_shown(tint_y * 40, 3)) == "36.667");
    CHECK(rt::format_number(as_shown(tint_z * 40, 3)) == "33.333");
    CHECK(rt::format_number(as_shown(40, 3)) == "40");
    CHECK(rt::format_number(as_shown(-0.0004, 3)) == "0");
    CHECK(as_shown(1e300, 3) == 1e300);
}

TEST_CASE("shown numbers: whatever the value, the text has at most the shown digits and reads back to the scene's value") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> mag(-6, 9);
    for (int i = 0; i < 20000; ++i) {
        const double v = std::pow(10.0, mag(rng)) * (rng() & 1 ? 1 : -1);
        const int d = int(rng() % 7);
        const double s = as_shown(v, d);
        const std::string text = rt::format_number(s);
        CAPTURE(v);
        CAPTURE(d);
        CAPTURE(text);
        // Plain decimals only: an exponent would need another count.
        if (text.find('e') == std::string::npos) CHECK(decimals_of(text) <= d);
        CHECK(read_back(text) == s);
        CHECK(std::fabs(s - v) <= 0.5 * std::pow(10.0, -d) * (1 + 1e-9) + std::fabs(v) * 1e-15);
    }
}

TEST_CASE("shown numbers: a colour picker's float channels: the untouched ones keep their value, the edited one is as shown") {
    // 0.8 has no float of its own: written back from the widget it would read 0.800000011920929.
    CHECK(rt::format_number(double(0.8f)) == "0.800000011920929");
    CHECK(from_widget(0.8, 0.8f, 3) == 0.8);
    CHECK(from_widget(0.95, float(0.95), 3) == 0.95);
    CHECK(rt::format_number(from_widget(0.9, 0.751f, 3)) == "0.751");
    CHECK(rt::format_number(from_widget(0.9, 0.75137252f, 3)) == "0.751");
    CHECK(from_widget(2.5, 3.0f, 3) == 3);
}
