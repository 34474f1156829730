// Schedule: the pass list and the stop rule copy rt::Renderer's (without coarse
// passes), so a run with the same settings sums the same samples in the same groups.
#include "schedule.h"

#include <algorithm>

#include "cli.h"

namespace rtmpi {

Schedule::Schedule(const ScheduleSettings& settings) : settings_(settings) {
    settings_.max_samples = std::max(1, settings_.max_samples);
    tiles_ = make_tiles(settings_.width, settings_.height, settings_.tile_side);
    int s = 0;
    while (s < settings_.max_samples) {
        int n = settings_.samples_per_pass > 0 ? settings_.samples_per_pass : std::clamp(s, 1, 16);
        n = std::min(n, settings_.max_samples - s);
        passes_.push_back({s, s + n});
        s += n;
    }
    film_.reset(settings_.width, settings_.height);
    begin_pass();
}

void Schedule::begin_pass() {
    state_.assign(tiles_.size(), State::Free);
    next_ = 0;
    tiles_done_ = 0;
}

bool Schedule::take(Assignment& a) {
    if (done_ || next_ >= tiles_.size()) return false;
    a.tile = int(next_);
    a.s0 = passes_[pass_].s0;
    a.s1 = passes_[pass_].s1;
    state_[next_++] = State::Out;
    return true;
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
    if (a.s0 != passes_[pass_].s0 || a.s1 != passes_[pass_].s1)
        return refused("tile " + std::to_string(a.tile) + " has samples " + std::to_string(a.s0) + ".." +
                       std::to_string(a.s1) + ", not those of the current pass");
    State& st = state_[std::size_t(a.tile)];
    if (st != State::Out)
        return refused("tile " + std::to_string(a.tile) + (st == State::Done ? " arrived twice" : " was never handed out"));
    st = State::Done;
    const Tile& t = tiles_[std::size_t(a.tile)];
    for (int y = t.y0; y < t.y1; ++y) {
        const std::size_t idx = std::size_t(y) * film_.width + t.x0;
        const int n = t.x1 - t.x0;
        std::copy(sums, sums + 3 * n, &film_.sum[3 * idx]);
        sums += 3 * n;
        std::fill_n(&film_.count[idx], n, std::uint32_t(a.s1));
    }
    rays_ += rays;
    if (std::size_t(++tiles_done_) < tiles_.size()) return {};

    // The pass is complete: the next one, or the end (as rt::Renderer::commit decides).
    samples_done_ = passes_[pass_].s1;
    const bool out_of_time = settings_.time_limit > 0 && elapsed >= settings_.time_limit;
    if (++pass_ >= passes_.size() || out_of_time) {
        done_ = true;
        return {};
    }
    begin_pass();
    return {};
}

bool Schedule::complete() const {
    if (!done_ || samples_done_ < 1) return false;
    return std::all_of(film_.count.begin(), film_.count.end(),
                       [&](std::uint32_t c) { return c == std::uint32_t(samples_done_); });
}

double Schedule::fraction() const {
    if (done_) return 1.0;
    const double pass = tiles_.empty() ? 1.0 : double(tiles_done_) / double(tiles_.size());
    const int max = settings_.max_samples;
    return (samples_done_ + pass * (max - samples_done_)) / max;
}

}  // namespace rtmpi
