// The pixel readout: for the picture pixel under the cursor, its linear colour from
// the film (before display mapping), the samples so far and what its ray hit, named
// and numbered as in the outline, with the hit distance.
#pragma once

#include <string>

#include "film.h"
#include "scene.h"
#include "world.h"

namespace rtview {

struct PixelReadout {
    int x = 0, y = 0;        // picture pixel
    bool has_colour = false;
    rt::Colour linear;       // the film's resolved value
    int samples = 0;         // samples per pixel so far
    rt::PickResult hit;      // what the pixel's own ray (sample 0) hits
    std::string hit_name;    // outline_name(hit); empty on a miss
};

// The ray of sample 0 of picture pixel (x, y) (the pixel's corner, the one every
// render traces) and what it hits.
rt::PickResult pick_pixel(const rt::World& world, const rt::Camera& view_camera, int film_w, int film_h, int x, int y);

// "object 3 (sphere)", "plane 1 (chess_plane)", "light 2 (lamp glow)": the outline's
// 1-based numbers; empty when nothing was hit.
std::string outline_name(const rt::Scene& scene, const rt::PickResult& hit);
// What the outline calls a shape: "sphere", ..., "CSG difference".
const char* shape_name(const rt::Shape& shape);

// One line for the status bar:
// "x 120 y 45   RGB 0.512 0.250 1.730   64 spp   object 3 (sphere) at 4.21"
std::string format_readout(const PixelReadout& r);

}  // namespace rtview
