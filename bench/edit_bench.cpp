// edit_bench: what an edit costs the viewer in a big scene, on the path the viewer
// takes (Document -> WorldSync -> World::update), without a window: per frame of a
// move-handle drag and of a material slider drag (the document edit and the world
// update), the commit of each, undo and redo of a move (with the world brought up to
// date), and a frame in which nothing changed (sync, bounds, modified: the per-frame
// questions the window asks of the document and the world), and the once-a-second
// check of the files on disk. With --reopen N, then
// the edited scene saved (to SCENE.txt.reopen.txt) and opened N times as the window
// opens a file (SceneLoader, the world adopted), with the resident memory after each.
//
//   edit_bench SCENE.txt [--frames N] [--reopen N]
//   bench/make-grid.sh 1000 /tmp/g1000.txt && edit_bench /tmp/g1000.txt   (1,000,000 spheres)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "document.h"
#include "loader.h"
#include "scene_edits.h"
#include "world_sync.h"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Times {
    std::vector<double> v;
    double median() const {
        std::vector<double> s = v;
        std::sort(s.begin(), s.end());
        return s.empty() ? 0 : s[s.size() / 2];
    }
    double max() const { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }
};

// This process's resident memory in MB (Linux), 0 if unknown.
double rss_mb() {
    FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    double kb = 0;
    while (std::fgets(line, sizeof line, f))
        if (!std::strncmp(line, "VmRSS:", 6)) kb = std::atof(line + 6);
    std::fclose(f);
    return kb / 1024;
}

// Opens `path` as the window does: read, parsed and compiled by the loader, the world
// adopted. False if it did not load.
bool open(const std::string& path, rtview::Document& doc, rtview::WorldSync& sync) {
    rtview::SceneLoader loader;
    loader.start(path);
    std::optional<rtview::LoadResult> r = loader.wait();
    std::shared_ptr<const rt::World> world;
    if (!r || !rtview::apply_load(*r, doc, world) || !world) return false;
    sync.adopt(std::move(world), doc.content_version());
    sync.finish(doc);
    return true;
}

double timed(const std::function<void()>& f) {
    const double t0 = now();
    f();
    return now() - t0;
}

void row(const char* what, const Times& t, const char* unit = "ms", double scale = 1e3) {
    std::printf("| %-44s | %10.4f | %10.4f | %4zu |  %s\n", what, t.median() * scale, t.max() * scale, t.v.size(), unit);
}

// Each frame of a drag: the document's edit, then the world brought up to date.
Times drag(rtview::Document& doc, rtview::WorldSync& sync, int frames, const std::function<void(int)>& edit) {
    Times t;
    for (int f = 1; f <= frames; ++f)
        t.v.push_back(timed([&] {
            edit(f);
            if (sync.sync(doc) != rtview::WorldSync::Step::Updated) std::fprintf(stderr, "edit_bench: not in place\n");
        }));
    return t;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: edit_bench SCENE.txt [--frames N]\n");
        return 2;
    }
    int frames = 30, reopen = 0;
    for (int i = 2; i + 1 < argc; ++i) {
        if (!std::strcmp(argv[i], "--frames")) frames = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--reopen")) reopen = std::max(0, std::atoi(argv[++i]));
    }
    rtview::Document doc;
    rtview::WorldSync sync;
    double t0 = now();
    if (!open(argv[1], doc, sync) || doc.scene().objects.empty()) {
        std::fprintf(stderr, "edit_bench: %s does not load or has no objects\n", argv[1]);
        return 1;
    }
    const double load = now() - t0, rss_loaded = rss_mb();
    const std::size_t n = doc.scene().objects.size(), obj = n / 2 + 7;
    std::printf("%s: %zu objects; opened (read, parsed, compiled) in %.0f ms, resident %.0f MB\n\n", argv[1], n,
                load * 1e3, rss_loaded);
    std::printf("| %-44s | %10s | %10s | %4s |\n|---|---:|---:|---:|\n", "measure", "median", "max", "n");

    // Two drags of the move handle (of two objects): a document's first commit costs more.
    Times move, move_commit[2];
    for (int k = 0; k < 2; ++k) {
        const std::size_t which = obj + 2 * std::size_t(k);
        const rt::Object start = doc.scene().objects[which];
        Times t = drag(doc, sync, frames, [&](int f) {
            rt::Object& o = doc.edit_object(which);
            o = start;
            rtview::translate(o, rt::Vec3{0.01, 0.02, 0.005} * double(f));
        });
        move.v.insert(move.v.end(), t.v.begin(), t.v.end());
        move_commit[k].v.push_back(timed([&] { doc.commit(); }));
    }
    const rt::Material m0 = doc.scene().objects[obj + 1].material;
    Times slider = drag(doc, sync, frames, [&](int f) {
        doc.edit_object(obj + 1).material.colour.x = m0.colour.x * (1 - 0.01 * f);
    });
    Times slider_commit;
    slider_commit.v.push_back(timed([&] { doc.commit(); }));
    // Undo and redo of the second move (the slider's step is above it: taken back
    // first, put back last, each time).
    Times undo, redo;
    auto step = [&](bool back) {
        back ? doc.undo() : doc.redo();
        if (sync.sync(doc) != rtview::WorldSync::Step::Updated) std::fprintf(stderr, "edit_bench: not in place\n");
    };
    for (int k = 0; k < 5; ++k) {
        step(true);
        undo.v.push_back(timed([&] { step(true); }));
        redo.v.push_back(timed([&] { step(false); }));
        step(false);
    }
    // A frame in which nothing changed: what the window asks every frame.
    const rt::World* w = sync.world().get();
    Times idle;
    double sink = 0;
    for (int k = 0; k < 1000; ++k)
        idle.v.push_back(timed([&] {
            sync.sync(doc);
            const rt::Aabb b = sync.world()->bounds();
            sink += b.hi.x - b.lo.x + double(doc.modified());
        }));
    if (sync.world().get() != w) std::fprintf(stderr, "edit_bench: the world changed with nothing edited\n");
    // The window's check of the files on disk (once a second): the scene file and the
    // models the scene names, nothing changed.
    Times disk;
    for (int k = 0; k < 20; ++k) disk.v.push_back(timed([&] { sink += double(doc.check_disk()); }));

    row("move drag: edit + world update, per frame", move);
    row("move: commit (the text patched), first", move_commit[0]);
    row("move: commit, second", move_commit[1]);
    row("material slider: edit + world update, per frame", slider);
    row("material: commit", slider_commit);
    row("undo of the move + world update", undo);
    row("redo of the move + world update", redo);
    row("a frame with nothing changed (sync, bounds, modified)", idle, "us", 1e6);
    row("a check of the files on disk, nothing changed", disk, "us", 1e6);
    std::printf("\n(%g)\n", sink > 0 ? 1.0 : 0.0);
    if (reopen > 0) {
        const std::string copy = std::string(argv[1]) + ".reopen.txt";
        if (!doc.save_as(copy).ok()) return 1;
        std::printf("\nresident memory: after the first open %.0f MB, after the edits and a save %.0f MB", rss_loaded,
                    rss_mb());
        for (int k = 0; k < reopen; ++k) {
            if (!open(copy, doc, sync)) return 1;
            std::printf(", open %d %.0f MB (%.2fx)", k + 2, rss_mb(), rss_mb() / rss_loaded);
        }
        std::printf("\n");
        std::remove(copy.c_str());
    }
    return 0;
}
