// Reuse in the scene format: named materials (define { material NAME { ... } } and
// `material NAME`) and `include "FILE"`: what they read, where their mistakes are
// reported (in the included file, with the chain of includes), the hostile includes
// (missing, a folder, /dev/zero, itself, a cycle of three, a chain of 65), and that the
// writer gives them back as written, or flattened.
#include <doctest/doctest.h>

#include <string>

#include "scene_parser.h"
#include "scene_writer.h"
#include "test_util.h"

using namespace rt;
using rt_test::contains;
using rt_test::parse_ok;

namespace {

const std::string kTail =
    "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\npicture_size { x_max 8 y_max 8 }\nend\n";

ParseResult parse_in(const rt_test::TempDir& dir, const std::string& text) {
    ParseOptions o;
    o.base_dir = dir.path.string();
    return parse_scene(text, o);
}

// The errors as `raytracer --check scene.txt` prints them, one a line.
std::string errors_of(const ParseResult& r) {
    std::string out;
    for (const Diagnostic& d : r.diagnostics)
        if (d.is_error()) out += format_diagnostic("scene.txt", d) + "\n";
    return out;
}

// The first error of `body` followed by the usual camera and lights: "line:col: message".
std::string first_error(const std::string& body) {
    const ParseResult r = parse_scene(body + kTail);
    for (const Diagnostic& d : r.diagnostics)
        if (d.is_error()) return std::to_string(d.line) + ":" + std::to_string(d.col) + ": " + d.message;
    return "no error";
}

}  // namespace

TEST_CASE("named materials: defined once, used by name by objects, operands and planes") {
    const Scene s = parse_ok(
        "define {\n material glass { refraction 0.9 reflection 0.1 scattering 0 refractive_index 1.5 colour 1 1 1 }\n"
        " material red { colour 1 0 0 }\n}\n"
        "thing {\n sphere { material glass position 5 0 1 }\n"
        " constructive_solid_geometry { left { box { material red } } right { sphere { } } material red }\n}\n"
        "special_thing { chess_plane { material 1 red material 2 glass } }\n" + kTail);
    REQUIRE(s.materials.size() == 2);
    CHECK(s.materials[0].name == "glass");
    CHECK(s.materials[0].material.refraction == 0.9);
    // A use holds the definition's values and says which it is.
    const Material& m = s.objects[0].material;
    CHECK(m.named == 0);
    CHECK(m.refractive_index == 1.5);
    CHECK(m.scattering == 0);
    CHECK(s.objects[0].has_material);
    CHECK(s.objects[1].material.named == 1);
    CHECK(s.objects[1].material.colour == Vec3{1, 0, 0});
    CHECK(std::get<Csg>(s.objects[1].shape).operands[0].material.named == 1);
    CHECK(s.planes[0].material.named == 1);
    CHECK(s.planes[0].material2.named == 0);
    // Written back by name, and read back the same.
    const std::string text = write_scene(s);
    CHECK(contains(text, "define {\n  material glass { reflection 0.1 refraction 0.9 scattering 0"));
    CHECK(contains(text, "  sphere {\n    material glass\n"));
    CHECK(contains(text, "    material 1 red\n    material 2 glass\n"));
    CHECK(parse_ok(text) == s);
    // A use whose values were changed (an editor's panel) is written out in full.
    Scene edited = s;
    edited.objects[0].material.colour = {0, 1, 0};
    const std::string edited_text = write_scene(edited);
    CHECK(contains(edited_text, "  sphere {\n    material { reflection 0.1 refraction 0.9"));
    CHECK(parse_ok(edited_text).objects[0].material.colour == Vec3{0, 1, 0});
    // Flattened: every material in full and no definitions, the same values.
    const std::string flat = write_scene(s, true);
    CHECK_FALSE(contains(flat, "define"));
    CHECK_FALSE(contains(flat, "glass"));
    const Scene f = parse_ok(flat);
    REQUIRE(f.objects.size() == 2);
    CHECK(f.objects[0].material.named == -1);
    CHECK(f.objects[0].material.same_bits(s.objects[0].material));
    CHECK(f.planes[0].material2.same_bits(s.planes[0].material2));
}

TEST_CASE("include: another file's sections, read where the include stands, relative to the including file") {
    rt_test::TempDir dir;
    std::filesystem::create_directories(dir / "lib");
    rt_test::put(dir / "lib" / "parts.txt",
                 "// no end needed\ninclude \"colours.txt\"\n"
                 "thing { box { material brass corner_1 0 0 0 corner_2 1 1 1 } }\nlight { spotlight { } }\n");
    rt_test::put(dir / "lib" / "colours.txt", "define { material brass { colour 0.9 0.7 0.3 } }\nend\n");
    const std::string scene = "thing { sphere { radius 2 } }\ninclude \"lib/parts.txt\"\n"
                              "thing { cone { material brass } }\n" + kTail;
    const ParseResult r = parse_in(dir, scene);
    REQUIRE_MESSAGE(r.ok(), errors_of(r));
    const Scene& s = r.scene;
    // In reading order: the sphere, the included box, the cone that uses its material.
    REQUIRE(s.objects.size() == 3);
    CHECK(std::holds_alternative<Sphere>(s.objects[0].shape));
    CHECK(std::holds_alternative<Box>(s.objects[1].shape));
    CHECK(std::holds_alternative<Cone>(s.objects[2].shape));
    CHECK(s.objects[0].origin == 0);
    CHECK(s.objects[1].origin == 1);
    CHECK(s.objects[2].origin == 0);
    CHECK(s.objects[2].material.colour == Vec3{0.9, 0.7, 0.3});
    CHECK(s.lights.size() == 1);
    REQUIRE(s.includes.size() == 1);  // the scene file's own include only
    CHECK(s.includes[0].file == "lib/parts.txt");
    CHECK(s.includes[0].objects == 1);
    // Written back with the include line where it stood, not what it read.
    const std::string text = write_scene(s);
    CHECK(contains(text, "thing {\n  sphere {\n    position 1 1 1\n    radius 2\n  }\n}\ninclude \"lib/parts.txt\"\nthing {\n  cone {"));
    CHECK_FALSE(contains(text, "box"));
    CHECK_FALSE(contains(text, "spotlight"));
    const ParseResult back = parse_in(dir, text);
    REQUIRE(back.ok());
    CHECK(back.scene == s);
    // Flattened: one file that needs no other, the same scene but for where it came from.
    const std::string flat = write_scene(s, true);
    CHECK_FALSE(contains(flat, "include"));
    const Scene f = parse_ok(flat);
    REQUIRE(f.objects.size() == 3);
    CHECK(f.objects[1] .shape == s.objects[1].shape);
    CHECK(f.objects[2].material.same_bits(s.objects[2].material));
    CHECK(f.lights == s.lights);
}

TEST_CASE("include: a mistake in an included file is reported there, with the chain of includes") {
    rt_test::TempDir dir;
    std::filesystem::create_directories(dir / "lib");
    rt_test::put(dir / "lib" / "a.txt", "\n  include \"b.txt\"\n");
    rt_test::put(dir / "lib" / "b.txt", "thing {\n  sphere { radius -1 }\n}\n");
    const ParseResult r = parse_in(dir, "thing { sphere { } }\ninclude \"lib/a.txt\"\n" + kTail);
    const std::string b = (dir / "lib" / "b.txt").string(), a = (dir / "lib" / "a.txt").string();
    CHECK(errors_of(r) == b + ":2:19: error: sphere radius must be greater than 0 (included from " + a +
                              ":2:3, from scene.txt:2:1)\n");
    // A camera in an included file is the scene's business.
    rt_test::put(dir / "cam.txt", "camera { position 1 1 1 }\n");
    CHECK(contains(errors_of(parse_in(dir, "include \"cam.txt\"\n" + kTail)),
                   ":1:1: error: 'camera' belongs in the scene file itself, not in an included file (included from scene.txt:1:1)"));
}

TEST_CASE("include: missing files, folders, devices, itself, a cycle of three and a chain of 65 are errors at the include") {
    rt_test::TempDir dir;
    auto error = [&](const std::string& scene) { return errors_of(parse_in(dir, scene + kTail)); };
    CHECK(error("include \"nothing.txt\"\n") ==
          "scene.txt:1:1: error: cannot include 'nothing.txt': No such file or directory\n");
    std::filesystem::create_directories(dir / "folder");
    CHECK(error("include \"folder\"\n") == "scene.txt:1:1: error: cannot include 'folder': it is a folder, not a scene file\n");
    CHECK(error("include \"/dev/zero\"\n") ==
          "scene.txt:1:1: error: cannot include '/dev/zero': not a regular file (a device, pipe or socket)\n");
    CHECK(contains(error("include }\n"), "scene.txt:1:9: error: expected a file name in double quotes after 'include', got '}'"));
    // A file that includes itself.
    rt_test::put(dir / "self.txt", "include \"self.txt\"\n");
    const std::string self = (dir / "self.txt").string();
    CHECK(error("include \"self.txt\"\n") == self + ":1:1: error: include cycle: " + self + " includes " + self +
                                                 ", which is already being read (included from scene.txt:1:1)\n");
    // The scene file itself, when the parser knows it.
    rt_test::put(dir / "scene.txt", "include \"scene.txt\"\n" + kTail);
    ParseOptions named;
    named.base_dir = dir.path.string();
    named.scene_file = (dir / "scene.txt").string();
    CHECK(errors_of(parse_scene(rt_test::slurp(dir / "scene.txt"), named)) ==
          "scene.txt:1:1: error: include cycle: the scene includes " + (dir / "scene.txt").string() +
              ", the scene itself\n");
    // A cycle of three: a -> b -> c -> a.
    rt_test::put(dir / "a.txt", "include \"b.txt\"\n");
    rt_test::put(dir / "b.txt", "include \"c.txt\"\n");
    rt_test::put(dir / "c.txt", "thing { sphere { } }\ninclude \"a.txt\"\n");
    const std::string cyc = error("include \"a.txt\"\n");
    const std::string p = dir.path.string() + "/";
    CHECK(cyc == p + "c.txt:2:1: error: include cycle: " + p + "a.txt includes " + p + "b.txt includes " + p +
                     "c.txt includes " + p + "a.txt, which is already being read (included from " + p + "b.txt:1:1, from " +
                     p + "a.txt:1:1, from scene.txt:1:1)\n");
    // A chain of 65 files, each including the next: the 65th is one too deep.
    for (int i = 1; i <= 66; ++i)
        rt_test::put(dir / ("n" + std::to_string(i) + ".txt"),
                     i < 66 ? "include \"n" + std::to_string(i + 1) + ".txt\"\n" : "thing { sphere { } }\n");
    const ParseResult deep = parse_in(dir, "include \"n1.txt\"\n" + kTail);
    const std::string e = errors_of(deep);
    CHECK(contains(e, p + "n64.txt:1:1: error: includes nested too deeply (limit 64 files): " + p + "n1.txt includes "));
    CHECK(contains(e, p + "n64.txt includes " + p + "n65.txt (included from " + p + "n63.txt:1:1"));
    CHECK(deep.scene.objects.empty());
    // 64 deep is fine.
    rt_test::put(dir / "n64.txt", "thing { sphere { } }\n");
    const ParseResult ok = parse_in(dir, "include \"n1.txt\"\n" + kTail);
    CHECK_MESSAGE(ok.ok(), errors_of(ok));
    CHECK(ok.scene.objects.size() == 1);
}

#include "renderer.h"
#include "shapes.h"
#include "world.h"

namespace {
Image render_text(const std::string& text) {
    rt::ThreadPool r_pool(3);
    Renderer r(r_pool);
    r.start(compile_world(parse_ok(text)), RenderSettings{});
    r.wait();
    return r.snapshot();
}
const std::string kLit = R"(
special_thing { plane { material { colour 0.6 0.6 0.6 } point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 1 } }
light { lamp { position 2 3 6  colour 50 50 50  size 0.2 } }
camera { position 0 -1 2.5  centre 5 0 0.8  up 5 0 1.8  angle_x 50  angle_y 40 }
picture_size { x_max 96 y_max 72 }
end
)";
const std::string kCsg =
    "constructive_solid_geometry { type C left { box { corner_1 -0.5 -0.5 0 corner_2 0.5 0.5 1 } } "
    "right { sphere { position 0.5 0.5 1 radius 0.45 scale 1 1 0.5 } } material { colour 0.9 0.5 0.2 } ";
}  // namespace

TEST_CASE("instances: a defined object placed twice renders as the two objects written out") {
    const std::string placed = "define { object block { " + kCsg + "} } }\nthing {\n"
                               " instance { object block  translate 5 -1 0 }\n"
                               " instance { object block  rotation 0 0 90  scale 1.2  translate 5.5 1 0 }\n}\n";
    const std::string written = "thing {\n " + kCsg + " translate 5 -1 0 }\n " + kCsg +
                                " rotation 0 0 90  scale 1.2  translate 5.5 1 0 }\n}\n";
    const Image a = render_text(placed + kLit), b = render_text(written + kLit);
    REQUIRE(a.rgb.size() == b.rgb.size());
    int differ = 0, lit = 0;
    for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
        double d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, double(std::fabs(a.rgb[i + c] - b.rgb[i + c])));
        differ += d > 1e-4;
        lit += a.rgb[i] > 0.3f && a.rgb[i + 2] < 0.3f;  // the orange blocks
    }
    CHECK(differ <= 3);
    CHECK(lit > 300);
    // Both placements share the definition's nodes: one copy, however many placements.
    std::string many = "define { object block { " + kCsg + "} } }\nthing {\n";
    for (int i = 0; i < 100; ++i) many += " instance { object block  translate " + std::to_string(i) + " 0 0 }\n";
    const Geometry g = build_geometry(parse_ok(many + "}\n" + kLit));
    CHECK(g.nodes.size() == 100 + 4);  // a placement each; once: the CSG, the box, the scaled sphere's placement and the sphere
    CHECK(g.boxes.size() == 1);
    CHECK(g.object_bounds[99].lo.x == doctest::Approx(99 - 0.5).epsilon(1e-9));
}

TEST_CASE("instances: written back by name, flattened as copies that render the same") {
    const std::string text = "define { material m { colour 0.2 0.8 0.3 } object block { " + kCsg +
                             "rotation 0 0 10 } } object ball { sphere { radius 0.5 } } }\nthing {\n"
                             " instance { object block  translate 5 -1 0 }\n"
                             " instance { object ball  material m  scale 1 1 2  translate 5 1 0.5 }\n}\n" + kLit;
    const Scene s = parse_ok(text);
    REQUIRE(s.defined.size() == 2);
    const std::string back = write_scene(s);
    CHECK(contains(back, "define {\n  material m {"));
    CHECK(contains(back, "  object block {\n    constructive_solid_geometry {\n"));
    CHECK(contains(back, "  instance {\n    object ball\n    material m\n    scale 1 1 2\n    translate 5 1 0.5\n  }\n"));
    CHECK(parse_ok(back) == s);
    const std::string flat = write_scene(s, true);
    CHECK_FALSE(contains(flat, "instance"));
    CHECK_FALSE(contains(flat, "define"));
    const Image a = render_text(text), b = render_text(flat);
    int differ = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) differ += std::fabs(a.rgb[i] - b.rgb[i]) > 1e-4f;
    CHECK(differ <= 6);
}

TEST_CASE("named materials and instances: each mistake an error at the name") {
    // Each scene text with its first error (or "no error").
    const std::pair<const char*, const char*> cases[] = {
        // Named materials: use before definition, two definitions, bad names.
        {"thing { sphere { material glass } }\ndefine { material glass { } }\n",
         "1:27: unknown material 'glass' (a named material is defined before its first use: define { material "
         "glass { ... } })"},
        {"define { material a { } }\ndefine { material a { colour 1 1 1 } }\n",
         "2:19: material 'a' is defined twice (first at line 1, column 19)"},
        {"define { material 9lives { } }\n",
         "1:19: expected a name after 'material' (a letter or '_', then letters, digits and '_'), got '9lives'"},
        {"define { sphere ball { } }\n",
         "1:10: unknown definition 'sphere' (expected material or object)"},
        {"define { material m { colour 1 } }\n",
         "1:32: expected 3 numbers after 'colour', got '}'"},
        // A material name where an object belongs is no object.
        {"define { material m { } }\nthing { m { } }\n",
         "2:9: unknown object 'm' (expected sphere, tetrahedron, cylinder, torus, box, cone, "
         "constructive_solid_geometry, mesh, instance)"},
        {"define { material m { } }\nthing { sphere { material m } }\n",
         "no error"},
        // Instances: unknown names, a material's name, CSG operands, meshes and instances in
        // definitions.
        {"thing { instance { object chair } }\n",
         "1:27: unknown object 'chair' (an object is defined before its first use: define { object chair { ... } })"},
        {"define { material gold { } }\nthing { instance { object gold } }\n",
         "2:27: 'gold' is a material, not an object"},
        {"define { object a { sphere { } } }\nthing { constructive_solid_geometry { left { instance { object a } } "
         "right { sphere { } } } }\n",
         "2:46: an instance cannot be a CSG operand: define the whole CSG as an object and place that"},
        {"define { object m { mesh { file a.obj } } }\n",
         "1:21: a mesh cannot be defined as an object: mesh blocks already share their model"},
        {"define { object a { sphere { } } object b { instance { object a } } }\n",
         "1:45: an instance cannot be defined as an object: define the object itself"},
        {"define { object a { sphere { } } object a { box { } } }\n",
         "1:41: object 'a' is defined twice"},
        {"define { object a { sphere { } } material a { } }\n",
         "1:43: the name 'a' is already an object's"},
        {"define { object a { sphere { } sphere { } } }\n",
         "1:32: expected '}' after the object defined as 'a' (it holds exactly one object), got 'sphere'"},
        {"thing { instance { } }\n",
         "1:9: instance needs an 'object' (the name of a defined object)"},
        {"define { object a { sphere { radius 2 } } }\nthing { instance { object a scale 0 } }\n",
         "2:35: scale must be 1e-9 .. 1e9 on every axis (0 and negative scales, mirrors, are refused)"},
    };
    for (const auto& [text, error] : cases) {
        const std::string scene = text;  // (CAPTURE's lambda cannot take a binding)
        CAPTURE(scene);
        CHECK(first_error(scene) == error);
    }
}
