// The window's layout arithmetic: the picture frame's film.
#include <doctest/doctest.h>

#include <cstdint>

#include "layout.h"

using namespace rtview;

TEST_CASE("the picture frame renders the scene's picture_size, however it is shown") {
    int w = 0, h = 0;
    picture_film_size(640, 480, w, h);
    CHECK((w == 640 && h == 480));
    picture_film_size(1, 16384, w, h);
    CHECK((w == 1 && h == 16384));
    // Past the viewer's film limit: the largest film of the same aspect within it.
    picture_film_size(16384, 16384, w, h);
    CHECK((w == 4096 && h == 4096));
    picture_film_size(16384, 8000, w, h);
    CHECK(std::int64_t(w) * h <= kMaxFilmPixels);
    CHECK(w > 5800);
    CHECK(double(w) / h == doctest::Approx(16384.0 / 8000).epsilon(0.001));
    picture_film_size(0, -3, w, h);
    CHECK((w == 1 && h == 1));
}
