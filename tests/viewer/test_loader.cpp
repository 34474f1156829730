// Loading off the UI thread: a load delivers the file's text, scene and world; a
// cancelled load delivers nothing and a failed one an error, and neither touches the
// document that was open.
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "default_scene.h"
#include "document.h"
#include "loader.h"
#include "test_util.h"
#include "scene_parser.h"

using namespace rtview;

namespace {

struct TempFile {
    std::string path;
    explicit TempFile(const std::string& text) {
        char t[] = "/tmp/rtview-load-XXXXXX";
        int fd = mkstemp(t);
        path = t;
        if (fd >= 0) close(fd);
        std::ofstream(path, std::ios::binary) << text;
    }
    ~TempFile() { std::remove(path.c_str()); }
};

// About `n` spheres: a text that takes a while to parse and build.
std::string many_spheres(int n) {
    std::string s = "thing {\n";
    for (int i = 0; i < n; ++i)
        s += "  sphere { position " + std::to_string(i % 100) + " " + std::to_string(i / 100) + " 0 radius 0.4 }\n";
    s += "}\ncamera { position 50 -100 80 centre 50 50 0 up 50 50 1 }\nend\n";
    return s;
}

struct DocSnapshot {
    std::string text, path;
    rt::Scene scene;
    std::uint64_t scene_version, text_version;
    explicit DocSnapshot(const Document& d)
        : text(d.editor_text()), path(d.path()), scene(d.scene()), scene_version(d.scene_version()),
          text_version(d.text_version()) {}
    void check_same(const Document& d) const {
        CHECK(d.editor_text() == text);
        CHECK(d.path() == path);
        CHECK(d.scene() == scene);
        CHECK(d.scene_version() == scene_version);
        CHECK(d.text_version() == text_version);
    }
};

}  // namespace

TEST_CASE("a load delivers the text, the parsed scene and the compiled world") {
    TempFile f(rt::kDefaultScene);
    SceneLoader loader;
    loader.start(f.path);
    CHECK(loader.active());
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    CHECK_FALSE(loader.active());
    REQUIRE(r->status == LoadResult::Status::Ok);
    CHECK(r->text == rt::kDefaultScene);
    CHECK(r->parsed.ok());
    CHECK(r->parsed.scene == rt::parse_scene(rt::kDefaultScene).scene);
    REQUIRE(r->world);
    Document d;
    std::shared_ptr<const rt::World> world;
    REQUIRE(apply_load(*r, d, world));
    CHECK(world);
    CHECK(d.path() == f.path);
    CHECK(d.editor_text() == rt::kDefaultScene);
    CHECK_FALSE(d.modified());
    CHECK(d.scene() == rt::parse_scene(rt::kDefaultScene).scene);
}

TEST_CASE("a load begun by one loader is finished by another, which is told when it is done") {
    // The default scene with many spheres more: a load that takes a while.
    std::string text = rt::kDefaultScene;
    text.insert(0, many_spheres(3000).substr(0, many_spheres(3000).find("}\ncamera") + 2));
    TempFile f(text);
    SceneLoader early;
    early.start(f.path);
    SceneLoader loader;
    std::atomic<int> told{0};
    loader.set_on_finished([&told] { ++told; });
    loader.take_over(early);
    CHECK_FALSE(early.active());
    CHECK(loader.active());
    // poll() only: the callback says when there is something to take.
    std::optional<LoadResult> r;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!r && std::chrono::steady_clock::now() < until) {
        r = loader.poll();
        if (!r) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    REQUIRE(r);
    REQUIRE(r->status == LoadResult::Status::Ok);
    REQUIRE(r->parsed.ok());
    CHECK(r->parsed.scene.objects.size() > 3000);
    // Either the taken-over job was told (it finished after the hand-over) or it had
    // finished before it: never twice.
    CHECK(told.load() <= 1);
    REQUIRE(r->text_hash);
    CHECK(*r->text_hash == text_hash(r->text));
    Document d;
    std::shared_ptr<const rt::World> world;
    REQUIRE(apply_load(*r, d, world));
    CHECK(d.saved_hash() == text_hash(d.editor_text()));
    CHECK_FALSE(d.modified());

    // A load this loader starts itself tells it once it can be taken.
    TempFile g(rt::kDefaultScene);
    loader.start(g.path);
    std::optional<LoadResult> r2 = loader.wait();
    REQUIRE(r2);
    CHECK(r2->status == LoadResult::Status::Ok);
    CHECK(told.load() >= 1);
}

TEST_CASE("a failed load reports why and keeps the old scene") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    d.edit_light(0).colour = {1, 2, 3};  // with an unsaved edit, even
    d.commit();
    const DocSnapshot before(d);
    SceneLoader loader;
    loader.start("/nonexistent/dir/scene.txt");
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error.find("No such file") != std::string::npos);
    std::shared_ptr<const rt::World> world;
    CHECK_FALSE(apply_load(*r, d, world));
    CHECK_FALSE(world);
    before.check_same(d);
    CHECK(d.modified());
    CHECK(d.can_undo());
    // A directory is not a scene either.
    loader.start("/tmp");
    r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK_FALSE(apply_load(*r, d, world));
    before.check_same(d);
}

TEST_CASE("a device is no scene: the load fails at once") {
    SceneLoader loader;
    loader.start("/dev/zero");
    std::optional<LoadResult> r = loader.wait();  // /dev/zero would never end
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error == "not a regular file or a pipe (a device or a socket)");
}

TEST_CASE("a FIFO is read as its writer writes; with no writer, Cancel ends the wait") {
    rt_test::TempDir dir;
    const std::string fifo = (dir / "pipe.txt").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    {
        SceneLoader first;
        // No writer yet: the loader waits (a read now would say "end of file", an empty
        // scene) and a cancel ends it.
        first.start(fifo);
        rt_test::wait_until(rt_test::a_thread_polling, "the loader to wait for the FIFO's writer");
        CHECK(first.active());
        CHECK_FALSE(first.poll());
        first.cancel();
        CHECK_FALSE(first.active());
    }  // (its thread joined: it no longer waits on the FIFO, where it could take the writer's first piece)
    // A writer that comes late and writes in two pieces: the whole scene arrives.
    SceneLoader loader;
    loader.start(fifo);
    rt_test::wait_until(rt_test::a_thread_polling, "the loader to wait for the FIFO's writer again");
    std::thread writer([&] {
        std::FILE* f = std::fopen(fifo.c_str(), "w");
        REQUIRE(f);
        const std::string text = rt::kDefaultScene;
        std::fwrite(text.data(), 1, text.size() / 2, f);
        std::fflush(f);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));  // (a pause between the pieces)
        std::fwrite(text.data() + text.size() / 2, 1, text.size() - text.size() / 2, f);
        std::fclose(f);
    });
    std::optional<LoadResult> r = loader.wait();
    writer.join();
    REQUIRE(r);
    REQUIRE(r->status == LoadResult::Status::Ok);
    CHECK(r->text == std::string(rt::kDefaultScene));
}

TEST_CASE("a folder is no scene: the load says so and the scene stays") {
    rt_test::TempDir dir;
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const DocSnapshot before(d);
    SceneLoader loader;
    loader.start(dir.path.string());
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error == "a folder, not a scene file");
    std::shared_ptr<const rt::World> world;
    CHECK_FALSE(apply_load(*r, d, world));
    before.check_same(d);
}

TEST_CASE("a binary file is no scene: the load says why, and the scene and text stay") {
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const DocSnapshot before(d);
    SceneLoader loader;
    // Random bytes (a fixed seed): a NUL among the first hundred or so.
    std::string bytes(200000, '\0');
    std::uint64_t x = 88172645463325252ull;
    for (char& c : bytes) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        c = char(x >> 56);
    }
    const std::size_t nul = bytes.find('\0');
    REQUIRE(nul != std::string::npos);
    TempFile binary(bytes);
    loader.start(binary.path);
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error == "not a scene text: a NUL byte at byte " + std::to_string(nul + 1) + " (a binary file?)");
    std::shared_ptr<const rt::World> world;
    CHECK_FALSE(apply_load(*r, d, world));
    before.check_same(d);
    CHECK_FALSE(d.modified());
    // The same bytes without their NULs: refused as not UTF-8.
    bytes.erase(std::remove(bytes.begin(), bytes.end(), '\0'), bytes.end());
    TempFile noise(bytes);
    loader.start(noise.path);
    r = loader.wait();
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Failed);
    CHECK(r->error.find("bytes are not UTF-8 text") != std::string::npos);
    before.check_same(d);
}

// Another program still writing the file: the read would be half old, half new.
TEST_CASE("a file that grows or shrinks while it is read is refused, with a message") {
    const std::string text = many_spheres(200000);  // ~10 MB: read in several pieces
    for (int change : {+1, -1}) {
        CAPTURE(change);
        TempFile f(text);
        std::string out;
        std::atomic<bool> cancel{false};
        bool changed = false;
        const rt::Status st = read_scene_file(f.path, out, cancel, [&](std::uint64_t, std::uint64_t) {
            if (changed) return;
            changed = true;  // after the first piece: appended to, or cut short
            if (change > 0) std::ofstream(f.path, std::ios::binary | std::ios::app) << "// more\n";
            else REQUIRE(::truncate(f.path.c_str(), off_t(text.size() / 2)) == 0);
        });
        CHECK(changed);
        CHECK_FALSE(st.ok());
        CHECK(st.message().find("changed while it was read") != std::string::npos);
        CHECK(out.empty());
    }
    // Unchanged, the same file reads whole.
    TempFile f(text);
    std::string out;
    std::atomic<bool> cancel{false};
    CHECK(read_scene_file(f.path, out, cancel, [](std::uint64_t, std::uint64_t) {}).ok());
    CHECK(out == text);
}

TEST_CASE("a load can be cancelled: nothing arrives, and the next load does") {
    TempFile big(many_spheres(200000));  // ~10 MB: reading, parsing and building take a while
    TempFile small(rt::kDefaultScene);
    Document d;
    d.load_text(rt::kDefaultScene, "", "default.txt");
    const DocSnapshot before(d);
    SceneLoader loader;
    loader.start(big.path);
    CHECK(loader.active());
    loader.cancel();
    CHECK_FALSE(loader.active());
    // Nothing is ever delivered for it, however long we wait.
    auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    while (std::chrono::steady_clock::now() < until) {
        CHECK_FALSE(loader.poll());
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    before.check_same(d);
    // Opening another file while one loads cancels the first: only the second arrives.
    loader.start(big.path);
    loader.start(small.path);
    std::optional<LoadResult> r;
    for (int i = 0; i < 3000 && !r; ++i) {
        r = loader.poll();
        if (!r) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    REQUIRE(r);
    CHECK(r->status == LoadResult::Status::Ok);
    CHECK(r->path == small.path);
    CHECK_FALSE(loader.poll());
}

TEST_CASE("the parse stage reports the bytes parsed and the objects made so far") {
    const std::string text = many_spheres(200000);
    TempFile big(text);
    SceneLoader loader;
    loader.start(big.path, false);
    SceneLoader::Progress seen;
    auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < until && loader.active()) {
        SceneLoader::Progress p = loader.progress();
        if (p.stage == SceneLoader::Stage::Parsing && p.bytes > 0) {
            seen = p;
            break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    REQUIRE(seen.stage == SceneLoader::Stage::Parsing);
    CHECK(seen.total == text.size());
    CHECK(seen.bytes <= seen.total);
    CHECK(seen.objects > 0);
    CHECK(seen.objects < 200000);
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    CHECK(r->parsed.scene.objects.size() == 200000);
}

TEST_CASE("a file with errors loads as text with its diagnostics and no world") {
    TempFile f("thing { sphere { radius x } }\nend\n");
    SceneLoader loader;
    loader.start(f.path);
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    REQUIRE(r->status == LoadResult::Status::Ok);
    CHECK_FALSE(r->parsed.ok());
    CHECK_FALSE(r->world);
    Document d;
    std::shared_ptr<const rt::World> world;
    REQUIRE(apply_load(*r, d, world));
    CHECK_FALSE(d.has_scene());
    CHECK(d.has_errors());
}

TEST_CASE("a load brings where the text's items are: the first edit patches the text as a fresh scan would") {
    std::string text = many_spheres(300);
    text.replace(text.find("up 50 50 1 }"), 12, "up 50 50 1 angle_x 60 angle_y 45 }\npicture_size { x_max 8 y_max 8 }");
    TempFile f(text);
    SceneLoader loader;
    loader.start(f.path);
    std::optional<LoadResult> r = loader.wait();
    REQUIRE(r);
    REQUIRE(r->status == LoadResult::Status::Ok);
    for (const auto& d : r->parsed.diagnostics) MESSAGE(d.line << ": " << d.message);
    REQUIRE(r->parsed.ok());
    CHECK(r->world);
    REQUIRE(r->layout);
    const SceneLayout fresh = scan_layout(text);
    REQUIRE(r->layout->ok);
    REQUIRE(r->layout->objects.size() == fresh.objects.size());
    for (std::size_t i = 0; i < fresh.objects.size(); ++i) {
        CHECK(r->layout->objects[i].begin == fresh.objects[i].begin);
        CHECK(r->layout->objects[i].end == fresh.objects[i].end);
    }
    Document loaded, scanned;
    std::shared_ptr<const rt::World> world;
    REQUIRE(apply_load(*r, loaded, world));
    scanned.load_text(text, f.path, "scene.txt");
    for (Document* d : {&loaded, &scanned}) {
        for (std::size_t i : {std::size_t(7), std::size_t(250)}) {
            rt::Object& o = d->edit_object(i);
            std::get<rt::Sphere>(o.shape).position.x += 0.5;
            d->commit();
        }
    }
    CHECK(loaded.editor_text() == scanned.editor_text());
    CHECK(loaded.editor_text() != text);
    CHECK(rt::parse_scene(loaded.editor_text()).scene == loaded.scene());
}
