// Tests for core/scene_writer.cpp: numbers print in the format's syntax with the
// fewest digits that read back exactly, and parse_scene(write_scene(s)) == s for
// hand-built scenes covering every construct and for seeded random scenes.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "scene_parser.h"
#include "scene_schema.h"
#include "scene_writer.h"
#include "test_util.h"

using namespace rt;
using rt_test::parse_ok;

namespace {

// The format's number syntax: [+-]digits[.digits][e[+-]digits], also .5 and 5.
bool number_syntax(const std::string& s) {
    std::size_t i = 0, n = s.size(), digits = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
    if (i < n && s[i] == '.') {
        ++i;
        while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        std::size_t exp_digits = 0;
        while (i < n && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++exp_digits;
        if (exp_digits == 0) return false;
    }
    return i == n;
}

// Significant digits in a number's text: the mantissa without sign, point and
// leading zeros.
int significant_digits(const std::string& s) {
    std::string m;
    for (char c : s.substr(0, s.find_first_of("eE"))) {
        if (std::isdigit(static_cast<unsigned char>(c)) && !(m.empty() && c == '0')) m += c;
    }
    while (!m.empty() && m.back() == '0') m.pop_back();
    return int(m.size());
}

std::string errors_of(const ParseResult& r) {
    std::string errors;
    for (const Diagnostic& d : r.diagnostics)
        if (d.is_error()) errors += format_diagnostic("written", d) + "\n";
    return errors;
}

// The texture images of `from` given to the same materials of `to` (read without
// them): what the round trip checks is the names.
void adopt_textures(Object& to, const Object& from) {
    to.material.texture_image = from.material.texture_image;
    const Csg* a = std::get_if<Csg>(&from.shape);
    Csg* b = std::get_if<Csg>(&to.shape);
    if (a && b && a->operands.size() == b->operands.size())
        for (std::size_t k = 0; k < a->operands.size(); ++k) adopt_textures(b->operands[k], a->operands[k]);
}
void adopt_textures(Scene& to, const Scene& from) {
    for (std::size_t i = 0; i < to.objects.size() && i < from.objects.size(); ++i) adopt_textures(to.objects[i], from.objects[i]);
    for (std::size_t i = 0; i < to.planes.size() && i < from.planes.size(); ++i) {
        to.planes[i].material.texture_image = from.planes[i].material.texture_image;
        to.planes[i].material2.texture_image = from.planes[i].material2.texture_image;
    }
}

void check_round_trip(const Scene& s) {
    const std::string text = write_scene(s);
    INFO("text:\n" << text);
    ParseOptions o = rt_test::scenes_options();
    o.read_textures = false;  // the names are checked, not the files
    ParseResult r = parse_scene(text, o);
    INFO("errors:\n" << errors_of(r));
    REQUIRE(r.ok());
    adopt_textures(r.scene, s);
    CHECK(r.scene == s);
    // Writing what was read gives the same text again.
    CHECK(write_scene(r.scene) == text);
}

Material material(double refl, double refr, double scat, double transl, double index, Colour c) {
    Material m;
    m.reflection = refl;
    m.refraction = refr;
    m.scattering = scat;
    m.translusans = transl;
    m.refractive_index = index;
    m.colour = c;
    return m;
}

Object with_material(Shape shape, const Material& m) {
    Object o;
    o.shape = std::move(shape);
    o.material = m;
    o.has_material = true;
    return o;
}

Object bare(Shape shape) {
    Object o;
    o.shape = std::move(shape);
    return o;
}

Object csg(CsgType type, Object left, Object right) {
    Csg c;
    c.type = type;
    c.operands.push_back(std::move(left));
    c.operands.push_back(std::move(right));
    return bare(std::move(c));
}

Scene base_scene() {
    Scene s;
    s.camera.position = {0, 0, 2};
    s.camera.centre = {6, 0, 1};
    s.camera.up = {6, 0, 2};
    s.camera.angle_x = 60;
    s.camera.angle_y = 45;
    s.width = 320;
    s.height = 240;
    return s;
}

Sphere sphere(Vec3 p, double r) {
    Sphere s;
    s.position = p;
    s.radius = r;
    return s;
}

}  // namespace

TEST_CASE("format_number: fixed examples") {
    CHECK(format_number(0) == "0");
    CHECK(format_number(1) == "1");
    CHECK(format_number(60) == "60");  // not "6e+01"
    CHECK(format_number(100) == "100");
    CHECK(format_number(-0.1) == "-0.1");
    CHECK(format_number(0.5) == "0.5");
    CHECK(format_number(1.0 / 3) == "0.3333333333333333");
    CHECK(format_number(0.1 + 0.2) == "0.30000000000000004");
    CHECK(format_number(123456789.123) == "123456789.123");
    CHECK(format_number(1e-300) == "1e-300");
    CHECK(format_number(1e15) == "1e+15");
    CHECK(format_number(1.5e-5) == "1.5e-05");
    CHECK(format_number(1e20) == "1e+20");
    CHECK(format_number(8.8134680156415394e+19) == "8.81346801564154e+19");  // no 20-digit integer
    // No spelling for these exists in the format; whatever is written must still be a number.
    CHECK(number_syntax(format_number(HUGE_VAL)));
    CHECK(number_syntax(format_number(-HUGE_VAL)));
    CHECK(number_syntax(format_number(NAN)));
}

TEST_CASE("format_number: random doubles round-trip in the format's syntax with the fewest digits") {
    std::mt19937_64 rng(2013);
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<int> exponent(-320, 308), small_exp(-8, 12), digits(1, 15);
    std::uniform_int_distribution<long long> mantissa(1, 999999999999999LL);
    for (int i = 0; i < 20000; ++i) {
        // Half arbitrary doubles over the whole range, half short decimals like 12.375.
        double v;
        int decimal_digits = 0;
        if (i % 2 == 0) {
            v = u(rng) * std::pow(10.0, exponent(rng));
        } else {
            decimal_digits = digits(rng);
            const long long m = mantissa(rng) % (long long)std::pow(10.0, decimal_digits);
            char buf[64];
            std::snprintf(buf, sizeof buf, "%lldE%d", m, small_exp(rng));
            v = std::strtod(buf, nullptr);
        }
        const std::string s = format_number(v);
        INFO(s);
        CHECK(number_syntax(s));
        CHECK(std::strtod(s.c_str(), nullptr) == v);
        // Shortest: one digit fewer would not read back.
        const int sig = significant_digits(s);
        if (sig > 1) {
            char shorter[400];
            std::snprintf(shorter, sizeof shorter, "%.*g", sig - 1, v);
            CHECK(std::strtod(shorter, nullptr) != v);
        }
        if (decimal_digits > 0) CHECK(sig <= decimal_digits);
    }
}

TEST_CASE("write_camera writes one camera block that a scene can use") {
    Camera c;
    c.position = {1, 2, 3};
    c.centre = {4, 5.5, 6};
    c.up = {4, 5.5, 7};
    c.projection = Projection::Polar;
    c.angle_x = 70;
    c.angle_y = 1.0 / 3;
    const std::string block = write_camera(c);
    CHECK(block.rfind("camera {", 0) == 0);
    CHECK(block.find("projection polar") != std::string::npos);
    CHECK(block.find("picture_size") == std::string::npos);
    CHECK(block.find("end") == std::string::npos);
    const Scene s = parse_ok(block + "picture_size { x_max 10 y_max 10 }\nend\n");
    CHECK(s.camera == c);
}

TEST_CASE("round trip: every object kind, with and without materials") {
    Scene s = base_scene();
    const Material glass = material(0.1, 0.8, 0.1, 0.9, 1.5, {0.9, 0.95, 1});
    s.objects.push_back(with_material(sphere({6, 1.5, 0.8}, 0.8), glass));
    s.objects.push_back(bare(sphere({1, 2, 3}, 4)));
    Tetrahedron t;
    t.v[0] = {5, -2, 0};
    t.v[1] = {6, -1, 0};
    t.v[2] = {6.5, -2.5, 0};
    t.v[3] = {5.8, -1.8, 1.6};
    s.objects.push_back(with_material(t, material(0.3, 0, 0.7, 1, 1, {1, 0.3, 0.2})));
    s.objects.push_back(bare(t));
    Cylinder cy;
    cy.end1 = {8, 0, 0};
    cy.end2 = {8, 0, 2};
    cy.radius = 0.5;
    s.objects.push_back(with_material(cy, material(0, 0, 1, 1, 1, {0.3, 0.4, 1})));
    s.objects.push_back(bare(cy));
    Torus to;
    to.position = {4.5, 0, 0.25};
    to.direction = {0, 0.6, 0.8};
    to.major = 0.6;
    to.minor = 0.2;
    s.objects.push_back(with_material(to, material(0.4, 0, 0.6, 0, 1, {1, 0.8, 0.2})));
    s.objects.push_back(bare(Torus{}));  // the odd defaults (minor 2 > major 1)
    s.objects.push_back(with_material(Box{{1, 2, 3}, {-0.5, 0.25, 7}}, material(0, 0, 1, 1, 1, {0.2, 0.9, 0.1})));
    s.objects.push_back(bare(Box{}));
    s.objects.push_back(with_material(Cone{{1, 2, 3}, {2, 3, 1}, 0, 0.75}, material(0, 0, 1, 1, 1, {1, 1, 0})));
    s.objects.push_back(bare(Cone{{0, 0, 0}, {1, 0, 0}, 0.5, 0.25}));
    s.objects.push_back(bare(Cone{}));
    // Values the parser clamps are stored clamped, so write what is stored.
    s.objects.push_back(with_material(sphere({0, 0, 0}, 1), material(0, 0, 1, 0, 1, {2, -1, 0})));
    // All-zero weights only warn.
    s.objects.push_back(with_material(sphere({0, 3, 0}, 1), material(0, 0, 0, 1, 1, {1, 1, 1})));
    check_round_trip(s);
}

TEST_CASE("round trip: nested CSG keeps every type and the operands' materials") {
    Scene s = base_scene();
    const Material red = material(0, 0, 1, 1, 1, {1, 0, 0});
    const Material green = material(0.2, 0, 0.8, 1, 1, {0.3, 1, 0.4});
    Object lens = csg(CsgType::Intersection, with_material(sphere({7, -0.3, 2.2}, 0.8), red),
                      bare(sphere({7, 0.5, 2.2}, 0.8)));
    Cylinder cy;
    cy.end1 = {6.5, 0.1, 1.5};
    cy.end2 = {6.5, 0.1, 3};
    cy.radius = 0.2;
    Object bites = csg(CsgType::Union, bare(sphere({6.5, 0.1, 2.6}, 0.3)), with_material(cy, green));
    Object outer = csg(CsgType::Difference, std::move(lens), std::move(bites));
    outer.material = green;
    outer.has_material = true;
    s.objects.push_back(outer);
    // Deeper: a chain of differences four levels down.
    Object chain = bare(sphere({0, 0, 0}, 5));
    for (int i = 0; i < 4; ++i) chain = csg(CsgType::Difference, std::move(chain), bare(sphere({0, 0, double(i)}, 1)));
    s.objects.push_back(chain);
    check_round_trip(s);
}

TEST_CASE("round trip: planes, chess planes with either or both materials, both light kinds, polar") {
    Scene s = base_scene();
    s.camera.projection = Projection::Polar;
    const Material white = material(0.3, 0, 0.7, 1, 1, {1, 1, 1});
    const Material black = material(0, 0, 1, 1, 1, {0.1, 0.1, 0.1});
    for (int mask = 0; mask < 4; ++mask) {
        Plane p;
        p.chess = true;
        p.point[0] = {0.5, 0.5, 0};
        p.point[1] = {1.5, 0.5, 0};
        p.point[2] = {0.5, 1.5, 0};
        p.point[3] = {0, 0, 1};
        if (mask & 1) p.material = white, p.has_material = true;
        if (mask & 2) p.material2 = black, p.has_material2 = true;
        s.planes.push_back(p);
    }
    Plane wall;
    wall.point[0] = {20, 0, 0};
    wall.point[1] = {20, 1, 0};
    wall.point[2] = {20, 0, 1};
    wall.point[3] = {0, 0, 0};
    s.planes.push_back(wall);
    wall.material = material(0, 0, 1, 1, 1, {0.6, 0.7, 0.9});
    wall.has_material = true;
    s.planes.push_back(wall);
    Plane defaults;  // the default points
    s.planes.push_back(defaults);
    Light lamp;
    lamp.lamp = true;
    lamp.position = {2, 3, 5};
    lamp.colour = {60, 60, 50};
    lamp.size = 0.3;
    s.lights.push_back(lamp);
    lamp.size = -1;  // invisible glow
    s.lights.push_back(lamp);
    Light spot;
    spot.position = {0, -4, 3};
    spot.colour = {40, 40, 60};
    s.lights.push_back(spot);
    check_round_trip(s);

    s.camera.projection = Projection::Linear;
    check_round_trip(s);
}

TEST_CASE("round trip: awkward numbers") {
    Scene s = base_scene();
    s.objects.push_back(bare(sphere({1e-300, -0.1, 1.0 / 3}, 123456789.123)));
    s.objects.push_back(bare(sphere({-0.0, 5e-324, 1e15}, 1e-300)));
    s.objects.push_back(with_material(sphere({0.1 + 0.2, -1e-5, 2.0 / 3}, 1.0 / 7),
                                      material(1.0 / 3, 2.0 / 3, 1e-300, 1.0 / 3, 1 + 1e-15, {1e-300, 0.1, 1.0 / 9})));
    s.camera.position = {-1.0 / 3, 1e-300, 2};
    s.camera.angle_x = 179.99999999999997;
    s.camera.angle_y = 1e-300;
    s.width = 16384;
    s.height = 1;
    check_round_trip(s);
}

TEST_CASE("round trip: an empty scene is just camera and picture size") {
    Scene s = base_scene();
    const std::string text = write_scene(s);
    CHECK(text.find("thing") == std::string::npos);
    CHECK(text.find("light") == std::string::npos);
    check_round_trip(s);
}

namespace {

struct RandomScene {
    std::mt19937_64 rng;
    explicit RandomScene(std::uint64_t seed) : rng(seed) {}

    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
    bool coin(double p = 0.5) { return std::bernoulli_distribution(p)(rng); }

    // A mix of short decimals, full-precision doubles and awkward magnitudes.
    double number(double range) {
        switch (integer(0, 5)) {
            case 0: return double(integer(-10, 10));
            case 1: return std::round(uniform(-range, range) * 1000) / 1000;
            case 2: return uniform(-range, range) * std::pow(10.0, integer(-300, 0));
            case 3: return coin() ? -0.0 : 1.0 / integer(1, 99);
            default: return uniform(-range, range);
        }
    }
    double positive(double range) {
        for (;;) {
            double v = std::fabs(number(range));
            if (v > 0) return v;
        }
    }
    Vec3 vec(double range) { return {number(range), number(range), number(range)}; }

    Material mat() {
        Material m;
        m.reflection = std::fabs(number(1));
        m.refraction = std::fabs(number(1));
        m.scattering = std::fabs(number(1));
        m.translusans = std::fmin(std::fabs(number(1)), 1.0);
        m.refractive_index = 1 + std::fabs(number(2));
        m.colour = {std::fabs(number(1)), std::fabs(number(1)), std::fabs(number(1))};
        return m;
    }

    Shape leaf() {
        switch (integer(0, 5)) {
            case 4: {
                Box b;
                b.corner1 = vec(100);
                for (int k = 0; k < 3; ++k)
                    do b.corner2[k] = b.corner1[k] + (coin() ? 1 : -1) * positive(10);
                    while (b.corner2[k] == b.corner1[k]);
                return b;
            }
            case 5: {
                Cone c;
                c.end1 = vec(100);
                do c.end2 = vec(100);
                while (c.end2 == c.end1);
                c.radius1 = coin() ? 0.0 : positive(10);
                c.radius2 = c.radius1 == 0 || coin() ? positive(10) : 0.0;
                return c;
            }
            case 0: return sphere(vec(100), positive(10));
            case 1: {
                // Corners of a well-shaped tetrahedron, jittered (the parser rejects flat ones).
                Tetrahedron t;
                const Vec3 c = vec(100);
                const double r = 0.5 + std::fabs(number(5));
                const Vec3 corner[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
                for (int i = 0; i < 4; ++i)
                    t.v[i] = c + corner[i] * r + Vec3{uniform(-0.2, 0.2), uniform(-0.2, 0.2), uniform(-0.2, 0.2)} * r;
                return t;
            }
            case 2: {
                Cylinder cy;
                cy.end1 = vec(100);
                do cy.end2 = vec(100);
                while (cy.end2 == cy.end1);
                cy.radius = positive(10);
                return cy;
            }
            default: {
                Torus t;
                t.position = vec(100);
                do t.direction = vec(1);
                while (length2(t.direction) == 0);
                t.major = std::fabs(number(10));
                t.minor = positive(5);
                return t;
            }
        }
    }

    Object object(int depth) {
        Object o;
        if (depth < 4 && coin(0.25)) {
            Csg c;
            const char types[3] = {'U', 'I', 'C'};
            c.type = static_cast<CsgType>(types[integer(0, 2)]);
            c.operands.push_back(object(depth + 1));
            c.operands.push_back(object(depth + 1));
            o.shape = std::move(c);
        } else {
            o.shape = leaf();
        }
        if (coin()) {
            o.material = mat();
            o.has_material = true;
        }
        return o;
    }

    Plane plane() {
        Plane p;
        p.chess = coin();
        for (;;) {
            for (Vec3& q : p.point) q = vec(50);
            const Vec3 e1 = p.point[1] - p.point[0], e2 = p.point[2] - p.point[0];
            if (length2(cross(e1, e2)) > 1e-6 * length2(e1) * length2(e2)) break;
        }
        if (coin()) p.material = mat(), p.has_material = true;
        if (p.chess && coin()) p.material2 = mat(), p.has_material2 = true;
        return p;
    }

    Light light() {
        Light l;
        l.lamp = coin();
        l.position = vec(100);
        l.colour = {std::fabs(number(200)), std::fabs(number(200)), std::fabs(number(200))};
        if (l.lamp) l.size = number(2);  // a spotlight has no size key, so it keeps the default
        return l;
    }

    Scene scene() {
        Scene s;
        const int objects = integer(0, 8), planes = integer(0, 3), lights = integer(0, 4);
        for (int i = 0; i < objects; ++i) s.objects.push_back(object(0));
        for (int i = 0; i < planes; ++i) s.planes.push_back(plane());
        for (int i = 0; i < lights; ++i) s.lights.push_back(light());
        Camera& c = s.camera;
        c.position = vec(100);
        do c.centre = vec(100);
        while (c.centre == c.position);
        for (;;) {
            c.up = c.centre + vec(10);
            const Vec3 f = normalize(c.centre - c.position), u = c.up - c.centre;
            if (length(u - f * dot(u, f)) > 1e-3 * length(u)) break;
        }
        c.projection = coin() ? Projection::Polar : Projection::Linear;
        c.angle_x = uniform(1, 179);
        c.angle_y = coin() ? 45.0 : uniform(1, 179);
        s.width = integer(1, Limits::max_picture_side);
        s.height = integer(1, Limits::max_picture_side);
        return s;
    }
};

}  // namespace

TEST_CASE("round trip: random scenes") {
    RandomScene gen(1234567);
    int csgs = 0;
    for (int i = 0; i < 400; ++i) {
        const Scene s = gen.scene();
        for (const Object& o : s.objects) csgs += std::holds_alternative<Csg>(o.shape);
        INFO("scene " << i);
        check_round_trip(s);
    }
    CHECK(csgs > 50);  // the generator really did exercise CSG
}

TEST_CASE("round trip: every example scene in scenes/") {
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(RT_SOURCE_DIR "/scenes")) {
        if (entry.path().extension() != ".txt") continue;
        INFO(entry.path().string());
        ++files;
        check_round_trip(parse_ok(rt_test::slurp(entry.path())));
    }
    CHECK(files >= 15);
}

// Every key of every block, set through the schema's own accessors to a value other
// than its default, must be written and read back: the writer and the parser cannot
// skip a key the schema lists, nor confuse two of them.
namespace {

// A value the format accepts for key `k` that differs from what `item` holds.
template <class T>
void change_key(const schema::Key<T>& k, T& item, int i, double step) {
    switch (k.kind) {
    case schema::Kind::Number: {
        double& v = k.access.number(item, i);
        v = k.range.contains(v + step) ? v + step : v - step;  // stay inside a clamp or rule
        break;
    }
    case schema::Kind::Vec3: k.access.vec3(item, i) += Vec3{step, 2 * step, -step}; break;
    case schema::Kind::Integer: {
        int& v = k.access.integer(item, i);
        v = v + 7 <= k.range.max ? v + 7 : int(k.range.min) + (v == int(k.range.min));  // stay in range
        break;
    }
    case schema::Kind::File: k.access.text(item, i) += "x.obj"; break;
    case schema::Kind::Choice: {
        // Another value of the list.
        const int now = k.access.get_choice(item);
        for (const auto& w : k.choice->words)
            if (w.value != now) {
                k.access.set_choice(item, w.value);
                break;
            }
        break;
    }
    case schema::Kind::Material:
        k.access.material(item, i).colour = Colour{0.1 * step, 0.2, 0.3};
        k.access.has_material(item, i) = true;
        break;
    case schema::Kind::Operand: {
        Object* o = k.access.operand(item, i);
        REQUIRE(o != nullptr);
        std::get<Sphere>(o->shape).radius += step;
        break;
    }
    }
}

}  // namespace

TEST_CASE("round trip: every key the schema lists, changed one at a time, is written and read back") {
    const std::string kCamera = "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n";
    int keys = 0;
    auto check_item = [&](const std::string& section, const std::string& name, auto make, const auto& block,
                          auto get_list) {
        for (const auto& k : block.keys) {
            for (int i = 0; i < std::max(k.count, 1); ++i) {
                CAPTURE(name);
                CAPTURE(std::string(k.name));
                CAPTURE(i);
                auto item = make();
                if constexpr (std::is_same_v<decltype(item), Object>) {
                    if (auto* t = std::get_if<Tetrahedron>(&item.shape))  // the default one is flat
                        *t = Tetrahedron{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
                    if (auto* m = std::get_if<Mesh>(&item.shape)) m->file = "models/a b.obj";  // none by default
                }
                change_key(k, item, i, 0.375);
                // Two defined objects for an instance to name (its name changed: the other).
                Scene s = parse_ok("define { object ball { sphere { radius 2 } } object crate { box { } } }\n" + kCamera +
                                   "picture_size { x_max 4 y_max 4 }\nend\n");
                if constexpr (std::is_same_v<decltype(item), Object>) {
                    if (auto* in = std::get_if<Instance>(&item.shape)) {
                        const int d = k.name == "object" ? 1 : 0;
                        in->object = s.defined[std::size_t(d)].name;
                        in->defined = s.defined[std::size_t(d)].object;
                        if (!item.has_material) item.material = in->defined->material;
                    }
                }
                get_list(s).push_back(item);
                const std::string text = write_scene(s);
                CHECK(text.find(section + " {") != std::string::npos);
                CHECK(text.find(std::string(k.name)) != std::string::npos);
                ParseOptions o;
                o.read_models = false;  // the names are checked, not the files
                o.read_textures = false;
                ParseResult r = parse_scene(text, o);
                INFO(text);
                REQUIRE(r.ok());
                CHECK(r.scene == s);
                ++keys;
            }
        }
    };
    for (const auto& b : schema::object_blocks())
        check_item("thing", std::string(b.name), b.make, b, [](Scene& s) -> std::vector<Object>& { return s.objects; });
    for (const auto& b : schema::plane_blocks())
        check_item("special_thing", std::string(b.name), b.make, b,
                   [](Scene& s) -> std::vector<Plane>& { return s.planes; });
    for (const auto& b : schema::light_blocks())
        check_item("light", std::string(b.name), b.make, b, [](Scene& s) -> std::vector<Light>& { return s.lights; });
    // sphere ... box, cone, CSG (each with rotation, scale, translate), mesh (translate) ... spotlight
    CHECK(keys == (3 + 5 + 4 + 5 + 3 + 5 + 4) + 7 * 3 + 6 + 1 + 2 + 3 + (4 + 1) + (4 + 2) + 4 + 3);  // (instance: 2 + 3)

    // Camera, picture size and material keys through whole scenes.
    for (const auto& k : schema::camera_block().keys) {
        CAPTURE(std::string(k.name));
        Scene s = base_scene();
        change_key(k, s.camera, 0, 0.5);
        check_round_trip(s);
    }
    for (const auto& k : schema::picture_size_block().keys) {
        Scene s = base_scene();
        change_key(k, s, 0, 1);
        check_round_trip(s);
    }
    for (const auto& k : schema::material_block().keys) {
        CAPTURE(std::string(k.name));
        Material m;
        change_key(k, m, 0, 0.25);
        Scene s = base_scene();
        s.objects.push_back(with_material(sphere({5, 0, 1}, 1), m));
        check_round_trip(s);
    }
}

namespace {

// The reference's line for a block, spelled out as text the parser takes: its material
// placeholders as the reference's own material line, an operand as a sphere, the model
// as a cube of tests/models.
std::string spelled(std::string line, const std::string& material) {
    auto replace_all = [&line](const std::string& from, const std::string& to) {
        for (std::size_t at = 0; (at = line.find(from, at)) != std::string::npos; at += to.size())
            line.replace(at, from.size(), to);
    };
    replace_all("{...}", material);
    replace_all("{ OBJECT }", "{ sphere { radius 1 } }");
    replace_all("\"MODEL.obj\"", "\"cube.obj\"");
    return line;
}

// The line of `ref` that starts (after its indent) with `name {`.
std::string line_of(const std::string& ref, const std::string& name) {
    std::istringstream in(ref);
    for (std::string line; std::getline(in, line);)
        if (line.find_first_not_of(' ') != std::string::npos && line.substr(line.find_first_not_of(' ')).rfind(name + " {", 0) == 0)
            return line;
    return {};
}

// Each block of `blocks` read back from its reference line inside `section`: the
// block's defaults exactly, or, where the defaults break the block's own rule (a flat
// tetrahedron), just that rule's error.
template <class T, class Items>
void blocks_read_back(const std::string& ref, const std::string& frame, const char* section,
                      const std::vector<schema::Block<T>>& blocks, const std::string& material, Items items) {
    for (const schema::Block<T>& b : blocks) {
        const std::string line = line_of(ref, std::string(b.name));
        INFO("reference line: " << line);
        REQUIRE(!line.empty());
        // Every key is there (a key left out would read back as its default too).
        for (const schema::Key<T>& k : b.keys)
            for (int i = 0; i < std::max(k.count, 1); ++i) {
                const std::string key = std::string(k.name) + (k.count ? " " + std::to_string(i + 1) : "") + " ";
                const bool there = rt_test::contains(line, "  " + key) || rt_test::contains(line, "{ " + key);
                CHECK_MESSAGE(there, "key " << key);
            }
        // (An instance's line names an object, defined here.)
        const std::string define = rt_test::contains(line, "object NAME") ? "define { object NAME { sphere { } } }\n" : "";
        const std::string text = define + std::string(section) + " {\n" + spelled(line, material) + "\n}\n" + frame;
        const ParseResult r = parse_scene(text, rt_test::options_for(RT_SOURCE_DIR "/tests/models"));
        T want = b.make();
        for (const schema::Key<T>& k : b.keys)
            if (k.kind == schema::Kind::File) k.access.text(want, 0) = "cube.obj";  // as spelled()
        const schema::Problem rule = b.check ? b.check(want) : schema::Problem{};
        if (rule.severity == schema::Problem::Severity::Error) {
            REQUIRE(r.diagnostics.size() == 1);
            CHECK(r.diagnostics[0].message == rule.message);
            continue;
        }
        REQUIRE_MESSAGE(r.ok(), r.status("reference").message());
        const auto& got = items(r.scene);
        REQUIRE(got.size() == 1);
        // Every key but the material (given in the line, absent from make()).
        for (const schema::Key<T>& k : b.keys) {
            if (k.kind == schema::Kind::Material || k.kind == schema::Kind::Operand || k.kind == schema::Kind::File) continue;
            for (int i = 0; i < std::max(k.count, 1); ++i) {
                INFO("key " << std::string(k.name) << " " << i + 1);
                switch (k.kind) {
                case schema::Kind::Number: CHECK(k.number(got[0], i) == k.number(want, i)); break;
                case schema::Kind::Vec3: CHECK(k.vec3(got[0], i) == k.vec3(want, i)); break;
                case schema::Kind::Integer: CHECK(k.integer(got[0], i) == k.integer(want, i)); break;
                case schema::Kind::Choice: CHECK(k.access.get_choice(got[0]) == k.access.get_choice(want)); break;
                default: break;
                }
            }
        }
    }
}

}  // namespace

TEST_CASE("format_reference: every block's line reads back as the block's defaults, and the rules are listed") {
    const std::string ref = format_reference();
    // The material line and the camera and picture size lines make a frame for each block.
    const std::string material_line = line_of(ref, "material {...} is material");
    REQUIRE(!material_line.empty());
    const std::string material = material_line.substr(material_line.find("is material ") + 12);
    const std::string camera = line_of(ref, "camera"), picture = line_of(ref, "picture_size");
    REQUIRE(!camera.empty());
    REQUIRE(!picture.empty());
    const std::string frame = camera + "\n" + picture + "\nend\n";
    const Scene framed = parse_ok(frame);
    CHECK(framed.camera == schema::camera_block().make());
    CHECK(framed.width == schema::picture_size_block().make().width);
    CHECK(framed.height == schema::picture_size_block().make().height);
    const Scene with_material = parse_ok("thing { sphere { material " + material + " } }\n" + frame);
    CHECK(with_material.objects.at(0).material == schema::material_block().make());

    blocks_read_back(ref, frame, "thing", schema::object_blocks(), material, [](const Scene& s) -> const auto& { return s.objects; });
    blocks_read_back(ref, frame, "special_thing", schema::plane_blocks(), material, [](const Scene& s) -> const auto& { return s.planes; });
    blocks_read_back(ref, frame, "light", schema::light_blocks(), material, [](const Scene& s) -> const auto& { return s.lights; });

    // Each section is named in file order, and each rule a value can break is there.
    std::size_t at = 0;
    for (const schema::Section& s : schema::sections()) {
        const char* after = s.kind == schema::SectionKind::End ? "\n" : s.kind == schema::SectionKind::Include ? " \"" : " {";
        const std::size_t next = ref.find("\n" + std::string(s.name) + after, at);
        CHECK_MESSAGE(next != std::string::npos, "section " << std::string(s.name));
        if (next != std::string::npos) at = next;
    }
    CHECK(rt_test::contains(ref, "sphere radius must be greater than 0"));
    CHECK(rt_test::contains(ref, "constructive_solid_geometry type: one of U, I, C"));
    CHECK(rt_test::contains(ref, "material translusans is clamped to 0..1"));
    CHECK(rt_test::contains(ref, "camera: position, centre, up, angle_x, angle_y"));
}
