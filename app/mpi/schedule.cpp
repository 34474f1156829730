// Schedule: the pass list is rt::Renderer's (rt::sample_passes, without coarse passes)
// and the stop rule is its rule, so a run with the same settings sums the same samples
// in the same groups; an adaptive render decides between rounds with the renderer's own
// decide_rows(). The tiles themselves are rendered by rt::Renderer (tile_pool.h).
#include "schedule.h"

#include <algorithm>
#include <cmath>

#include "adaptive.h"
#include "cli.h"
#include "renderer.h"

namespace rtmpi {

Schedule::Schedule(const ScheduleSettings& settings) : settings_(settings) {
    settings_.max_samples = std::max(1, settings_.max_samples);
    tiles_ = make_tiles(settings_.width, settings_.height, settings_.tile_side);
    // Adaptive: the first sample; the decisions and refine rounds follow it.
    rt::RenderSettings plan;
    plan.samples_per_pass = settings_.samples_per_pass;
    plan.time_limit = settings_.time_limit;
    for (const auto& p : rt::sample_passes(plan, 0, adaptive() ? 1 : settings_.max_samples)) passes_.push_back({p[0], p[1]});
    film_.reset(settings_.width, settings_.height, false);
    if (adaptive()) {
        const std::size_t pixels = std::size_t(settings_.width) * std::size_t(settings_.height);
        film_.squares.reset(pixels);
        active_.assign(pixels, 0);
        changed_.assign(pixels, 0);
        refining_ = std::int64_t(pixels);
    }
    begin_pass();
}

void Schedule::begin_pass() {
    state_.assign(tiles_.size(), State::Free);
    next_ = 0;
    tiles_done_ = 0;
    if (round_ < 0) return;
    // A refine round: the tiles without a marked pixel are done already.
    for (std::size_t k = 0; k < tiles_.size(); ++k) {
        const Tile& t = tiles_[k];
        bool marked = false;
        for (int y = t.y0; y < t.y1 && !marked; ++y) {
            const std::uint8_t* row = &active_[std::size_t(y) * film_.width];
            marked = std::any_of(row + t.x0, row + t.x1, [](std::uint8_t m) { return m != 0; });
        }
        if (!marked) state_[k] = State::Done, ++tiles_done_;
    }
}

bool Schedule::take(Assignment& a, double elapsed) {
    if (!done_ && samples_done_ >= 1 && out_of_time(elapsed)) {
        stopping_ = true;
        if (out_ == 0) done_ = true;
        return false;
    }
    while (next_ < tiles_.size() && state_[next_] != State::Free) ++next_;
    if (done_ || next_ >= tiles_.size()) return false;
    a.tile = int(next_);
    a.refine = round_;
    a.s0 = round_ < 0 ? passes_[pass_].s0 : 0;
    a.s1 = round_ < 0 ? passes_[pass_].s1 : 0;
    state_[next_++] = State::Out;
    ++out_;
    return true;
}

void Schedule::refine_input(const Assignment& a, float* sums, float* squares, std::uint32_t* n0,
                            std::uint32_t* n1) const {
    const Tile& t = tiles_[std::size_t(a.tile)];
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) {
            const std::size_t idx = std::size_t(y) * film_.width + x;
            sums = std::copy_n(&film_.sum[3 * idx], 3, sums);
            *squares++ = film_.squares[idx];
            *n0 = film_.count[idx];
            *n1++ = active_[idx] ? rt::refine_count(*n0, std::uint32_t(settings_.max_samples)) : *n0;
            ++n0;
        }
}

void Schedule::commit_refine(const Tile& t, const float* sums) {
    const float* squares = sums + 3 * std::size_t(t.pixels());
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x, sums += 3, ++squares) {
            const std::size_t idx = std::size_t(y) * film_.width + x;
            if (!active_[idx]) continue;
            std::copy_n(sums, 3, &film_.sum[3 * idx]);
            film_.squares[idx] = *squares;
            film_.count[idx] = rt::refine_count(film_.count[idx], std::uint32_t(settings_.max_samples));
        }
}

// After the first sample and after every refine round: marks the pixels to refine
// next, as rt::Renderer's decision passes do (the same function over the same film).
// False if none is.
bool Schedule::decide() {
    if (round_ >= 0) active_.swap(changed_);  // what the round just refined
    refining_ = std::int64_t(rt::decide_rows(film_, settings_.aa_threshold, settings_.max_samples,
                                             round_ >= 0 ? changed_.data() : nullptr, 0, film_.height,
                                             active_.data()));
    return refining_ > 0;
}

std::uint64_t Schedule::film_samples() const {
    std::uint64_t n = 0;
    for (std::uint32_t c : film_.count) n += c;
    return n;
}

void Schedule::prior_sums(const Assignment& a, float* out) const {
    const Tile& t = tiles_[std::size_t(a.tile)];
    for (int y = t.y0; y < t.y1; ++y) {
        const float* row = &film_.sum[3 * (std::size_t(y) * film_.width + t.x0)];
        out = std::copy(row, row + 3 * (t.x1 - t.x0), out);
    }
}

rt::Status Schedule::commit(const Assignment& a, const float* sums, std::uint64_t rays, double elapsed) {
    auto refused = [](const std::string& why) { return rt::Status::error(why, kExitMpi); };
    if (done_) return refused("a tile arrived after the render was complete");
    if (a.tile < 0 || std::size_t(a.tile) >= tiles_.size())
        return refused("tile " + std::to_string(a.tile) + " does not exist");
    if (a.refine != round_ || (round_ < 0 && (a.s0 != passes_[pass_].s0 || a.s1 != passes_[pass_].s1)))
        return refused("tile " + std::to_string(a.tile) + " has samples " + std::to_string(a.s0) + ".." +
                       std::to_string(a.s1) + " (refine round " + std::to_string(a.refine) +
                       "), not those of the current pass");
    State& st = state_[std::size_t(a.tile)];
    if (st != State::Out)
        return refused("tile " + std::to_string(a.tile) + (st == State::Done ? " arrived twice" : " was never handed out"));
    st = State::Done;
    --out_;
    const Tile& t = tiles_[std::size_t(a.tile)];
    if (a.refine >= 0) commit_refine(t, sums);
    for (int y = t.y0; y < t.y1 && a.refine < 0; ++y) {
        const std::size_t idx = std::size_t(y) * film_.width + t.x0;
        const int n = t.x1 - t.x0;
        std::copy(sums, sums + 3 * n, &film_.sum[3 * idx]);
        sums += 3 * n;
        std::fill_n(&film_.count[idx], n, std::uint32_t(a.s1));
    }
    rays_ += rays;
    if (std::size_t(++tiles_done_) < tiles_.size()) {
        if (stopping_ && out_ == 0) done_ = true;  // the last tile out is back
        return {};
    }

    // The pass is complete: the next one, or the end (as rt::Renderer::commit decides).
    if (round_ < 0) samples_done_ = passes_[pass_].s1;
    if (stopping_ || out_of_time(elapsed) || (!adaptive() && ++pass_ >= passes_.size()) ||
        (adaptive() && !decide())) {
        done_ = true;
        return {};
    }
    if (adaptive()) ++round_;
    begin_pass();
    return {};
}

bool Schedule::complete() const {
    if (!done_ || samples_done_ < 1) return false;
    // Stopped in the middle of a pass, its tiles out before the stop hold its samples.
    const std::uint32_t partial = stopping_ && !adaptive() ? std::uint32_t(passes_[pass_].s1) : 0;
    return std::all_of(film_.count.begin(), film_.count.end(), [&](std::uint32_t c) {
        return adaptive() ? c >= 1 : c == std::uint32_t(samples_done_) || c == partial;
    });
}

double Schedule::fraction() const {
    if (done_) return 1.0;
    const double pass = tiles_.empty() ? 1.0 : double(tiles_done_) / double(tiles_.size());
    if (adaptive()) return round_ < 0 ? 0.5 * pass : 1 - 0.5 * std::pow(0.5, round_) * (1 - 0.5 * pass);
    const int max = settings_.max_samples;
    return (samples_done_ + pass * (max - samples_done_)) / max;
}

}  // namespace rtmpi
