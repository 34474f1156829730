// A fixed set of threads that run the iterations of a loop with the calling thread
// (pbrt-v4's ParallelFor in miniature): the caller takes part, so a pool of one thread
// is a plain loop, and nothing is handed over when there is nothing to share. The same
// threads run tasks posted to run later (a renderer's tiles), one pool for all work.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace rt {

class ThreadPool {
public:
    // `threads` counts the caller: threads - 1 are started (at least none).
    explicit ThreadPool(int threads);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return int(workers_.size()) + 1; }
    // The threads that run posted tasks: size() - 1.
    int workers() const { return int(workers_.size()); }

    // Calls fn(i) once for every i in [0, n), on the pool's threads and the caller's,
    // and returns when every call has returned. The first exception thrown by a call
    // (a bad_alloc on a worker, say) is rethrown here once all have stopped; the
    // iterations not yet begun are then skipped. One loop at a time per pool.
    void parallel_for(int n, const std::function<void(int)>& fn);

    // Runs fn() once on one of the workers, later, and returns at once. Tasks start in
    // the order posted, each after the loop items waiting then (a loop's caller is
    // waiting for those). fn must not throw. Needs a worker (workers() >= 1); the
    // tasks still waiting when the pool ends do not run, so whoever posts one waits
    // for it before the pool goes.
    void post(std::function<void()> fn);

private:
    // One loop: every thread that joins it holds it, so a worker that wakes late
    // finds its items all taken instead of taking the next loop's.
    struct Loop {
        const std::function<void(int)>* fn = nullptr;
        int n = 0;
        std::atomic<int> next{0};
        std::atomic<bool> failed{false};
        std::exception_ptr error;  // under the pool's mutex
        int busy = 0;              // workers inside it (under the pool's mutex)
    };
    void work();
    void run_items(Loop& loop);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::shared_ptr<Loop> loop_;  // the latest loop posted (under mutex_)
    std::deque<std::function<void()>> tasks_;  // posted, not yet started (under mutex_)
    bool quit_ = false;
};

// f(0) here and f(1) on another thread when `two` and a thread can be had; else f(0)
// then f(1). An exception from either is rethrown here once both have ended. (The
// BVH builds' halves: work split once, where a pool's loop would cost more than it.)
template <class F>
void two_ways(bool two, F&& f) {
    std::thread t;
    std::exception_ptr failed;
    if (two) {
        try {
            t = std::thread([&] {
                try {
                    f(1);
                } catch (...) {
                    failed = std::current_exception();
                }
            });
        } catch (const std::system_error&) {
            // No thread: both parts here.
        }
    }
    try {
        f(0);
        if (!t.joinable()) f(1);
    } catch (...) {
        if (t.joinable()) t.join();
        throw;
    }
    if (t.joinable()) t.join();
    if (failed) std::rethrow_exception(failed);
}

}  // namespace rt
