// raytracer-mpi's workers, ranks 1..N-1: they take the tiles rank 0 assigns, render
// them in their pool and send the sums back (see raytracer_mpi.cpp).
#pragma once

#include "messages.h"

namespace rtmpi {
namespace {


// A worker's tiles in flight: rendering, then being sent back (std::map: the
// buffers stay put while MPI and the pool use them).
struct WorkerState {
    struct Held {
        AssignHeader a;
        std::vector<float> buf;  // ResultHeader + sums (+ squares)
        std::vector<std::uint32_t> counts;  // a refine assignment's n0, then n1
        MPI_Request req = MPI_REQUEST_NULL;
        bool sending = false;
    };
    std::map<int, Held> held;
    int next_id = 0;
    bool stop = false;
    std::vector<float> in;  // the posted receive of the next assignment
    MPI_Request rreq = MPI_REQUEST_NULL;

    void post_receive() {
        check(MPI_Irecv(in.data(), bytes_of(in.size()), MPI_BYTE, 0, kTagAssign, MPI_COMM_WORLD, &rreq),
              "MPI_Irecv (assignment)");
    }
};

// Takes an assignment if one has arrived: into the pool's queue, or the stop. True
// if one did.
bool take_assignment(const std::vector<Tile>& tiles, TilePool& pool, WorkerState& w) {
    const std::size_t ah = head_floats<AssignHeader>(), rh = head_floats<ResultHeader>();
    int arrived = 0;
    MPI_Status st;
    check(MPI_Test(&w.rreq, &arrived, &st), "waiting for a tile from rank 0");
    if (!arrived) return false;
    const int got = received_bytes(st);
    if (got < int(sizeof(AssignHeader))) fail(kExitMpi, "short message from rank 0");
    const auto a = get_header<AssignHeader>(w.in);
    if (a.tile == -1) {
        w.stop = true;  // rank 0 sends it only once this rank holds nothing
        return true;
    }
    if (a.tile < 0 || std::size_t(a.tile) >= tiles.size() || (a.refine < 0 && (a.s0 < 0 || a.s1 <= a.s0)))
        fail(kExitMpi, "rank 0 sent an invalid tile");
    const Tile& t = tiles[std::size_t(a.tile)];
    const std::size_t px = std::size_t(t.pixels()), n = result_floats(a.refine, px);
    if (got != bytes_of(ah + assign_floats(a, px))) fail(kExitMpi, "rank 0 sent a tile of the wrong size");
    WorkerState::Held& h = w.held[w.next_id];
    h.a = a;
    h.buf.assign(rh + n, 0.f);
    if (a.has_prior || a.refine >= 0) std::copy_n(w.in.data() + ah, n, h.buf.data() + rh);
    if (a.refine >= 0) {
        h.counts.resize(2 * px);
        std::memcpy(h.counts.data(), w.in.data() + ah + n, 2 * px * sizeof(std::uint32_t));
        pool.submit_refine(w.next_id++, t, h.counts.data(), h.counts.data() + px, h.buf.data() + rh,
                           h.buf.data() + rh + 3 * px);
    } else {
        pool.submit(w.next_id++, t, a.s0, a.s1, h.buf.data() + rh);
    }
    w.post_receive();  // `in` is free again
    return true;
}

// Sends every tile the pool has finished back to rank 0. True if any.
bool send_finished(TilePool& pool, WorkerState& w, bool crash_me) {
    bool any = false;
    for (const TilePool::Finished& f : pool.take_finished()) {
        any = true;
        WorkerState::Held& h = w.held.at(f.id);
        ResultHeader r;
        r.tile = h.a.tile;
        r.s0 = h.a.s0;
        r.s1 = h.a.s1;
        r.refine = h.a.refine;
        r.rays = f.rays;
        put_header(h.buf, r);
        check(MPI_Isend(h.buf.data(), bytes_of(h.buf.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD, &h.req),
              "sending a tile to rank 0");
        h.sending = true;
        if (crash_me) {
            wait_polling(h.req, nullptr, "sending a tile to rank 0");
            std::cerr << "raytracer-mpi: rank " << g_rank << ": aborting on purpose (RAYTRACER_MPI_TEST_CRASH_RANK)\n"
                      << std::flush;
            std::abort();
        }
    }
    return any;
}

// Ranks 1..N-1: render what rank 0 assigns until told to stop. Every assignment goes
// into the pool's queue the moment it arrives, so the render threads always find the
// next tile waiting; this thread only moves messages.
void run_worker(const std::vector<Tile>& tiles, int side, TilePool& pool) {
    // Test hook: RAYTRACER_MPI_TEST_CRASH_RANK=R makes rank R abort after sending its
    // first tile, to check that a dying rank fails the job and leaves OUT untouched.
    const char* crash = std::getenv("RAYTRACER_MPI_TEST_CRASH_RANK");
    const bool crash_me = crash && std::atoi(crash) == g_rank;

    WorkerState w;
    w.in.resize(head_floats<AssignHeader>() + 6 * std::size_t(side) * std::size_t(side));
    w.post_receive();
    for (;;) {
        bool busy = false;
        if (!w.stop) busy = take_assignment(tiles, pool, w);
        busy |= send_finished(pool, w, crash_me);
        // Also keeps MPI moving: a result too big to send eagerly only completes while
        // this rank calls into MPI.
        for (auto it = w.held.begin(); it != w.held.end();) {
            int sent = 0;
            if (it->second.sending) check(MPI_Test(&it->second.req, &sent, MPI_STATUS_IGNORE), "sending a tile to rank 0");
            it = sent ? w.held.erase(it) : std::next(it);
        }
        if (w.stop && w.held.empty()) return;
        if (!busy) pool.wait_finished(kPoll);
    }
}

}  // namespace
}  // namespace rtmpi
