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

namespace {
// The factors of the up and side vectors for the row j and the column i.
inline double row_factor(const CameraBasis& b, double j) {
    if (b.projection == Projection::Linear) {
        double hh = b.height / 2.0;
        return b.tan_y * (hh - j) / hh;
    }
    double ay = 2 * b.half_y;
    return b.height > 1 ? std::tan((b.half_y - ay * j / (b.height - 1)) * kDegree) : 0.0;
}
inline double column_factor(const CameraBasis& b, double i) {
    double sx;
    if (b.projection == Projection::Linear) {
        double hw = b.width / 2.0;
        sx = b.tan_x * (hw - i) / hw;
    } else {
        double ax = 2 * b.half_x;
        sx = b.width > 1 ? std::tan((b.half_x - ax * i / (b.width - 1)) * kDegree) : 0.0;
    }
    // The original puts column 0 on the +side (F x U) half: a mirrored picture.
    return b.mirror ? sx : -sx;
}
}  // namespace

Vec3 CameraBasis::direction(double i, double j) const {
    return forward + up * row_factor(*this, j) + side * column_factor(*this, i);
}

void CameraBasis::unit_directions(int i0, int step, int count, double j, Vec3* out) const {
    // (forward + up sy) + side sx, as direction() adds them.
    const Vec3 row = forward + up * row_factor(*this, j);
    for (int k = 0; k < count; ++k) out[k] = normalize(row + side * column_factor(*this, i0 + k * step));
}

}  // namespace rt
