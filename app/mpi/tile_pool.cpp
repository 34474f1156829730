// TilePool: one tile at a time through rt::Renderer, cut into tiles of its own small
// enough for every thread to take part in a tile.
#include "tile_pool.h"

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace rtmpi {

namespace {
// The renderer's tiles within a rank's tile: a 32x32 tile splits into 16, for the
// threads to balance.
constexpr int kInnerTile = 8;
}  // namespace

std::vector<Tile> make_tiles(int width, int height, int side) {
    return rt::tile_grid(width, height, {0, 0, width, height}, side, rt::TileOrder::CentreOut);
}

TilePool::TilePool(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height,
                   bool mirror, int max_samples, rt::ThreadPool& pool)
    : world_(std::move(world)),
      camera_(camera),
      width_(width),
      height_(height),
      mirror_(mirror),
      max_samples_(max_samples),
      renderer_(pool) {}

TilePool::~TilePool() { renderer_.cancel(); }

void TilePool::submit(int id, const Tile& tile, int s0, int s1, float* sums) {
    Job job;
    job.s0 = s0;
    job.s1 = s1;
    queue(job, id, tile, sums);
}

void TilePool::submit_refine(int id, const Tile& tile, const std::uint32_t* n0, const std::uint32_t* n1, float* sums,
                             float* squares) {
    Job job;
    job.n0 = n0;
    job.n1 = n1;
    job.squares = squares;
    queue(job, id, tile, sums);
}

void TilePool::queue(Job job, int id, const Tile& tile, float* sums) {
    job.id = id;
    job.tile = tile;
    job.sums = sums;
    jobs_.push_back(job);
    ++outstanding_;
    advance();
}

void TilePool::start_front() {
    const Job& job = jobs_.front();
    rt::RenderSettings st;
    st.width = width_;
    st.height = height_;
    st.camera = camera_;
    st.mirror = mirror_;
    st.coarse = false;
    st.crop = job.tile;
    st.tile_size = kInnerTile;
    const std::size_t px = std::size_t(job.tile.pixels());
    if (job.n0) {
        // A refine round: the pixels marked are those that go on.
        std::vector<std::uint8_t> marked(px);
        for (std::size_t i = 0; i < px; ++i) marked[i] = job.n1[i] != job.n0[i];
        renderer_.load_window(width_, height_, job.tile, job.sums, job.n0, job.squares, marked.data());
        st.refine_marked = true;
        st.max_samples = max_samples_;
    } else {
        if (job.s0 > 0) {
            const std::vector<std::uint32_t> counts(px, std::uint32_t(job.s0));
            renderer_.load_window(width_, height_, job.tile, job.sums, counts.data());
        }
        st.first_sample = job.s0;
        st.max_samples = job.s1;
        st.samples_per_pass = job.s1 - job.s0;  // one pass
    }
    renderer_.start(world_, st);
    running_ = true;
}

void TilePool::advance() {
    if (running_) {
        const rt::RenderProgress p = renderer_.progress();
        if (!p.done) return;
        if (!p.error.empty()) throw std::runtime_error(p.error);
        const Job& job = jobs_.front();
        renderer_.read_window(job.tile, job.sums, job.squares);
        finished_.push_back({job.id, p.rays});
        jobs_.pop_front();
        running_ = false;
    }
    if (!jobs_.empty()) start_front();
}

std::vector<TilePool::Finished> TilePool::take_finished() {
    advance();
    std::vector<Finished> out;
    out.swap(finished_);
    outstanding_ -= int(out.size());
    return out;
}

void TilePool::wait_finished(std::chrono::microseconds timeout) {
    if (!finished_.empty()) return;
    if (!running_) {
        std::this_thread::sleep_for(timeout);  // nothing renders: the caller waits for messages
        return;
    }
    renderer_.wait_for(std::chrono::duration<double>(timeout).count());
    advance();
}

}  // namespace rtmpi
