// Models with their materials: OBJ mtllib/usemtl and the MTL mapping, texture
// coordinates (OBJ vt, PLY u v), PLY vertex colours, a mesh's material block over the
// file's, the hostile MTL cases, and Debian's spider with its five textured materials.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "model.h"
#include "model_readers.h"
#include "scene_parser.h"
#include "shapes.h"
#include "test_textures.h"
#include "test_util.h"
#include "texture.h"
#include "texture_map.h"
#include "world.h"

using namespace rt;
using rt_test::put;
using rt_test::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kModels = RT_SOURCE_DIR "/tests/models";

double lin(double v8) {
    const double c = v8 / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

std::string scene_with(const std::string& mesh) {
    return "thing { " + mesh +
           " }\nlight { lamp { position 0 0 5 colour 1 1 1 } }\n"
           "camera { position 0 -5 1 centre 0 0 0 up 0 0 1 angle_x 40 angle_y 30 }\n"
           "picture_size { x_max 8 y_max 6 }\nend\n";
}

// The colour shading gives the hit of a ray straight down onto model-space (x, y) of
// the mesh (object 0, placed as it is in the file), and the material it shades with.
Colour look_down(const Scene& s, double x, double y, const ShadeMaterial& object, const ShadeMaterial*& m) {
    Geometry g = build_geometry(s);
    SpanScratch scratch;
    SpanEnd e;
    REQUIRE(g.hit(0, {x, y, 5}, {0, 0, -1}, 0.0, e, scratch));
    const Vec3 p{x, y, 5 - e.t};
    m = &object;
    Colour cp = object.colour;
    object_look(g, 0, e, p, m, cp);
    return cp;
}

}  // namespace

TEST_CASE("model materials: an OBJ's two MTL materials, mapped key by key, per face") {
    MeshData m;
    ModelError e;
    REQUIRE(read_model(kModels + "/two_materials.obj", m, e));
    INFO(e.message);
    CHECK(m.warnings.empty());
    REQUIRE(m.materials.size() == 2);
    // The quad (a polygon, cut after the file's triangles) is red; the triangles textured.
    REQUIRE(m.triangle_material.size() == 4);
    CHECK(m.triangle_material == std::vector<std::uint16_t>{1, 1, 0, 0});
    const Material& red = m.materials[0];
    CHECK(red.colour == Colour{0.8, 0.1, 0.1});
    CHECK(red.specular == 0.6);  // the largest of Ks
    CHECK(red.shininess == 200);
    CHECK(red.refraction == 0.25);  // 1 - d
    CHECK(red.scattering == 0.75);
    CHECK(red.refractive_index == 1.4);
    CHECK(red.texture.empty());
    CHECK_FALSE(red.texture_image);
    const Material& tex = m.materials[1];
    CHECK(tex.colour == Colour{1, 1, 1});
    CHECK(tex.refraction == 0.1);  // Tr
    CHECK(tex.texture == "checker.png");
    REQUIRE(tex.texture_image);
    CHECK(tex.texture_image->width() == 2);
    // Texture coordinates per corner: the first triangle is 2/1 5/2 6/3.
    REQUIRE(m.corner_uv.size() == 4 * 6);
    CHECK(std::vector<float>(m.corner_uv.begin(), m.corner_uv.begin() + 6) == std::vector<float>{0, 0, 1, 0, 1, 1});
}

TEST_CASE("model materials: shading takes each face's material, its texture through the corners' coordinates") {
    const Scene s = rt_test::parse_ok(scene_with("mesh { file \"two_materials.obj\" }"), rt_test::options_for(kModels));
    const ShadeMaterial object = ShadeMaterial::of(s.objects[0]);
    REQUIRE(object.file);
    CHECK(object.file->materials.size() == 2);
    // Light refracted in through the transparent faces is not absorbed on its way
    // (the object's own material, translusans 0, would absorb all of it).
    CHECK(object.log_tint == Colour{0, 0, 0});
    CHECK(ShadeMaterial::from(s.objects[0].material).log_tint.x == -HUGE_VAL);
    const ShadeMaterial* m = nullptr;
    // On the quad: the red material, no texture.
    Colour c = look_down(s, 0.5, 0.3, object, m);
    CHECK(m == &object.file->materials[0]);
    CHECK(c == Colour{0.8, 0.1, 0.1});
    CHECK(m->refraction == doctest::Approx(0.25));
    // On the first textured triangle (corners (1,0) (2,0) (2,1) with uv (0,0) (1,0)
    // (1,1)): the point (1.9, 0.1) has uv (0.9, 0.1): the bottom-right texel, blue's
    // neighbour... worked out by the bilinear rule: x = 0.9 * 2 - 0.5 = 1.3, y = (1 - 0.1)
    // * 2 - 0.5 = 1.3: texels (1,1) white, (0,1) blue (wrapped (2,1)), (1,0) green,
    // (0,0) red (wrapped), weights 0.7 0.3 in each direction.
    c = look_down(s, 1.9, 0.1, object, m);
    CHECK(m == &object.file->materials[1]);
    const Colour white{1, 1, 1}, blue{0, 0, 1}, green{0, 1, 0}, red{1, 0, 0};
    const Colour row1 = white * 0.7 + blue * 0.3, row2 = green * 0.7 + red * 0.3;  // y = 1 and y = 2 (wrapped to 0)
    const Colour want = row1 * 0.7 + row2 * 0.3;
    CHECK(c.x == doctest::Approx(want.x));
    CHECK(c.y == doctest::Approx(want.y));
    CHECK(c.z == doctest::Approx(want.z));
}

TEST_CASE("model materials: a material block in the mesh overrides the file's, keeping its coordinates") {
    TempDir dir("rt-mtl");
    fs::copy(kModels + "/two_materials.obj", dir / "two_materials.obj");
    fs::copy(kModels + "/two_materials.mtl", dir / "two_materials.mtl");
    fs::copy(kModels + "/checker.png", dir / "checker.png");
    put(dir / "grey.png", rt_test::png_rgb8(1, 1, {128, 128, 128}));
    const Scene s = rt_test::parse_ok(
        scene_with("mesh { file \"two_materials.obj\" material { colour 0.2 0.4 0.6 texture \"grey.png\" } }"),
        rt_test::options_for(dir.path.string()));
    const ShadeMaterial object = ShadeMaterial::of(s.objects[0]);
    CHECK_FALSE(object.file);
    const ShadeMaterial* m = nullptr;
    for (double x : {0.5, 1.9}) {
        const Colour c = look_down(s, x, 0.1, object, m);
        CHECK(m == &object);
        CHECK(c.x == doctest::Approx(0.2 * lin(128)));
        CHECK(c.z == doctest::Approx(0.6 * lin(128)));
    }
}

TEST_CASE("model materials: PLY texture coordinates (u v or s t) and vertex colours") {
    TempDir dir("rt-ply");
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\n";
    put(dir / "uv.ply", header + "property float s\nproperty float t\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n3 0 1 2\n");
    put(dir / "colours.ply", header + "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                      "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 128\n3 0 1 2\n");
    MeshData m;
    ModelError e;
    REQUIRE(read_model((dir / "uv.ply").string(), m, e));
    CHECK(m.corner_uv == std::vector<float>{0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f});
    REQUIRE(read_model((dir / "colours.ply").string(), m, e));
    REQUIRE(m.colours.size() == 9);
    CHECK(m.colours[0] == 1.0f);
    CHECK(m.colours[4] == 1.0f);
    CHECK(m.colours[8] == doctest::Approx(lin(128)));
    // Shaded: the colours blended by the point's barycentric coordinates.
    const Scene s = rt_test::parse_ok(scene_with("mesh { file \"colours.ply\" }"), rt_test::options_for(dir.path.string()));
    const ShadeMaterial object = ShadeMaterial::of(s.objects[0]);
    REQUIRE(object.file);
    CHECK(object.file->vertex_colours);
    const ShadeMaterial* sm = nullptr;
    const Colour c = look_down(s, 0.25, 0.5, object, sm);  // weights 0.25 (corner 0), 0.25, 0.5
    CHECK(c.x == doctest::Approx(0.25));
    CHECK(c.y == doctest::Approx(0.25));
    CHECK(c.z == doctest::Approx(0.5 * lin(128)));
}

TEST_CASE("model materials: a missing MTL warns and the mesh's colour is used; bad ones are errors") {
    TempDir dir("rt-mtl");
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl a\nf 1 2 3\n";
    auto parse = [&](const std::string& obj) {
        put(dir / "m.obj", obj);
        ParseOptions o = rt_test::options_for(dir.path.string());
        o.models = nullptr;  // fresh reads: the files change between cases
        o.textures = nullptr;
        return parse_scene(scene_with("mesh { file \"m.obj\" material { colour 0.1 0.2 0.3 } }"), o);
    };
    auto message = [](const ParseResult& r) {
        REQUIRE_FALSE(r.diagnostics.empty());
        return format_diagnostic("s.txt", r.diagnostics.front());
    };
    {
        const ParseResult r = parse("mtllib gone.mtl\n" + quad);
        CHECK(r.ok());
        CHECK(message(r) == "s.txt:1:21: warning: m.obj: material file gone.mtl: No such file or directory; the "
                            "mesh's own colour is used");
    }
    {
        put(dir / "self.mtl", "newmtl a\nKd 1 0 0\nmap_Kd self.mtl\n");
        const ParseResult r = parse("mtllib self.mtl\n" + quad);
        CHECK_FALSE(r.ok());
        CHECK(message(r) == "s.txt:1:21: error: m.obj: self.mtl:3: map_Kd self.mtl names the material file itself");
    }
    {
        put(dir / "missing_tex.mtl", "newmtl a\nKd 1 0 0\nmap_Kd .\\nowhere.png\n");
        const ParseResult r = parse("mtllib missing_tex.mtl\n" + quad);
        CHECK_FALSE(r.ok());
        CHECK(message(r) ==
              "s.txt:1:21: error: m.obj: missing_tex.mtl:3: map_Kd ./nowhere.png: No such file or directory");
    }
    {
        const ParseResult r = parse("mtllib m.obj\n" + quad);
        CHECK(message(r) == "s.txt:1:21: error: m.obj: mtllib m.obj names the model file itself");
    }
    {
        put(dir / "bad.mtl", "newmtl a\nKd 1 zero 0\n");
        const ParseResult r = parse("mtllib bad.mtl\n" + quad);
        CHECK(message(r) == "s.txt:1:21: error: m.obj: bad.mtl:2: Kd value 'zero' is not a number");
    }
    {
        fs::create_directory(dir / "folder.mtl");
        const ParseResult r = parse("mtllib folder.mtl\n" + quad);
        CHECK(r.ok());
        CHECK(message(r).find("folder.mtl: is a folder, not a material file") != std::string::npos);
    }
    {
        // A FIFO: refused at once, never waited on.
        REQUIRE(::mkfifo((dir / "pipe.mtl").c_str(), 0600) == 0);
        const ParseResult r = parse("mtllib pipe.mtl\n" + quad);
        CHECK(r.ok());
        CHECK(message(r).find("pipe.mtl: is not a regular file") != std::string::npos);
    }
}

TEST_CASE("model materials: MTL statements read one by one") {
    std::vector<MtlMaterial> out;
    ModelError e;
    REQUIRE(read_mtl("newmtl x\r\nKd 0.5\r\nKs 2 0 0\r\nNs 0\r\nd 0.25\r\nNi 0.5\r\n"
                     "map_Kd -o 0.5 0.5 -clamp on -bm 1 dir\\sub dir\\my tex.png\r\nillum 9\r\nnewmtl\r\nNs 1e9\n",
                     out, e));
    REQUIRE(out.size() == 2);
    CHECK(out[0].name == "x");
    CHECK(out[0].material.colour == Colour{0.5, 0.5, 0.5});
    CHECK(out[0].material.specular == 1);      // clamped
    CHECK(out[0].material.shininess == 1);     // clamped
    CHECK(out[0].material.refraction == 0.75);
    CHECK(out[0].material.refractive_index == 1);  // at least 1
    CHECK(out[0].texture == "dir/sub dir/my tex.png");
    CHECK(out[0].texture_line == 7);
    CHECK(out[1].name.empty());
    CHECK(out[1].material.shininess == 10000);
    CHECK_FALSE(read_mtl("Kd 1 1 1\n", out, e));
    CHECK(e.message == "Kd before any newmtl");
    CHECK_FALSE(read_mtl("newmtl a\nKd 1 1\n", out, e));
    CHECK(e.line == 2);
    CHECK_FALSE(read_mtl("newmtl a\nKd spectral x.rfl\n", out, e));
    CHECK(e.message.find("spectral") != std::string::npos);
    CHECK_FALSE(read_mtl("newmtl a\nmap_Kd  \n", out, e));
    CHECK(e.message == "map_Kd needs a file name");
}

TEST_CASE("model materials: Debian's spider keeps its five MTL materials and textures") {
    const std::string spider = "/usr/share/assimp/models/OBJ/spider.obj";
    if (!fs::exists(spider)) {
        MESSAGE("assimp-testmodels is not installed: skipped");
        return;
    }
    ParseOptions o = rt_test::options_for("/usr/share/assimp/models/OBJ");
    const ParseResult r = parse_scene(scene_with("mesh { file \"spider.obj\" }"), o);
    REQUIRE(r.ok());
    CHECK(r.diagnostics.empty());
    const MeshData& d = std::get<Mesh>(r.scene.objects[0].shape).model->data();
    // spider.mtl's five, of which the faces use four (Brusttex is never used).
    CHECK(d.material_names == std::vector<std::string>{"HLeibTex", "Skin", "BeinTex", "Augentex"});
    REQUIRE(d.materials.size() == 4);
    // Skin: Kd 0.827451 0.792157 0.772549, map_Kd .\wal67ar_small.jpg, Ks 0, Ns 0.
    const Material& skin = d.materials[1];
    CHECK(skin.colour == Colour{0.827451, 0.792157, 0.772549});
    CHECK(skin.texture == "./wal67ar_small.jpg");
    CHECK(skin.specular == 0);
    CHECK(skin.shininess == 1);
    CHECK(skin.refraction == 0);
    for (const Material& m : d.materials) {
        REQUIRE(m.texture_image);
        CHECK(m.texture_image->width() > 0);
    }
    // Every face has its material; the texture coordinates are there.
    for (std::uint16_t k : d.triangle_material) CHECK(k < 4);
    CHECK(d.corner_uv.size() == 6 * d.triangle_count());
    // The body's texture is the one file, shared by every material naming it.
    CHECK(d.materials[0].texture_image->path().find("SpiderTex.jpg") != std::string::npos);
}
