// Texture mapping (see texture_map.h): each surface's own coordinates, and the
// colour a hit takes from its texture, its model's materials or its vertex colours.
#include "texture_map.h"

#include <algorithm>
#include <cmath>

#include "model.h"
#include "texture.h"

namespace rt {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;
constexpr double kPi = 3.1415926535897932384626433832795;

// An angle from atan2 as a fraction of a turn in [0, 1).
double turn(double y, double x) {
    double a = std::atan2(y, x) / kTwoPi;
    return a < 0 ? a + 1 : a;
}

// Where p lies about the axis from e1 along the unit a: the turn round it (from the
// axis frame's u toward its v), the height along it, the distance out from it.
struct AboutAxis {
    double turn, height, out;
};
AboutAxis about_axis(const Vec3& p, const Vec3& e1, const Vec3& a) {
    const Frame f = Frame::from_axis(a);
    const Vec3 w = p - e1;
    const double h = dot(w, a);
    const Vec3 radial = w - a * h;
    return {turn(dot(radial, f.v), dot(radial, f.u)), h, length(radial)};
}

}  // namespace

Uv primitive_uv(const Geometry& g, std::uint32_t n, std::uint8_t face, const Vec3& p, double scale) {
    const Node& node = g.nodes[n];
    switch (node.kind) {
        case NodeKind::Sphere: {
            const SphereG& s = g.spheres[node.index];
            const Vec3 d = p - s.c;
            const double r = length(d);
            const double z = r > 0 ? std::clamp(d.z / r, -1.0, 1.0) : 0.0;
            return {turn(d.y, d.x), std::asin(z) / kPi + 0.5};
        }
        case NodeKind::Tetra: {
            const Frame f = Frame::from_axis(g.tetras[node.index].n[face & 3]);
            return {dot(p, f.u) / scale, dot(p, f.v) / scale};
        }
        case NodeKind::Cylinder: {
            const CylinderG& s = g.cylinders[node.index];
            const AboutAxis at = about_axis(p, s.e1, s.a);
            if (face == 0 || face == 1) return {at.turn, s.r > 0 ? at.out / s.r : 0.0};
            return {at.turn, s.len > 0 ? at.height / s.len : 0.0};
        }
        case NodeKind::Torus: {
            const TorusG& s = g.tori[node.index];
            const Vec3 l = s.frame.to_local(p - s.c);
            const double ring = std::sqrt(l.x * l.x + l.y * l.y);
            return {turn(l.y, l.x), turn(l.z, ring - s.R)};
        }
        case NodeKind::Box: {
            // Each face by the two axes along it, in scene units per repeat.
            const int k = (face >> 1) % 3, a = (k + 1) % 3, b = (k + 2) % 3;
            return {p[a] / scale, p[b] / scale};
        }
        case NodeKind::Cone: {
            // As the cylinder: round the axis, and along it (or out from it on the caps).
            const ConeG& s = g.cones[node.index];
            const AboutAxis at = about_axis(p, s.e1, s.a);
            const double cap = face == 0 ? s.r1 : s.r2;
            if (face == 0 || face == 1) return {at.turn, cap > 0 ? at.out / cap : 0.0};
            return {at.turn, s.len > 0 ? at.height / s.len : 0.0};
        }
        case NodeKind::Xform: {
            // The shape's own coordinates, where it is as written.
            const XformG& x = g.xforms[node.index];
            return primitive_uv(g, x.child, face, x.inst.point_to_model(p), scale);
        }
        case NodeKind::Instance:
        case NodeKind::Csg:
        case NodeKind::Mesh: break;
    }
    return {};
}

Uv plane_uv(const PlaneShape& pl, const Vec3& p, double scale) {
    const Vec3 r = p - pl.p1;
    return {dot(pl.uv_row[0], r) / scale, dot(pl.uv_row[1], r) / scale};
}

namespace {

// A mesh's hit: its triangle's material from the model (if the mesh uses the file's),
// its vertex colours, and its texture through the corners' coordinates.
void mesh_look(const MeshG& mg, const SpanEnd& e, const Vec3& p, const ShadeMaterial*& m, Colour& cp) {
    if (!mg.accel || !mg.model) return;
    const std::uint32_t tri = mg.accel->ids[e.node];
    const MeshData& d = mg.model->data();
    const ModelShading* file = m->file;
    if (file && tri < d.triangle_material.size()) {
        const std::uint16_t k = d.triangle_material[tri];
        if (k < file->materials.size()) m = &file->materials[k];
    }
    cp = m->colour;
    const bool colours = file && file->vertex_colours && d.colours.size() == d.positions.size();
    const bool uvs = m->texture && 6 * std::size_t(tri) + 6 <= d.corner_uv.size();
    double w[3] = {1, 0, 0};
    if (colours || uvs) {
        // The point's barycentric coordinates in the triangle, in the model's space.
        Vec3 c[3];
        mg.accel->corners(e.node, c);
        const Vec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
        const Vec3 q = mg.instance.point_to_model(p) - c[0];
        const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(q, e1), d21 = dot(q, e2);
        const double den = d00 * d11 - d01 * d01;
        if (den > 0) {
            const double b1 = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
            const double b2 = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - b1);
            w[0] = 1 - b1 - b2, w[1] = b1, w[2] = b2;
        }
    }
    if (colours) {
        const std::uint32_t* v = &d.triangles[3 * std::size_t(tri)];
        Colour s;
        for (int k = 0; k < 3; ++k) {
            const float* rgb = &d.colours[3 * std::size_t(v[k])];
            s += Colour{rgb[0], rgb[1], rgb[2]} * w[k];
        }
        cp = s;
    }
    if (m->texture) {
        double u = 0, v = 0;
        if (uvs) {
            const float* t = &d.corner_uv[6 * std::size_t(tri)];
            u = t[0] * w[0] + t[2] * w[1] + t[4] * w[2];
            v = t[1] * w[0] + t[3] * w[1] + t[5] * w[2];
        }
        cp = mul(cp, m->texture->sample(u, v));
    }
}

}  // namespace

void object_look(const Geometry& g, std::uint32_t obj, const SpanEnd& e, const Vec3& p, const ShadeMaterial*& m,
                 Colour& cp) {
    const Node& top = g.nodes[g.object_node[obj]];
    if (top.kind == NodeKind::Mesh) {
        mesh_look(g.meshes[top.index], e, p, m, cp);
        return;
    }
    cp = m->colour;
    if (!m->texture) return;
    // A placement of a defined object: its nodes are the definition's, in its space.
    const Vec3 q = top.kind == NodeKind::Instance ? g.instances[top.index].inst.point_to_model(p) : p;
    const Uv uv = primitive_uv(g, e.node, e.face, q, m->texture_scale);
    cp = mul(cp, m->texture->sample(uv.u, uv.v));
}

Colour plane_look(const PlaneShape& pl, const ShadeMaterial& m, const Vec3& p) {
    if (!m.texture) return m.colour;
    const Uv uv = plane_uv(pl, p, m.texture_scale);
    return mul(m.colour, m.texture->sample(uv.u, uv.v));
}

}  // namespace rt
