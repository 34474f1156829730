// Helpers the viewer's unit tests share (with tests/test_util.h, which they also use):
// a text with a replacement made, a demo scene with every kind of block, rendering a scene to the end, and parsing a
// viewer command line.
#pragma once

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "options.h"
#include "renderer.h"
#include "scene_parser.h"
#include "test_util.h"
#include "text_replacement.h"

namespace rtview_test {

using rt_test::parse_ok;

// `s` with the replacement made in it.
inline std::string applied(const rtview::TextReplacement& r, std::string s) {
    r.apply(s);
    return s;
}

// Every block kind, keys left out (torus direction, torus material), comments inside
// blocks, blocks sharing lines.
inline constexpr const char* kDemoScene = R"(// demo scene
thing {
  sphere {                         // glass ball
    material { reflection 0.1 refraction 0.8 scattering 0.1
               translusans 0.9 refractive_index 1.5 colour 0.9 0.95 1 }
    position 6 1.5 0.8
    radius 0.8  // big enough
  }
  tetrahedron {
    material { reflection 0.3 scattering 0.7 colour 1 0.3 0.2 }
    vect1 5 -2 0  vect2 6 -1 0  vect3 6.5 -2.5 0  vect4 5.8 -1.8 1.6
  }
  cylinder { material { colour 0.3 0.4 1 } end_1 8 0 0 end_2 8 0 2 radius 0.5 } torus { position 4.5 0 0.25 major 0.6 minor 0.2 }
  constructive_solid_geometry {    // a lens
    type C
    left { sphere { position 7 -0.3 2.2 radius 0.8 } }
    right { sphere { position 7 0.5 2.2 radius 0.8 } }
    material { reflection 0.2 scattering 0.8 colour 0.3 1 0.4 }
  }
}
special_thing {
  chess_plane {
    material 1 { reflection 0.3 scattering 0.7 colour 1 1 1 }
    material 2 { colour 0.1 0.1 0.1 }
    point 1 0.5 0.5 0  point 2 1.5 0.5 0  point 3 0.5 1.5 0  point 4 0 0 1
  }
  plane { point 1 20 0 0  point 2 20 1 0  point 3 20 0 1  point 4 0 0 0 }
}
light {
  lamp { colour 60 60 50 position 2 3 5 size 0.3 } // warm
  spotlight { colour 40 40 60 position 0 -4 3 }
}
camera { position 0 0 2 centre 6 0 1 up 6 0 2 projection x angle_x 60 angle_y 45 }
picture_size { x_max 320 y_max 240 }
end
)";

// Renders `scene` on two threads to `samples` samples per pixel, to the end.
// Two spheres (one red) over a chess plane, lit by a lamp with its glow disc: a
// picture of width x height.
inline std::string two_spheres(int width, int height) {
    return std::string(R"(
thing { sphere { material { colour 1 0.2 0.2 } position 10 0 1 radius 1 }
        sphere { position 12 2.5 1.5 radius 1.5 } }
special_thing { chess_plane { point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 5 } }
light { lamp { position 4 -3 4 colour 30 30 30 size 0.3 } }
camera { position 0 0 1 centre 10 0 1 up 10 0 2 angle_x 60 angle_y 45 }
)") + "picture_size { x_max " + std::to_string(width) + " y_max " + std::to_string(height) + " }\nend\n";
}

inline void render_to_end(rt::Renderer& renderer, const rt::Scene& scene, int samples) {
    rt::RenderSettings st;
    st.max_samples = samples;
    renderer.start(rt::compile_world(scene), st);
    renderer.wait();
}

// Parses the viewer's command line `args` into `o`: "" or the usage message.
inline std::string parse_args(std::vector<const char*> args, rtview::Options& o) {
    args.insert(args.begin(), "raytracer-view");
    return rtview::parse_options(int(args.size()), args.data(), o).message();
}

}  // namespace rtview_test
