// Moving an item's points (translate) and a CSG operand's, and the frames an operand
// is written in (see scene_edits.h): what duplicate with an offset and the move tool use.
#include "scene_edits.h"

#include <charconv>
#include <cmath>
#include <utility>
#include <variant>
#include <vector>

namespace rtview {

using rt::Vec3;

namespace {

// A sum like 2.07 - 2.5 gives -0.43000000000000016; twelve significant digits drop
// that noise, so a moved item's numbers read as a person would write them.
double tidy(double v) {
    if (!std::isfinite(v)) return v;
    char buf[40];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 12);
    double back = v;
    std::from_chars(buf, r.ptr, back);
    return back;
}
void move_point(Vec3& p, Vec3 d) {
    p += d;
    p = {tidy(p.x), tidy(p.y), tidy(p.z)};
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

rt::MeshInstance compose(const rt::MeshInstance& a, const rt::MeshInstance& b) {
    rt::MeshInstance out;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            out.l[i][j] = a.l[i][0] * b.l[0][j] + a.l[i][1] * b.l[1][j] + a.l[i][2] * b.l[2][j];
            out.m[i][j] = b.m[i][0] * a.m[0][j] + b.m[i][1] * a.m[1][j] + b.m[i][2] * a.m[2][j];
        }
    out.position = a.point_to_world(b.position);
    return out;
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
