// The edit's path from the document to the renderer: the document names what each
// edit changed (Document::changes_since), and the world that follows it (WorldSync)
// takes that in place, or compiles anew in the background when the lists changed. After
// random sequences of edits, undos and text changes, the world equals a full compile
// of the document's scene, table for table and picture for picture.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "document.h"
#include "scene_edits.h"
#include "scene_writer.h"
#include "test_random.h"
#include "test_world_compare.h"
#include "world_sync.h"

using namespace rtview;
using rt_test::Rng;

namespace {

rt::Material random_material(Rng& rng) {
    rt::Material m;
    m.reflection = rng.uni() < 0.4 ? 0.5 : 0;
    m.refraction = rng.uni() < 0.3 ? 0.6 : 0;
    m.scattering = 0.5;
    m.translusans = 0.75;
    m.refractive_index = 1.25;
    m.colour = {0.25 + 0.5 * rng.uni(), 0.5, 0.75};
    return m;
}

rt::Object random_object(Rng& rng, double size) {
    const rt::Vec3 c{std::round(rng.uni(-size, size)), std::round(rng.uni(-size, size)), std::round(rng.uni(0, size))};
    rt::Object o;
    switch (rng.index(3)) {
        case 0: o.shape = rt::Sphere{c, 0.5}; break;
        case 1: o.shape = rt::Cylinder{c, c + rt::Vec3{0, 0, 1}, 0.25}; break;
        default: {
            rt::Csg csg;
            csg.type = rt::CsgType::Difference;
            csg.operands.resize(2);
            csg.operands[0].shape = rt::Sphere{c, 0.5};
            csg.operands[1].shape = rt::Sphere{c + rt::Vec3{0.25, 0, 0}, 0.25};
            o.shape = csg;
        }
    }
    o.material = random_material(rng);
    o.has_material = true;
    return o;
}

// A scene as text, for a document.
std::string random_scene_text(Rng& rng, int objects) {
    rt::Scene s;
    const double size = std::cbrt(double(objects)) * 1.5;
    for (int i = 0; i < objects; ++i) s.objects.push_back(random_object(rng, size));
    rt::Plane floor;
    floor.chess = true;
    floor.point[3] = {0, 0, 1};
    floor.material = random_material(rng);
    floor.material2 = random_material(rng);
    floor.has_material = floor.has_material2 = true;
    s.planes.push_back(floor);
    for (int k = 0; k < 3; ++k) {
        rt::Light l;
        l.lamp = k != 0;
        l.position = {rng.uni(-size, size), rng.uni(-size, size), 2 * size};
        l.colour = {4 * size * size, 4 * size * size, 4 * size * size};
        l.size = 0.5;
        s.lights.push_back(l);
    }
    s.camera.position = {2 * size, -2 * size, 1.5 * size};
    s.camera.centre = {0, 0, 0};
    s.camera.up = {0, 0, 1};
    s.width = 32;
    s.height = 24;
    return rt::write_scene(s);
}

// One random edit of the kinds the viewer makes. Returns whether it changed the lists
// (then the world is compiled anew).
bool random_edit(Rng& rng, Document& doc) {
    const rt::Scene& s = doc.scene();
    const std::size_t i = rng.index(s.objects.size());
    switch (rng.index(9)) {
        case 0:
        case 1: {  // a drag of the move handle: several frames, then the commit
            const rt::Object start = s.objects[i];
            for (int f = 1, frames = 1 + int(rng.index(4)); f <= frames; ++f) {
                rt::Object& o = doc.edit_object(i);
                o = start;
                translate(o, rt::Vec3{0.25, -0.5, 0.125} * double(f));
            }
            if (rng.uni() < 0.15) doc.cancel_edit();
            else doc.commit();
            return false;
        }
        case 2:  // a material slider
            for (int f = 0; f < 3; ++f) doc.edit_object(i).material.colour.x = 0.1 + 0.2 * f + 0.1 * rng.uni();
            doc.commit();
            return false;
        case 3: {
            const std::size_t k = rng.index(s.lights.size());
            translate(doc.edit_light(k), {0.5, 0, 0});
            if (rng.uni() < 0.3) doc.edit_light(k).size = doc.scene().lights[k].size > 0 ? 0 : 0.5;
            doc.commit();
            return false;
        }
        case 4:
            doc.edit_plane(0).material2.colour = {rng.uni(), 0.5, 0.5};
            doc.commit();
            return false;
        case 5:
            if (rng.uni() < 0.5) doc.undo();
            else doc.redo();
            return false;  // (an undo of a structural edit is one too: the world follows anyway)
        case 6: {  // typing in the text, then applying it: one object's radius
            const std::string before = doc.editor_text();
            std::string& text = doc.typing_text();
            const std::size_t at = text.find("radius 0.5");
            if (at != std::string::npos) text.replace(at, 10, "radius 0.625");
            doc.note_typed();
            doc.apply_text();
            return false;
        }
        case 7: {  // duplicate or delete: the lists change
            const std::string& text = std::as_const(doc).editor_text();
            std::optional<SceneEdit> e = rng.uni() < 0.5
                                             ? duplicate_item(text, s, {SceneItem::Kind::Object, int(i)}, {1, 0, 0})
                                             : delete_item(text, s, {SceneItem::Kind::Object, int(i)});
            REQUIRE(e);
            REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
            return true;
        }
        default: {  // the scene camera: not the world's content
            doc.set_camera([&] {
                rt::Camera c = s.camera;
                c.position = c.position + rt::Vec3{0.5, 0, 0};
                return c;
            }());
            return false;
        }
    }
}

}  // namespace

TEST_CASE("document: changes_since names the items each edit changed") {
    Rng rng(7);
    Document doc;
    doc.load_text(random_scene_text(rng, 20), "", "t.txt");
    const std::uint64_t v0 = doc.content_version();
    CHECK(doc.changes_since(v0).empty());
    CHECK(doc.changes_since(0).everything);  // not a version of this document's

    // A drag: every frame is a content version; all of them together name one object.
    for (int f = 0; f < 5; ++f) translate(doc.edit_object(4), {0.1, 0, 0});
    rt::SceneDelta d = doc.changes_since(v0);
    CHECK(!d.everything);
    CHECK(d.objects == std::vector<std::uint32_t>{4});
    CHECK(d.planes.empty());
    CHECK(d.lights.empty());
    const std::uint64_t mid = doc.content_version() - 2;
    CHECK(doc.changes_since(mid).objects == std::vector<std::uint32_t>{4});
    doc.commit();
    const std::uint64_t v1 = doc.content_version();
    CHECK(doc.changes_since(v1).empty());  // writing the text is no change of the scene

    doc.edit_light(2).colour = {1, 2, 3};
    doc.edit_plane(0).material.colour = {0.5, 0.5, 0.5};
    doc.commit();
    d = doc.changes_since(v1);
    CHECK(d.objects.empty());
    CHECK(d.lights == std::vector<std::uint32_t>{2});
    CHECK(d.planes == std::vector<std::uint32_t>{0});

    // Undo takes back the items its step changed.
    const std::uint64_t v2 = doc.content_version();
    REQUIRE(doc.undo());
    d = doc.changes_since(v2);
    CHECK(d.lights == std::vector<std::uint32_t>{2});
    CHECK(d.planes == std::vector<std::uint32_t>{0});
    CHECK(doc.changes_since(v0).objects == std::vector<std::uint32_t>{4});

    // The scene camera is not the world's content.
    const std::uint64_t v3 = doc.content_version();
    rt::Camera c = doc.scene().camera;
    c.position = c.position + rt::Vec3{1, 0, 0};
    REQUIRE(doc.set_camera(c));
    CHECK(doc.content_version() == v3);

    // A text applied with one changed number names that object; a new object changes
    // the lists.
    std::string& text = doc.typing_text();
    const std::size_t at = text.find("radius 0.5");
    REQUIRE(at != std::string::npos);
    text.replace(at, 10, "radius 0.75");
    doc.note_typed();
    REQUIRE(doc.apply_text());
    d = doc.changes_since(v3);
    CHECK(!d.everything);
    CHECK(d.objects.size() == 1);
    const std::uint64_t v4 = doc.content_version();
    std::optional<SceneEdit> e = duplicate_item(doc.editor_text(), doc.scene(), {SceneItem::Kind::Object, 3});
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK(doc.changes_since(v4).everything);
    CHECK(doc.changes_since(v3).everything);

    // Loading is everything; and a version from before the log's oldest entry too.
    doc.load_text(random_scene_text(rng, 5), "", "u.txt");
    CHECK(doc.changes_since(v4).everything);
    const std::uint64_t v5 = doc.content_version();
    for (int k = 0; k < 300; ++k) doc.edit_object(std::size_t(k % 5)).material.colour.y = 0.001 * k;
    doc.commit();
    CHECK(doc.changes_since(v5).everything);
    CHECK(!doc.changes_since(doc.content_version() - 3).everything);
}

TEST_CASE("world sync: random document edits keep the world equal to a full compile") {
    Rng rng(11);
    Document doc;
    doc.load_text(random_scene_text(rng, 80), "", "t.txt");
    WorldSync sync;
    CHECK(sync.finish(doc) == WorldSync::Step::Built);
    int updated = 0, built = 0;
    for (int step = 0; step < 60; ++step) {
        CAPTURE(step);
        const bool lists = random_edit(rng, doc);
        const std::uint64_t before = sync.version();
        const WorldSync::Step s = sync.sync(doc);
        if (doc.content_version() == before) {
            CHECK(s == WorldSync::Step::None);
            continue;
        }
        if (lists) CHECK(s == WorldSync::Step::Building);
        if (s == WorldSync::Step::Building) {
            ++built;
            sync.finish(doc);
        } else {
            ++updated;
        }
        REQUIRE(sync.version() == doc.content_version());
        const std::shared_ptr<const rt::World> fresh = rt::compile_world(doc.scene());
        rt_test::check_same_world(*sync.world(), *fresh);
        if (step % 4 == 0) rt_test::check_same_pictures(sync.world(), fresh);
    }
    CHECK(updated > 20);
    CHECK(built > 0);
    MESSAGE(updated << " updates in place, " << built << " compiles in the background");
}

TEST_CASE("world sync: a scene copied for a compile over several frames takes the edits made meanwhile") {
    Rng rng(14);
    Document doc;
    doc.load_text(random_scene_text(rng, 20000), "", "t.txt");
    WorldSync sync;
    sync.set_copy_budget(0);  // one share of 4,096 objects a sync
    sync.finish(doc);
    std::optional<SceneEdit> e =
        delete_item(std::as_const(doc).editor_text(), doc.scene(), {SceneItem::Kind::Object, 100}, doc.layout());
    REQUIRE(e);
    // (Parsed whole, not spliced: a change the world cannot take in place.)
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "d", nullptr));
    CHECK(sync.sync(doc) == WorldSync::Step::Building);  // (copying: 4,096 of 19,999)
    CHECK(sync.building());
    // An object already copied and one not yet, changed in place while the copy goes on.
    doc.edit_object(10).material.colour = {0.1, 0.9, 0.1};
    doc.commit();
    CHECK(sync.sync(doc) == WorldSync::Step::Building);
    doc.edit_object(19000).material.colour = {0.9, 0.1, 0.1};
    doc.commit();
    int syncs = 2;
    while (sync.copying()) {
        sync.sync(doc);
        ++syncs;
    }
    CHECK(syncs >= 5);
    sync.finish(doc);
    REQUIRE(sync.version() == doc.content_version());
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));
}

TEST_CASE("world sync: a frame with nothing changed does nothing, and the world stays the same") {
    Rng rng(12);
    Document doc;
    doc.load_text(random_scene_text(rng, 30), "", "t.txt");
    WorldSync sync;
    sync.finish(doc);
    const rt::World* w = sync.world().get();
    for (int k = 0; k < 3; ++k) CHECK(sync.sync(doc) == WorldSync::Step::None);
    CHECK(sync.world().get() == w);
    // A camera edit is not content either.
    rt::Camera c = doc.scene().camera;
    c.angle_x = 50;
    doc.set_camera(c);
    CHECK(sync.sync(doc) == WorldSync::Step::None);
    CHECK(sync.world().get() == w);
}

TEST_CASE("world sync: edits made while a compile runs go into its world once it is there") {
    Rng rng(13);
    Document doc;
    doc.load_text(random_scene_text(rng, 40), "", "t.txt");
    WorldSync sync;
    sync.finish(doc);
    std::optional<SceneEdit> e = delete_item(doc.editor_text(), doc.scene(), {SceneItem::Kind::Object, 5});
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK(sync.sync(doc) == WorldSync::Step::Building);
    // Meanwhile: a material; the old world cannot take it (its lists are the old ones).
    doc.edit_object(7).material.colour = {0.1, 0.9, 0.1};
    doc.commit();
    const WorldSync::Step s = sync.sync(doc);
    CHECK((s == WorldSync::Step::None || s == WorldSync::Step::Updated));
    sync.finish(doc);
    CHECK(sync.version() == doc.content_version());
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));
    // A loaded world adopted meanwhile replaces a build without waiting for it.
    e = delete_item(doc.editor_text(), doc.scene(), {SceneItem::Kind::Object, 2});
    REQUIRE(e);
    REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text));
    CHECK(sync.sync(doc) == WorldSync::Step::Building);
    std::shared_ptr<const rt::World> loaded = rt::compile_world(doc.scene());
    sync.adopt(loaded, doc.content_version());
    CHECK(!sync.building());
    CHECK(sync.world().get() == loaded.get());
    CHECK(sync.sync(doc) == WorldSync::Step::None);
}

TEST_CASE("world sync: a new tree's links are made in the background, and the first move uses them") {
    Rng rng(14);
    Document doc;
    doc.load_text(random_scene_text(rng, 40), "", "t.txt");
    WorldSync sync;
    sync.finish(doc);
    const std::shared_ptr<const rt::BvhLinks> links = sync.links();
    REQUIRE(bool(links));
    CHECK(!sync.world()->geometry->bvh.links);  // the compiled tree has none of its own
    translate(doc.edit_object(3), {0.25, 0, 0});
    REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(sync.world()->geometry->bvh.links.get() == links.get());
    translate(doc.edit_object(3), {0.25, 0, 0});
    REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(sync.world()->geometry->bvh.links.get() == links.get());  // the tree keeps them
    doc.commit();
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));
    // An adopted world gets links of its own tree.
    std::shared_ptr<const rt::World> loaded = rt::compile_world(doc.scene());
    sync.adopt(loaded, doc.content_version());
    sync.finish(doc);
    REQUIRE(bool(sync.links()));
    CHECK(sync.links().get() != links.get());
    translate(doc.edit_object(5), {0, 0.25, 0});
    REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(sync.world()->geometry->bvh.links.get() == sync.links().get());
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));
}

TEST_CASE("world sync: an adopted world's links wait for start_links, and a move before them still works") {
    Rng rng(17);
    Document doc;
    doc.load_text(random_scene_text(rng, 40), "", "t.txt");
    WorldSync sync;
    sync.adopt(rt::compile_world(doc.scene()), doc.content_version());
    CHECK(sync.sync(doc) == WorldSync::Step::None);
    CHECK(!sync.links());
    // A move before the links: the update makes its own.
    translate(doc.edit_object(3), {0.25, 0, 0});
    REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(bool(sync.world()->geometry->bvh.links));
    doc.commit();
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));

    sync.adopt(rt::compile_world(doc.scene()), doc.content_version());
    sync.start_links();
    sync.finish(doc);
    REQUIRE(bool(sync.links()));
    translate(doc.edit_object(5), {0, 0.25, 0});
    REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(sync.world()->geometry->bvh.links.get() == sync.links().get());
    doc.commit();
    rt_test::check_same_world(*sync.world(), *rt::compile_world(doc.scene()));
}

TEST_CASE("world sync: same_world tells a world from its successor without keeping either alive") {
    Rng rng(15);
    Document doc;
    doc.load_text(random_scene_text(rng, 10), "", "t.txt");
    std::shared_ptr<const rt::World> a = rt::compile_world(doc.scene());
    std::weak_ptr<const rt::World> seen = a;
    CHECK(same_world(seen, a));
    CHECK(!same_world(seen, rt::compile_world(doc.scene())));
    CHECK(!same_world(seen, nullptr));
    CHECK(same_world(std::weak_ptr<const rt::World>(), nullptr));
    a.reset();
    CHECK(seen.expired());  // the view's pointer did not keep it
    // A new world, perhaps at the old one's address, is still another world.
    for (int k = 0; k < 4; ++k) CHECK(!same_world(seen, rt::compile_world(doc.scene())));
}

TEST_CASE("world sync: an adopted world replaces the last one, which nothing in the sync keeps alive") {
    Rng rng(16);
    Document doc;
    doc.load_text(random_scene_text(rng, 30), "", "t.txt");
    // A world whose tree keeps its own links (a move made them).
    WorldSync other;
    other.finish(doc);
    translate(doc.edit_object(2), {0.25, 0, 0});
    REQUIRE(other.sync(doc) == WorldSync::Step::Updated);
    std::shared_ptr<const rt::World> moved = other.world();
    REQUIRE(bool(moved->geometry->bvh.links));

    WorldSync sync;
    sync.adopt(rt::compile_world(doc.scene()), doc.content_version());
    sync.finish(doc);
    REQUIRE(bool(sync.links()));
    std::weak_ptr<const rt::World> old = sync.world();
    std::weak_ptr<const rt::Geometry> old_geometry = sync.world()->geometry;
    sync.adopt(moved, doc.content_version());
    sync.finish(doc);
    CHECK(old.expired());
    CHECK(old_geometry.expired());
    CHECK(!sync.links());  // the new tree has its own
    CHECK(sync.world().get() == moved.get());
}

TEST_CASE("world sync: a moved mesh and a mesh's new material reach the world as a full compile makes it") {
    const std::string dir = std::string(RT_SOURCE_DIR) + "/tests/models";
    Document doc;
    doc.load_text("thing {\n"
                  "  sphere { position 0 0 3 radius 0.5 material { colour 1 0 0 } }\n"
                  "  mesh { file \"cube.obj\" position 0 0 0 scale 1 material { colour 0.5 0.5 0.5 } }\n"
                  "}\n"
                  "light { lamp { position 3 -4 6 colour 40 40 40 size 0.5 } }\n"
                  "camera { position 6 -6 4 centre 0 0 0.5 up 6 -6 5 angle_x 40 angle_y 30 }\n"
                  "picture_size { x_max 32 y_max 24 }\nend\n",
                  dir + "/scene.txt", "scene.txt");
    for (const auto& d : doc.diagnostics()) MESSAGE(d.line << ": " << d.message);
    REQUIRE(doc.has_scene());
    REQUIRE(doc.scene().objects.size() == 2);
    WorldSync sync;
    sync.finish(doc);
    const rt::Aabb before = sync.world()->geometry->object_bounds[1];
    REQUIRE_FALSE(before.empty());
    // A drag of the move handle: frames, then the commit.
    const rt::Object start = doc.scene().objects[1];
    for (int f = 1; f <= 3; ++f) {
        rt::Object& o = doc.edit_object(1);
        o = start;
        translate(o, rt::Vec3{0.5, 0, 0} * double(f));
        sync.sync(doc);
    }
    doc.commit();
    sync.finish(doc);
    REQUIRE(sync.version() == doc.content_version());
    // (A moved mesh is compiled anew into a slot of its own.)
    CHECK(sync.world()->geometry->object_bounds[sync.world()->slot_of(1)].lo.x == doctest::Approx(before.lo.x + 1.5));
    std::shared_ptr<const rt::World> fresh = rt::compile_world(doc.scene());
    rt_test::check_same_world(*sync.world(), *fresh);
    rt_test::check_same_pictures(sync.world(), fresh);
    // A material slider on the mesh: in place, no new compile.
    for (int f = 0; f < 3; ++f) doc.edit_object(1).material.colour.y = 0.2 + 0.2 * f;
    doc.commit();
    sync.sync(doc);
    sync.finish(doc);
    fresh = rt::compile_world(doc.scene());
    rt_test::check_same_world(*sync.world(), *fresh);
    rt_test::check_same_pictures(sync.world(), fresh);
}

TEST_CASE("world sync: Add, Duplicate, Delete and their undo and redo go into the world at once, picked by the "
          "document's numbers") {
    Rng rng(31);
    Document doc;
    doc.load_text(random_scene_text(rng, 300), "", "t.txt");
    WorldSync sync;
    sync.finish(doc);
    auto apply = [&](const std::optional<SceneEdit>& e) {
        REQUIRE(e);
        REQUIRE(e->splice);
        REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "edit",
                                 &*e->splice));
    };
    // Each step must reach the world in the same frame, and give a full compile's world.
    auto step = [&] {
        CHECK(sync.sync(doc) == WorldSync::Step::Updated);
        CHECK(!sync.building());
        REQUIRE(sync.version() == doc.content_version());
        std::shared_ptr<const rt::World> fresh = rt::compile_world(doc.scene());
        rt_test::check_same_world(*sync.world(), *fresh);
        // Rays toward every 7th object's box pick what a full compile picks.
        const rt::Vec3 eye = doc.scene().camera.position;
        for (std::size_t i = 0; i < doc.scene().objects.size(); i += 7) {
            const rt::Aabb b = fresh->geometry->object_bounds[i];
            if (b.empty()) continue;
            const rt::Ray r{eye, rt::normalize(b.centre() - eye)};
            const rt::PickResult x = rt::pick(*sync.world(), r), y = rt::pick(*fresh, r);
            CHECK(x.object == y.object);
            CHECK(x.t == y.t);
        }
    };
    Placement at;
    at.point = {0.25, 0.5, 0.0};
    at.normal = {0, 0, 1};
    apply(add_item(std::as_const(doc).editor_text(), doc.scene(), NewItem::Sphere, at, doc.layout(),
                   sync.world().get()));
    step();
    REQUIRE(doc.undo());
    step();
    REQUIRE(doc.redo());
    step();
    apply(duplicate_item(std::as_const(doc).editor_text(), doc.scene(), {SceneItem::Kind::Object, 40},
                         rt::Vec3{0.7, 0, 0}, doc.layout()));
    step();
    apply(delete_item(std::as_const(doc).editor_text(), doc.scene(), {SceneItem::Kind::Object, 12}, doc.layout()));
    step();
    REQUIRE(doc.undo());
    step();
    REQUIRE(doc.undo());
    step();
    REQUIRE(doc.redo());
    step();
    CHECK(sync.world()->spliced() > 0);
    rt_test::check_same_pictures(sync.world(), rt::compile_world(doc.scene()));
}

TEST_CASE("world sync: a world far from its compile is compiled anew behind it, the document's all along") {
    Rng rng(32);
    Document doc;
    doc.load_text(random_scene_text(rng, 20), "", "t.txt");
    WorldSync sync;
    sync.finish(doc);
    auto delete_first = [&] {
        std::optional<SceneEdit> e =
            delete_item(std::as_const(doc).editor_text(), doc.scene(), {SceneItem::Kind::Object, 0}, doc.layout());
        REQUIRE(e);
        REQUIRE(e->splice);
        REQUIRE(doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "d", &*e->splice));
    };
    // Deletes undone: each a removal and an insertion in the world's tables. The fold
    // starts in the sync that takes the world past kMaxSpliced, and is looked for right
    // there: a compile of 20 objects may be done by the next sync, which takes it.
    int pairs = 0;
    auto sync_starts_fold = [&] {
        REQUIRE(sync.sync(doc) == WorldSync::Step::Updated);
        return sync.folding();
    };
    for (;;) {
        REQUIRE(++pairs <= int(WorldSync::kMaxSpliced));
        delete_first();
        if (sync_starts_fold()) break;
        REQUIRE(doc.undo());
        if (sync_starts_fold()) break;
    }
    CHECK(pairs == int(WorldSync::kMaxSpliced / 2 + 1));
    CHECK(sync.world()->spliced() > WorldSync::kMaxSpliced);
    // The compile behind the world is no lag: nothing waits for it.
    CHECK(!sync.building());
    CHECK(sync.version() == doc.content_version());
    // An edit meanwhile goes into the world on screen at once, and into the new one.
    delete_first();
    CHECK(sync.sync(doc) == WorldSync::Step::Updated);
    CHECK(sync.version() == doc.content_version());
    while (sync.folding()) sync.sync(doc);
    CHECK(sync.version() == doc.content_version());
    CHECK(sync.world()->spliced() <= 2);
    const std::shared_ptr<const rt::World> fresh = rt::compile_world(doc.scene());
    rt_test::check_same_world(*sync.world(), *fresh);
    rt_test::check_same_pictures(sync.world(), fresh);
}
