// Scene -> scene-format text, indented two spaces per level. Every key is written,
// defaults included, so the text does not depend on the parser's defaults; numbers
// use the shortest digits that read back to the same double.
#include "scene_writer.h"

#include <cfloat>
#include <charconv>
#include <cmath>
#include <string>
#include <variant>

namespace rt {

std::string format_number(double v) {
    // The format has no spelling for these; a huge finite value or 0 at least keeps the
    // text well-formed, and the parser's range check then points at the culprit.
    if (std::isnan(v)) v = 0;
    if (std::isinf(v)) v = std::copysign(DBL_MAX, v);
    // to_chars/from_chars are printf("%.*g")/strtod without the locale: a viewer that
    // sets a locale with a decimal comma must not change what gets written.
    char buf[64];
    auto print = [&](int precision) {
        auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, precision);
        return std::string(buf, res.ptr);
    };
    auto exact = [&](const std::string& s) {
        double back = 0;
        std::from_chars(s.data(), s.data() + s.size(), back);
        return back == v;
    };
    int precision = 1;
    while (precision < 17 && !exact(print(precision))) ++precision;
    std::string shortest = print(precision);
    // %g switches to an exponent once the integer part has more digits than the
    // precision, so the shortest text for 60 would be "6e+01". Allow up to six
    // padding zeros to keep round numbers plain. Below 2^53 such a value is exactly
    // that integer, so the padding really is zeros (above, it would be the double's
    // exact binary expansion: 20 digits instead of "8.8134680156415394e+19").
    if (v != 0 && std::fabs(v) < 9007199254740992.0) {
        const int int_digits = int(std::floor(std::log10(std::fabs(v)))) + 1;
        if (int_digits > precision && int_digits <= precision + 6) {
            std::string plain = print(int_digits);
            if (exact(plain)) return plain;
        }
    }
    return shortest;
}

namespace {

class Writer {
public:
    std::string out;

    void line(int depth, const std::string& text) {
        out.append(2 * std::size_t(depth), ' ');
        out += text;
        out += '\n';
    }
    static std::string num(double v) { return format_number(v); }
    static std::string vec(const Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }

    // One line: six keys are easier to scan side by side than stacked.
    static std::string material_body(const Material& m) {
        return "{ reflection " + num(m.reflection) + " refraction " + num(m.refraction) + " scattering " +
               num(m.scattering) + " translusans " + num(m.translusans) + " refractive_index " +
               num(m.refractive_index) + " colour " + vec(m.colour) + " }";
    }

    void object(int depth, const Object& obj) {
        std::visit([&](const auto& s) { shape(depth, s, obj); }, obj.shape);
    }

    // Only when the file had a block: has_material is part of the scene, and a
    // block-less object's default (translusans 0) differs from a block's (1).
    void material_of(int depth, const Object& obj) {
        if (obj.has_material) line(depth, "material " + material_body(obj.material));
    }

    void shape(int depth, const Sphere& s, const Object& obj) {
        line(depth, "sphere {");
        material_of(depth + 1, obj);
        line(depth + 1, "position " + vec(s.position));
        line(depth + 1, "radius " + num(s.radius));
        line(depth, "}");
    }
    void shape(int depth, const Tetrahedron& s, const Object& obj) {
        line(depth, "tetrahedron {");
        material_of(depth + 1, obj);
        for (int i = 0; i < 4; ++i) line(depth + 1, "vect" + std::to_string(i + 1) + " " + vec(s.v[i]));
        line(depth, "}");
    }
    void shape(int depth, const Cylinder& s, const Object& obj) {
        line(depth, "cylinder {");
        material_of(depth + 1, obj);
        line(depth + 1, "end_1 " + vec(s.end1));
        line(depth + 1, "end_2 " + vec(s.end2));
        line(depth + 1, "radius " + num(s.radius));
        line(depth, "}");
    }
    void shape(int depth, const Torus& s, const Object& obj) {
        line(depth, "torus {");
        material_of(depth + 1, obj);
        line(depth + 1, "position " + vec(s.position));
        line(depth + 1, "direction " + vec(s.direction));
        line(depth + 1, "major " + num(s.major));
        line(depth + 1, "minor " + num(s.minor));
        line(depth, "}");
    }
    void shape(int depth, const Csg& s, const Object& obj) {
        line(depth, "constructive_solid_geometry {");
        line(depth + 1, std::string("type ") + static_cast<char>(s.type));
        material_of(depth + 1, obj);
        static const char* const side[2] = {"left", "right"};
        for (std::size_t i = 0; i < s.operands.size() && i < 2; ++i) {
            line(depth + 1, std::string(side[i]) + " {");
            object(depth + 2, s.operands[i]);
            line(depth + 1, "}");
        }
        line(depth, "}");
    }

    void plane(int depth, const Plane& p) {
        line(depth, p.chess ? "chess_plane {" : "plane {");
        if (p.chess) {
            if (p.has_material) line(depth + 1, "material 1 " + material_body(p.material));
            if (p.has_material2) line(depth + 1, "material 2 " + material_body(p.material2));
        } else if (p.has_material) {
            line(depth + 1, "material " + material_body(p.material));
        }
        for (int i = 0; i < 4; ++i) line(depth + 1, "point " + std::to_string(i + 1) + " " + vec(p.point[i]));
        line(depth, "}");
    }

    void light(int depth, const Light& l) {
        line(depth, l.lamp ? "lamp {" : "spotlight {");
        line(depth + 1, "position " + vec(l.position));
        line(depth + 1, "colour " + vec(l.colour));
        if (l.lamp) line(depth + 1, "size " + num(l.size));
        line(depth, "}");
    }

    void camera(const Camera& c) {
        line(0, "camera {");
        line(1, "position " + vec(c.position));
        line(1, "centre " + vec(c.centre));
        line(1, "up " + vec(c.up));
        line(1, c.projection == Projection::Polar ? "projection polar" : "projection linear");
        line(1, "angle_x " + num(c.angle_x));
        line(1, "angle_y " + num(c.angle_y));
        line(0, "}");
    }
};

}  // namespace

std::string write_camera(const Camera& camera) {
    Writer w;
    w.camera(camera);
    return w.out;
}

std::string write_scene(const Scene& scene) {
    Writer w;
    if (!scene.objects.empty()) {
        w.line(0, "thing {");
        for (const Object& o : scene.objects) w.object(1, o);
        w.line(0, "}");
    }
    if (!scene.planes.empty()) {
        w.line(0, "special_thing {");
        for (const Plane& p : scene.planes) w.plane(1, p);
        w.line(0, "}");
    }
    if (!scene.lights.empty()) {
        w.line(0, "light {");
        for (const Light& l : scene.lights) w.light(1, l);
        w.line(0, "}");
    }
    w.camera(scene.camera);
    w.line(0, "picture_size {");
    w.line(1, "x_max " + std::to_string(scene.width));
    w.line(1, "y_max " + std::to_string(scene.height));
    w.line(0, "}");
    w.line(0, "end");
    return w.out;
}

}  // namespace rt
