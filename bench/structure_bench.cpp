// structure_bench: what a structural edit (Add, Duplicate, Delete) and its undo and redo
// cost the viewer in a big scene, on the path the window takes, without a window: the
// edit planned on the text (scene_edits.h), made by the document (one undo step), the
// world's sync() on the UI thread, the time until the world is the document's again,
// and until the first preview of it is traced (the viewer's first picture after an
// edit: 1280x800 in blocks of 8, 160x100 rays on the process pool's threads). Each on
// the UI thread must stay under 50 ms.
//
// Then group Delete and Duplicate of several objects spread over the list (multi-select),
// spliced item by item (Document::splice_texts) and, once, as the one replacement of
// the text that is parsed whole (the way it was).
//
//   structure_bench SCENE.txt [--rounds N] [--group N]
//   bench/make-grid.sh 1000 /tmp/g1000.txt && structure_bench /tmp/g1000.txt   (1,000,000 spheres)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench_args.h"
#include "camera.h"
#include "document.h"
#include "parallel.h"
#include "loader.h"
#include "scene_edits.h"
#include "selection.h"
#include "viewport.h"
#include "world_sync.h"

namespace {

using bench::now;

double timed(const std::function<void()>& f) {
    const double t0 = now();
    f();
    return now() - t0;
}

struct Row {
    std::string what;
    double plan = 0, doc = 0, sync = 0, world = 0, picture = 0;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return bench::usage("structure_bench SCENE.txt [--rounds N] [--group N]");
    const int rounds = bench::count_option(argc, argv, "--rounds", 2);
    const int group = bench::count_option(argc, argv, "--group", 10);
    rtview::Document doc;
    rtview::WorldSync sync;
    {
        rtview::SceneLoader loader;
        loader.start(argv[1]);
        std::optional<rtview::LoadResult> r = loader.wait();
        std::shared_ptr<const rt::World> world;
        if (!r || !rtview::apply_load(*r, doc, world) || !world || doc.scene().objects.empty()) {
            std::fprintf(stderr, "structure_bench: %s does not load or has no objects\n", argv[1]);
            return 1;
        }
        sync.adopt(std::move(world), doc.content_version());
        sync.finish(doc);
    }
    const std::size_t n = doc.scene().objects.size();
    std::printf("%s: %zu objects\n\n", argv[1], n);
    std::vector<Row> rows;
    // The first preview of a world, as the viewer traces it after an edit.
    auto preview = [](const rt::World& w) {
        constexpr int kW = 160, kH = 100;
        const rt::CameraBasis cam = rt::CameraBasis::make(w.camera, kW, kH, false);
        std::vector<rt::Colour> out(std::size_t(kW) * kH);
        rt::process_pool().parallel_for(kH, [&](int j) {
            rt::RayStats stats;
            for (int i = 0; i < kW; ++i) out[std::size_t(j) * kW + std::size_t(i)] = w.trace_camera(cam, i + 0.5, j + 0.5, stats);
        });
    };
    {
        const double t0 = now();
        preview(*sync.world());
        std::printf("a first preview of the loaded world: %.1f ms\n\n", (now() - t0) * 1e3);
    }
    // One operation: `plan` makes the edit (may be empty), `act` makes the document do
    // it; then the world's sync() as the frame calls it, and the wait until the world
    // is the document's.
    auto measure = [&](const char* what, const std::function<std::optional<rtview::SceneEdit>()>& plan,
                       const std::function<bool(const std::optional<rtview::SceneEdit>&)>& act) {
        Row r;
        r.what = what;
        const double t0 = now();
        std::optional<rtview::SceneEdit> e;
        r.plan = timed([&] { e = plan(); });
        bool ok = false;
        r.doc = timed([&] { ok = act(e); });
        if (!ok) std::fprintf(stderr, "structure_bench: %s did not happen\n", what);
        r.sync = timed([&] { sync.sync(doc); });
        while (sync.version() != doc.content_version()) {
            sync.finish(doc);
        }
        r.world = now() - t0;
        preview(*sync.world());
        r.picture = now() - t0;
        rows.push_back(r);
    };
    auto none = [] { return std::optional<rtview::SceneEdit>(); };
    auto apply = [&](const std::optional<rtview::SceneEdit>& e) {
        return e && doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, "edit",
                                     e->splice ? &*e->splice : nullptr);
    };
    auto undo = [&](const std::optional<rtview::SceneEdit>&) { return doc.undo(); };
    auto redo = [&](const std::optional<rtview::SceneEdit>&) { return doc.redo(); };
    const std::size_t mid = n / 2 + 7;
    for (int k = 0; k < rounds; ++k) {
        rtview::Placement at;
        at.point = {0.25, 0.5, 0.0};
        at.normal = {0, 0, 1};
        measure("Add sphere", [&] { return rtview::add_item(std::as_const(doc).editor_text(), doc.scene(), rtview::NewItem::Sphere, at, doc.layout(), sync.world().get()); },
                apply);
        measure("Undo (the add)", none, undo);
        measure("Redo (the add)", none, redo);
        measure("Duplicate (an object in the middle)", [&] {
            return rtview::duplicate_item(std::as_const(doc).editor_text(), doc.scene(), {rtview::SceneItem::Kind::Object, int(mid)},
                                          rt::Vec3{2.5, 0, 0}, doc.layout());
        }, apply);
        measure("Undo (the duplicate)", none, undo);
        measure("Redo (the duplicate)", none, redo);
        measure("Delete (an object in the middle)", [&] {
            return rtview::delete_item(std::as_const(doc).editor_text(), doc.scene(), {rtview::SceneItem::Kind::Object, int(mid + 3)},
                                       doc.layout());
        }, apply);
        measure("Undo (the delete)", none, undo);
        measure("Redo (the delete)", none, redo);
    }
    // Box select (Ctrl+Shift+drag) on a 1280x800 film shown 1:1, the whole picture and a
    // quarter of it: a grid of up to 40,000 primary rays traced whole (as it was), and as
    // items_in_box() traces it now (a coarse grid, then finer ones within 30 ms).
    {
        const rt::World& w = *sync.world();
        const rtview::Rect image{0, 0, 1280, 800};
        struct Box {
            const char* what;
            double x0, y0, x1, y1;
        };
        for (const Box& b : {Box{"the whole picture", 0, 0, 1280, 800}, Box{"a quarter", 320, 200, 960, 600}}) {
            const double pixels = (b.x1 - b.x0) * (b.y1 - b.y0);
            const int step = std::max(1, int(std::ceil(std::sqrt(pixels / 40000.0))));
            std::size_t rays = 0, hits = 0;
            const double whole_grid = timed([&] {
                for (double y = b.y0 + 0.5; y < b.y1; y += step)
                    for (double x = b.x0 + 0.5; x < b.x1; x += step, ++rays)
                        hits += rtview::pick_at(w, w.camera, image, 1280, 800, x, y).object >= 0;
            });
            std::size_t found = 0, found_whole = 0;
            const double now_ms = timed([&] {
                found = rtview::items_in_box(w, w.camera, image, 1280, 800, b.x0, b.y0, b.x1, b.y1).size();
            });
            found_whole = rtview::items_in_box(w, w.camera, image, 1280, 800, b.x0, b.y0, b.x1, b.y1, 40000, 1e9).size();
            std::printf("box select, %s: %zu rays traced whole %.1f ms; now %.1f ms, %zu things (%zu with time for every ray)\n",
                        b.what, rays, whole_grid * 1e3, now_ms * 1e3, found, found_whole);
            (void)hits;
        }
        std::printf("\n");
    }
    // Group edits of `group` objects spread evenly over the list.
    std::optional<rtview::GroupEdit> g;
    auto spread = [&] {
        std::vector<rtview::SceneItem> items;
        const std::size_t m = doc.scene().objects.size();
        for (int k = 0; k < group; ++k)
            items.push_back({rtview::SceneItem::Kind::Object, int((2 * std::size_t(k) + 1) * m / (2 * std::size_t(group)))});
        return items;
    };
    auto plan_group = [&](bool del) {
        return [&, del] {
            const std::string& t = std::as_const(doc).editor_text();
            g = del ? rtview::delete_items(t, doc.scene(), spread(), doc.layout())
                    : rtview::duplicate_items(t, doc.scene(), spread(), rt::Vec3{0, 0, 1.5}, doc.layout());
            return std::optional<rtview::SceneEdit>();
        };
    };
    auto spliced = [&](const std::optional<rtview::SceneEdit>&) {
        return g && !g->splices.empty() && doc.splice_texts(g->splices, "group");
    };
    auto whole = [&](const std::optional<rtview::SceneEdit>&) {
        if (!g) return false;
        const auto r = rtview::whole_replacement(std::as_const(doc).editor_text(), *g);
        return doc.replace_text(r.offset, r.length, r.text, "group");
    };
    const std::string nd = std::to_string(group);
    for (int k = 0; k < rounds; ++k) {
        measure(("Group delete (" + nd + " objects)").c_str(), plan_group(true), spliced);
        measure("Undo (the group delete)", none, undo);
        measure("Redo (the group delete)", none, redo);
        measure(("Group duplicate (" + nd + " objects)").c_str(), plan_group(false), spliced);
        measure("Undo (the group duplicate)", none, undo);
        measure("Redo (the group duplicate)", none, redo);
    }
    // A group move (the move handle of several things): 30 frames of the drag, each
    // moving every item (GroupMove::apply) and the world's sync, then the commit (one
    // undo step that rewrites each block), its sync, and its undo.
    for (int count : {10, 100, 1000}) {
        const std::size_t m = doc.scene().objects.size();
        std::vector<rtview::SceneItem> items;
        for (int k = 0; k < count; ++k)
            items.push_back({rtview::SceneItem::Kind::Object, int((2 * std::size_t(k) + 1) * m / (2 * std::size_t(count)))});
        const rtview::GroupMove move(doc.scene(), items);
        double frame = 0, frame_sync = 0;
        for (int f = 1; f <= 30; ++f) {
            frame = std::max(frame, timed([&] { move.apply(doc, rt::Vec3{0, 0, 0.05 * f}); }));
            frame_sync = std::max(frame_sync, timed([&] { sync.sync(doc); }));
        }
        while (sync.version() != doc.content_version()) sync.finish(doc);
        const std::string c = std::to_string(count);
        std::printf("group move of %d objects: a frame of the drag %.1f ms at most, its sync %.1f ms at most\n", count,
                    frame * 1e3, frame_sync * 1e3);
        measure(("Group move, the commit (" + c + ")").c_str(), none, [&](const std::optional<rtview::SceneEdit>&) {
            doc.commit();
            return true;
        });
        measure(("Undo (the group move of " + c + ")").c_str(), none, undo);
    }
    // (Their text, beyond the undo budget, is no undo step.)
    measure(("Group delete, parsed whole (" + nd + ")").c_str(), plan_group(true), whole);
    measure(("Group duplicate, parsed whole (" + nd + ")").c_str(), plan_group(false), whole);
    std::printf("| %-38s | %9s | %9s | %9s | %9s | %10s |\n|---|---:|---:|---:|---:|---:|\n", "operation (ms)", "plan",
                "document", "sync", "to world", "to picture");
    for (const Row& r : rows)
        std::printf("| %-38s | %9.1f | %9.1f | %9.1f | %9.1f | %10.1f |\n", r.what.c_str(), r.plan * 1e3, r.doc * 1e3,
                    r.sync * 1e3, r.world * 1e3, r.picture * 1e3);
    std::printf("\n%zu objects at the end (%zu at the start plus %d); %llu items spliced in all\n",
                doc.scene().objects.size(), n, 2 * rounds, static_cast<unsigned long long>(doc.spliced_count()));
    return 0;
}
