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

}  // namespace rtview
