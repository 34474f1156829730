// Textures in the viewer: a material's texture set through its field is read through
// the document's store (one decoded copy per file, shared with the scene's parses),
// named from the scene's folder, one undo step, and a file that does not read is
// refused with the texture reader's message, the scene as it was; a texture file
// changed on disk is read again as a model file is.
#include <doctest/doctest.h>

#include <array>
#include <fstream>
#include <string>
#include <vector>

#include "document.h"
#include "item_fields.h"
#include "paths.h"
#include "png.h"
#include "scene_parser.h"
#include "texture.h"
#include "test_util.h"

using namespace rtview;

namespace {

void write(const rt_test::fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

// A PNG of `w` x 1 pixels, each of the colours in turn (8-bit sRGB).
std::string png_row(const std::vector<std::array<std::uint8_t, 3>>& pixels) {
    std::vector<std::uint8_t> rgb;
    for (const auto& p : pixels) rgb.insert(rgb.end(), p.begin(), p.end());
    std::string out;
    REQUIRE(rt::encode_png(rgb.data(), int(pixels.size()), 1, out, 1));
    return out;
}

const std::string kScene =
    "thing { sphere { position 0 0 0 radius 1 material { colour 1 1 1 texture \"t.png\" } } }\n"
    "thing { sphere { position 3 0 0 radius 1 } }\n"
    "special_thing { plane { point 1 0 0 -1 point 2 1 0 -1 point 3 0 1 -1 point 4 0 0 0 "
    "material { texture \"t.png\" texture_scale 2 } } }\n"
    "camera { position 0 0 -5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
    "picture_size { x_max 8 y_max 8 }\nend\n";

ItemRef obj(int i) { return {{SceneItem::Kind::Object, i}, {}}; }

Field field(const rt::Scene& s, const ItemRef& ref, const std::string& label) {
    for (const Field& f : item_fields(s, ref))
        if (f.label == label) return f;
    FAIL("no field " << label);
    return {};
}

// The material's texel at (0, 0), or -1s when it has no texture.
rt::Colour texel0(const rt::Material& m) { return m.texture_image ? m.texture_image->texel(0, 0) : rt::Colour{-1, -1, -1}; }

}  // namespace

TEST_CASE("textures: one decoded copy per file; a texture file changed on disk is read again") {
    rt_test::TempDir dir;
    write(dir / "t.png", png_row({{255, 0, 0}, {0, 255, 0}}));
    write(dir / "scene.txt", kScene);
    Document doc;
    REQUIRE(doc.load_file((dir / "scene.txt").string()));
    REQUIRE(doc.has_scene());
    const rt::Material& sphere = doc.scene().objects[0].material;
    REQUIRE(sphere.texture_image);
    // The sphere's and the plane's materials name one file: one decoded copy, and the
    // document's store hands out that copy, not a second decoding.
    CHECK(doc.scene().planes[0].material.texture_image == sphere.texture_image);
    std::string error;
    CHECK(doc.load_texture("t.png", error) == sphere.texture_image);
    CHECK(texel0(sphere) == rt::Colour{1, 0, 0});  // sRGB 255 is linear 1
    CHECK(doc.check_disk() == Document::DiskEvent::None);

    // New texels, three of them (a new size: the file's identity differs within one tick).
    write(dir / "t.png", png_row({{0, 0, 255}, {255, 255, 255}, {0, 0, 0}}));
    const std::uint64_t v = doc.content_version();
    CHECK(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    CHECK(doc.content_version() > v);
    CHECK_FALSE(doc.modified());  // the text did not change
    const rt::Material& now = doc.scene().objects[0].material;
    CHECK(texel0(now) == rt::Colour{0, 0, 1});
    CHECK(now.texture_image->width() == 3);
    CHECK(doc.scene().planes[0].material.texture_image == now.texture_image);
    CHECK(doc.check_disk() == Document::DiskEvent::None);

    // Not an image any more: said once, the texture as it was stays.
    write(dir / "t.png", "not an image at all");
    CHECK(doc.check_disk() == Document::DiskEvent::ModelUnreadable);
    CHECK(doc.model_problem().find("t.png") != std::string::npos);
    CHECK(doc.check_disk() == Document::DiskEvent::None);
    CHECK(texel0(doc.scene().objects[0].material) == rt::Colour{0, 0, 1});

    // Mended: read again.
    write(dir / "t.png", png_row({{0, 255, 0}}));
    CHECK(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    CHECK(texel0(doc.scene().objects[0].material) == rt::Colour{0, 1, 0});
    CHECK(doc.model_problem().empty());
}

TEST_CASE("textures: undo after a texture file changed on disk shows the texture as it is now") {
    rt_test::TempDir dir;
    write(dir / "t.png", png_row({{255, 0, 0}}));
    write(dir / "scene.txt", kScene);
    Document doc;
    REQUIRE(doc.load_file((dir / "scene.txt").string()));
    // A move of the sphere: one step holding its material (and texture) before and after.
    std::get<rt::Sphere>(doc.edit_object(0).shape).position = rt::Vec3{0, 1, 0};
    doc.commit();
    write(dir / "t.png", png_row({{0, 0, 255}, {0, 0, 255}}));
    REQUIRE(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    REQUIRE(doc.undo());
    CHECK(std::get<rt::Sphere>(doc.scene().objects[0].shape).position == rt::Vec3{0, 0, 0});
    CHECK(texel0(doc.scene().objects[0].material) == rt::Colour{0, 0, 1});
    REQUIRE(doc.redo());
    CHECK(texel0(doc.scene().objects[0].material) == rt::Colour{0, 0, 1});
}

TEST_CASE("textures: a file is named from the scene's folder when it is in it, else by its absolute path") {
    CHECK(scene_file_name("/a/b/tex/w.png", "/a/b/scene.txt") == "tex/w.png");
    CHECK(scene_file_name("/a/b/w.png", "/a/b/scene.txt") == "w.png");
    CHECK(scene_file_name("/a/b/./tex/../w.png", "/a/b/scene.txt") == "w.png");
    CHECK(scene_file_name("/a/w.png", "/a/b/scene.txt") == "/a/w.png");
    CHECK(scene_file_name("/a/bc/w.png", "/a/b/scene.txt") == "/a/bc/w.png");
    CHECK(scene_file_name("/a/b/w.png", "") == "/a/b/w.png");  // an unsaved scene has no folder
    // A scene named without a folder is in the current one.
    const std::string cwd = rt_test::fs::current_path().string();
    CHECK(scene_file_name(cwd + "/x/w.png", "scene.txt") == "x/w.png");
}

TEST_CASE("textures: the material field sets a texture, one undo step; a file that does not read is refused") {
    rt_test::TempDir dir;
    rt_test::fs::create_directories(dir / "tex");
    write(dir / "t.png", png_row({{255, 0, 0}}));
    write(dir / "tex" / "g.png", png_row({{0, 255, 0}, {0, 0, 255}}));
    write(dir / "bad.png", "\x89PNG\r\n\x1a\n truncated");
    write(dir / "scene.txt", kScene);
    Document doc;
    REQUIRE(doc.load_file((dir / "scene.txt").string()));
    const ItemRef ref = obj(1);  // the sphere with no material block
    const Field f = field(doc.scene(), ref, "material");
    REQUIRE(f.kind == rt::schema::Kind::Material);
    const std::size_t steps = doc.undo_depth();

    // As the file browser's answer: named from the scene's folder.
    FieldValue v = *field_value(doc.scene(), ref, f);
    v.material.texture = scene_file_name((dir / "tex" / "g.png").string(), doc.path());
    CHECK(v.material.texture == "tex/g.png");
    FieldResult r = set_field(doc, ref, f, v);
    REQUIRE(r.applied());
    doc.commit();
    CHECK(doc.undo_depth() == steps + 1);
    CHECK(texel0(doc.scene().objects[1].material) == rt::Colour{0, 1, 0});
    CHECK(doc.editor_text().find("texture \"tex/g.png\"") != std::string::npos);
    // The text as written parses to the same texture, the same decoded copy.
    rt::ParseResult back = rt::parse_scene(doc.editor_text(), doc.parse_options(doc.path()));
    REQUIRE(back.ok());
    CHECK(back.scene.objects[1].material.texture_image == doc.scene().objects[1].material.texture_image);

    // texture_scale, another key of the same material: the texture stays.
    v = *field_value(doc.scene(), ref, f);
    v.material.texture_scale = 0.25;
    REQUIRE(set_field(doc, ref, f, v).applied());
    doc.commit();
    CHECK(doc.scene().objects[1].material.texture_scale == 0.25);
    CHECK(texel0(doc.scene().objects[1].material) == rt::Colour{0, 1, 0});
    CHECK(doc.editor_text().find("texture_scale 0.25") != std::string::npos);
    v.material.texture_scale = 0;
    r = set_field(doc, ref, f, v);
    CHECK_FALSE(r.applied());
    CHECK(r.status.message() == "texture_scale must be greater than 0");

    // Files that do not read: the reader's message, as the parser gives it for the
    // same name in the text; the scene and the text stay as they were.
    const std::string before = doc.editor_text();
    for (const std::string name : {"missing.png", "bad.png", "tex"}) {
        CAPTURE(name);
        v = *field_value(doc.scene(), ref, f);
        v.material.texture = name;
        r = set_field(doc, ref, f, v);
        CHECK_FALSE(r.applied());
        doc.commit();
        std::string parser_message;
        std::string text = before;
        text.replace(text.find("tex/g.png"), 9, name);
        for (const rt::Diagnostic& d : rt::parse_scene(text, doc.parse_options(doc.path())).diagnostics)
            if (d.is_error() && parser_message.empty()) parser_message = d.message;
        CHECK(r.status.message() == parser_message);
        CHECK(r.status.message().rfind(name + ": ", 0) == 0);
        CHECK(doc.editor_text() == before);
        CHECK(texel0(doc.scene().objects[1].material) == rt::Colour{0, 1, 0});
    }
    v.material.texture = "a\"b.png";
    r = set_field(doc, ref, f, v);
    CHECK_FALSE(r.applied());
    CHECK(r.status.message().find("holds a double quote") != std::string::npos);
    CHECK(doc.undo_depth() == steps + 2);

    // No name: no texture.
    v = *field_value(doc.scene(), ref, f);
    v.material.texture.clear();
    REQUIRE(set_field(doc, ref, f, v).applied());
    doc.commit();
    CHECK_FALSE(doc.scene().objects[1].material.texture_image);
    CHECK(doc.editor_text().find("tex/g.png") == std::string::npos);

    // Undo: the texture back, the same decoded copy.
    REQUIRE(doc.undo());
    CHECK(texel0(doc.scene().objects[1].material) == rt::Colour{0, 1, 0});
    REQUIRE(doc.undo());
    REQUIRE(doc.undo());
    CHECK_FALSE(doc.scene().objects[1].material.texture_image);
    CHECK(doc.scene().objects[1].material.texture.empty());
}
