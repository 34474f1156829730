// Numbers as the panels show them (see shown_numbers.h).
#include "shown_numbers.h"

#include <charconv>
#include <cmath>

namespace rtview {

double twelve_digits(double v) {
    if (!std::isfinite(v)) return v;
    char buf[40];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 12);
    double back = v;
    std::from_chars(buf, r.ptr, back);
    return back;
}

double as_shown(double v, int decimals) {
    if (!std::isfinite(v)) return v;
    // to_chars/from_chars: the same digits whatever locale the viewer runs in.
    char buf[512];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals < 0 ? 0 : decimals);
    if (r.ec != std::errc()) return v;
    double back = v;
    std::from_chars(buf, r.ptr, back);
    return back == 0 ? 0.0 : back;  // "0", not "-0", for a small negative value
}

double from_widget(double was, float now, int decimals) {
    if (static_cast<float>(was) == now) return was;
    return as_shown(double(now), decimals);
}

}  // namespace rtview
