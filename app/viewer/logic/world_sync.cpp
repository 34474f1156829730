// The world that follows the document (see world_sync.h).
#include "world_sync.h"

#include <chrono>
#include <utility>

namespace rtview {

namespace {

bool ready(const std::future<std::shared_ptr<const rt::World>>& f) {
    return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

}  // namespace

WorldSync::~WorldSync() {
    if (build_.valid()) build_.wait();
    for (auto& f : dropped_) f.wait();
}

void WorldSync::reap() {
    for (auto it = dropped_.begin(); it != dropped_.end();) {
        if (ready(*it)) it = dropped_.erase(it);
        else ++it;
    }
}

bool WorldSync::take_build() {
    if (!build_.valid() || !ready(build_)) return false;
    world_ = build_.get();
    version_ = build_version_;
    return true;
}

WorldSync::Step WorldSync::sync(const Document& doc) {
    reap();
    Step step = take_build() ? Step::Built : Step::None;
    if (!doc.has_scene() || (world_ && doc.content_version() == version_)) return step;
    if (world_) {
        const rt::SceneDelta delta = doc.changes_since(version_);
        if (!delta.everything && delta.objects.size() + delta.planes.size() + delta.lights.size() <= kMaxDeltaItems) {
            if (std::shared_ptr<const rt::World> w = world_->update(doc.scene(), delta)) {
                world_ = std::move(w);
                version_ = doc.content_version();
                return Step::Updated;
            }
        }
    }
    // One build at a time: what changes meanwhile goes into its world once it is there.
    if (build_.valid()) return step;
    build_version_ = doc.content_version();
    build_ = std::async(std::launch::async, [scene = doc.scene()] { return rt::compile_world(scene, nullptr); });
    return Step::Building;
}

void WorldSync::adopt(std::shared_ptr<const rt::World> world, std::uint64_t version) {
    if (build_.valid()) dropped_.push_back(std::move(build_));
    build_ = {};
    world_ = std::move(world);
    version_ = version;
}

WorldSync::Step WorldSync::finish(const Document& doc) {
    Step step = sync(doc);
    while (build_.valid()) {
        build_.wait();
        step = sync(doc);
    }
    return step;
}

}  // namespace rtview
