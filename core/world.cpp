// The tables of a World: its shading materials and planes, and what it tells about
// itself. Tracing is in shade.cpp (and shade_avx2.cpp), making a World in
// world_compile.cpp and world_update.cpp, the light buffers in light_buffer.cpp.

#include "world.h"

#include <cmath>

#include "model.h"
#include "shade.h"
#include "shapes.h"
#include "world_build.h"

namespace rt {

ShadeMaterial ShadeMaterial::from(const Material& m) {
    ShadeMaterial s;
    double sum = m.reflection + m.refraction + m.scattering;
    if (sum != 0 && std::isfinite(sum)) {
        s.reflection = m.reflection / sum;
        s.refraction = m.refraction / sum;
        s.scattering = m.scattering / sum;
    } else {
        s.reflection = s.refraction = s.scattering = 0;
    }
    s.translusans = std::clamp(m.translusans, 0.0, 1.0);
    s.ior = std::max(1.0, m.refractive_index);
    s.colour = m.colour;
    s.specular = m.specular;
    s.shininess = m.shininess;
    Colour base = m.colour * s.translusans;
    for (int k = 0; k < 3; ++k) s.log_tint[k] = base[k] > 0 ? std::log(base[k]) : -kInf;
    s.texture = m.texture_image.get();
    s.texture_scale = m.texture_scale > 0 ? m.texture_scale : 1;
    return s;
}

ShadeMaterial ShadeMaterial::of(const Object& o) {
    ShadeMaterial s = from(o.material);
    if (const Mesh* mesh = std::get_if<Mesh>(&o.shape); mesh && mesh->model && !o.has_material) {
        s.file = mesh->model->shading();
        // Light refracted through a face the file makes transparent crosses the model
        // unabsorbed (MTL's dissolve says how much is seen through, not a tint); the
        // object's own material would absorb all of it (translusans 0).
        if (s.file) s.log_tint = {};
    }
    return s;
}

const ModelShading* MeshModel::shading() const {
    std::call_once(shading_made_, [this] {
        const MeshData& d = data_;
        if (d.materials.empty() && d.colours.empty()) return;
        auto made = std::make_shared<ModelShading>();
        for (const Material& m : d.materials) made->materials.push_back(ShadeMaterial::from(m));
        made->vertex_colours = !d.colours.empty() && d.colours.size() == d.positions.size();
        shading_ = std::move(made);
    });
    return shading_.get();
}

PlaneShape PlaneShape::from(const Plane& p) {
    PlaneShape q;
    Vec3 e1 = p.point[1] - p.point[0], e2 = p.point[2] - p.point[0], e3 = p.point[3] - p.point[0];
    q.n = normalize(cross(e1, e2));
    if (dot(q.n, e3) < 0) q.n = -q.n;
    q.D = -dot(q.n, p.point[0]);
    q.p1 = p.point[0];
    q.chess = p.chess;
    double det = dot(e1, cross(e2, e3));
    // Point 4 in the plane leaves the cell decomposition singular.
    q.singular = !(std::fabs(det) > 1e-12 * length(e1) * length(e2) * length(e3));
    if (!q.singular) {
        q.inv_row[0] = cross(e2, e3) / det;
        q.inv_row[1] = cross(e3, e1) / det;
        q.inv_row[2] = cross(e1, e2) / det;
    }
    // p - p1 = a e1 + b e2 (+ off the plane) by the plane's 2 x 2 system; its rows
    // times the axes' lengths give scene units along each.
    const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2);
    const double g = g11 * g22 - g12 * g12;
    if (g > 0) {
        q.uv_row[0] = (e1 * g22 - e2 * g12) * (std::sqrt(g11) / g);
        q.uv_row[1] = (e2 * g11 - e1 * g12) * (std::sqrt(g22) / g);
    }
    return q;
}

int PlaneShape::cell(const Vec3& p) const {
    if (!chess || singular) return 0;
    Vec3 r = p - p1;
    double a = dot(inv_row[0], r), b = dot(inv_row[1], r);
    // Far beyond any picture's resolution the parity is meaningless; keep it defined.
    if (!(std::fabs(a) < 1e15 && std::fabs(b) < 1e15)) return 0;
    // floor() by conversion: std::floor is a library call without SSE4.1.
    auto ifloor = [](double v) {
        long long i = static_cast<long long>(v);
        return i - (double(i) > v ? 1 : 0);
    };
    return int((ifloor(a) + ifloor(b)) & 1);
}

Aabb World::bounds() const { return tallies ? tallies->bounds : Aabb{}; }

}  // namespace rt
