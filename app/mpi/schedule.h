// Rank 0's book of the render: which tile of which pass is free, out or done, the
// film the finished tiles go into, and the completion check before anything is written.
// No MPI and no locking here; the coordinator guards it with its own mutex.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "film.h"
#include "status.h"
#include "tile_pool.h"

namespace rtmpi {

// One unit of work: samples [s0, s1) of every pixel of tiles()[tile]; or, in round
// `refine` >= 0 of an adaptive render, more samples for the tile's pixels that the
// decision before the round marked (see refine_input).
struct Assignment {
    int tile = -1;
    int s0 = 0, s1 = 0;
    int refine = -1;
};

struct ScheduleSettings {
    int width = 0, height = 0;
    int tile_side = 32;
    int max_samples = 1;
    int samples_per_pass = 0;  // 0: 1, 1, 2, 4, 8, 16, 16, ... (rt::sample_passes)
    double time_limit = 0;     // seconds: past it (every pixel sampled once) no more tiles are handed out
    double aa_threshold = -1;  // >= 0: adaptive anti-aliasing, as rt::RenderSettings
};

class Schedule {
public:
    explicit Schedule(const ScheduleSettings& settings);

    const std::vector<Tile>& tiles() const { return tiles_; }
    int tile_side() const { return settings_.tile_side; }
    int width() const { return film_.width; }
    int height() const { return film_.height; }

    // The next free tile of the current pass; false if none is free right now (all out,
    // or the render is done). A pass starts only when the previous one is complete,
    // because its pixels continue the previous pass's sums. `elapsed`: seconds since the
    // render began; past the time limit, once every pixel has its first sample, no tile
    // is handed out any more and the render ends when the tiles out come back (as
    // rt::Renderer stops in the middle of a pass: pixels then hold one pass more or less).
    bool take(Assignment& a, double elapsed);
    // The sums of samples [0, a.s0) of the tile's pixels, which the renderer of `a`
    // continues (3 floats per pixel, row by row).
    void prior_sums(const Assignment& a, float* out) const;
    // For a refine assignment, per pixel of the tile (row by row): its sums (3) and
    // sum of squares so far, and the sample counts it has (n0) and goes to (n1; the
    // same for a pixel not marked), as rt::refine_rect takes them.
    void refine_input(const Assignment& a, float* sums, float* squares, std::uint32_t* n0, std::uint32_t* n1) const;
    // Stores a finished tile (for a refine assignment, sums then squares); a tile that
    // is not out in the current pass (never handed out, or returned twice) is refused,
    // saying why (kExitMpi).
    rt::Status commit(const Assignment& a, const float* sums, std::uint64_t rays, double elapsed);

    bool done() const { return done_; }
    // True when every pixel holds the samples of the passes done (stopped by the time
    // limit in the middle of a pass: or of that pass too; adaptive: at least one):
    // checked before the picture is written, so a lost tile can never leave a hole in a
    // written image.
    bool complete() const;
    rt::Image image() const { return film_.resolve(); }

    std::uint64_t rays() const { return rays_; }
    int samples_done() const { return samples_done_; }
    bool adaptive() const { return settings_.aa_threshold >= 0; }
    // Adaptive: the pixels not settled (as rt::RenderProgress::refining), and the
    // samples of all pixels together.
    std::int64_t refining() const { return refining_; }
    std::uint64_t film_samples() const;
    int pass_index() const { return int(pass_); }
    int pass_count() const { return int(passes_.size()); }
    int pass_tiles_done() const { return tiles_done_; }
    // Fraction of the whole render done, as raytracer's progress bar computes it.
    double fraction() const;

private:
    struct Pass {
        int s0 = 0, s1 = 0;
    };
    enum class State : unsigned char { Free, Out, Done };
    void begin_pass();
    bool decide();
    void commit_refine(const Tile& t, const float* sums);

    ScheduleSettings settings_;
    std::vector<Tile> tiles_;
    std::vector<Pass> passes_;
    std::size_t pass_ = 0;
    std::vector<State> state_;  // per tile, for the current pass
    std::size_t next_ = 0;      // next free tile of the current pass
    int tiles_done_ = 0;
    int out_ = 0;               // tiles handed out and not back yet
    bool stopping_ = false;     // past the time limit: the tiles out are the last
    bool out_of_time(double elapsed) const { return settings_.time_limit > 0 && elapsed >= settings_.time_limit; }
    int samples_done_ = 0;
    bool done_ = false;
    std::uint64_t rays_ = 0;
    rt::Film film_;
    // Adaptive: per pixel, marked by the last decision and by the one before; the
    // round under way (-1: the first sample's pass).
    std::vector<std::uint8_t> active_, changed_;
    int round_ = -1;
    std::int64_t refining_ = 0;
};

}  // namespace rtmpi
