// The turn and size handles' maths (see transform_handle.h).
#include "transform_handle.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "scene_edits.h"
#include "shown_numbers.h"
#include "triangles.h"

namespace rtview {

namespace {

using rt::Vec3;

constexpr double kPi = 3.14159265358979323846;
const Vec3 kAxes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// Twelve significant digits, as the move tool keeps its numbers (no float noise in
// the text), and -0 as 0.
double tidy(double v) { return twelve_digits(v) + 0.0; }

// `v` on a grid of the power of ten at or below `q` (noise far below what the scene
// shows gone: 7.6499999999 is 7.65), tidied.
double on_grid(double v, double q) {
    if (!(q > 0) || !std::isfinite(q)) return tidy(v);
    const double e = std::floor(std::log10(q));
    // Divided by an exact power of ten, so that the grid's multiples are the doubles
    // nearest them.
    const double p = std::pow(10.0, -e);
    const double r = std::round(v * p) / p;
    return std::isfinite(r) ? tidy(r) : tidy(v);
}

double distance_to_segment(double px, double py, ScreenPoint a, ScreenPoint b) {
    double dx = b.x - a.x, dy = b.y - a.y;
    double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

// The pointer's angle about `o` on screen, counter-clockwise (window y grows down).
double screen_angle(ScreenPoint o, double x, double y) { return std::atan2(-(y - o.y), x - o.x) * 180 / kPi; }

double max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

}  // namespace

const char* handle_mode_name(HandleMode m) {
    switch (m) {
        case HandleMode::Move: return "move";
        case HandleMode::Turn: return "turn";
        case HandleMode::Size: return "size";
    }
    return "move";
}

Mat3 Mat3::operator*(const Mat3& b) const {
    Mat3 out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out.m[i][j] = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j];
    return out;
}

Mat3 Mat3::transposed() const {
    Mat3 t;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) t.m[i][j] = m[j][i];
    return t;
}

Mat3 rotation_matrix(const Vec3& degrees) {
    // The renderer's own matrix (exact at multiples of 90 degrees).
    const rt::MeshInstance in = rt::MeshInstance::make({0, 0, 0}, {1, 1, 1}, degrees);
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = in.l[i][j];
    return r;
}

Vec3 rotation_degrees(const Mat3& r) {
    // R = Rz(c) Ry(b) Rx(a): R20 = -sin b, R21 = cos b sin a, R22 = cos b cos a,
    // R10 = sin c cos b, R00 = cos c cos b.
    const double s = std::clamp(-r.m[2][0], -1.0, 1.0);
    double a, b, c;
    if (std::fabs(s) > 1 - 1e-12) {
        // Gimbal lock: only a - c (or a + c) counts; all of it in c.
        b = s > 0 ? kPi / 2 : -kPi / 2;
        a = 0;
        c = std::atan2(-r.m[0][1], r.m[1][1]);
    } else {
        b = std::asin(s);
        a = std::atan2(r.m[2][1], r.m[2][2]);
        c = std::atan2(r.m[1][0], r.m[0][0]);
    }
    auto deg = [](double v) {
        double d = std::round(v * 180 / kPi * 1e6) / 1e6;
        if (d <= -180) d += 360;
        return tidy(d);
    };
    return {deg(a), deg(b), deg(c)};
}

Mat3 axis_rotation(const Vec3& axis, double degrees) {
    for (int k = 0; k < 3; ++k)
        if (axis == kAxes[k]) {
            Vec3 d{0, 0, 0};
            d[k] = degrees;
            return rotation_matrix(d);
        }
    const double a = degrees * kPi / 180, c = std::cos(a), s = std::sin(a), t = 1 - c;
    const Vec3 u = rt::normalize(axis);
    Mat3 r;
    r.m[0][0] = c + u.x * u.x * t, r.m[0][1] = u.x * u.y * t - u.z * s, r.m[0][2] = u.x * u.z * t + u.y * s;
    r.m[1][0] = u.y * u.x * t + u.z * s, r.m[1][1] = c + u.y * u.y * t, r.m[1][2] = u.y * u.z * t - u.x * s;
    r.m[2][0] = u.z * u.x * t - u.y * s, r.m[2][1] = u.z * u.y * t + u.x * s, r.m[2][2] = c + u.z * u.z * t;
    return r;
}

Placing placing_of(const rt::Object& o) {
    Placing p;
    const rt::Transform& t = o.transform.get();
    if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape)) {
        p.rotation = m->rotation;
        p.scale = m->scale;
        p.t = m->position;
        p.after = t.translate;
        return p;
    }
    p.rotation = t.rotation;
    p.scale = t.scale;
    p.t = t.translate;
    return p;
}

void set_placing(rt::Object& o, const Placing& p) {
    if (rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape)) {
        m->rotation = p.rotation;
        m->scale = p.scale;
        m->position = p.t;
        return;
    }
    rt::Transform& t = o.transform.edit();
    t.rotation = p.rotation;
    t.scale = p.scale;
    t.translate = p.t;
}

void turn_object(rt::Object& o, const Vec3& axis, double degrees, const Vec3& anchor) {
    Placing p = placing_of(o);
    const Mat3 q = axis_rotation(axis, degrees);
    p.rotation = rotation_degrees(q * rotation_matrix(p.rotation));
    // The anchor stays: x -> q (x - anchor) + anchor for every point x of the object.
    const Vec3 t = q * (p.t + p.after - anchor) + anchor - p.after;
    // (The rounded rotation moves the anchor by far less than this grid.)
    const double grid = 1e-10 * (1 + max_abs(anchor) + max_abs(p.t));
    p.t = {on_grid(t.x, grid), on_grid(t.y, grid), on_grid(t.z, grid)};
    set_placing(o, p);
}

void size_object(rt::Object& o, const Vec3& factors, const Vec3& anchor) {
    Placing p = placing_of(o);
    const Mat3 r = rotation_matrix(p.rotation);
    // The anchor in the object's turned (not sized) frame: b = S a_local.
    const Vec3 b = r.transposed() * (anchor - p.t - p.after);
    Vec3 s = p.scale, f = factors;
    for (int k = 0; k < 3; ++k) {
        const double want = std::clamp(s[k] * f[k], 1e-6, 1e9);
        f[k] = want / s[k];
        s[k] = tidy(want);
    }
    p.scale = s;
    const Vec3 t = anchor - p.after - r * Vec3{f.x * b.x, f.y * b.y, f.z * b.z};
    const double grid = 1e-10 * (1 + max_abs(anchor) + max_abs(p.t));
    p.t = {on_grid(t.x, grid), on_grid(t.y, grid), on_grid(t.z, grid)};
    set_placing(o, p);
}

Mat3 object_axes(const rt::Object& o) { return rotation_matrix(placing_of(o).rotation); }

bool turn_operand(rt::Object& top, const std::vector<int>& path, const Vec3& axis, double degrees, const Vec3& anchor,
                  std::string* why) {
    rt::Object* o = operand_of(top, path);
    if (!o) return false;
    if (path.empty()) {
        turn_object(*o, axis, degrees, anchor);
        return true;
    }
    // The turn in the frame the operand is written in: q = L^-1 Q L (L: the CSGs' map).
    const rt::MeshInstance p = parent_placement(top, path);
    Mat3 l, inv;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) l.m[i][j] = p.l[i][j], inv.m[i][j] = p.m[i][j];
    const Mat3 q = inv * axis_rotation(axis, degrees) * l;
    // The operand's new map from its shape to that frame is q R S; written as R' S' (its
    // `rotation` and `scale`) only when its columns stay at right angles (S': their
    // lengths). An even scale above keeps them so; an uneven one does for turns that
    // keep the CSG's axes on its axes (a quarter turn about one of them).
    Placing pl = placing_of(*o);
    const Mat3 m = q * rotation_matrix(pl.rotation);
    Vec3 c[3] = {}, s{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        c[k] = m.column(k) * pl.scale[k];
        s[k] = rt::length(c[k]);
        if (!(s[k] > 0) || !std::isfinite(s[k])) return false;
    }
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (std::fabs(rt::dot(c[i], c[j])) > 1e-9 * s[i] * s[j]) {
                if (why)
                    *why = "a turn of this operand by " + std::to_string(int(std::lround(degrees))) +
                           " degrees cannot be written: a CSG it is in scales unequally along its axes, so the "
                           "turned operand would be sheared (a quarter turn about one of the CSG's axes can be; "
                           "or turn the whole CSG)";
                return false;
            }
    Mat3 r;
    for (int k = 0; k < 3; ++k) {
        const Vec3 u = c[k] / s[k];
        r.m[0][k] = u.x, r.m[1][k] = u.y, r.m[2][k] = u.z;
    }
    const Vec3 a = p.point_to_model(anchor);
    const Vec3 t = q * (pl.t + pl.after - a) + a - pl.after;
    pl.rotation = rotation_degrees(r);
    for (int k = 0; k < 3; ++k) pl.scale[k] = tidy(std::clamp(s[k], 1e-6, 1e9));
    const double grid = 1e-10 * (1 + max_abs(a) + max_abs(pl.t));
    pl.t = {on_grid(t.x, grid), on_grid(t.y, grid), on_grid(t.z, grid)};
    set_placing(*o, pl);
    return true;
}

bool size_operand(rt::Object& top, const std::vector<int>& path, const Vec3& factors, const Vec3& anchor) {
    rt::Object* o = operand_of(top, path);
    if (!o) return false;
    size_object(*o, factors, path.empty() ? anchor : parent_placement(top, path).point_to_model(anchor));
    return true;
}

Mat3 operand_axes(const rt::Object& top, const std::vector<int>& path) {
    const rt::Object* o = operand_of(top, path);
    if (!o || path.empty()) return object_axes(o ? *o : top);
    const rt::MeshInstance p = parent_placement(top, path);
    const Mat3 own = object_axes(*o);
    Mat3 out;
    for (int k = 0; k < 3; ++k) {
        const Vec3 c = own.column(k);
        Vec3 w{p.l[0][0] * c.x + p.l[0][1] * c.y + p.l[0][2] * c.z, p.l[1][0] * c.x + p.l[1][1] * c.y + p.l[1][2] * c.z,
               p.l[2][0] * c.x + p.l[2][1] * c.y + p.l[2][2] * c.z};
        const double n = rt::length(w);
        if (n > 0) w = w / n;
        out.m[0][k] = w.x, out.m[1][k] = w.y, out.m[2][k] = w.z;
    }
    return out;
}

TurnShape turn_shape(const ScreenView& view, const Vec3& anchor, double radius) {
    TurnShape h;
    std::optional<ScreenPoint> o = view.project(anchor);
    if (!o) return h;
    h.visible = true;
    h.origin = *o;
    h.view_radius = radius * 1.25;
    // World units per window unit near the anchor: a step across the view measured.
    const Vec3 to = anchor - view.eye();
    const double dist = rt::length(to);
    const Vec3 look = dist > 0 ? to / dist : view.forward();
    Vec3 across = rt::cross(look, std::fabs(look.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0});
    across = rt::normalize(across);
    const double step = 0.05 * (dist > 0 ? dist : 1);
    std::optional<ScreenPoint> e = view.project(anchor + across * step);
    if (!e) return h;
    const double px = std::hypot(e->x - o->x, e->y - o->y);
    if (!(px > 1e-9)) return h;
    const double r = radius / px * step;
    constexpr int kSegments = 64;
    for (int k = 0; k < 3; ++k) {
        const Vec3 u = kAxes[(k + 1) % 3], v = kAxes[(k + 2) % 3];
        for (int i = 0; i < kSegments; ++i) {
            const double a = 2 * kPi * i / kSegments;
            if (std::optional<ScreenPoint> p = view.project(anchor + (u * std::cos(a) + v * std::sin(a)) * r))
                h.ring[k].push_back(*p);
            else
                h.ring[k].clear();  // behind the eye: no ring rather than a broken one
            if (h.ring[k].empty() && i > 0) break;
        }
    }
    return h;
}

HandlePart hit_turn(const TurnShape& h, double x, double y, double tolerance) {
    if (!h.visible) return HandlePart::None;
    HandlePart best = HandlePart::None;
    double best_d = tolerance;
    for (int k = 0; k < 3; ++k) {
        const std::vector<ScreenPoint>& ring = h.ring[k];
        for (std::size_t i = 0; i < ring.size(); ++i) {
            const double d = distance_to_segment(x, y, ring[i], ring[(i + 1) % ring.size()]);
            if (d <= best_d) {
                best_d = d;
                best = HandlePart(int(HandlePart::X) + k);
            }
        }
    }
    const double d = std::fabs(std::hypot(x - h.origin.x, y - h.origin.y) - h.view_radius);
    if (d <= best_d) best = HandlePart::Plane;
    return best;
}

SizeShape size_shape(const ScreenView& view, const Vec3& anchor, const Mat3& axes, double length) {
    SizeShape h;
    std::optional<ScreenPoint> o = view.project(anchor);
    if (!o) return h;
    h.visible = true;
    h.origin = *o;
    h.box = std::max(4.0, length * 0.06);
    const Vec3 to = anchor - view.eye();
    const double dist = rt::length(to);
    const Vec3 look = dist > 0 ? to / dist : view.forward();
    for (int k = 0; k < 3; ++k) {
        const Vec3 a = axes.column(k);
        if (std::fabs(rt::dot(a, look)) > 0.985) continue;  // nearly at the eye
        std::optional<ScreenPoint> e = view.project(anchor + a * (0.05 * dist));
        if (!e) continue;
        const double dx = e->x - o->x, dy = e->y - o->y, l = std::hypot(dx, dy);
        if (!(l > 1e-9)) continue;
        h.tip[k] = {o->x + dx / l * length, o->y + dy / l * length};
        h.axis_shown[k] = true;
    }
    return h;
}

HandlePart hit_size(const SizeShape& h, double x, double y, double tolerance) {
    if (!h.visible) return HandlePart::None;
    const double reach = h.box + tolerance * 0.5;
    if (std::fabs(x - h.origin.x) <= reach && std::fabs(y - h.origin.y) <= reach) return HandlePart::Plane;
    HandlePart best = HandlePart::None;
    double best_d = tolerance;
    for (int k = 0; k < 3; ++k) {
        if (!h.axis_shown[k]) continue;
        // The box at the tip, or the line to it.
        double d = distance_to_segment(x, y, h.origin, h.tip[k]);
        if (std::fabs(x - h.tip[k].x) <= reach && std::fabs(y - h.tip[k].y) <= reach) d = 0;
        if (d <= best_d) {
            best_d = d;
            best = HandlePart(int(HandlePart::X) + k);
        }
    }
    return best;
}

TurnDrag::TurnDrag(HandlePart part, const Vec3& anchor, const ScreenView& view, double x, double y)
    : part_(part), axis_{0, 0, 1} {
    const Vec3 to = anchor - view.eye();
    const double dist = rt::length(to);
    const Vec3 look = dist > 0 ? to / dist : view.forward();
    if (part >= HandlePart::X && part <= HandlePart::Z) {
        axis_ = kAxes[int(part) - int(HandlePart::X)];
        // Seen from its tip a positive turn is counter-clockwise; from behind, clockwise.
        sign_ = rt::dot(axis_, look) <= 0 ? 1 : -1;
    } else {
        axis_ = -look;  // towards the eye
        sign_ = 1;
    }
    origin_ = view.project(anchor).value_or(ScreenPoint{x, y});
    start_ = screen_angle(origin_, x, y);
    last_ = 0;
}

double TurnDrag::degrees(double x, double y, bool snap) const {
    if (std::hypot(x - origin_.x, y - origin_.y) < 1e-9) return last_ + turns_ * 360;  // no direction at the middle
    double a = screen_angle(origin_, x, y) - start_;
    a = std::remainder(a, 360.0);  // (-180, 180]
    // Unwrapped: a drag that goes round more than half a turn keeps counting.
    if (a - last_ > 180) turns_ -= 1;
    else if (a - last_ < -180) turns_ += 1;
    last_ = a;
    const double total = sign_ * (a + turns_ * 360);
    return snap ? std::round(total / 15) * 15 + 0.0 : std::round(total * 10) / 10 + 0.0;
}

SizeDrag::SizeDrag(HandlePart part, const SizeShape& shape, double length, double x, double y)
    : part_(part), origin_(shape.origin), press_{x, y}, length_(length > 0 ? length : 1) {
    if (part >= HandlePart::X && part <= HandlePart::Z) {
        const int k = int(part) - int(HandlePart::X);
        const double dx = shape.tip[k].x - origin_.x, dy = shape.tip[k].y - origin_.y, l = std::hypot(dx, dy);
        if (l > 1e-9) dir_x_ = dx / l, dir_y_ = dy / l;
        start_ = (x - origin_.x) * dir_x_ + (y - origin_.y) * dir_y_;
        // Pressed at the middle: a handle's length is the unit.
        if (!(std::fabs(start_) > 1)) start_ = length_;
    }
}

Vec3 SizeDrag::factors(double x, double y, bool snap) const {
    double f = 1;
    if (part_ >= HandlePart::X && part_ <= HandlePart::Z)
        f = ((x - origin_.x) * dir_x_ + (y - origin_.y) * dir_y_) / start_;
    else
        f = 1 + ((x - press_.x) - (y - press_.y)) / length_;
    const double step = snap ? 0.1 : 0.01;
    f = std::max(0.01, std::round(f / step) * step);
    f = tidy(f);
    if (part_ >= HandlePart::X && part_ <= HandlePart::Z) {
        Vec3 v{1, 1, 1};
        v[int(part_) - int(HandlePart::X)] = f;
        return v;
    }
    return {f, f, f};
}

}  // namespace rtview
