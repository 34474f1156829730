// Window layout arithmetic (see layout.h).
#include "layout.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace rtview {

void picture_film_size(int x_max, int y_max, int& film_w, int& film_h) {
    film_w = std::max(1, x_max);
    film_h = std::max(1, y_max);
    const double pixels = double(film_w) * film_h;
    if (pixels <= double(kMaxFilmPixels)) return;
    const double s = std::sqrt(double(kMaxFilmPixels) / pixels);
    film_w = std::max(1, int(std::floor(film_w * s)));
    film_h = std::max(1, int(std::floor(film_h * s)));
}

float sidebar_min_width(float window_w, float scale) {
    return std::floor(std::min(160 * scale, window_w * 0.35f));
}

float sidebar_max_width(float window_w, float scale) {
    // The picture keeps 40 % of the window, and at least a small picture's width.
    const float picture = std::max(window_w * 0.4f, 160 * scale);
    return std::floor(std::max(sidebar_min_width(window_w, scale), window_w - picture));
}

float sidebar_width(float window_w, float scale, float content_min, double wanted) {
    const float lo = sidebar_min_width(window_w, scale), hi = sidebar_max_width(window_w, scale);
    float w;
    if (wanted > 0 && std::isfinite(wanted)) {
        w = std::round(float(wanted) * window_w);
    } else {
        // A third of the window, as wide as the fields need while the picture keeps
        // most of it (at a large UI scale in a small window they scroll instead).
        const float narrowest = std::min(content_min, window_w * 0.4f);
        w = std::clamp(window_w * 0.34f, narrowest, std::max(narrowest, 470 * scale));
    }
    return std::floor(std::clamp(w, lo, hi));
}

std::vector<std::string> wrap_words(const std::string& text, float width,
                                    const std::function<float(std::string_view)>& measure) {
    std::vector<std::string> rows;
    std::string row;
    std::size_t i = 0;
    while (i < text.size()) {
        // The next word with the spaces before it.
        std::size_t start = i;
        while (i < text.size() && text[i] == ' ') ++i;
        std::size_t word_start = i;
        while (i < text.size() && text[i] != ' ') ++i;
        std::string_view spaces(text.data() + start, word_start - start);
        std::string_view word(text.data() + word_start, i - word_start);
        if (row.empty() || measure(row + std::string(spaces) + std::string(word)) <= width) {
            if (!row.empty() || rows.empty()) row += spaces;
            row += word;
        } else {
            rows.push_back(row);
            row = std::string(word);
        }
        // A word wider than a whole row: cut it, as there is no space to break at.
        while (measure(row) > width && row.size() > 1) {
            std::size_t n = row.size() - 1;
            while (n > 1 && measure(std::string_view(row).substr(0, n)) > width) --n;
            rows.push_back(row.substr(0, n));
            row.erase(0, n);
        }
    }
    if (!row.empty() || rows.empty()) rows.push_back(row);
    return rows;
}

std::string elide_end(const std::string& text, float width, const std::function<float(std::string_view)>& measure) {
    if (measure(text) <= width) return text;
    // The cut points are character boundaries; the widths grow with the cut's length,
    // so the longest that fits is found by bisection.
    std::vector<std::size_t> cuts;
    for (std::size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || (static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) cuts.push_back(i);
    auto fits = [&](std::size_t n) { return measure(text.substr(0, n) + "...") <= width; };
    if (!fits(0)) return "";
    std::size_t lo = 0, hi = cuts.size() - 1;  // cuts[lo] fits; cuts[hi] (the whole text) does not
    while (hi - lo > 1) {
        const std::size_t mid = (lo + hi) / 2;
        (fits(cuts[mid]) ? lo : hi) = mid;
    }
    std::string out = text.substr(0, cuts[lo]);
    if (cuts[lo] < text.size() && text[cuts[lo]] != ' ') {
        // Inside a word: back to the word's start, or, in the first word, off any
        // digits at the cut ("5.21" cut to "5." would read as another number).
        if (const std::size_t sp = out.rfind(' '); sp != std::string::npos) out.erase(sp);
        else
            while (!out.empty() && (std::isdigit(static_cast<unsigned char>(out.back())) || out.back() == '.' ||
                                    out.back() == '-' || out.back() == ','))
                out.pop_back();
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out + "...";
}

std::string elide_middle(const std::string& text, float width, const std::function<float(std::string_view)>& measure) {
    if (measure(text) <= width) return text;
    std::vector<std::size_t> cuts;  // character boundaries
    for (std::size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || (static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) cuts.push_back(i);
    const std::size_t chars = cuts.size() - 1;
    // k characters kept: two fifths from the start, the rest from the end.
    auto made = [&](std::size_t k) {
        const std::size_t head = k * 2 / 5, tail = k - head;
        return text.substr(0, cuts[head]) + "..." + text.substr(cuts[chars - tail]);
    };
    if (measure("...") > width) return "";
    std::size_t lo = 0, hi = chars;  // made(lo) fits; made(hi) (longer than the text) does not
    while (hi - lo > 1) {
        const std::size_t mid = (lo + hi) / 2;
        (measure(made(mid)) <= width ? lo : hi) = mid;
    }
    return made(lo);
}

std::string elide_pieces(const std::vector<std::pair<std::string, std::string>>& pieces, float width,
                         const std::function<float(std::string_view)>& measure) {
    std::string all;
    for (const auto& [sep, text] : pieces) all += sep + text;
    if (measure(all) <= width) return all;
    std::string shown;
    for (const auto& [sep, text] : pieces) {
        const std::string more = shown.empty() ? text : shown + sep + text;
        if (measure(more + "...") > width) break;
        shown = more;
    }
    if (shown.empty()) return pieces.empty() ? std::string() : elide_end(pieces.front().second, width, measure);
    return shown + "...";
}

}  // namespace rtview
