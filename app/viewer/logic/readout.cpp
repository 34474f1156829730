// Pixel readout (see readout.h).
#include "readout.h"

#include <cmath>
#include <cstdio>

#include "camera.h"

namespace rtview {

const char* shape_name(const rt::Shape& s) {
    switch (s.index()) {
        case 0: return "sphere";
        case 1: return "tetrahedron";
        case 2: return "cylinder";
        case 3: return "torus";
        case 5: return "mesh";
        default: {
            switch (std::get<rt::Csg>(s).type) {
                case rt::CsgType::Union: return "CSG union";
                case rt::CsgType::Intersection: return "CSG intersection";
                case rt::CsgType::Difference: return "CSG difference";
            }
            return "CSG";
        }
    }
}

rt::PickResult pick_pixel(const rt::World& world, const rt::Camera& view_camera, int pic_w, int pic_h, int x, int y) {
    rt::CameraBasis basis = rt::CameraBasis::make(view_camera, pic_w, pic_h, false);
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
