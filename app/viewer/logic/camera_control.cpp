// Camera motions for the viewer (see camera_control.h). All angles inside are
// radians; the scene format's degrees appear only where a Camera field is written.
#include "camera_control.h"

#include <algorithm>
#include <cmath>

namespace rtview {

using rt::Camera;
using rt::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
// The scene format converts degrees with the original's pi (camera.h); the fitted
// angle must use the same factor or the displayed picture would be a hair off.
constexpr double kDeg = rt::kDegree;

// A horizontal reference direction for azimuths: world x projected onto the plane
// orthogonal to up (world y if x is parallel to up).
void horizontal_axes(const Vec3& up, Vec3& a, Vec3& b) {
    Vec3 x{1, 0, 0};
    if (std::fabs(rt::dot(x, up)) > 0.99) x = {0, 1, 0};
    a = rt::normalize(x - up * rt::dot(x, up));
    b = rt::cross(up, a);
}

}  // namespace

Vec3 rotate(const Vec3& v, const Vec3& k, double angle) {
    double c = std::cos(angle), s = std::sin(angle);
    return v * c + rt::cross(k, v) * s + k * (rt::dot(k, v) * (1 - c));
}

Vec3 world_up_of(const Camera& cam) {
    Vec3 u = rt::normalize(cam.up - cam.centre);
    return rt::length2(u) > 0 ? u : Vec3{0, 0, 1};
}

Camera fit_camera_to_aspect(const Camera& cam, int width, int height) {
    Camera c = cam;
    if (width < 1 || height < 1) return c;
    double ay = cam.angle_y;
    double ax;
    if (cam.projection == rt::Projection::Linear) {
        ax = 2 * std::atan(std::tan(ay / 2 * kDeg) * width / height) / kDeg;
    } else {
        // Polar: equal angle per pixel step, and steps are (size - 1) apart.
        ax = height > 1 ? ay * (width - 1) / double(height - 1) : ay;
    }
    c.angle_x = std::clamp(ax, 1e-3, 179.0);
    return c;
}

Camera translate(const Camera& cam, const Vec3& offset) {
    Camera c = cam;
    c.position += offset;
    c.centre += offset;
    c.up += offset;
    return c;
}

Camera orbit(const Camera& cam, const Vec3& pivot, const Vec3& world_up, double yaw, double elevation) {
    Vec3 u = rt::normalize(world_up);
    if (rt::length2(u) == 0) u = {0, 0, 1};
    Camera c = cam;
    auto spin = [&](const Vec3& axis, double angle) {
        c.position = pivot + rotate(c.position - pivot, axis, angle);
        c.centre = pivot + rotate(c.centre - pivot, axis, angle);
        c.up = pivot + rotate(c.up - pivot, axis, angle);
    };
    if (yaw != 0) spin(u, yaw);
    if (elevation != 0) {
        Vec3 f = rt::normalize(c.centre - c.position);
        // Raising the eye turns the view direction away from up: clamp the resulting
        // angle to [1, 179] degrees so the rig never tips over the pole.
        double phi = std::acos(std::clamp(rt::dot(f, u), -1.0, 1.0));
        double lim = 1 * kPi / 180;
        elevation = std::clamp(elevation, lim - phi, kPi - lim - phi);
        // up x forward is horizontal; rotating about it by +e raises the eye.
        Vec3 axis = rt::cross(u, f);
        if (rt::length2(axis) < 1e-20) {
            // Looking straight along up: use the camera's own side instead.
            rt::CameraBasis b = rt::CameraBasis::make(c, 2, 2, false);
            axis = -b.side;
        }
        spin(rt::normalize(axis), elevation);
    }
    return c;
}

double scene_reach(const Camera& cam, const rt::Aabb& bounds) {
    double reach = rt::length(cam.centre - cam.position);
    if (bounds.empty() || !rt::finite(bounds.lo) || !rt::finite(bounds.hi)) return reach;
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner{(k & 1 ? bounds.hi : bounds.lo).x, (k & 2 ? bounds.hi : bounds.lo).y,
                          (k & 4 ? bounds.hi : bounds.lo).z};
        reach = std::max(reach, rt::length(corner - cam.position));
    }
    return reach;
}

Vec3 clamp_pivot(const Vec3& eye, const Vec3& pivot, double reach) {
    const double d = rt::length(pivot - eye);
    if (!(d > reach) || !(reach > 0)) return pivot;
    return eye + (pivot - eye) * (reach / d);
}

Vec3 pan_offset(const rt::CameraBasis& view, const Vec3& anchor, double i0, double j0, double i1, double j1) {
    double depth = rt::dot(anchor - view.origin, view.forward);
    if (!(depth > 0)) depth = 1;
    // Point at the anchor's depth along a pixel's ray (depth measured along forward).
    auto at_depth = [&](double i, double j) {
        Vec3 d = view.direction(i, j);
        double along = rt::dot(d, view.forward);
        return view.origin + d * (depth / (along > 1e-12 ? along : 1e-12));
    };
    return at_depth(i0, j0) - at_depth(i1, j1);
}

namespace {

// The fraction of the way to the target a dolly of `notches` goes.
double dolly_fraction(double notches) {
    // Never reach (or pass) the target: the point under the cursor stays in front.
    return std::min(1 - std::pow(0.8, notches), 0.9);
}

}  // namespace

Vec3 dolly_offset(const Vec3& eye, const Vec3& target, double notches) {
    return (target - eye) * dolly_fraction(notches);
}

Camera tidy_camera(const Camera& cam) {
    const double d = length(cam.centre - cam.position);
    if (!(d > 0) || !std::isfinite(d)) return cam;
    // The grid's step is 10^-m; dividing by 10^m (exact for |m| <= 22) gives the
    // double nearest the decimal, which the writer prints in its few digits.
    const int m = std::clamp(int(std::ceil(-std::log10(d * 1e-7))), -22, 22);
    const double scale = std::pow(10.0, std::abs(m));
    auto snap = [&](double v) {
        const double q = m >= 0 ? std::round(v * scale) / scale : std::round(v / scale) * scale;
        return std::isfinite(q) ? q : v;
    };
    auto snap3 = [&](const Vec3& v) { return Vec3{snap(v.x), snap(v.y), snap(v.z)}; };
    Camera c = cam;
    c.position = snap3(cam.position);
    c.centre = snap3(cam.centre);
    c.up = snap3(cam.up);
    return c;
}

Camera dolly(const Camera& cam, const Vec3& target, double notches) {
    const double scale = 1 - dolly_fraction(notches);
    Camera c = cam;
    c.position = cam.position + dolly_offset(cam.position, target, notches);
    c.centre = target + (cam.centre - target) * scale;
    c.up = c.centre + (cam.up - cam.centre);
    return c;
}

Vec3 fly_offset(const Camera& cam, const Vec3& world_up, const Vec3& local, double step) {
    Vec3 u = rt::normalize(world_up);
    Vec3 f = rt::normalize(cam.centre - cam.position);
    Vec3 r = rt::normalize(rt::cross(f, u));
    if (rt::length2(r) == 0) r = rt::CameraBasis::make(cam, 2, 2, false).side;
    return (r * local.x + u * local.y + f * local.z) * step;
}

Camera frame_bounds(const Camera& cam, const rt::Aabb& bounds) {
    if (bounds.empty() || !rt::finite(bounds.lo) || !rt::finite(bounds.hi)) return cam;
    Vec3 centre = bounds.centre();
    double radius = std::max(rt::length(bounds.hi - bounds.lo) / 2, 1e-6);
    double half = std::min(cam.angle_x, cam.angle_y) / 2 * kDeg;
    double dist = radius / std::sin(std::max(half, 1e-3)) * 1.05;
    Vec3 f = rt::normalize(cam.centre - cam.position);
    Camera c = cam;
    c.centre = centre;
    c.position = centre - f * dist;
    c.up = centre + (cam.up - cam.centre);
    return c;
}

ViewAngles view_angles(const Camera& cam, const Vec3& world_up) {
    Vec3 u = rt::normalize(world_up);
    Vec3 a, b;
    horizontal_axes(u, a, b);
    Vec3 d = cam.position - cam.centre;
    ViewAngles r;
    r.distance = rt::length(d);
    if (r.distance == 0) return r;
    Vec3 n = d / r.distance;
    r.elevation = std::asin(std::clamp(rt::dot(n, u), -1.0, 1.0)) * 180 / kPi;
    r.azimuth = std::atan2(rt::dot(n, b), rt::dot(n, a)) * 180 / kPi;
    return r;
}

Camera set_view_angles(const Camera& cam, const Vec3& world_up, const ViewAngles& want) {
    ViewAngles now = view_angles(cam, world_up);
    Camera c = orbit(cam, cam.centre, world_up, (want.azimuth - now.azimuth) * kPi / 180,
                     (want.elevation - now.elevation) * kPi / 180);
    double dist = std::max(want.distance, 1e-9);
    Vec3 d = rt::normalize(c.position - c.centre);
    if (rt::length2(d) > 0) c.position = c.centre + d * dist;
    return c;
}

bool project(const rt::CameraBasis& view, const Vec3& p, double& i, double& j) {
    Vec3 d = p - view.origin;
    double z = rt::dot(d, view.forward);
    if (!(z > 0)) return false;
    double sy = rt::dot(d, view.up) / z;
    double sx = rt::dot(d, view.side) / z;
    if (!view.mirror) sx = -sx;  // undo CameraBasis::direction's sign flip
    if (view.projection == rt::Projection::Linear) {
        double hw = view.width / 2.0, hh = view.height / 2.0;
        i = hw - sx * hw / view.tan_x;
        j = hh - sy * hh / view.tan_y;
    } else {
        double ax = 2 * view.half_x, ay = 2 * view.half_y;
        i = (view.half_x - std::atan(sx) / kDeg) * (view.width - 1) / ax;
        j = (view.half_y - std::atan(sy) / kDeg) * (view.height - 1) / ay;
    }
    return true;
}

}  // namespace rtview
