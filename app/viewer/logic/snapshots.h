// Snapshots of the picture to compare with later: a few linear films kept under a
// memory cap (oldest dropped first), what changed in the scene between two of them,
// and the difference image of two pictures with a scale.
#pragma once

#include <cstdint>
#include <ctime>
#include <string>
#include <vector>

#include "film.h"
#include "scene.h"

namespace rtview {

// Memory an object takes, with its CSG operands (for the stores' limits: snapshots
// here, the undo history in document.cpp).
std::size_t object_bytes(const rt::Object& o);

struct Snapshot {
    int id = 0;             // 1, 2, ... in the order taken; never reused
    rt::Image image;        // the linear film, so exposure and differences apply to it as to the live one
    int samples = 0;        // samples per pixel it had
    std::time_t time = 0;   // when it was taken
    rt::Scene scene;        // the scene it shows (for "what changed")
    std::string change;     // what changed since the snapshot before it ("" for the first)
    std::size_t bytes() const;
};

class SnapshotStore {
public:
    static constexpr std::size_t kDefaultBytes = std::size_t(512) << 20;
    static constexpr std::size_t kDefaultCount = 8;
    explicit SnapshotStore(std::size_t max_bytes = kDefaultBytes, std::size_t max_count = kDefaultCount)
        : max_bytes_(max_bytes), max_count_(max_count) {}

    // Keeps a snapshot, dropping the oldest ones until the store fits its caps. Null
    // (and nothing dropped) if this one alone is over the memory cap.
    const Snapshot* add(rt::Image image, int samples, const rt::Scene& scene, std::time_t time);
    const std::vector<Snapshot>& list() const { return items_; }  // oldest first
    const Snapshot* find(int id) const;
    bool remove(int id);
    void clear() { items_.clear(); }
    std::size_t bytes() const;
    std::size_t max_bytes() const { return max_bytes_; }

private:
    std::vector<Snapshot> items_;
    std::size_t max_bytes_, max_count_;
    int next_id_ = 1;
};

// "camera; material of object 3; light 2" for the list of snapshots: what differs
// between two scenes, in the outline's numbering, at most `max_items` items.
std::string describe_change(const rt::Scene& before, const rt::Scene& after, int max_items = 3);

struct DiffStats {
    double max_abs = 0;          // largest channel difference (linear)
    double mean_abs = 0;         // over all channels
    std::size_t differing = 0;   // pixels with any channel different
};

// |a - b| * scale per channel as RGBA8 with the renderer's rounding (so scale 1 shows
// a difference of 1 as white). False, and nothing written, if the sizes differ.
bool difference_rgba8(const rt::Image& a, const rt::Image& b, double scale, std::vector<std::uint8_t>& rgba,
                      DiffStats* stats = nullptr);

// A pixel of `img` with another picture's size (nearest), so that a snapshot taken at
// another window size can still be compared side by side.
rt::Image resample_nearest(const rt::Image& img, int width, int height);

}  // namespace rtview
