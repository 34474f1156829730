// Pixel readout (see readout.h).
#include "readout.h"

#include <cmath>
#include <cstdio>
#include <type_traits>
#include <variant>

#include "camera.h"

namespace rtview {

const char* shape_name(const rt::Shape& s) {
    if (const rt::Csg* c = std::get_if<rt::Csg>(&s)) {
        switch (c->type) {
            case rt::CsgType::Union: return "CSG union";
            case rt::CsgType::Intersection: return "CSG intersection";
            case rt::CsgType::Difference: return "CSG difference";
        }
        return "CSG";
    }
    // (Every shape by its own type: a new one cannot fall into another's name.)
    return std::visit(
        [](const auto& v) -> const char* {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, rt::Sphere>) return "sphere";
            else if constexpr (std::is_same_v<T, rt::Tetrahedron>) return "tetrahedron";
            else if constexpr (std::is_same_v<T, rt::Cylinder>) return "cylinder";
            else if constexpr (std::is_same_v<T, rt::Torus>) return "torus";
            else if constexpr (std::is_same_v<T, rt::Mesh>) return "mesh";
            else if constexpr (std::is_same_v<T, rt::Box>) return "box";
            else if constexpr (std::is_same_v<T, rt::Cone>) return "cone";
            else if constexpr (std::is_same_v<T, rt::Instance>) return "instance";
            else return "CSG";
        },
        s);
}

rt::PickResult pick_pixel(const rt::World& world, const rt::Camera& view_camera, int film_w, int film_h, int x, int y) {
    rt::CameraBasis basis = rt::CameraBasis::make(view_camera, film_w, film_h, false);
    return rt::pick(world, basis.ray(x, y));
}

std::string outline_name(const rt::Scene& s, const rt::PickResult& hit) {
    if (!hit.hit) return {};
    if (hit.object >= 0 && hit.object < int(s.objects.size()))
        return "object " + std::to_string(hit.object + 1) + " (" + shape_name(s.objects[std::size_t(hit.object)].shape) +
               ")";
    if (hit.plane >= 0 && hit.plane < int(s.planes.size()))
        return "plane " + std::to_string(hit.plane + 1) + (s.planes[std::size_t(hit.plane)].chess ? " (chess_plane)" : " (plane)");
    if (hit.light >= 0 && hit.light < int(s.lights.size())) return "light " + std::to_string(hit.light + 1) + " (lamp glow)";
    return {};
}

std::string format_readout(const PixelReadout& r) {
    char buf[256];
    int n = std::snprintf(buf, sizeof buf, "x %d y %d", r.x, r.y);
    std::string s(buf, std::size_t(std::max(n, 0)));
    if (r.has_colour) {
        std::snprintf(buf, sizeof buf, "   RGB %.3f %.3f %.3f", r.linear.x, r.linear.y, r.linear.z);
        s += buf;
    }
    s += "   " + std::to_string(r.samples) + " spp";
    if (!r.hit_name.empty()) {
        s += "   " + r.hit_name;
        if (std::isfinite(r.hit.t)) {
            std::snprintf(buf, sizeof buf, " at %.3g", r.hit.t);
            s += buf;
        }
    } else {
        s += "   background";
    }
    return s;
}

}  // namespace rtview
