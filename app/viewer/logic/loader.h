// Opening a scene file off the UI thread: reading (with byte progress), parsing and
// building the world run on a worker, so the window keeps painting and the old scene
// stays on screen until the new one is ready. A load can be cancelled (Esc, or opening
// another file); a cancelled or failed load leaves the caller's scene alone.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "document.h"
#include "parallel.h"
#include "scene_parser.h"
#include "world.h"

namespace rtview {

struct LoadResult {
    enum class Status { Ok, Failed, Cancelled } status = Status::Failed;
    std::string path;
    // The file was a model (.obj, .ply): the text is a new scene showing it, to be
    // opened unsaved (named after the model).
    bool new_scene = false;
    std::string error;      // Failed: why the file could not be read
    std::string text;       // the file's bytes (Ok)
    rt::ParseResult parsed; // Ok: the scene, or the diagnostics of a text that does not parse
    std::shared_ptr<const rt::World> world;  // Ok and parsed: compiled
    // Ok and parsed: where the text's items are, scanned beside the compile, so that
    // the first edit of a big scene patches the text at once (no pass over 100 MB then).
    std::optional<SceneLayout> layout;
    // Ok: text_hash() of the text, taken beside the compile (the document's saved
    // state, without a pass over 100 MB on the UI thread when the load arrives).
    std::optional<std::uint64_t> text_hash;
    // Seconds each stage took (raytracer-view -v prints them beside raytracer --stats').
    struct Times {
        double read = 0, parse = 0, build = 0;
        double compile = 0, scan = 0;  // the build's two parts, side by side
    } times;
};

// Reads a scene file as the loader does: with the command line's reader (rt::read_file,
// strict): a regular file or a FIFO (a folder or a device fails at once, never
// blocking), with `report(bytes, total)` as it arrives,
// stopping once `cancel` is set (a FIFO is waited for in polls that see it). A regular
// file that changes while it is read (another program still writing it) fails too:
// its bytes could be half old and half new.
rt::Status read_scene_file(const std::string& path, std::string& out, const std::atomic<bool>& cancel,
                           const std::function<void(std::uint64_t, std::uint64_t)>& report);

// Puts a finished load into `doc` (moving the text and scene in: nothing is copied
// or parsed again) and hands over its compiled world. Only an Ok result does that; a
// failed or cancelled load leaves `doc` exactly as it was and returns false.
bool apply_load(LoadResult& result, Document& doc, std::shared_ptr<const rt::World>& world);

class SceneLoader {
public:
    enum class Stage { Idle, Reading, Parsing, Building, Done };
    struct Progress {
        Stage stage = Stage::Idle;
        std::uint64_t bytes = 0, total = 0;  // read (parsed) so far, of the file's size
        std::size_t objects = 0;             // made so far
        std::string path;
    };

    SceneLoader() = default;
    ~SceneLoader();
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    // Starts loading `path`, cancelling a load under way. `compile`: build the world
    // too (the viewer does; the world is then ready when the result arrives).
    // `models`: where the scene's models are read and kept (the document's store),
    // null for a store of the load's own. A model file (.obj, .ply) opens as a new
    // scene showing it (LoadResult::new_scene).
    void start(const std::string& path, bool compile = true, rt::ModelStore* models = nullptr);
    // Stops the load under way; its result is never delivered.
    void cancel();
    // Takes over the load `other` has under way (a start-up file whose load began
    // before the window opened); `other` is then idle.
    void take_over(SceneLoader& other);
    // Called on the worker thread once a load's result is ready to poll() (to wake
    // a UI thread that sleeps until then); set before start().
    void set_on_finished(std::function<void()> f) { on_finished_ = std::move(f); }
    bool active() const;
    Progress progress() const;
    // The finished load, once; nothing while it runs (or after a cancel).
    std::optional<LoadResult> poll();
    // Blocks until the load under way finishes (headless start, tests).
    std::optional<LoadResult> wait();

private:
    struct Job;
    static void run(std::shared_ptr<Job> job);
    static void compile_and_scan(LoadResult& r);
    void reap(bool wait_all);

    std::shared_ptr<Job> job_;
    rt::Job<void> thread_;
    std::function<void()> on_finished_;
    std::vector<std::pair<std::shared_ptr<Job>, rt::Job<void>>> retired_;  // cancelled, still finishing a stage
};

}  // namespace rtview
