// Scenes that several tests share.
#pragma once

#include <string>

namespace rt_test {

// Glass, a mirror, a torus, a CSG, a tetrahedron and a cylinder over a chess plane,
// lit by a lamp (with its glow disc in view) and a spotlight: edges of every kind, and
// flat-ish regions between them; a picture of width x height.
inline std::string mixed_scene(int width, int height) {
    return std::string(R"(
thing {
  sphere {
    material { reflection 0.1 refraction 0.8 scattering 0.1 translusans 0.95 refractive_index 1.5 colour 0.9 0.95 1 }
    position 5 0.9 1  radius 1
  }
  sphere {
    material { reflection 0.9 scattering 0.1 colour 0.9 0.9 0.9 }
    position 7.5 -1.6 1.3  radius 1.3
  }
  torus {
    material { reflection 0.3 scattering 0.7 colour 1 0.75 0.2 }
    position 4.2 -1.4 0.3  direction 0.2 0.3 1  major 0.6  minor 0.3
  }
  constructive_solid_geometry {
    type C
    left { sphere { position 8 2.4 1 radius 1 } }
    right { cylinder { end_1 6.5 2.4 1 end_2 9.5 2.4 1 radius 0.45 } }
    material { reflection 0.2 scattering 0.8 colour 0.3 0.9 0.4 }
  }
  tetrahedron {
    material { reflection 0.2 scattering 0.8 colour 1 0.35 0.25 }
    vect1 10 -4 0  vect2 11.5 -3 0  vect3 10.2 -2.2 0  vect4 10.6 -3 1.8
  }
  cylinder { material { colour 0.3 0.45 1 } end_1 11 3.5 0  end_2 11 3.5 2.5  radius 0.6 }
}
special_thing {
  chess_plane {
    material 1 { reflection 0.25 scattering 0.75 colour 0.95 0.95 0.95 }
    material 2 { reflection 0.25 scattering 0.75 colour 0.15 0.15 0.2 }
    point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 10
  }
}
light {
  lamp { colour 120 110 100 position 9 1 4 size 0.3 }
  spotlight { colour 60 60 80 position -2 -5 6 }
}
camera { position -1 0 2.5  centre 7 0 0.8  up 7 0 1.8  projection linear  angle_x 60  angle_y 45 }
)") + "picture_size { x_max " + std::to_string(width) + " y_max " + std::to_string(height) + " }\nend\n";
}

}  // namespace rt_test
