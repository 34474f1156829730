// Texture mapping: the texture coordinates of a hit at a known point of each shape,
// worked out by hand from the mapping's definition (docs/scene-format.md, Textures),
// and the colour a ray's real hit takes there (through object_look, the code shading
// uses); both ISA paths render a textured scene to the same bytes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "image_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "simd.h"
#include "test_textures.h"
#include "test_util.h"
#include "texture.h"
#include "texture_map.h"
#include "world.h"

using namespace rt;
using rt_test::TempDir;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A texture whose every texel differs, so that a sample tells where it was taken:
// 16 x 8, red along u, green along v (from the bottom), blue a checker.
std::shared_ptr<const Texture> probe_texture() {
    std::vector<unsigned char> rgb;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            rgb.push_back((unsigned char)(15 + 15 * x));
            rgb.push_back((unsigned char)(20 + 30 * (7 - y)));
            rgb.push_back((x + y) % 2 ? 250 : 10);
        }
    std::string error;
    std::shared_ptr<const Texture> t = decode_texture(rt_test::png_rgb8(16, 8, rgb), error);
    REQUIRE(t);
    return t;
}

Object textured(Shape shape, const std::shared_ptr<const Texture>& t, double scale = 1) {
    Object o;
    o.shape = std::move(shape);
    o.has_material = true;
    o.material = Material{};
    o.material.colour = {0.5, 1, 0.25};
    o.material.texture = "probe.png";
    o.material.texture_image = t;
    o.material.texture_scale = scale;
    return o;
}

// Shoots a ray from `from` through `at` at object 0 of `scene`: the coordinates
// primitive_uv gives for its hit, and the colour object_look gives there.
struct Probe {
    Uv uv;
    Colour cp;
    Vec3 p;
};
Probe probe(const Scene& scene, const Vec3& from, const Vec3& at) {
    Geometry g = build_geometry(scene);
    SpanScratch scratch;
    const Vec3 d = normalize(at - from);
    SpanEnd e;
    REQUIRE(g.hit(0, from, d, 0.0, e, scratch));
    Probe out;
    out.p = from + d * e.t;
    CHECK(length(out.p - at) < 1e-9);
    const ShadeMaterial sm = ShadeMaterial::of(scene.objects[0]);
    out.uv = primitive_uv(g, e.node, e.face, out.p, sm.texture_scale);
    const ShadeMaterial* m = &sm;
    out.cp = sm.colour;
    object_look(g, 0, e, out.p, m, out.cp);
    return out;
}

void check_uv(const Uv& got, double u, double v) {
    CHECK(got.u == doctest::Approx(u).epsilon(1e-9));
    CHECK(got.v == doctest::Approx(v).epsilon(1e-9));
}

// The colour the material gives at (u, v): its colour times the texel there.
void check_look(const Probe& p, const Texture& t, double u, double v);

// The point seen from `from` toward `at` has texture coordinates (u, v) and shows the
// texel there.
Probe check_at(const Scene& s, const Texture& t, const Vec3& from, const Vec3& at, double u, double v) {
    const Probe p = probe(s, from, at);
    check_uv(p.uv, u, v);
    check_look(p, t, u, v);
    return p;
}

void check_look(const Probe& p, const Texture& t, double u, double v) {
    const Colour want = mul(Colour{0.5, 1, 0.25}, t.sample(u, v));
    CHECK(p.cp.x == doctest::Approx(want.x).epsilon(1e-9));
    CHECK(p.cp.y == doctest::Approx(want.y).epsilon(1e-9));
    CHECK(p.cp.z == doctest::Approx(want.z).epsilon(1e-9));
}

}  // namespace

TEST_CASE("texture map: spheres by longitude about z from +x and latitude") {
    const auto t = probe_texture();
    Scene s;
    s.objects.push_back(textured(Sphere{{1, 2, 3}, 2}, t));
    // Due +y of the centre: longitude 90 degrees, on the equator.
    check_at(s, *t, {1, 10, 3}, {1, 4, 3}, 0.25, 0.5);
    // 45 degrees up toward +x: longitude 0, latitude 45 degrees.
    const Vec3 q = Vec3{1, 2, 3} + Vec3{1, 0, 1} * (2 / std::sqrt(2.0));
    Probe p = probe(s, Vec3{1, 2, 3} + Vec3{1, 0, 1} * 5, q);
    check_uv(p.uv, 0, 0.75);
    // Toward -x -y (longitude 225 degrees), 30 degrees below the equator.
    const double lat = -kPi / 6, lon = 5 * kPi / 4;
    const Vec3 dir{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
    check_at(s, *t, Vec3{1, 2, 3} + dir * 6, Vec3{1, 2, 3} + dir * 2, 0.625, 1.0 / 3);
}

TEST_CASE("texture map: cylinders by angle and height, caps by angle and distance from the axis") {
    const auto t = probe_texture();
    Scene s;
    // Along z: the angle is measured from +x toward +y (the frame about z).
    s.objects.push_back(textured(Cylinder{{0, 0, 0}, {0, 0, 4}, 1}, t));
    check_at(s, *t, {0, 5, 1}, {0, 1, 1}, 0.25, 0.25);
    Probe p = probe(s, {-5, 0, 3}, {-1, 0, 3});
    check_uv(p.uv, 0.5, 0.75);
    // The cap at end_2, half way out along +x: angle 0, distance 1/2.
    check_at(s, *t, {0.5, 0, 9}, {0.5, 0, 4}, 0, 0.5);
}

TEST_CASE("texture map: cones as cylinders, by angle and height, the base by distance from the axis") {
    const auto t = probe_texture();
    Scene s;
    // Along z, radius 2 at z = 0 narrowing to a point at z = 4.
    s.objects.push_back(textured(Cone{{0, 0, 0}, {0, 0, 4}, 2, 0}, t));
    // +y at a quarter of the height (the radius there 1.5): angle 90 degrees, height 1/4.
    check_at(s, *t, {0, 6, 1}, {0, 1.5, 1}, 0.25, 0.25);
    // The base, half way out along +x: angle 0, distance 1/2 of its radius.
    check_at(s, *t, {1, 0, -5}, {1, 0, 0}, 0, 0.5);
}

TEST_CASE("texture map: tori by the angle about their axis and the angle about the tube") {
    const auto t = probe_texture();
    Scene s;
    s.objects.push_back(textured(Torus{{0, 0, 0}, {0, 0, 1}, 2, 0.5}, t));
    // Outermost point at +y: axis angle 90 degrees, tube angle 0.
    check_at(s, *t, {0, 9, 0}, {0, 2.5, 0}, 0.25, 0);
    // Top of the tube at -x: axis angle 180 degrees, tube angle 90 degrees.
    check_at(s, *t, {-2, 0, 7}, {-2, 0, 0.5}, 0.5, 0.25);
}

TEST_CASE("texture map: a tetrahedron's faces by their own plane, in scene units over texture_scale") {
    const auto t = probe_texture();
    Scene s;
    // The face on z = 0 faces -z; its frame about (0, 0, -1) has axes +x and -y.
    s.objects.push_back(textured(Tetrahedron{{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}}}, t, 0.5));
    check_at(s, *t, {0.3, 0.2, -4}, {0.3, 0.2, 0}, 0.6, -0.4);
    // Along the face the coordinates change by distance / scale, whatever the face.
    const Probe a = probe(s, {0.2, -4, 0.2}, {0.2, 0, 0.2}), b = probe(s, {0.7, -4, 0.5}, {0.7, 0, 0.5});
    const double du = b.uv.u - a.uv.u, dv = b.uv.v - a.uv.v;
    CHECK(std::sqrt(du * du + dv * dv) == doctest::Approx(std::sqrt(0.25 + 0.09) / 0.5).epsilon(1e-9));
}

TEST_CASE("texture map: CSG takes the mapping of the primitive hit, with the CSG's texture") {
    const auto t = probe_texture();
    Scene s;
    Csg c;
    c.type = CsgType::Difference;
    Object left, right;
    left.shape = Sphere{{0, 0, 0}, 2};
    right.shape = Cylinder{{0, 0, -3}, {0, 0, 3}, 1};
    c.operands = {left, right};
    s.objects.push_back(textured(c, t));
    // Down the hole the cylinder's wall is hit: angle 90 degrees (+y), height 3 of 6.
    check_at(s, *t, {0, 0.5, 0}, {0, 1, 0}, 0.25, 0.5);  // from inside the hole, outward
    // Outside, the sphere: due -y on the equator.
    Probe p = probe(s, {0, -9, 0}, {0, -2, 0});
    check_uv(p.uv, 0.75, 0.5);
}

TEST_CASE("texture map: planes by point 1 -> 2 and point 1 -> 3 in scene units over texture_scale") {
    const auto t = probe_texture();
    Plane pl;
    // Axes of length 2 (along x) and sqrt 2 (diagonal): not square.
    pl.point[0] = {1, 1, 0}, pl.point[1] = {3, 1, 0}, pl.point[2] = {2, 2, 0}, pl.point[3] = {1, 1, 1};
    const PlaneShape shape = PlaneShape::from(pl);
    // p1 + 0.5 (p2 - p1) + 0.25 (p3 - p1): 1 unit along the first axis, sqrt(2) / 4
    // along the second.
    const Vec3 p = Vec3{1, 1, 0} + Vec3{2, 0, 0} * 0.5 + Vec3{1, 1, 0} * 0.25;
    check_uv(plane_uv(shape, p, 2), 0.5, std::sqrt(2.0) / 8);
    check_uv(plane_uv(shape, p + Vec3{0, 0, 3}, 1), 1, std::sqrt(2.0) / 4);  // off the plane: projected
    ShadeMaterial m = ShadeMaterial::from(Material{});
    m.texture = t.get();
    m.texture_scale = 2;
    const Colour want = mul(m.colour, t->sample(0.5, std::sqrt(2.0) / 8)), got = plane_look(shape, m, p);
    CHECK(got.x == doctest::Approx(want.x));
    CHECK(got.y == doctest::Approx(want.y));
    CHECK(got.z == doctest::Approx(want.z));
    // Point 4 in the plane (no chess cells): the texture still maps.
    pl.point[3] = {5, 5, 0};
    check_uv(plane_uv(PlaneShape::from(pl), p, 2), 0.5, std::sqrt(2.0) / 8);
}

TEST_CASE("texture map: an untextured material's colour is its own, bit for bit") {
    Scene s;
    Object o;
    o.shape = Sphere{{0, 0, 0}, 1};
    o.material.colour = {0.1, 0.7, 0.3};
    s.objects.push_back(o);
    const ShadeMaterial m = ShadeMaterial::of(s.objects[0]);
    CHECK(m.texture == nullptr);
    CHECK(m.file == nullptr);
}

TEST_CASE("texture map: both ISA paths render a textured scene to the same bytes") {
    rt_test::IsaGuard guard;
    if (!isa_supported(Isa::Avx2)) {
        MESSAGE("no AVX2 here: nothing to compare");
        return;
    }
    const Scene scene = rt_test::parse_ok(R"(
thing {
  sphere { position 4 -2 1 radius 1 material { texture "textures/uv-grid.png" } }
  cylinder { end_1 4 0 0 end_2 4 0 2 radius 0.7 material { texture "textures/uv-grid.png" reflection 0.2 } }
  torus { position 4 2.3 0.5 direction 0 0 1 major 0.8 minor 0.35 material { texture "textures/uv-grid.png" } }
  tetrahedron { vect1 2 -1 0 vect2 2.5 0 0 vect3 2 1 0 vect4 2.3 0 1.2 material { texture "textures/uv-grid.png" texture_scale 0.5 } }
}
special_thing { chess_plane { material 1 { texture "textures/uv-grid.png" texture_scale 2 } point 1 0 0 0 point 2 1 0 0 point 3 0 1 0 point 4 0 0 1 } }
light { lamp { position -2 -3 8 colour 100 100 100 } }
camera { position -3 0 3 centre 4 0.5 0.8 up 4 0.5 10 angle_x 70 angle_y 45 }
picture_size { x_max 64 y_max 40 }
end
)");
    REQUIRE(scene.objects[0].material.texture_image);
    std::vector<std::vector<std::uint8_t>> pictures;
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        REQUIRE(set_isa(isa));
        rt::ThreadPool renderer_pool(3);
        Renderer renderer(renderer_pool);
        RenderSettings settings;
        settings.width = 64;
        settings.height = 40;
        settings.coarse = false;
        renderer.start(compile_world(scene), settings);
        renderer.wait();
        pictures.push_back(to_rgb8(renderer.snapshot()));
    }
    CHECK(pictures[0] == pictures[1]);
    // And the texture shows: many distinct colours on the sphere's rows.
    std::vector<std::uint32_t> seen;
    for (std::size_t i = 0; i + 2 < pictures[0].size(); i += 3)
        seen.push_back(std::uint32_t(pictures[0][i]) << 16 | std::uint32_t(pictures[0][i + 1]) << 8 | pictures[0][i + 2]);
    std::sort(seen.begin(), seen.end());
    CHECK(std::unique(seen.begin(), seen.end()) - seen.begin() > 200);
}
