// Camera rays as in docs/rendering.md §1, with column 0 on the camera's left unless the
// original's mirrored picture is asked for.
#include "camera.h"

#include <cmath>

namespace rt {

const char* camera_problem(const Camera& cam) {
    Vec3 f = cam.centre - cam.position;
    if (length2(f) == 0) return "'centre' equals 'position', so there is no view direction";
    Vec3 up = cam.up - cam.centre;
    Vec3 fu = normalize(f);
    Vec3 ortho = up - fu * dot(up, fu);
    if (!(length(ortho) > 1e-9 * length(up)) || length2(up) == 0)
        return "'up' point gives an up direction (up - centre) parallel to the view direction";
    if (!(cam.angle_x > 0 && cam.angle_x < 180)) return "angle_x must be between 0 and 180 degrees";
    if (!(cam.angle_y > 0 && cam.angle_y < 180)) return "angle_y must be between 0 and 180 degrees";
    return nullptr;
}

CameraBasis CameraBasis::make(const Camera& cam, int width, int height, bool mirror) {
    CameraBasis b;
    b.origin = cam.position;
    b.forward = normalize(cam.centre - cam.position);
    Vec3 v = cam.up - cam.centre;
    b.up = normalize(v - b.forward * dot(v, b.forward));
    b.side = normalize(cross(b.forward, b.up));
    b.half_x = cam.angle_x / 2;
    b.half_y = cam.angle_y / 2;
    b.tan_x = std::tan(b.half_x * kDegree);
    b.tan_y = std::tan(b.half_y * kDegree);
    b.projection = cam.projection;
    b.width = width < 1 ? 1 : width;
    b.height = height < 1 ? 1 : height;
    b.mirror = mirror;
    return b;
}

Vec3 CameraBasis::direction(double i, double j) const {
    double sx, sy;
    if (projection == Projection::Linear) {
        double hw = width / 2.0, hh = height / 2.0;
        sx = tan_x * (hw - i) / hw;
        sy = tan_y * (hh - j) / hh;
    } else {
        double ax = 2 * half_x, ay = 2 * half_y;
        sx = width > 1 ? std::tan((half_x - ax * i / (width - 1)) * kDegree) : 0.0;
        sy = height > 1 ? std::tan((half_y - ay * j / (height - 1)) * kDegree) : 0.0;
    }
    // The original puts column 0 on the +side (F x U) half: a mirrored picture.
    if (!mirror) sx = -sx;
    return forward + up * sy + side * sx;
}

}  // namespace rt
