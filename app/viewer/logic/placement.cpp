// Where new items go (see placement.h): the scene's size, the size of a new object,
// and the first place where one stands clear of the others.
#include "placement.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>
#include <vector>

#include "move_handle.h"
#include "triangles.h"
#include "world.h"

namespace rtview {

namespace {

using rt::Vec3;

void grow(rt::Aabb& b, Vec3 p, double r = 0) {
    if (!rt::finite(p) || !std::isfinite(r)) return;
    b.lo = rt::vmin(b.lo, p - Vec3{r, r, r});
    b.hi = rt::vmax(b.hi, p + Vec3{r, r, r});
}

void grow(rt::Aabb& b, const rt::Object& o);

// The box of an object's shape as written, in the frame of its own transform.
void grow_shape(rt::Aabb& b, const rt::Object& o) {
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, rt::Sphere>) grow(b, s.position, std::fabs(s.radius));
            else if constexpr (std::is_same_v<T, rt::Cylinder>) {
                grow(b, s.end1, std::fabs(s.radius));
                grow(b, s.end2, std::fabs(s.radius));
            } else if constexpr (std::is_same_v<T, rt::Cone>) {
                grow(b, s.end1, std::fabs(s.radius1));
                grow(b, s.end2, std::fabs(s.radius2));
            } else if constexpr (std::is_same_v<T, rt::Box>) {
                grow(b, s.corner1);
                grow(b, s.corner2);
            } else if constexpr (std::is_same_v<T, rt::Instance>) {
                if (s.defined) grow(b, *s.defined);  // the definition, with its own transform
                else grow(b, Vec3{0, 0, 0});
            } else if constexpr (std::is_same_v<T, rt::Tetrahedron>) {
                for (const Vec3& v : s.v) grow(b, v);
            } else if constexpr (std::is_same_v<T, rt::Torus>) {
                grow(b, s.position, std::fabs(s.major) + std::fabs(s.minor));
            } else if constexpr (std::is_same_v<T, rt::Mesh>) {
                const rt::Aabb m = s.model ? rt::MeshInstance::make(s.position, s.scale, s.rotation)
                                                 .world_bounds(s.model->bounds())
                                           : rt::Aabb();
                if (m.empty()) {
                    grow(b, s.position);
                } else {
                    grow(b, m.lo);
                    grow(b, m.hi);
                }
            } else {
                for (const rt::Object& op : s.operands) grow(b, op);
            }
        },
        o.shape);
}

// The box of an object where its transform puts it (a mesh's keys place it itself).
void grow(rt::Aabb& b, const rt::Object& o) {
    if (!o.transform.set() && !std::holds_alternative<rt::Instance>(o.shape)) return grow_shape(b, o);
    if (std::holds_alternative<rt::Mesh>(o.shape)) return grow_shape(b, o);
    rt::Aabb local;
    grow_shape(local, o);
    if (local.lo.x > local.hi.x) return;
    const rt::Transform& t = o.transform.get();
    const rt::Aabb w = rt::MeshInstance::make(t.translate, t.scale, t.rotation).world_bounds(local);
    grow(b, w.lo);
    grow(b, w.hi);
}

}  // namespace

double nice_size(double v) {
    if (!(v > 0) || !std::isfinite(v)) return 1;
    double e = std::floor(std::log10(v));
    double p = std::pow(10.0, e);
    double m = v / p;  // 1 <= m < 10
    double steps[] = {1, 2, 5, 10};
    double best = 1;
    for (double s : steps)
        if (std::fabs(std::log(m / s)) < std::fabs(std::log(m / best))) best = s;
    // Divide by an exact power of ten for small values so 0.2 is the double nearest 0.2.
    return e < 0 ? best / std::pow(10.0, -e) : best * p;
}

Vec3 up_of(const rt::Scene& scene, const Placement& at) {
    if (rt::length2(at.normal) > 0) return rt::normalize(at.normal);
    Vec3 up = rt::normalize(scene.camera.up - scene.camera.centre);
    return rt::length2(up) > 0 ? up : Vec3{0, 0, 1};
}

double scene_extent(const rt::Scene& scene, const rt::World* world) {
    rt::Aabb b;
    if (world) {
        b = world->bounds();
        if (!rt::finite(b.lo) || !rt::finite(b.hi)) b = rt::Aabb();
    } else {
        for (const rt::Object& o : scene.objects) grow(b, o);
        for (const rt::Light& l : scene.lights) grow(b, l.position);
    }
    if (b.lo.x <= b.hi.x) {
        double d = rt::length(b.hi - b.lo);
        if (d > 0 && std::isfinite(d)) return d;
    }
    double d = rt::length(scene.camera.centre - scene.camera.position);
    return d > 0 && std::isfinite(d) ? d : 1;
}

double typical_object_size(const rt::Scene& scene) {
    // Half the box diagonal over sqrt(3): a sphere's radius for a sphere. Of a big
    // scene, a sample of objects spread evenly over the list (a menu click on a
    // million objects must not wait for a pass over all of them).
    constexpr std::size_t kSample = 8192;
    const std::size_t n = scene.objects.size(), stride = n > kSample ? (n + kSample - 1) / kSample : 1;
    std::vector<double> sizes;
    sizes.reserve(std::min(n, kSample));
    for (std::size_t i = 0; i < n; i += stride) {
        const rt::Object& o = scene.objects[i];
        rt::Aabb b;
        grow(b, o);
        double d = rt::length(b.hi - b.lo) / (2 * std::sqrt(3.0));
        if (b.lo.x <= b.hi.x && d > 0 && std::isfinite(d)) sizes.push_back(d);
    }
    if (sizes.empty()) return 0.05 * scene_extent(scene);  // a twentieth of the scene
    // (The lower median of an even count: new objects, which count too, do not grow
    // one after another.)
    const std::size_t mid = (sizes.size() - 1) / 2;
    std::nth_element(sizes.begin(), sizes.begin() + std::ptrdiff_t(mid), sizes.end());
    return sizes[mid];
}

std::optional<std::size_t> first_clear(const rt::Scene& scene, const std::vector<Placement>& candidates,
                                       const std::function<bool(const rt::Vec3&, double)>& seen) {
    std::vector<rt::Aabb> boxes;
    boxes.reserve(scene.objects.size());
    for (const rt::Object& o : scene.objects) {
        rt::Aabb b;
        grow(b, o);
        if (b.lo.x <= b.hi.x) boxes.push_back(b);
    }
    const double r = nice_size(typical_object_size(scene)), reach = 1.5 * r;
    // At most ~4M box tests (a menu click, not a wait): in a million-object scene the
    // first 4 candidates.
    constexpr std::size_t kMaxTests = 4'000'000;
    const std::size_t per_candidate = std::max<std::size_t>(1, boxes.size());
    const std::size_t tried = std::min(candidates.size(), std::max<std::size_t>(1, kMaxTests / per_candidate));
    std::optional<std::size_t> unseen;  // the first clear one that `seen` refused
    for (std::size_t i = 0; i < tried; ++i) {
        const Placement& at = candidates[i];
        if (!rt::finite(at.point)) continue;
        // The new object's middle: a size above the surface (add_item's sphere).
        const Vec3 c = rt::length2(at.normal) > 0 ? at.point + up_of(scene, at) * r : at.point;
        const bool clear = std::none_of(boxes.begin(), boxes.end(), [&](const rt::Aabb& b) {
            const Vec3 q = rt::vmin(rt::vmax(c, b.lo), b.hi);  // the box's point nearest c
            return rt::length2(q - c) < reach * reach;
        });
        if (!clear) continue;
        if (!seen || seen(c, reach)) return i;
        if (!unseen) unseen = i;
    }
    return unseen;
}

Placement placement_at(const PictureView& view, double px, double py) {
    // On the surface under the point (its normal from two neighbouring picks), or in
    // front of the camera at the distance it looks at.
    const rt::Camera& vc = view.camera;
    const Rect& im = view.image;
    Placement at;
    const rt::World* w = view.world;
    rt::PickResult r0 = w ? pick_at(*w, vc, im, view.film_w, view.film_h, px, py) : rt::PickResult{};
    if (r0.hit && std::isfinite(r0.t)) {
        at.point = r0.point;
        rt::PickResult rx = pick_at(*w, vc, im, view.film_w, view.film_h, px + 2, py);
        rt::PickResult ry = pick_at(*w, vc, im, view.film_w, view.film_h, px, py + 2);
        bool same = rx.hit && ry.hit && rx.object == r0.object && ry.object == r0.object && rx.plane == r0.plane &&
                    ry.plane == r0.plane;
        if (same) {
            rt::Vec3 n = rt::normalize(rt::cross(rx.point - r0.point, ry.point - r0.point));
            if (rt::dot(n, vc.position - r0.point) < 0) n = -n;
            at.normal = n;
        }
    } else {
        rt::Ray ray = ray_at(vc, im, view.film_w, view.film_h, px, py);
        at.point = ray.origin + ray.dir * rt::length(vc.centre - vc.position);
    }
    at.toward = vc.position - at.point;
    return at;
}

Placement new_item_placement(const PictureView& view, const rt::Scene* scene, bool object,
                             std::optional<std::pair<double, double>> pointed) {
    const Rect& im = view.image;
    const double px = pointed ? pointed->first : im.x + im.w / 2, py = pointed ? pointed->second : im.y + im.h / 2;
    const Placement centre = placement_at(view, px, py);
    if (pointed || !object || !scene) return centre;
    // From the menu, an object goes where it is seen and stands free: on a surface in
    // the picture, nearest the point under its centre, where it meets no other object
    // (in front of an object it would hide it, or stand inside it); in the air only
    // where no surface has room.
    std::vector<std::pair<double, Placement>> around;
    const double step = std::max(1.0, im.w / 16.0);
    for (int j = -5; j <= 5; ++j)
        for (int i = -7; i <= 7; ++i) {
            const double x = px + i * step, y = py + j * step;
            if ((i == 0 && j == 0) || x < im.x || y < im.y || x >= im.x + im.w || y >= im.y + im.h) continue;
            Placement at = placement_at(view, x, y);
            const double d = rt::length(at.point - centre.point);
            if (std::isfinite(d)) around.push_back({rt::length2(at.normal) > 0 ? d : 1e300, at});
        }
    std::stable_sort(around.begin(), around.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Placement> candidates{centre};
    for (auto& a : around) candidates.push_back(a.second);
    // ... and the whole of it in the picture.
    const ScreenView screen(view.camera, im, view.film_w, view.film_h);
    auto in_picture = [&](const rt::Vec3& middle, double reach) {
        for (int axis = 0; axis < 3; ++axis)
            for (double side : {-reach, reach}) {
                rt::Vec3 q = middle;
                (axis == 0 ? q.x : axis == 1 ? q.y : q.z) += side;
                const std::optional<ScreenPoint> sp = screen.project(q);
                if (!sp || sp->x < im.x || sp->y < im.y || sp->x > im.x + im.w || sp->y > im.y + im.h) return false;
            }
        return true;
    };
    const std::optional<std::size_t> k = first_clear(*scene, candidates, in_picture);
    return k ? candidates[*k] : centre;
}

}  // namespace rtview
