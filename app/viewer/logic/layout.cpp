// Window layout arithmetic (see layout.h).
#include "layout.h"

#include <algorithm>
#include <cmath>

namespace rtview {

void picture_film_size(int pic_w, int pic_h, int& film_w, int& film_h) {
    film_w = std::max(1, pic_w);
    film_h = std::max(1, pic_h);
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

}  // namespace rtview
