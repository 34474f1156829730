// raytracer-mpi's rank 0: the Coordinator owns the schedule, serves the workers and
// feeds its own pool, and how rank 0 ends on a signal (see raytracer_mpi.cpp).
#pragma once

#include "messages.h"

namespace rtmpi {
namespace {

// --- signals (rank 0) ----------------------------------------------------------------
// Ctrl+C reaches mpirun, which signals the ranks; rank 0's handler (app/cli) ends it at
// once in every phase but the write of OUT, which removes its temporary file first
// and then comes here.
// Exits without MPI_Abort: the exit status (not 0, no MPI_Finalize) is enough for
// mpirun to end the rest of the job, and mpirun has usually started doing so already.
[[noreturn]] void interrupted() {
    const int sig = caught_signal();
    if (sig == SIGTERM)
        std::cerr << "raytracer-mpi: terminated (SIGTERM, as mpirun ends a job when a rank fails or the job is "
                     "cancelled); nothing written\n";
    else
        std::cerr << "raytracer-mpi: interrupted (" << (sig == SIGINT ? "SIGINT" : "signal") << "); nothing written\n";
    std::cerr << std::flush;
    std::_Exit(128 + sig);
}


// Rank 0's main thread: owns the schedule, serves the workers and feeds its own pool.
// Single-threaded apart from the pool, so the schedule needs no lock.
class Coordinator {
public:
    Coordinator(const ScheduleSettings& settings, TilePool& pool) : sched_(settings), pool_(pool) {
        peers_.resize(std::size_t(g_size));
        reqs_.assign(std::size_t(g_size), MPI_REQUEST_NULL);
        tiles_by_rank_.assign(std::size_t(g_size), 0);
    }

    // Renders the whole picture; returns with the schedule complete (or fails the job).
    void run(bool show_progress) {
        t0_ = Clock::now();
        ProgressBar bar(show_progress);
        auto next_draw = Clock::now();
        for (;;) {
            if (caught_signal()) interrupted();
            bool busy = collect_local();
            busy |= receive_results();
            busy |= feed_local();
            busy |= hand_out();
            reap_sends();
            if (sched_.done() && local_.empty() &&
                std::all_of(peers_.begin() + 1, peers_.end(), [](const Peer& p) { return p.stopped; }))
                break;
            if (show_progress && Clock::now() >= next_draw) {
                next_draw = Clock::now() + std::chrono::milliseconds(100);
                const double elapsed = seconds_since(t0_);
                const std::string pass =
                    sched_.pass_count() > 1 ? "pass " + std::to_string(sched_.pass_index() + 1) + ", " : "";
                char detail[160];
                std::snprintf(detail, sizeof detail, "%stiles %d/%zu, %s, %.2f M rays/s", pass.c_str(),
                              sched_.pass_tiles_done(), sched_.tiles().size(), count(std::size_t(g_size), "rank").c_str(),
                              elapsed > 0 ? double(sched_.rays()) / elapsed / 1e6 : 0.0);
                bar.update(sched_.fraction(), elapsed, detail);
            }
            // Sleeps until rank 0's own pool finishes a tile, or for one poll period.
            if (!busy) pool_.wait_finished(kPoll);
        }
        bar.clear();
        // Every stop has been sent; wait until MPI is done with the buffers.
        while (!sends_.empty()) reap_sends(), std::this_thread::sleep_for(kPoll);
        render_time_ = seconds_since(t0_);
        if (!sched_.complete()) fail(kExitMpi, "internal error: the render ended with pixels missing");
    }

    rt::Image image() const { return sched_.image(); }
    const Schedule& schedule() const { return sched_; }
    double render_time() const { return render_time_; }
    const std::vector<int>& tiles_by_rank() const { return tiles_by_rank_; }
    std::uint64_t bytes_received() const { return bytes_received_; }
    std::uint64_t messages_received() const { return messages_received_; }

private:
    struct Peer {
        std::vector<Assignment> out;  // handed out and not back yet
        std::vector<float> buf;      // receives the result of out.front()
        bool stopped = false;
    };
    struct Send {
        std::vector<float> buf;
        MPI_Request req = MPI_REQUEST_NULL;
    };
    struct Local {
        Assignment a;
        std::vector<float> sums;  // (+ squares, for a refine assignment)
        std::vector<std::uint32_t> counts;
    };

    // Rank 0's own share: kLocalDepth tiles queued in its pool.
    bool feed_local() {
        bool fed = false;
        Assignment a;
        while (local_.size() < std::size_t(kLocalDepth) && sched_.take(a, seconds_since(t0_))) {
            Local& l = local_[next_local_];
            const Tile& t = sched_.tiles()[std::size_t(a.tile)];
            const std::size_t px = std::size_t(t.pixels());
            l.a = a;
            l.sums.assign(result_floats(a.refine, px), 0.f);
            if (a.refine >= 0) {
                l.counts.resize(2 * px);
                sched_.refine_input(a, l.sums.data(), l.sums.data() + 3 * px, l.counts.data(), l.counts.data() + px);
                pool_.submit_refine(next_local_++, t, l.counts.data(), l.counts.data() + px, l.sums.data(),
                                    l.sums.data() + 3 * px);
            } else {
                if (a.s0 > 0) sched_.prior_sums(a, l.sums.data());
                pool_.submit(next_local_++, t, a.s0, a.s1, l.sums.data());
            }
            fed = true;
        }
        return fed;
    }

    bool collect_local() {
        const std::vector<TilePool::Finished> done = pool_.take_finished();
        for (const TilePool::Finished& f : done) {
            auto it = local_.find(f.id);
            if (const rt::Status st = sched_.commit(it->second.a, it->second.sums.data(), f.rays, seconds_since(t0_)); !st)
                fail(kExitMpi, "internal error: " + st.message());
            ++tiles_by_rank_[0];
            local_.erase(it);
        }
        return !done.empty();
    }

    void post_receive(int w) {
        Peer& p = peers_[std::size_t(w)];
        p.buf.resize(head_floats<ResultHeader>() + 4 * std::size_t(sched_.tile_side()) * std::size_t(sched_.tile_side()));
        check(MPI_Irecv(p.buf.data(), bytes_of(p.buf.size()), MPI_BYTE, w, kTagResult, MPI_COMM_WORLD,
                        &reqs_[std::size_t(w)]),
              "MPI_Irecv (tile)");
    }

    // Commits every result that has arrived. True if any did.
    bool receive_results() {
        if (g_size < 2) return false;
        int n = 0;
        idx_.resize(std::size_t(g_size));
        st_.resize(std::size_t(g_size));
        const int rc = MPI_Testsome(g_size, reqs_.data(), &n, idx_.data(), st_.data());
        if (rc == MPI_ERR_IN_STATUS)
            for (int i = 0; i < n; ++i) check(st_[std::size_t(i)].MPI_ERROR, "receiving a tile");
        check(rc, "receiving a tile");
        if (n == MPI_UNDEFINED || n == 0) return false;
        for (int i = 0; i < n; ++i) {
            const int w = idx_[std::size_t(i)];
            Peer& p = peers_[std::size_t(w)];
            const int got = received_bytes(st_[std::size_t(i)]);
            // The pool finishes tiles in any order (a cheap one can overtake a costly one).
            const auto r = got >= int(sizeof(ResultHeader)) ? get_header<ResultHeader>(p.buf) : ResultHeader{};
            auto it = std::find_if(p.out.begin(), p.out.end(), [&](const Assignment& x) {
                return x.tile == r.tile && x.s0 == r.s0 && x.s1 == r.s1 && x.refine == r.refine;
            });
            if (it == p.out.end())
                fail(kExitMpi, "rank " + std::to_string(w) + " sent back tile " + std::to_string(r.tile) +
                                   ", which it does not hold");
            const Assignment a = *it;
            p.out.erase(it);
            const std::size_t sums = result_floats(a.refine, std::size_t(sched_.tiles()[std::size_t(a.tile)].pixels()));
            if (got != bytes_of(head_floats<ResultHeader>() + sums))
                fail(kExitMpi, "rank " + std::to_string(w) + " sent tile " + std::to_string(a.tile) +
                                   " with the wrong size");
            bytes_received_ += std::uint64_t(got);
            ++messages_received_;
            if (const rt::Status st =
                    sched_.commit(a, p.buf.data() + head_floats<ResultHeader>(), r.rays, seconds_since(t0_));
                !st)
                fail(kExitMpi, "rank " + std::to_string(w) + ": " + st.message());
            ++tiles_by_rank_[std::size_t(w)];
            if (!p.out.empty()) post_receive(w);
        }
        return true;
    }

    // Tops every worker up to kDepth tiles, or stops it once the render is complete.
    // True if anything was sent.
    bool hand_out() {
        bool sent = false;
        for (int w = 1; w < g_size; ++w) {
            Peer& p = peers_[std::size_t(w)];
            if (p.stopped) continue;
            Assignment a;
            while (p.out.size() < std::size_t(kDepth) && sched_.take(a, seconds_since(t0_))) {
                send(w, assignment(a));
                p.out.push_back(a);
                if (p.out.size() == 1) post_receive(w);
                sent = true;
            }
            // Stop a worker only when the render is complete and it holds nothing.
            if (sched_.done() && p.out.empty()) {
                Send s;
                s.buf.resize(head_floats<AssignHeader>());
                put_header(s.buf, AssignHeader{});
                send(w, std::move(s));
                p.stopped = true;
                sent = true;
            }
        }
        return sent;
    }

    // The message that hands out `a`: its header, then what the worker continues.
    Send assignment(const Assignment& a) const {
        const std::size_t px = std::size_t(sched_.tiles()[std::size_t(a.tile)].pixels());
        const AssignHeader h{a.tile, a.s0, a.s1, a.refine < 0 && a.s0 > 0, a.refine, 0};
        Send s;
        s.buf.resize(head_floats<AssignHeader>() + assign_floats(h, px));
        put_header(s.buf, h);
        float* data = s.buf.data() + head_floats<AssignHeader>();
        if (h.has_prior) sched_.prior_sums(a, data);
        if (a.refine >= 0) {
            std::vector<std::uint32_t> counts(2 * px);
            sched_.refine_input(a, data, data + 3 * px, counts.data(), counts.data() + px);
            std::memcpy(data + 4 * px, counts.data(), 2 * px * sizeof(std::uint32_t));
        }
        return s;
    }

    void send(int w, Send&& s) {
        sends_.push_back(std::move(s));
        Send& b = sends_.back();
        check(MPI_Isend(b.buf.data(), bytes_of(b.buf.size()), MPI_BYTE, w, kTagAssign, MPI_COMM_WORLD, &b.req),
              "sending a tile");
    }

    // Frees the buffers of completed sends (std::list: the others must not move).
    void reap_sends() {
        for (auto it = sends_.begin(); it != sends_.end();) {
            int done = 0;
            check(MPI_Test(&it->req, &done, MPI_STATUS_IGNORE), "sending a tile");
            it = done ? sends_.erase(it) : std::next(it);
        }
    }

    Schedule sched_;
    TilePool& pool_;
    std::map<int, Local> local_;  // tiles in rank 0's own pool, by submit id
    int next_local_ = 0;
    Clock::time_point t0_;
    std::vector<Peer> peers_;        // by rank; [0] unused
    std::vector<MPI_Request> reqs_;  // by rank: the posted receive of each worker's next tile
    std::vector<int> idx_;
    std::vector<MPI_Status> st_;
    std::list<Send> sends_;
    std::vector<int> tiles_by_rank_;
    std::uint64_t bytes_received_ = 0, messages_received_ = 0;
    double render_time_ = 0;
};

}  // namespace
}  // namespace rtmpi
