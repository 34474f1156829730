// Parser: every key and its default, the format's clamps, the New: lexical rules, and
// one test per error kind with its line and column.
#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "scene_parser.h"

using namespace rt;

namespace {

const char* kCamera =
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
    "picture_size { x_max 32 y_max 24 }\n";

ParseResult parse_with_camera(const std::string& body) { return parse_scene(body + "\n" + kCamera + "end\n"); }

// The first error, or a failing check if there is none.
Diagnostic first_error(const ParseResult& r) {
    for (const auto& d : r.diagnostics)
        if (d.is_error()) return d;
    FAIL("expected an error");
    return {};
}

bool has_message(const ParseResult& r, const std::string& part) {
    for (const auto& d : r.diagnostics)
        if (d.message.find(part) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("sphere keys and defaults") {
    auto r = parse_with_camera("thing { sphere { } sphere { position 1 -2 3.5 radius 0.25 } }");
    REQUIRE(r.ok());
    REQUIRE(r.scene.objects.size() == 2);
    const auto& a = std::get<Sphere>(r.scene.objects[0].shape);
    CHECK(a.position == Vec3{1, 1, 1});
    CHECK(a.radius == 1);
    const auto& b = std::get<Sphere>(r.scene.objects[1].shape);
    CHECK(b.position == Vec3{1, -2, 3.5});
    CHECK(b.radius == 0.25);
}

TEST_CASE("object without a material block gets translusans 0, a block gets 1") {
    auto r = parse_with_camera("thing { sphere { } sphere { material { } } }");
    REQUIRE(r.ok());
    const Material& none = r.scene.objects[0].material;
    CHECK_FALSE(r.scene.objects[0].has_material);
    CHECK(none.reflection == 0);
    CHECK(none.refraction == 0);
    CHECK(none.scattering == 1);
    CHECK(none.translusans == 0);
    CHECK(none.refractive_index == 1);
    CHECK(none.colour == Vec3{0.5, 0.5, 0.5});
    const Material& block = r.scene.objects[1].material;
    CHECK(r.scene.objects[1].has_material);
    CHECK(block.translusans == 1);
    CHECK(block.scattering == 1);
}

TEST_CASE("material keys, last value wins, clamps of translusans and refractive index") {
    auto r = parse_with_camera(
        "thing { sphere { material { reflection 0.2 refraction 3 scattering 0.5 translusans 7 "
        "refractive_index 0.0 colour 0.1 0.2 0.3 reflection 0.4 } } "
        "sphere { material { translusans -2 refractive_index 1.33 } } }");
    REQUIRE(r.ok());
    const Material& m = r.scene.objects[0].material;
    CHECK(m.reflection == 0.4);
    CHECK(m.refraction == 3);
    CHECK(m.scattering == 0.5);
    CHECK(m.translusans == 1);
    CHECK(m.refractive_index == 1);
    CHECK(m.colour == Vec3{0.1, 0.2, 0.3});
    CHECK(r.scene.objects[1].material.translusans == 0);
    CHECK(r.scene.objects[1].material.refractive_index == 1.33);
}

TEST_CASE("all-zero weights are a warning, not an error") {
    auto r = parse_with_camera("thing { sphere { material { reflection 0 refraction 0 scattering 0 } } }");
    CHECK(r.ok());
    REQUIRE(r.diagnostics.size() == 1);
    CHECK(r.diagnostics[0].severity == Diagnostic::Severity::Warning);
    CHECK(r.diagnostics[0].line == 1);
    CHECK(r.diagnostics[0].col == 18);
}

TEST_CASE("tetrahedron, cylinder and torus keys and defaults") {
    auto r = parse_with_camera(
        "thing { tetrahedron { vect1 0 0 0 vect2 1 0 0 vect3 0 1 0 vect4 0 0 1 }\n"
        "cylinder { } cylinder { end_1 1 2 3 end_2 4 5 6 radius 0.5 }\n"
        "torus { } torus { position 1 2 3 direction 0 1 0 major 2 minor 0.5 } }");
    REQUIRE(r.ok());
    const auto& t = std::get<Tetrahedron>(r.scene.objects[0].shape);
    CHECK(t.v[3] == Vec3{0, 0, 1});
    const auto& c0 = std::get<Cylinder>(r.scene.objects[1].shape);
    CHECK(c0.end1 == Vec3{0, 0, 0});
    CHECK(c0.end2 == Vec3{1, 1, 1});
    CHECK(c0.radius == 1);
    const auto& c1 = std::get<Cylinder>(r.scene.objects[2].shape);
    CHECK(c1.end2 == Vec3{4, 5, 6});
    CHECK(c1.radius == 0.5);
    const auto& t0 = std::get<Torus>(r.scene.objects[3].shape);
    CHECK(t0.position == Vec3{0, 0, 0});
    CHECK(t0.direction == Vec3{0, 0, 1});
    CHECK(t0.major == 1);
    CHECK(t0.minor == 2);
    const auto& t1 = std::get<Torus>(r.scene.objects[4].shape);
    CHECK(t1.direction == Vec3{0, 1, 0});
    CHECK(t1.minor == 0.5);
}

TEST_CASE("CSG: nested operands, type, own material") {
    auto r = parse_with_camera(
        "thing { constructive_solid_geometry { type C\n"
        "  left { constructive_solid_geometry { type I left { sphere { } } right { sphere { radius 2 } } } }\n"
        "  right { cylinder { material { colour 1 0 0 } } }\n"
        "  material { colour 0 1 0 } } }");
    REQUIRE(r.ok());
    const Csg& c = std::get<Csg>(r.scene.objects[0].shape);
    CHECK(c.type == CsgType::Difference);
    REQUIRE(c.operands.size() == 2);
    const Csg& inner = std::get<Csg>(c.operands[0].shape);
    CHECK(inner.type == CsgType::Intersection);
    CHECK(std::get<Sphere>(inner.operands[1].shape).radius == 2);
    CHECK(std::holds_alternative<Cylinder>(c.operands[1].shape));
    CHECK(r.scene.objects[0].material.colour == Vec3{0, 1, 0});
    CHECK(c.operands[1].material.colour == Vec3{1, 0, 0});
}

TEST_CASE("CSG type defaults to U") {
    auto r = parse_with_camera("thing { constructive_solid_geometry { left { sphere { } } right { sphere { } } } }");
    REQUIRE(r.ok());
    CHECK(std::get<Csg>(r.scene.objects[0].shape).type == CsgType::Union);
}

TEST_CASE("planes: point defaults, numbered points, chess materials") {
    auto r = parse_with_camera(
        "special_thing { plane { } plane { point 4 0 0 -5 material { colour 1 0 0 } }\n"
        "chess_plane { point 1 1 1 0 material 2 { colour 0 0 1 } material 1 { colour 1 1 1 } } }");
    REQUIRE(r.ok());
    REQUIRE(r.scene.planes.size() == 3);
    const Plane& p = r.scene.planes[0];
    CHECK_FALSE(p.chess);
    CHECK(p.point[0] == Vec3{0, 0, 0});
    CHECK(p.point[1] == Vec3{1, 0, 0});
    CHECK(p.point[2] == Vec3{0, 1, 0});
    CHECK(p.point[3] == Vec3{0, 0, 1});
    CHECK(p.material.translusans == 0);
    CHECK(r.scene.planes[1].point[3] == Vec3{0, 0, -5});
    CHECK(r.scene.planes[1].material.colour == Vec3{1, 0, 0});
    const Plane& c = r.scene.planes[2];
    CHECK(c.chess);
    CHECK(c.point[0] == Vec3{1, 1, 0});
    CHECK(c.material.colour == Vec3{1, 1, 1});
    CHECK(c.material2.colour == Vec3{0, 0, 1});
}

TEST_CASE("lights: lamp and spotlight defaults") {
    auto r = parse_with_camera("light { lamp { } spotlight { colour 10 20 30 } lamp { size 0.5 position 1 2 3 } }");
    REQUIRE(r.ok());
    REQUIRE(r.scene.lights.size() == 3);
    CHECK(r.scene.lights[0].lamp);
    CHECK(r.scene.lights[0].position == Vec3{1, 1, 1});
    CHECK(r.scene.lights[0].colour == Vec3{0.5, 0.5, 0.5});
    CHECK(r.scene.lights[0].size == 1);
    CHECK_FALSE(r.scene.lights[1].lamp);
    CHECK(r.scene.lights[1].colour == Vec3{10, 20, 30});
    CHECK(r.scene.lights[2].size == 0.5);
}

TEST_CASE("camera keys persist across sections; projection 1 is polar") {
    auto r = parse_scene(
        "camera { position 1 2 3 centre 4 5 6 }\n"
        "picture_size { x_max 10 }\n"
        "camera { up 4 5 7 angle_x 30 angle_y 20 projection 1 }\n"
        "picture_size { y_max 7 }\nend\n");
    REQUIRE(r.ok());
    const Camera& c = r.scene.camera;
    CHECK(c.position == Vec3{1, 2, 3});
    CHECK(c.centre == Vec3{4, 5, 6});
    CHECK(c.up == Vec3{4, 5, 7});
    CHECK(c.angle_x == 30);
    CHECK(c.angle_y == 20);
    CHECK(c.projection == Projection::Polar);
    CHECK(r.scene.width == 10);
    CHECK(r.scene.height == 7);
}

TEST_CASE("projection: any other single character is linear; words accepted") {
    for (const char* p : {"2", "i", "c", "x", "linear"}) {
        auto r = parse_scene(std::string("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 projection ") +
                             p + " }\npicture_size { x_max 4 y_max 4 }\nend");
        REQUIRE(r.ok());
        CHECK(r.scene.camera.projection == Projection::Linear);
    }
    for (const char* p : {"polar", "angular"}) {
        auto r = parse_scene(std::string("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 projection ") +
                             p + " }\npicture_size { x_max 4 y_max 4 }\nend");
        REQUIRE(r.ok());
        CHECK(r.scene.camera.projection == Projection::Polar);
    }
    auto bad = parse_scene("camera { projection 12 }\nend");
    CHECK(first_error(bad).col == 21);
}

TEST_CASE("sections in any order and repeated; objects accumulate in file order") {
    auto r = parse_scene(std::string(kCamera) + "thing { sphere { radius 1 } }\nlight { spotlight { } }\n"
                                                "thing { sphere { radius 2 } }\nend");
    REQUIRE(r.ok());
    REQUIRE(r.scene.objects.size() == 2);
    CHECK(std::get<Sphere>(r.scene.objects[1].shape).radius == 2);
}

TEST_CASE("lexical: braces are tokens, // comments anywhere, text after end ignored") {
    auto r = parse_scene(
        "thing{sphere{radius 2}}// a comment right after a brace\n"
        "thing { sphere { position // comment among numbers\n 1 2 3 } }\n"
        "camera{position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45}\n"
        "picture_size { x_max 3 y_max 2 }\n"
        "end this { is not } parsed { at all");
    REQUIRE(r.ok());
    REQUIRE(r.scene.objects.size() == 2);
    CHECK(std::get<Sphere>(r.scene.objects[0].shape).radius == 2);
    CHECK(std::get<Sphere>(r.scene.objects[1].shape).position == Vec3{1, 2, 3});
    // New: a warning says so, at the first word after it; comments and blanks alone
    // after `end` are no text.
    REQUIRE(r.diagnostics.size() == 1);
    CHECK_FALSE(r.diagnostics[0].is_error());
    CHECK(r.diagnostics[0].line == 6);
    CHECK(r.diagnostics[0].col == 5);
    CHECK(r.diagnostics[0].message == "text after 'end' is not read (the scene ends at 'end')");
    auto quiet = parse_scene(
        "camera{position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45}\npicture_size { x_max 3 y_max 2 }\n"
        "end // the end\n\n  \n");
    REQUIRE(quiet.ok());
    CHECK(quiet.diagnostics.empty());
}

TEST_CASE("numbers: the accepted syntax") {
    auto r = parse_with_camera("thing { sphere { position 5. -.5 +2 radius 1e-3 } sphere { radius 1E+1 } }");
    REQUIRE(r.ok());
    CHECK(std::get<Sphere>(r.scene.objects[0].shape).position == Vec3{5, -0.5, 2});
    CHECK(std::get<Sphere>(r.scene.objects[0].shape).radius == 1e-3);
    CHECK(std::get<Sphere>(r.scene.objects[1].shape).radius == 10);
}

TEST_CASE("numbers: not numbers, or out of range, are errors at the token") {
    for (const char* v : {"inf", "nan", "0x10", "1.5.2", "1e", "--1", ".", "1,5", "1e400", "-1e16"}) {
        auto r = parse_with_camera(std::string("thing { sphere { radius ") + v + " } }");
        Diagnostic d = first_error(r);
        CHECK(d.line == 1);
        CHECK(d.col == 25);
    }
}

TEST_CASE("integer slots must be whole integers") {
    auto r = parse_with_camera("special_thing { plane { point 1.5 2 3 4 } }");
    auto d = first_error(r);
    CHECK(d.col == 31);
    CHECK(d.message.find("integer") != std::string::npos);
    auto s = parse_scene("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
                         "picture_size { x_max 2.5 y_max 2 }\nend");
    CHECK(first_error(s).line == 2);
    CHECK(first_error(s).col == 22);
}

TEST_CASE("errors: unknown key names the valid keys, at its line and column") {
    auto r = parse_with_camera("thing {\n  sphere {\n    positio 1 2 3\n  }\n}");
    auto d = first_error(r);
    CHECK(d.line == 3);
    CHECK(d.col == 5);
    CHECK(d.message.find("'positio'") != std::string::npos);
    CHECK(d.message.find("position, radius, material") != std::string::npos);
    // Recovery: exactly one error for one typo.
    int errors = 0;
    for (const auto& x : r.diagnostics) errors += x.is_error();
    CHECK(errors == 1);
}

TEST_CASE("errors: each kind at its position") {
    struct Case {
        const char* body;
        int line, col;
        const char* message_part;
    };
    const Case cases[] = {
        {"thing { cube { } }", 1, 9, "unknown object 'cube'"},
        {"thing { sphere radius 1 } }", 1, 16, "expected '{' after 'sphere'"},
        {"thing { sphere { radius x } }", 1, 25, "expected a number after 'radius', got 'x'"},
        {"thing { sphere { position 1 2 } }", 1, 31, "expected 3 numbers after 'position'"},
        {"thing { sphere { radius 0 } }", 1, 25, "radius must be greater than 0"},
        {"thing { cylinder { end_2 0 0 0 } }", 1, 9, "same point"},
        {"thing { tetrahedron { } }", 1, 9, "flat"},
        {"thing { constructive_solid_geometry { type X left { sphere { } } right { sphere { } } } }", 1, 44,
         "CSG type must be U, I or C"},
        {"thing { constructive_solid_geometry { type Union left { sphere { } } right { sphere { } } } }", 1, 44,
         "CSG type must be U, I or C"},
        {"thing { constructive_solid_geometry { right { sphere { } } } }", 1, 9, "missing its 'left' operand"},
        {"thing { constructive_solid_geometry { left { sphere { } sphere { } } right { sphere { } } } }", 1, 57,
         "expected '}'"},
        {"special_thing { plane { point 5 1 2 3 } }", 1, 31, "point number must be 1..4"},
        {"special_thing { chess_plane { material 3 { } } }", 1, 40, "material number must be 1 or 2"},
        {"special_thing { plane { point 2 0 0 0 } }", 1, 17, "lie on one line"},
        {"special_thing { disc { } }", 1, 17, "unknown special thing 'disc'"},
        {"light { torch { } }", 1, 9, "unknown light 'torch'"},
        {"light { spotlight { size 2 } }", 1, 21, "unknown key 'size' in spotlight"},
        {"scenery { }", 1, 1, "unknown section 'scenery'"},
    };
    for (const Case& c : cases) {
        std::string body = c.body;
        CAPTURE(body);
        auto r = parse_with_camera(c.body);
        auto d = first_error(r);
        CHECK(d.line == c.line);
        CHECK(d.col == c.col);
        CHECK(d.message.find(c.message_part) != std::string::npos);
    }
}

TEST_CASE("errors: camera and picture size are required and checked") {
    auto none = parse_scene("thing { sphere { } }\nend\n");
    CHECK(has_message(none, "no 'camera' section"));
    CHECK(has_message(none, "no 'picture_size' section"));
    auto half = parse_scene("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
                            "picture_size { x_max 4 }\nend\n");
    CHECK(has_message(half, "picture_size: missing 'y_max'"));
    CHECK(first_error(half).line == 2);
    CHECK(first_error(half).col == 1);
    auto partial = parse_scene("camera { position 0 0 0 centre 1 0 0 }\npicture_size { x_max 4 y_max 4 }\nend");
    CHECK(has_message(partial, "camera: missing 'up'"));
    CHECK(has_message(partial, "camera: missing 'angle_x'"));
    CHECK(first_error(partial).line == 1);
    auto same = parse_scene("camera { position 1 1 1 centre 1 1 1 up 1 1 2 angle_x 60 angle_y 45 }\n"
                            "picture_size { x_max 4 y_max 4 }\nend");
    CHECK(has_message(same, "'centre' equals 'position'"));
    auto parallel = parse_scene("camera { position 0 0 0 centre 1 0 0 up 2 0 0 angle_x 60 angle_y 45 }\n"
                                "picture_size { x_max 4 y_max 4 }\nend");
    CHECK(has_message(parallel, "parallel"));
    auto angle = parse_scene("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 180 angle_y 45 }\n"
                             "picture_size { x_max 4 y_max 4 }\nend");
    CHECK(has_message(angle, "angle_x"));
    for (const char* size : {"0", "16385", "99999999999999999999"}) {
        auto r = parse_scene(std::string("camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
                                         "picture_size { x_max ") + size + " y_max 4 }\nend");
        CHECK(has_message(r, "picture size must be 1..16384"));
    }
}

TEST_CASE("errors: end of file and missing end") {
    auto eof = parse_scene("thing {\n  sphere {\n    radius 1\n");
    auto d = first_error(eof);
    CHECK(d.line == 4);
    CHECK(d.col == 1);
    CHECK(d.message.find("unexpected end of file inside 'sphere'") != std::string::npos);
    auto noend = parse_scene(std::string(kCamera));
    CHECK(has_message(noend, "missing 'end'"));
    auto empty = parse_scene("");
    CHECK(has_message(empty, "missing 'end'"));
    auto inside = parse_scene("thing { sphere { end } }\nend");
    CHECK(has_message(inside, "'end' inside 'sphere'"));
}

TEST_CASE("a missing '}' before the next section is one error, and the rest still parses") {
    auto r = parse_scene("thing {\n  sphere { radius 2 }\n" + std::string(kCamera) + "end\n");
    int errors = 0;
    for (const auto& d : r.diagnostics) errors += d.is_error();
    CHECK(errors == 1);
    auto d = first_error(r);
    CHECK(d.line == 3);
    CHECK(d.col == 1);
    CHECK(d.message.find("'camera' inside 'thing': is a '}' missing") != std::string::npos);
    REQUIRE(r.scene.objects.size() == 1);
    CHECK(r.scene.camera.angle_x == 60);
}

TEST_CASE("weights that add up to zero are warned about too") {
    auto r = parse_with_camera("thing { sphere { material { reflection 1 scattering -1 } } }");
    CHECK(r.ok());
    REQUIRE(r.diagnostics.size() == 1);
    CHECK(r.diagnostics[0].message.find("add up to 0") != std::string::npos);
}

TEST_CASE("errors are capped at 20 and come in file order") {
    std::string body = "thing {\n";
    for (int i = 0; i < 50; ++i) body += "  sphere { bogus" + std::to_string(i) + " 1 }\n";
    body += "}\n";
    auto r = parse_with_camera(body);
    int errors = 0, last_line = 0;
    for (const auto& d : r.diagnostics) {
        errors += d.is_error();
        CHECK(d.line >= last_line);
        last_line = d.line;
    }
    CHECK(errors == 20);
}

TEST_CASE("hostile input: deep nesting, long numbers, NUL, BOM, CRLF, garbage") {
    auto start = std::chrono::steady_clock::now();
    std::string deep = "thing { ";
    for (int i = 0; i < 100000; ++i) deep += "constructive_solid_geometry { left { ";
    auto r = parse_scene(deep);
    CHECK_FALSE(r.ok());
    CHECK(has_message(r, "nested too deeply"));

    std::string braces(200000, '{');
    CHECK_FALSE(parse_scene("thing " + braces).ok());

    auto digits = parse_with_camera("thing { sphere { radius " + std::string(1000000, '7') + " } }");
    CHECK(has_message(digits, "too long"));

    auto nul = parse_with_camera(std::string("thing { sph\0ere { } }", 21));
    CHECK(first_error(nul).col == 9);
    CHECK(first_error(nul).message.find("\\x00") != std::string::npos);

    auto bom = parse_scene("\xEF\xBB\xBF" + std::string(kCamera) + "end");
    CHECK(bom.ok());
    auto crlf = parse_scene("thing {\r\n sphere {\r\n bad 1 }\r\n}\r\n" + std::string(kCamera) + "end\r\n");
    CHECK(first_error(crlf).line == 3);
    CHECK(first_error(crlf).col == 2);
    auto utf8 = parse_with_camera("thing { sphère { } }");
    CHECK_FALSE(utf8.ok());

    std::string garbage;
    std::uint32_t x = 12345;
    for (int i = 0; i < 200000; ++i) {
        x = x * 1664525u + 1013904223u;
        garbage += char(x >> 24);
    }
    CHECK_FALSE(parse_scene(garbage).ok());
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    MESSAGE("hostile inputs parsed in " << seconds << " s");
}

TEST_CASE("format_diagnostic prints file:line:col: error: message") {
    Diagnostic d{Diagnostic::Severity::Error, 3, 7, "expected '}'"};
    CHECK(format_diagnostic("scene.txt", d) == "scene.txt:3:7: error: expected '}'");
    d.severity = Diagnostic::Severity::Warning;
    CHECK(format_diagnostic("a.txt", d) == "a.txt:3:7: warning: expected '}'");
}

TEST_CASE("errors: an unknown key in each block names exactly that block's keys") {
    // The messages as the format documents them; each list is the block's keys in order.
    struct Case {
        const char* body;
        const char* message;
    };
    const Case cases[] = {
        {"thing { sphere { bogus 1 } }", "unknown key 'bogus' in sphere (expected position, radius, material, rotation, scale, translate)"},
        {"thing { tetrahedron { vect2 1 0 0 vect3 0 1 0 vect4 0 0 1 bogus 1 } }",
         "unknown key 'bogus' in tetrahedron (expected vect1, vect2, vect3, vect4, material, rotation, scale, translate)"},
        {"thing { cylinder { bogus 1 } }", "unknown key 'bogus' in cylinder (expected end_1, end_2, radius, material, rotation, scale, translate)"},
        {"thing { torus { bogus 1 } }",
         "unknown key 'bogus' in torus (expected position, direction, major, minor, material, rotation, scale, translate)"},
        {"thing { constructive_solid_geometry { left { sphere { } } right { sphere { } } bogus 1 } }",
         "unknown key 'bogus' in constructive_solid_geometry (expected left, right, type, material, rotation, scale, translate)"},
        {"thing { sphere { material { bogus 1 } } }",
         "unknown key 'bogus' in material (expected reflection, refraction, scattering, translusans, "
         "refractive_index, colour, specular, shininess, texture, texture_scale)"},
        {"special_thing { plane { bogus 1 } }", "unknown key 'bogus' in plane (expected point, material)"},
        {"special_thing { chess_plane { bogus 1 } }", "unknown key 'bogus' in chess_plane (expected point, material)"},
        {"light { lamp { bogus 1 } }", "unknown key 'bogus' in lamp (expected position, colour, size, radius)"},
        {"light { spotlight { bogus 1 } }", "unknown key 'bogus' in spotlight (expected position, colour, radius)"},
        {"camera { bogus 1 }",
         "unknown key 'bogus' in camera (expected position, centre, up, projection, angle_x, angle_y, aperture, focus_distance, background)"},
        {"picture_size { bogus 1 }", "unknown key 'bogus' in picture_size (expected x_max, y_max)"},
        // A key of another block is just as unknown: none is taken for a default.
        {"thing { sphere { major 1 } }", "unknown key 'major' in sphere (expected position, radius, material, rotation, scale, translate)"},
        {"light { spotlight { size 1 } }", "unknown key 'size' in spotlight (expected position, colour, radius)"},
        {"special_thing { plane { radius 1 } }", "unknown key 'radius' in plane (expected point, material)"},
        {"picture_size { position 1 }", "unknown key 'position' in picture_size (expected x_max, y_max)"},
    };
    for (const Case& c : cases) {
        const std::string body = c.body;
        CAPTURE(body);
        auto r = parse_with_camera(c.body);
        REQUIRE_FALSE(r.ok());
        CHECK(first_error(r).message == std::string(c.message));
        int errors = 0;
        for (const auto& d : r.diagnostics) errors += d.is_error();
        CHECK(errors == 1);  // the value after it is skipped quietly
    }
    auto section = parse_with_camera("scenery { }");
    CHECK(first_error(section).message ==
          "unknown section 'scenery' (expected include, define, thing, special_thing, light, camera, picture_size or end)");
    auto object = parse_with_camera("thing { cube { } }");
    CHECK(first_error(object).message ==
          "unknown object 'cube' (expected sphere, tetrahedron, cylinder, torus, box, cone, constructive_solid_geometry, mesh, instance)");
}
