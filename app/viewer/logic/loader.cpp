// Background scene loading (see loader.h).
#include "loader.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <functional>
#include <utility>

#include "image_io.h"
#include "parallel.h"
#include "paths.h"
#include "scene.h"
#include "scene_edits.h"
#include "scene_text.h"
#include "status.h"

namespace rtview {

struct SceneLoader::Job {
    std::string path;
    bool compile = true;
    rt::ModelStore* models = nullptr;
    rt::ModelStore own_models;  // when no store is given
    std::atomic<bool> cancel{false};
    std::atomic<bool> finished{false};
    mutable std::mutex mutex;
    Progress progress;  // under mutex
    std::function<void()> on_finished;  // under mutex
    LoadResult result;  // written by the worker before `finished`
};

rt::Status read_scene_file(const std::string& path, std::string& out, const std::atomic<bool>& cancel,
                           const std::function<void(std::uint64_t, std::uint64_t)>& report) {
    rt::ReadControl control;
    control.cancel = &cancel;
    control.progress = report;
    control.strict = true;
    control.spare_share = 1.0 / 32;  // the document edits the text in place
    return rt::read_file(path, out, rt::Limits::max_file_size, &control);
}

namespace {

// A model opened on its own: a new scene showing it (scene_edits.h), the model read
// through the store (where the scene's parse finds it again). The scene names the
// file by its absolute path: it has no folder of its own until it is saved.
rt::Status model_scene_text(const std::string& path, rt::ModelStore& models, std::string& text) {
    std::error_code ec;
    const std::string absolute = std::filesystem::absolute(path, ec).lexically_normal().string();
    if (ec) return rt::Status::error(ec.message(), rt::kExitUsage);
    const rt::ModelStore::Loaded l = models.load(absolute);
    if (!l.model)
        return rt::Status::error((l.error.line > 0 ? "line " + std::to_string(l.error.line) + ": " : "") + l.error.message,
                                 rt::kExitUsage);
    text = model_scene(absolute, *l.model);
    return {};
}

}  // namespace

bool apply_load(LoadResult& r, Document& doc, std::shared_ptr<const rt::World>& world) {
    if (r.status != LoadResult::Status::Ok) return false;
    const std::string name = base_name(r.path);
    world = std::move(r.world);
    if (r.new_scene) {
        // A scene of its own, unsaved: Save asks where (the name offered beside the model).
        const std::size_t dot = name.find_last_of('.');
        doc.load_parsed(std::move(r.text), std::move(r.parsed), "", name.substr(0, dot) + ".txt", std::move(r.layout),
                        r.text_hash);
        return true;
    }
    doc.load_parsed(std::move(r.text), std::move(r.parsed), r.path, name, std::move(r.layout), r.text_hash);
    return true;
}

void SceneLoader::compile_and_scan(LoadResult& r) {
    // The scan and the text's hash beside the compile (they read the text only), on
    // the process pool.
    rt::two_ways(true, [&r](int part) {
        const auto t0 = std::chrono::steady_clock::now();
        if (part == 0) {
            r.world = rt::compile_world(r.parsed.scene, nullptr);
        } else {
            r.layout = scan_layout(r.text, r.parsed.scene.objects.size());
            r.text_hash = rtview::text_hash(r.text);
        }
        (part == 0 ? r.times.compile : r.times.scan) =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    });
}

SceneLoader::~SceneLoader() {
    cancel();
    reap(true);
}

namespace {

// Reading and parsing make way for the window's UI thread, as the pool's workers do
// (rt::set_process_worker_nice): the window and the load's progress show at once.
void lower_this_thread() {
    errno = 0;
    const pid_t self = pid_t(syscall(SYS_gettid));
    const int nice = getpriority(PRIO_PROCESS, self);
    if (errno == 0) setpriority(PRIO_PROCESS, self, std::min(19, nice + 10));
}

}  // namespace

void SceneLoader::run(std::shared_ptr<Job> job) {
    auto stage = [&](Stage s) {
        std::lock_guard<std::mutex> lock(job->mutex);
        job->progress.stage = s;
    };
    LoadResult r;
    r.path = job->path;
    auto t = std::chrono::steady_clock::now();
    auto lap = [&t] {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - t).count();
        t = now;
        return s;
    };
    rt::ModelStore& models = job->models ? *job->models : job->own_models;
    stage(Stage::Reading);
    r.new_scene = rt::is_model_file(job->path);
    const rt::Status read = r.new_scene ? model_scene_text(job->path, models, r.text) : read_scene_file(job->path, r.text, job->cancel, [&](std::uint64_t b, std::uint64_t t) {
        std::lock_guard<std::mutex> lock(job->mutex);
        job->progress.bytes = b;
        job->progress.total = t;
    });
    r.times.read = lap();
    // A file that is no text at all (a binary opened by mistake) is refused: the
    // scene and the editor keep what they have.
    std::string not_text = read && !r.new_scene && !job->cancel ? not_scene_text(r.text) : std::string();
    if (job->cancel) {
        r.status = LoadResult::Status::Cancelled;
    } else if (!read) {
        r.status = LoadResult::Status::Failed;
        r.error = read.message();
    } else if (!not_text.empty()) {
        r.status = LoadResult::Status::Failed;
        r.error = std::move(not_text);
        r.text = std::string();
    } else {
        {
            std::lock_guard<std::mutex> lock(job->mutex);
            job->progress.stage = Stage::Parsing;
            job->progress.bytes = 0;
            job->progress.total = r.text.size();
        }
        // Bytes parsed so far for the status bar; Esc stops the parse within a MB.
        rt::ParseOptions popts;
        popts.base_dir = r.new_scene ? std::string() : rt::folder_of(job->path);
        popts.models = &models;
        popts.progress = [&](std::size_t bytes, std::size_t objects) {
            std::lock_guard<std::mutex> lock(job->mutex);
            job->progress.bytes = bytes;
            job->progress.objects = objects;
            return !job->cancel;
        };
        r.parsed = rt::parse_scene(r.text, popts);
        r.times.parse = lap();
        if (job->cancel) {
            r.status = LoadResult::Status::Cancelled;
        } else {
            {
                std::lock_guard<std::mutex> lock(job->mutex);
                job->progress.objects = r.parsed.scene.objects.size();
            }
            if (job->compile && r.parsed.ok()) {
                stage(Stage::Building);
                compile_and_scan(r);
                r.times.build = lap();
            }
            r.status = job->cancel ? LoadResult::Status::Cancelled : LoadResult::Status::Ok;
        }
    }
    if (r.status == LoadResult::Status::Cancelled) r = LoadResult{LoadResult::Status::Cancelled, r.path, false, {}, {}, {}, {}, {}, {}, {}};
    job->result = std::move(r);
    std::function<void()> notify;
    {
        std::lock_guard<std::mutex> lock(job->mutex);
        job->progress.stage = Stage::Done;
        notify = job->on_finished;
    }
    job->finished = true;
    if (notify && !job->cancel) notify();
}

void SceneLoader::start(const std::string& path, bool compile, rt::ModelStore* models) {
    cancel();
    job_ = std::make_shared<Job>();
    job_->path = path;
    job_->compile = compile;
    job_->models = models;
    job_->progress.path = path;
    job_->progress.stage = Stage::Reading;
    job_->on_finished = on_finished_;
    thread_ = std::thread([job = job_] {
        lower_this_thread();
        run(job);
    });
}

void SceneLoader::take_over(SceneLoader& other) {
    cancel();
    job_ = std::move(other.job_);
    thread_ = std::move(other.thread_);
    other.job_ = nullptr;
    if (job_) {
        // A load that finished before this wakes nobody: it is polled for anyway.
        std::lock_guard<std::mutex> lock(job_->mutex);
        job_->on_finished = on_finished_;
    }
    for (auto& r : other.retired_) retired_.push_back(std::move(r));
    other.retired_.clear();
}

void SceneLoader::cancel() {
    if (!job_) return;
    job_->cancel = true;
    // The worker stops at its next check (a parse in progress runs to its end): it is
    // joined later, so cancelling never waits.
    retired_.emplace_back(std::move(job_), std::move(thread_));
    job_ = nullptr;
    reap(false);
}

void SceneLoader::reap(bool wait_all) {
    for (auto it = retired_.begin(); it != retired_.end();) {
        if (wait_all || it->first->finished) {
            it->second.join();
            it = retired_.erase(it);
        } else {
            ++it;
        }
    }
}

bool SceneLoader::active() const { return job_ != nullptr; }

SceneLoader::Progress SceneLoader::progress() const {
    if (!job_) return {};
    std::lock_guard<std::mutex> lock(job_->mutex);
    return job_->progress;
}

std::optional<LoadResult> SceneLoader::poll() {
    reap(false);
    if (!job_ || !job_->finished) return std::nullopt;
    thread_.join();
    LoadResult r = std::move(job_->result);
    job_ = nullptr;
    return r;
}

std::optional<LoadResult> SceneLoader::wait() {
    if (!job_) return std::nullopt;
    thread_.join();
    LoadResult r = std::move(job_->result);
    job_ = nullptr;
    return r;
}

}  // namespace rtview
