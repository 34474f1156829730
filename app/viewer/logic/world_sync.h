// The compiled world that follows the document, and the policy of how: what changed
// since the world's version (Document::changes_since) goes into it at once when the
// world can take it in place (World::update: a move refits the BVH, a material or a
// light rewrites its entry, an object inserted or removed takes a leaf or leaves one);
// when the lists changed, an object's structure changed or too much changed, the
// scene is compiled anew on another thread while the last world stays on screen, and
// what changed meanwhile goes into the new world as soon as it is there. Objects
// inserted and removed go in at once too (World::update), until so many did that the
// scene is compiled anew behind the world on screen. A new tree's
// parent links (what a refit walks: 41 ms for a million objects) are made on another
// thread too, before the first move needs them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "bvh_update.h"
#include "document.h"
#include "parallel.h"
#include "world.h"

namespace rtview {

// Whether `seen` was taken from `world`: what views of a world (the preview, the
// outline) compare with, without keeping a replaced scene's world alive. Still right
// once `seen` has expired (it keeps its control block: a new world made at the old
// one's address is another world).
inline bool same_world(const std::weak_ptr<const rt::World>& seen, const std::shared_ptr<const rt::World>& world) {
    return !seen.owner_before(world) && !world.owner_before(seen);
}

class WorldSync {
public:
    // What a sync() did.
    enum class Step {
        None,      // the world is the document's already (or cannot be yet)
        Updated,   // the changes went into the world in place
        Building,  // a full compile started in the background
        Built,     // a background compile finished and is the world now
    };
    // More changed items than this at once (a text applied with thousands of changed
    // numbers) are compiled anew rather than updated one by one.
    static constexpr std::size_t kMaxDeltaItems = std::size_t(1) << 16;
    // A world that took more inserted and removed objects than this since its compile
    // (rt::World::spliced: each insert hangs a leaf where it fits, not where a build
    // would put it) is compiled anew in the background while it stays on screen.
    static constexpr std::size_t kMaxSpliced = 1024;

    WorldSync() = default;
    ~WorldSync();
    WorldSync(const WorldSync&) = delete;
    WorldSync& operator=(const WorldSync&) = delete;

    // Brings the world as close to the document's scene as it can now (without
    // waiting). O(1) when nothing changed. A document without a scene leaves it alone.
    Step sync(const Document& doc);
    // A world compiled elsewhere (a scene loaded in the background) for the document's
    // content version `version`; a build under way is dropped (not waited for). Once
    // the world it replaces is gone (the renderer and the views let go of it), the
    // memory the allocator kept of it is given back to the system. Its tree's links
    // wait for start_links(): a loaded scene's first picture should not share the
    // processors with them.
    void adopt(std::shared_ptr<const rt::World> world, std::uint64_t version);
    // Starts making the links an adopted world's tree waits for (nothing otherwise).
    void start_links();
    // Starts the links an adopted world waits for, blocks until a build under way and
    // the links are done, then syncs (headless runs, tests).
    Step finish(const Document& doc);

    // The time a sync() may spend copying the scene for a compile (about 10 ms; 0: one
    // share of 4,096 objects a sync, for tests).
    void set_copy_budget(double seconds) { copy_budget_ = seconds; }

    const std::shared_ptr<const rt::World>& world() const { return world_; }
    // The content version of the document the world is compiled from.
    std::uint64_t version() const { return version_; }
    // A compile is under way: its scene being copied (a share per sync()) or its world
    // being built.
    // (Not a compile that only folds the inserted and removed objects into a new tree:
    // the world is the document's meanwhile.)
    bool building() const { return !folding_ && (build_.valid() || copy_.has_value()); }
    // The scene is being copied for a compile (the first part of building()).
    bool copying() const { return !folding_ && copy_.has_value(); }
    // A compile of the document's scene under way for a world that is the document's
    // already but far from its compile (kMaxSpliced).
    bool folding() const { return folding_; }
    // The parent links made in the background for the tree of the world last built or
    // adopted; null until they are there.
    const std::shared_ptr<const rt::BvhLinks>& links() const { return links_; }

private:
    // Takes a finished build; true if it did.
    bool take_build(const Document& doc);
    // Starts the compile of the copy made.
    void start_build();
    // Starts or goes on with the compile of a world far from its compile; returns step.
    Step fold(const Document& doc, Step step);
    void reap();
    // Gives freed memory back once the world adopt() replaced is gone.
    void return_memory();
    // Starts making the links of the world's tree unless it has them.
    void prepare_links();
    // Lets go of the links made or being made.
    void drop_links();
    // Takes the links once made; the links that go with the world's tree, or null.
    std::shared_ptr<const rt::BvhLinks> current_links();

    // The scene a compile is to start from, copied from the document's a share per
    // sync() so that no frame spends long on it (a million objects take most of a
    // second): items changed meanwhile are copied again, a change of the lists starts
    // it over.
    struct Copy {
        Copy() {}  // (declared: std::optional of a nested struct with member initializers, for clang)
        rt::Scene scene;
        std::size_t objects = 0;  // copied so far, of `total`
        std::size_t total = 0;
        std::uint64_t version = 0;
    };
    // Copies on while it takes less than the budget; true once the copy is complete.
    bool copy_on(const Document& doc);
    std::optional<Copy> copy_;
    double copy_budget_ = 0.010;

    std::shared_ptr<const rt::World> world_;
    std::uint64_t version_ = 0;
    rt::Job<std::shared_ptr<const rt::World>> build_;
    std::uint64_t build_version_ = 0;
    bool folding_ = false;  // the build (or copy) under way is a fold (folding())
    std::vector<rt::Job<std::shared_ptr<const rt::World>>> dropped_;  // still finishing
    std::weak_ptr<const rt::World> replaced_;  // by adopt(), until it is gone
    bool return_pending_ = false;
    // The links of links_geometry_'s tree: made (links_) or being made (links_build_).
    std::shared_ptr<const rt::Geometry> links_geometry_;
    std::shared_ptr<const rt::BvhLinks> links_;
    rt::Job<std::shared_ptr<const rt::BvhLinks>> links_build_;
    bool links_waiting_ = false;  // for start_links()
    std::vector<rt::Job<std::shared_ptr<const rt::BvhLinks>>> dropped_links_;
};

}  // namespace rtview
