// The world that follows the document (see world_sync.h).
#include "world_sync.h"

#include <chrono>
#include <tuple>
#include <utility>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "shapes.h"

namespace rtview {

namespace {

template <class T>
void reap_ready(std::vector<rt::Job<T>>& v) {
    for (auto it = v.begin(); it != v.end();) {
        if (it->ready()) it = v.erase(it);
        else ++it;
    }
}

}  // namespace

WorldSync::~WorldSync() {
    if (build_.valid()) build_.wait();
    if (links_build_.valid()) links_build_.wait();
    for (auto& f : dropped_) f.wait();
    for (auto& f : dropped_links_) f.wait();
}

void WorldSync::reap() {
    reap_ready(dropped_);
    reap_ready(dropped_links_);
}

void WorldSync::return_memory() {
    if (!return_pending_ || !replaced_.expired()) return;
    return_pending_ = false;
#ifdef __GLIBC__
    // A scene's tables are many blocks below the allocator's mmap threshold: freed,
    // they stay in its heaps, and a scene opened again would come on top of them.
    malloc_trim(0);
#endif
}

void WorldSync::drop_links() {
    // What was made or is being made for another tree is let go of (it must not keep
    // a replaced scene's geometry alive).
    if (links_build_.valid()) dropped_links_.push_back(std::move(links_build_));
    links_ = nullptr;
    links_geometry_ = nullptr;
    links_waiting_ = false;
}

void WorldSync::start_links() {
    if (links_waiting_) prepare_links();
}

void WorldSync::prepare_links() {
    drop_links();
    if (!world_ || !world_->geometry || world_->geometry->bvh.links || world_->geometry->object_bounds.size() == 0)
        return;
    links_geometry_ = world_->geometry;
    links_build_ = rt::process_pool().aside([g = links_geometry_] {
        return std::make_shared<const rt::BvhLinks>(g->bvh, g->object_bounds.size());
    });
}

std::shared_ptr<const rt::BvhLinks> WorldSync::current_links() {
    if (links_build_.valid() && links_build_.ready()) links_ = links_build_.get();
    // A world updated from the one they were made for has its tree's own links then.
    return world_ && world_->geometry == links_geometry_ ? links_ : nullptr;
}

bool WorldSync::take_build(const Document& doc) {
    if (!build_.valid() || !build_.ready()) return false;
    std::shared_ptr<const rt::World> built = build_.get();
    const bool fold = folding_;
    folding_ = false;
    if (fold && world_ && build_version_ != version_) {
        // A fold's world takes at once what the world on screen took since the copy (or
        // is not taken: the world on screen stays, and folds again).
        const rt::SceneDelta d = doc.has_scene() ? doc.changes_since(build_version_) : rt::SceneDelta::all();
        if (d.everything || !(built = built->update(doc.scene(), d))) return false;
        build_version_ = doc.content_version();
    }
    world_ = std::move(built);
    version_ = build_version_;
    return true;
}

void WorldSync::start_build() {
    build_version_ = copy_->version;
    // (The copy is let go of on the compile's thread: freeing a million objects takes a while.)
    build_ = rt::process_pool().aside([scene = std::move(copy_->scene)]() mutable {
        const rt::Scene s = std::move(scene);
        return rt::compile_world(s, nullptr);
    });
    copy_.reset();
}

WorldSync::Step WorldSync::fold(const Document& doc, Step step) {
    if (!folding_ && (!world_ || world_->spliced() <= kMaxSpliced || build_.valid())) return step;
    if (build_.valid()) return step;
    folding_ = true;
    if (copy_on(doc)) start_build();
    return step;
}

WorldSync::Step WorldSync::sync(const Document& doc) {
    reap();
    return_memory();
    Step step = take_build(doc) ? Step::Built : Step::None;
    if (step == Step::Built) prepare_links();
    if (!doc.has_scene()) return step;
    if (world_ && doc.content_version() == version_) return fold(doc, step);
    if (world_) {
        const rt::SceneDelta delta = doc.changes_since(version_);
        if (!delta.everything && delta.object_splices.size() + delta.objects.size() + delta.planes.size() +
                                         delta.lights.size() <= kMaxDeltaItems) {
            if (std::shared_ptr<const rt::World> w = world_->update(doc.scene(), delta, current_links())) {
                world_ = std::move(w);
                version_ = doc.content_version();
                return fold(doc, Step::Updated);
            }
        }
    }
    // The world lags the document now: a build under way for a fold is the one it waits for.
    folding_ = false;
    // One build at a time: what changes meanwhile goes into its world once it is there.
    if (build_.valid()) return step;
    if (!copy_on(doc)) return Step::Building;
    start_build();
    return Step::Building;
}

bool WorldSync::copy_on(const Document& doc) {
    const rt::Scene& from = doc.scene();
    if (copy_ && copy_->version != doc.content_version()) {
        // The document changed while it was copied: its changed items again, or all of it.
        const rt::SceneDelta d = doc.changes_since(copy_->version);
        if (!d.in_place() || from.objects.size() != copy_->total) {
            copy_.reset();
        } else {
            for (std::uint32_t i : d.objects)
                if (i < copy_->objects) copy_->scene.objects[i] = from.objects[i];
            copy_->version = doc.content_version();
        }
    }
    if (!copy_) {
        // The objects by shares.
        copy_.emplace();
        copy_->scene.objects.reserve(from.objects.size());
        copy_->total = from.objects.size();
        copy_->version = doc.content_version();
    }
    // (All but the objects: copied whole each time, being few.)
    rt::Scene& s = copy_->scene;
    std::tie(s.files_read, s.materials, s.defined, s.includes, s.planes, s.lights, s.camera, s.width, s.height,
             s.camera_loc) = std::tie(from.files_read, from.materials, from.defined, from.includes, from.planes,
                                      from.lights, from.camera, from.width, from.height, from.camera_loc);
    // About copy_budget_ of copying a sync, checked every few thousand objects.
    constexpr std::size_t kShare = 4096;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                              std::chrono::duration<double>(copy_budget_));
    while (copy_->objects < from.objects.size()) {
        const std::size_t end = std::min(from.objects.size(), copy_->objects + kShare);
        s.objects.insert(s.objects.end(), from.objects.begin() + std::ptrdiff_t(copy_->objects),
                         from.objects.begin() + std::ptrdiff_t(end));
        copy_->objects = end;
        if (std::chrono::steady_clock::now() > until) break;
    }
    return copy_->objects == from.objects.size();
}

void WorldSync::adopt(std::shared_ptr<const rt::World> world, std::uint64_t version) {
    if (build_.valid()) dropped_.push_back(std::move(build_));
    build_ = {};
    copy_.reset();
    folding_ = false;
    if (world_ && world_ != world) {
        replaced_ = world_;
        return_pending_ = true;
    }
    world_ = std::move(world);
    version_ = version;
    drop_links();
    links_waiting_ = true;
}

WorldSync::Step WorldSync::finish(const Document& doc) {
    start_links();
    Step step = sync(doc);
    while (building()) {
        if (build_.valid()) build_.wait();
        step = sync(doc);
    }
    if (links_build_.valid()) links_build_.wait();
    current_links();
    return step;
}

}  // namespace rtview
