// Models in the viewer: an .obj or .ply opened on its own becomes a new unsaved scene
// that frames it on a floor under a lamp; File > Add model writes a mesh block resting
// on the surface picked; a model file changed on disk is read again (and one that no
// longer reads is said once, the scene keeping the model as it was).
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "default_scene.h"
#include "document.h"
#include "loader.h"
#include "readout.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "test_util.h"
#include "triangles.h"
#include "viewer_test_util.h"

using namespace rtview;
using rtview_test::applied;

namespace {

const char* const kCube = RT_SOURCE_DIR "/tests/models/cube.obj";  // the unit cube, 12 triangles

void write(const rt_test::fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// A tetrahedron's four faces, `s` wide.
std::string tetra_obj(double s) {
    const std::string n = std::to_string(s);
    return "v 0 0 0\nv " + n + " 0 0\nv 0 " + n + " 0\nv 0 0 " + n + "\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

const rt::Mesh* mesh_of(const rt::Scene& s, std::size_t i) {
    return i < s.objects.size() ? std::get_if<rt::Mesh>(&s.objects[i].shape) : nullptr;
}

// The world box of a placed mesh.
rt::Aabb placed_bounds(const rt::Mesh& m) {
    return rt::MeshInstance::make(m.position, m.scale, m.rotation).world_bounds(m.model->bounds());
}

}  // namespace

TEST_CASE("models: a model opened on its own is a scene that frames it on a floor under a lamp") {
    rt::ModelStore store;
    const rt::ModelStore::Loaded l = store.load(kCube);
    REQUIRE(l.model);
    const std::string text = model_scene(kCube, *l.model);
    rt::ParseOptions o;
    o.models = &store;
    const rt::ParseResult r = rt::parse_scene(text, o);
    REQUIRE(r.ok());
    const rt::Scene& s = r.scene;
    REQUIRE(s.objects.size() == 1);
    const rt::Mesh* m = mesh_of(s, 0);
    REQUIRE(m);
    CHECK(m->file == kCube);
    CHECK(m->model == l.model);  // read once: the scene's parse found it in the store
    REQUIRE(s.lights.size() == 1);
    CHECK(s.lights[0].lamp);
    REQUIRE(s.planes.size() == 1);
    CHECK(s.planes[0].chess);
    // The floor is the plane y = 0 (the cube's lowest point), its cells facing up.
    CHECK(s.planes[0].point[0].y == 0);
    CHECK(s.planes[0].point[1].y == 0);
    CHECK(s.planes[0].point[2].y == 0);
    CHECK(s.planes[0].point[3].y > 0);
    // Every corner of the cube is inside the camera's field of view, in front of it,
    // and the lamp is above the floor.
    const rt::Camera& c = s.camera;
    const rt::Vec3 fwd = rt::normalize(c.centre - c.position);
    const rt::Vec3 right = rt::normalize(rt::cross(fwd, c.up - c.centre));
    const rt::Vec3 up = rt::cross(right, fwd);
    const double tx = std::tan(c.angle_x * M_PI / 360), ty = std::tan(c.angle_y * M_PI / 360);
    for (int k = 0; k < 8; ++k) {
        const rt::Vec3 v = rt::Vec3{double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)} - c.position;
        const double z = rt::dot(v, fwd);
        CAPTURE(k);
        REQUIRE(z > 0);
        CHECK(std::fabs(rt::dot(v, right)) / z < tx);
        CHECK(std::fabs(rt::dot(v, up)) / z < ty);
    }
    CHECK(s.lights[0].position.y > 1);
}

TEST_CASE("models: a model opened on its own keeps the materials of its MTL file") {
    rt_test::TempDir dir;
    write(dir / "m.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
    write(dir / "m.obj", "mtllib m.mtl\nusemtl red\n" + tetra_obj(1));
    write(dir / "plain.obj", tetra_obj(1));
    rt::ModelStore store;
    rt::ParseOptions o;
    o.models = &store;
    for (const char* name : {"m.obj", "plain.obj"}) {
        const std::string path = (dir / name).string();
        const rt::ModelStore::Loaded l = store.load(path);
        REQUIRE(l.model);
        const rt::ParseResult r = rt::parse_scene(model_scene(path, *l.model), o);
        REQUIRE(r.ok());
        const rt::Object& obj = r.scene.objects.at(0);
        CAPTURE(name);
        // With an MTL file no material block (it would override the file's); without,
        // a colour of the scene's own.
        CHECK(obj.has_material == (std::string(name) == "plain.obj"));
        if (std::string(name) == "m.obj") {
            REQUIRE(mesh_of(r.scene, 0)->model->data().materials.size() == 1);
            CHECK(mesh_of(r.scene, 0)->model->data().materials[0].colour.x == doctest::Approx(0.8));
        }
    }
}

TEST_CASE("models: the outline and the readout name a mesh") {
    CHECK(std::string(shape_name(rt::Shape{rt::Mesh{}})) == "mesh");
    CHECK(std::string(shape_name(rt::Shape{rt::Csg{}})) == "CSG union");
    // The shapes after the first six by their own names (a box in the outline ended
    // the program: its index fell into the CSG's branch).
    CHECK(std::string(shape_name(rt::Shape{rt::Box{}})) == "box");
    CHECK(std::string(shape_name(rt::Shape{rt::Cone{}})) == "cone");
    CHECK(std::string(shape_name(rt::Shape{rt::Instance{}})) == "instance");
    CHECK(std::string(shape_name(rt::Shape{rt::Torus{}})) == "torus");
}

TEST_CASE("models: Add model puts a mesh block on the surface picked, its size the scene's typical size") {
    rt::ModelStore store;
    const rt::ModelStore::Loaded l = store.load(kCube);
    REQUIRE(l.model);
    rt::ParseOptions o;
    o.models = &store;
    const rt::ParseResult before = rt::parse_scene(rt::kDefaultScene, o);
    REQUIRE(before.ok());
    const rt::Scene& scene = before.scene;
    const double up_z = rt::normalize(scene.camera.up - scene.camera.centre).z;
    // A point on a floor whose normal is z, and one in space.
    const Placement on_floor{{1, 2, 0}, {0, 0, 1}, {0, 0, 0}};
    const std::optional<SceneEdit> e = add_model(rt::kDefaultScene, scene, kCube, *l.model, on_floor);
    REQUIRE(e);
    const rt::ParseResult after = rt::parse_scene(applied(e->replacement, rt::kDefaultScene), o);
    REQUIRE(after.ok());
    REQUIRE(after.scene.objects.size() == scene.objects.size() + 1);
    CHECK(e->select == SceneItem{SceneItem::Kind::Object, int(scene.objects.size())});
    const rt::Mesh* m = mesh_of(after.scene, scene.objects.size());
    REQUIRE(m);
    CHECK(m->file == kCube);
    REQUIRE(m->model);
    // Resting on the floor at the point: lowest z 0, centred over (1, 2) in x and y.
    const rt::Aabb b = placed_bounds(*m);
    const double size = rt::length(b.hi - b.lo);
    CHECK(std::fabs(b.lo.z) < 1e-3 * size);
    CHECK(std::fabs((b.lo.x + b.hi.x) / 2 - 1) < 1e-3 * size);
    CHECK(std::fabs((b.lo.y + b.hi.y) / 2 - 2) < 1e-3 * size);
    // The model's y axis turned to z when the scene's up is z.
    if (up_z > 0.9) CHECK(m->rotation == rt::Vec3{90, 0, 0});
    // About as big as the scene's other objects (nice_size rounds to 1, 2 or 5).
    const double typical = typical_object_size(scene);
    const double own = size / (2 * std::sqrt(3.0));
    CHECK(own > typical / 2.5);
    CHECK(own < typical * 2.5);

    // In space (no normal): the box's centre is the point.
    const Placement in_space{{3, -1, 2}, {0, 0, 0}, {0, 0, 0}};
    const std::optional<SceneEdit> e2 = add_model(rt::kDefaultScene, scene, kCube, *l.model, in_space);
    REQUIRE(e2);
    const rt::ParseResult after2 = rt::parse_scene(applied(e2->replacement, rt::kDefaultScene), o);
    REQUIRE(after2.ok());
    const rt::Aabb b2 = placed_bounds(*mesh_of(after2.scene, scene.objects.size()));
    CHECK(std::fabs((b2.lo.z + b2.hi.z) / 2 - 2) < 1e-3 * size);
}

TEST_CASE("models: the loader opens a model file as a new unsaved scene named after it") {
    Document doc;
    SceneLoader loader;
    loader.start(kCube, true, &doc.models());
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    REQUIRE(r->status == LoadResult::Status::Ok);
    CHECK(r->new_scene);
    REQUIRE(r->parsed.ok());
    CHECK(r->world);
    std::shared_ptr<const rt::World> world;
    REQUIRE(apply_load(*r, doc, world));
    CHECK(doc.path().empty());  // Save asks where
    CHECK(doc.name() == "cube.txt");
    CHECK_FALSE(doc.modified());
    REQUIRE(doc.has_scene());
    const rt::Mesh* m = mesh_of(doc.scene(), 0);
    REQUIRE(m);
    CHECK(m->file == kCube);
    REQUIRE(m->model);
    CHECK(m->model->data().triangle_count() == 12);

    // A file that is no model gets the reader's message, and the document stays.
    rt_test::TempDir dir;
    write(dir / "bad.obj", "v 0 0 0\nf 1 2 3\n");
    loader.start((dir / "bad.obj").string(), true, &doc.models());
    r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error.find("line 2") != std::string::npos);
    CHECK(r->error.find("out of range") != std::string::npos);
    CHECK(doc.name() == "cube.txt");
}

TEST_CASE("models: a model file changed on disk is read again; one that no longer reads is said once") {
    rt_test::TempDir dir;
    write(dir / "m.obj", tetra_obj(1));
    const std::string text = "thing { mesh { file \"m.obj\" } }\n"
                             "camera { position 0 0 -5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 8 y_max 8 }\nend\n";
    write(dir / "scene.txt", text);
    Document doc;
    REQUIRE(doc.load_file((dir / "scene.txt").string()));
    REQUIRE(doc.has_scene());
    REQUIRE(mesh_of(doc.scene(), 0));
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 4);
    CHECK(doc.check_disk() == Document::DiskEvent::None);

    // Another model of a different size (so the stamp differs even within one tick).
    std::ifstream cube(kCube, std::ios::binary);
    write(dir / "m.obj", std::string(std::istreambuf_iterator<char>(cube), {}));
    const std::uint64_t v = doc.content_version();
    CHECK(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    CHECK(doc.content_version() > v);
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 12);
    CHECK_FALSE(doc.modified());  // the text did not change
    CHECK(doc.check_disk() == Document::DiskEvent::None);

    // Broken: said once, the cube stays.
    write(dir / "m.obj", "v 0 0 0\nf 1 2 3 9\n");
    CHECK(doc.check_disk() == Document::DiskEvent::ModelUnreadable);
    CHECK(doc.model_problem().find("out of range") != std::string::npos);
    CHECK(doc.check_disk() == Document::DiskEvent::None);
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 12);

    // Mended: read again.
    write(dir / "m.obj", tetra_obj(2));
    CHECK(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 4);
    CHECK(mesh_of(doc.scene(), 0)->model->bounds().hi.x == 2);
}

TEST_CASE("models: undo and redo after a model file changed on disk keep the model as it is now") {
    rt_test::TempDir dir;
    write(dir / "m.obj", tetra_obj(1));
    write(dir / "scene.txt", "thing { mesh { file \"m.obj\" } }\n"
                             "camera { position 0 0 -5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 8 y_max 8 }\nend\n");
    Document doc;
    REQUIRE(doc.load_file((dir / "scene.txt").string()));
    REQUIRE(mesh_of(doc.scene(), 0));
    // A move of the mesh: one undo step holding the mesh before and after.
    std::get<rt::Mesh>(doc.edit_object(0).shape).position = rt::Vec3{1, 0, 0};
    doc.commit();
    REQUIRE(doc.can_undo());

    std::ifstream cube(kCube, std::ios::binary);
    write(dir / "m.obj", std::string(std::istreambuf_iterator<char>(cube), {}));
    REQUIRE(doc.check_disk() == Document::DiskEvent::ModelsReloaded);
    REQUIRE(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 12);

    const std::uint64_t v = doc.content_version();
    REQUIRE(doc.undo());
    CHECK(mesh_of(doc.scene(), 0)->position == rt::Vec3{0, 0, 0});
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 12);
    CHECK(doc.content_version() > v);
    REQUIRE(doc.redo());
    CHECK(mesh_of(doc.scene(), 0)->position == rt::Vec3{1, 0, 0});
    CHECK(mesh_of(doc.scene(), 0)->model->data().triangle_count() == 12);
}
