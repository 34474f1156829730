// Moving an item's points (translate) and a CSG operand's, and the frames an operand
// is written in (see scene_edits.h): what duplicate with an offset and the move tool use.
#include "scene_edits.h"

#include <cmath>
#include <utility>
#include <variant>
#include <vector>

#include "shown_numbers.h"

namespace rtview {

using rt::Vec3;

namespace {

void move_point(Vec3& p, Vec3 d) {
    p += d;
    p = {twelve_digits(p.x), twelve_digits(p.y), twelve_digits(p.z)};
}

}  // namespace

void translate(rt::Object& o, Vec3 d) {
    if (std::holds_alternative<rt::Instance>(o.shape) ||
        (o.transform.set() && !std::holds_alternative<rt::Mesh>(o.shape))) {
        move_point(o.transform.edit().translate, d);
        return;
    }
    std::visit(
        [&](auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, rt::Sphere> || std::is_same_v<T, rt::Torus> || std::is_same_v<T, rt::Mesh>)
                move_point(s.position, d);
            else if constexpr (std::is_same_v<T, rt::Cylinder> || std::is_same_v<T, rt::Cone>) {
                move_point(s.end1, d);
                move_point(s.end2, d);
            } else if constexpr (std::is_same_v<T, rt::Box>) {
                move_point(s.corner1, d);
                move_point(s.corner2, d);
            } else if constexpr (std::is_same_v<T, rt::Instance>) {
                move_point(o.transform.edit().translate, d);
            } else if constexpr (std::is_same_v<T, rt::Tetrahedron>) {
                for (Vec3& v : s.v) move_point(v, d);
            } else {
                for (rt::Object& op : s.operands) translate(op, d);
            }
        },
        o.shape);
}

void translate(rt::Plane& p, Vec3 d) {
    for (Vec3& v : p.point) move_point(v, d);
}

void translate(rt::Light& l, Vec3 d) { move_point(l.position, d); }

const rt::Object* operand_of(const rt::Object& top, const std::vector<int>& path) {
    const rt::Object* o = &top;
    for (int k : path) {
        const auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || std::size_t(k) >= g->operands.size()) return nullptr;
        o = &g->operands[std::size_t(k)];
    }
    return o;
}

rt::Object* operand_of(rt::Object& top, const std::vector<int>& path) {
    return const_cast<rt::Object*>(operand_of(std::as_const(top), path));
}

bool translate_operand(rt::Object& top, const std::vector<int>& path, Vec3 d) {
    if (!operand_of(top, path)) return false;
    // The world's move in the frame the operand is written in.
    if (!path.empty()) d = parent_placement(top, path).to_model(d);
    translate(*operand_of(top, path), d);
    return true;
}

rt::MeshInstance own_placement(const rt::Object& o) {
    if (!o.transform.set() || std::holds_alternative<rt::Mesh>(o.shape))
        return rt::MeshInstance::make({0, 0, 0}, {1, 1, 1}, {0, 0, 0});
    const rt::Transform& t = o.transform.get();
    return rt::MeshInstance::make(t.translate, t.scale, t.rotation);
}

rt::MeshInstance parent_placement(const rt::Object& top, const std::vector<int>& path) {
    rt::MeshInstance p = rt::MeshInstance::make({0, 0, 0}, {1, 1, 1}, {0, 0, 0});
    const rt::Object* o = &top;
    for (int k : path) {
        p = compose(p, own_placement(*o));
        const auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || std::size_t(k) >= g->operands.size()) break;
        o = &g->operands[std::size_t(k)];
    }
    return p;
}

}  // namespace rtview
