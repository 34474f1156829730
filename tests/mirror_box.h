// A glass ball in a box of mirrors: ray trees as deep as a test wants, for the tests
// of stopping traces (the renderer's, the region's, the viewer's preview).
#pragma once

#include <memory>
#include <string>

#include "scene_parser.h"
#include "test_util.h"
#include "world.h"

namespace rt_test {

// A glass ball inside a closed box of six mirror planes, lit from inside. Every ray
// stays in the box; at the ball it splits into a reflected and a refracted ray.
inline std::string mirror_box(double mirror_reflection, double mirror_scattering, const char* ball, int w = 16, int h = 12) {
    std::string m = "material { reflection " + std::to_string(mirror_reflection) + " scattering " +
                    std::to_string(mirror_scattering) + " colour 0.9 0.9 0.9 }";
    std::string planes;
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-3, 3}) {
            double p[3][3] = {};
            for (auto& q : p) q[axis] = side;
            p[1][(axis + 1) % 3] = 1;
            p[2][(axis + 2) % 3] = 1;
            planes += "  plane { " + m;
            for (int i = 0; i < 3; ++i)
                planes += " point " + std::to_string(i + 1) + " " + std::to_string(p[i][0]) + " " +
                          std::to_string(p[i][1]) + " " + std::to_string(p[i][2]);
            planes += " point 4 0 0 0.5 }\n";  // shaded on the inside
        }
    return std::string("thing {\n  sphere { material { ") + ball +
           " translusans 1 refractive_index 1.5 colour 1 1 1 } position 0 0 0 radius 1.2 }\n}\n"
           "special_thing {\n" +
           planes +
           "}\n"
           "light { spotlight { colour 20 20 20 position 1.5 2 2.2 } }\n"
           "camera { position -2.5 -2 1 centre 0 0 0 up 0 0 1 angle_x 60 angle_y 45 }\n"
           "picture_size { x_max " +
           std::to_string(w) + " y_max " + std::to_string(h) + " }\nend\n";
}

// Perfect mirrors, the bound switched off and depth 1000: a pixel's tree doubles at
// every pass through the ball and would take longer than anyone waits.
inline std::shared_ptr<const rt::World> endless_world() {
    auto w = std::make_shared<rt::World>(*compile_world(parse_ok(mirror_box(1, 0, "reflection 0.45 refraction 0.45 scattering 0.1"))));
    w->options.max_depth = 1000;
    w->omit_weight = 0;
    return w;
}

}  // namespace rt_test
