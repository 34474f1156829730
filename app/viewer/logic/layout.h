// How the window is divided and what size of picture it renders: the film of the
// picture frame (the scene's picture_size, whatever the window). Pure arithmetic:
// unit-tested.
#pragma once

#include <cstdint>

namespace rtview {

// The most pixels the viewer renders as one film (a larger picture_size would take
// gigabytes): "Render to file" makes pictures of any size.
constexpr std::int64_t kMaxFilmPixels = std::int64_t(4096) * 4096;

// The film of the picture frame: the scene's picture_size, or, past kMaxFilmPixels,
// the largest film of its aspect within it (so the viewer says the saved image is
// smaller). Zoom and pan only place this film on the screen.
void picture_film_size(int pic_w, int pic_h, int& film_w, int& film_h);

}  // namespace rtview
