// The move tool's handle maths (see move_handle.h).
#include "move_handle.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "camera.h"
#include "shapes.h"

namespace rtview {

namespace {

glm::dvec3 to_glm(const rt::Vec3& v) { return {v.x, v.y, v.z}; }

double distance_to_segment(double px, double py, ScreenPoint a, ScreenPoint b) {
    double dx = b.x - a.x, dy = b.y - a.y;
    double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? std::clamp(((px - a.x) * dx + (py - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(px - (a.x + t * dx), py - (a.y + t * dy));
}

const rt::Vec3 kAxes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

}  // namespace

ScreenView::ScreenView(const rt::Camera& camera, const Rect& image, int film_w, int film_h)
    : camera_(camera), image_(image), film_w_(std::max(1, film_w)), film_h_(std::max(1, film_h)) {
    rt::CameraBasis b = rt::CameraBasis::make(camera, film_w_, film_h_, false);
    eye_ = b.origin;
    forward_ = b.forward;
    // Camera space as GL has it: x to the picture's right (the basis's side), y up, the
    // view along -z. The projection maps the field of view's edges to -1 and 1.
    glm::dmat4 view = glm::lookAt(to_glm(b.origin), to_glm(b.origin + b.forward), to_glm(b.up));
    glm::dmat4 proj(0.0);
    proj[0][0] = 1 / b.tan_x;
    proj[1][1] = 1 / b.tan_y;
    proj[2][2] = -1;
    proj[2][3] = -1;  // w = -z: the depth along the view
    proj[3][2] = -2 * 1e-3;
    std::memcpy(view_, glm::value_ptr(view), sizeof view_);
    std::memcpy(proj_, glm::value_ptr(proj), sizeof proj_);
    polar_ = camera.projection != rt::Projection::Linear;
    half_x_ = b.half_x;
    half_y_ = b.half_y;
}

std::optional<ScreenPoint> ScreenView::project(const rt::Vec3& p) const {
    glm::dmat4 view = glm::make_mat4(view_), proj = glm::make_mat4(proj_);
    glm::dvec4 c = view * glm::dvec4(p.x, p.y, p.z, 1.0);
    double depth = -c.z;
    if (!(depth > 1e-12 * (std::fabs(c.x) + std::fabs(c.y) + 1e-300))) return std::nullopt;
    double i, j;  // film coordinates, as CameraBasis::direction takes them
    if (!polar_) {
        glm::dvec4 clip = proj * c;
        double nx = clip.x / clip.w, ny = clip.y / clip.w;
        i = film_w_ / 2.0 * (1 + nx);
        j = film_h_ / 2.0 * (1 - ny);
    } else {
        // The polar projection's columns are equal steps of angle (camera.cpp).
        double ax = 2 * half_x_, ay = 2 * half_y_;
        i = (half_x_ + std::atan(c.x / depth) / rt::kDegree) * (film_w_ - 1) / ax;
        j = (half_y_ - std::atan(c.y / depth) / rt::kDegree) * (film_h_ - 1) / ay;
    }
    // Film coordinate k is drawn at the centre of texel k (viewport.h).
    ScreenPoint s{image_.x + (i + 0.5) / film_w_ * image_.w, image_.y + (j + 0.5) / film_h_ * image_.h};
    if (!std::isfinite(s.x) || !std::isfinite(s.y)) return std::nullopt;
    return s;
}

rt::Ray ScreenView::ray(double x, double y) const { return ray_at(camera_, image_, film_w_, film_h_, x, y); }

HandleShape handle_shape(const ScreenView& view, const rt::Vec3& anchor, double arrow) {
    HandleShape h;
    std::optional<ScreenPoint> o = view.project(anchor);
    if (!o) return h;
    h.visible = true;
    h.origin = *o;
    h.square = std::max(4.0, arrow * 0.09);
    rt::Vec3 to = anchor - view.eye();
    double dist = rt::length(to);
    rt::Vec3 look = dist > 0 ? to / dist : view.forward();
    for (int k = 0; k < 3; ++k) {
        // An axis pointing nearly at the viewer has no usable direction on screen.
        if (std::fabs(rt::dot(kAxes[k], look)) > 0.985) continue;
        std::optional<ScreenPoint> e = view.project(anchor + kAxes[k] * (0.05 * dist));
        if (!e) continue;
        double dx = e->x - o->x, dy = e->y - o->y, l = std::hypot(dx, dy);
        if (!(l > 1e-9)) continue;
        h.tip[k] = {o->x + dx / l * arrow, o->y + dy / l * arrow};
        h.axis_shown[k] = true;
    }
    return h;
}

HandlePart hit_handle(const HandleShape& h, double x, double y, double tolerance) {
    if (!h.visible) return HandlePart::None;
    if (std::fabs(x - h.origin.x) <= h.square + tolerance * 0.5 && std::fabs(y - h.origin.y) <= h.square + tolerance * 0.5)
        return HandlePart::Plane;
    HandlePart best = HandlePart::None;
    double best_d = tolerance;
    for (int k = 0; k < 3; ++k) {
        if (!h.axis_shown[k]) continue;
        double d = distance_to_segment(x, y, h.origin, h.tip[k]);
        if (d <= best_d) {
            best_d = d;
            best = HandlePart(int(HandlePart::X) + k);
        }
    }
    return best;
}

std::vector<LightMarker> light_markers(const rt::Scene& scene, const rt::World* world, const ScreenView& view,
                                       const Rect& image, std::size_t max) {
    std::vector<std::pair<double, LightMarker>> found;  // (distance, marker)
    for (std::size_t i = 0; i < scene.lights.size(); ++i) {
        const rt::Light& l = scene.lights[i];
        if (l.lamp && l.size > 0) continue;  // its glow shows it, and picking finds it
        std::optional<ScreenPoint> p = view.project(l.position);
        if (!p || !image.contains(p->x, p->y)) continue;
        const rt::Vec3 to = l.position - view.eye();
        const double d = rt::length(to);
        if (world && d > 0) {
            // Hidden when the view's ray toward it meets a surface first.
            rt::PickResult r = rt::pick(*world, rt::Ray{view.eye(), to / d});
            if (r.hit && r.light != int(i) && r.t < d * (1 - 1e-9)) continue;
        }
        found.push_back({d, LightMarker{int(i), *p}});
    }
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<LightMarker> out;
    for (std::size_t k = 0; k < found.size() && k < max; ++k) out.push_back(found[k].second);
    return out;
}

int light_at(const std::vector<LightMarker>& markers, double x, double y, double radius) {
    int best = -1;
    double best_d = radius;
    for (const LightMarker& m : markers) {
        const double d = std::hypot(x - m.at.x, y - m.at.y);
        if (d <= best_d) {
            best_d = d;
            best = m.light;
        }
    }
    return best;
}

double snap_step(double scene_extent) {
    double v = scene_extent / 50;
    if (!(v > 0) || !std::isfinite(v)) return 1;
    double e = std::floor(std::log10(v));
    double m = v / std::pow(10.0, e);
    double s = m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10;
    // Divided by an exact power of ten below 1, so that 0.2 is the double nearest 0.2.
    return e < 0 ? s / std::pow(10.0, -e) : s * std::pow(10.0, e);
}

MoveDrag::MoveDrag(HandlePart part, const rt::Vec3& anchor, const ScreenView& view, double x, double y)
    : part_(part), anchor_(anchor), normal_(view.forward()) {
    if (std::optional<rt::Vec3> g = grab(view, x, y)) {
        start_ = *g;
        ok_ = true;
    }
}

std::optional<rt::Vec3> MoveDrag::grab(const ScreenView& view, double x, double y) const {
    rt::Ray r = view.ray(x, y);
    if (part_ == HandlePart::Plane) {
        // The plane through the anchor facing the camera.
        double dn = rt::dot(r.dir, normal_);
        if (!(std::fabs(dn) > 1e-9)) return std::nullopt;
        double t = rt::dot(anchor_ - r.origin, normal_) / dn;
        if (!(t > 0) || !std::isfinite(t)) return std::nullopt;
        return r.origin + r.dir * t;
    }
    if (part_ == HandlePart::None) return std::nullopt;
    // The point of the axis line nearest the pointer's ray.
    const rt::Vec3& a = kAxes[int(part_) - int(HandlePart::X)];
    rt::Vec3 w0 = anchor_ - r.origin;
    double b = rt::dot(a, r.dir);
    double den = 1 - b * b;
    if (!(den > 1e-6)) return std::nullopt;  // the ray runs along the axis
    double s = (b * rt::dot(r.dir, w0) - rt::dot(a, w0)) / den;
    if (!std::isfinite(s)) return std::nullopt;
    return anchor_ + a * s;
}

rt::Vec3 MoveDrag::delta(const ScreenView& view, double x, double y, double snap) const {
    if (!ok_) return {};
    std::optional<rt::Vec3> g = grab(view, x, y);
    if (!g) return {};
    rt::Vec3 d = *g - start_;
    if (part_ >= HandlePart::X && part_ <= HandlePart::Z) {
        // Only along the axis (grab() stays on its line; this drops rounding off it).
        int k = int(part_) - int(HandlePart::X);
        double along = d[k];
        d = {};
        d[k] = along;
    }
    if (snap > 0) {
        rt::Vec3 p = anchor_ + d;
        for (int k = 0; k < 3; ++k) {
            bool moves = part_ == HandlePart::Plane || k == int(part_) - int(HandlePart::X);
            if (moves) d[k] = std::round(p[k] / snap) * snap - anchor_[k];
        }
    }
    return d;
}

std::optional<rt::Vec3> item_anchor(const rt::Scene& scene, const SceneItem& item, const std::vector<int>& path) {
    if (item.index < 0 || (!path.empty() && item.kind != SceneItem::Kind::Object)) return std::nullopt;
    std::size_t i = std::size_t(item.index);
    switch (item.kind) {
        case SceneItem::Kind::Light:
            if (i >= scene.lights.size()) return std::nullopt;
            return scene.lights[i].position;
        case SceneItem::Kind::Plane:
            if (i >= scene.planes.size()) return std::nullopt;
            return scene.planes[i].point[0];
        case SceneItem::Kind::Object: {
            if (i >= scene.objects.size()) return std::nullopt;
            const rt::Object* o = operand_of(scene.objects[i], path);
            if (!o) return std::nullopt;
            // The point in the frame the shape is written in, then placed by its own
            // transform and those of the CSGs above it.
            const rt::Shape& s = o->shape;
            rt::Vec3 local;
            if (const auto* sp = std::get_if<rt::Sphere>(&s)) {
                local = sp->position;
            } else if (const auto* t = std::get_if<rt::Torus>(&s)) {
                local = t->position;
            } else {
                rt::Scene one;
                one.objects.assign(1, *o);
                if (!std::holds_alternative<rt::Mesh>(s)) one.objects[0].transform = {};
                rt::Aabb b = rt::build_geometry(one, false).object_bounds[0];
                if (b.empty()) return std::nullopt;
                local = b.centre();
            }
            return parent_placement(scene.objects[i], path).point_to_world(own_placement(*o).point_to_world(local));
        }
    }
    return std::nullopt;
}

}  // namespace rtview
