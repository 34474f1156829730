// Where new items go (see placement.h): the scene's size, the size of a new object,
// and the first place where one stands clear of the others.
#include "placement.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>
#include <vector>

#include "triangles.h"

namespace rtview {

namespace {

using rt::Vec3;

void grow(rt::Aabb& b, Vec3 p, double r = 0) {
    if (!rt::finite(p) || !std::isfinite(r)) return;
    b.lo = rt::vmin(b.lo, p - Vec3{r, r, r});
    b.hi = rt::vmax(b.hi, p + Vec3{r, r, r});
}

void grow(rt::Aabb& b, const rt::Object& o) {
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, rt::Sphere>) grow(b, s.position, std::fabs(s.radius));
            else if constexpr (std::is_same_v<T, rt::Cylinder>) {
                grow(b, s.end1, std::fabs(s.radius));
                grow(b, s.end2, std::fabs(s.radius));
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

double scene_extent(const rt::Scene& scene) {
    rt::Aabb b;
    for (const rt::Object& o : scene.objects) grow(b, o);
    for (const rt::Light& l : scene.lights) grow(b, l.position);
    if (b.lo.x <= b.hi.x) {
        double d = rt::length(b.hi - b.lo);
        if (d > 0 && std::isfinite(d)) return d;
    }
    double d = rt::length(scene.camera.centre - scene.camera.position);
    return d > 0 && std::isfinite(d) ? d : 1;
}

double typical_object_size(const rt::Scene& scene) {
    // Half the box diagonal over sqrt(3): a sphere's radius for a sphere.
    std::vector<double> sizes;
    for (const rt::Object& o : scene.objects) {
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
    // At most ~20M box tests (a menu click, not a wait): in a million-object scene the
    // first 20 candidates.
    constexpr std::size_t kMaxTests = 20'000'000;
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

}  // namespace rtview
