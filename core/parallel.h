// A fixed set of threads that run the iterations of loops with their callers
// (pbrt-v4's ParallelFor in miniature): the caller takes part, so a pool of one thread
// is a plain loop, and nothing is handed over when there is nothing to share. The same
// threads run tasks posted to run later (a renderer's tiles), one pool for all work.
// process_pool() is the one the whole process shares (pbrt-v4's ParallelInit).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace rt {

// The result of a job run aside (ThreadPool::aside), as std::async's future: waiting
// for it, polling it, taking its value. Whoever holds one waits for the job to end
// before letting it go (destroyed or assigned over), so a job never outlives what it
// uses of its owner.
template <class T>
class Job {
public:
    Job() = default;
    explicit Job(std::future<T> f) : f_(std::move(f)) {}
    Job(Job&&) = default;
    Job& operator=(Job&& other) {
        if (this != &other) {
            if (f_.valid()) f_.wait();
            f_ = std::move(other.f_);
        }
        return *this;
    }
    ~Job() {
        if (f_.valid()) f_.wait();
    }
    bool valid() const { return f_.valid(); }
    // Ended (its value or exception is there to take). Needs valid().
    bool ready() const { return f_.wait_for(std::chrono::seconds(0)) == std::future_status::ready; }
    void wait() const { f_.wait(); }
    // Its value (or exception): once; valid() is false afterwards.
    T get() { return f_.get(); }

private:
    std::future<T> f_;
};

class ThreadPool {
public:
    // `threads` counts the caller: threads - 1 are started (at least none). The pool's
    // threads run `nice` steps below the thread that makes the pool (0: the same).
    explicit ThreadPool(int threads, int nice = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return int(workers_.size()) + 1; }
    // The threads that run posted tasks: size() - 1.
    int workers() const { return int(workers_.size()); }

    // Calls fn(i) once for every i in [0, n), on the pool's threads and the caller's
    // (fn(0) always on the caller's), and returns when every call has returned. The first exception thrown by a call
    // (a bad_alloc on a worker, say) is rethrown here once all have stopped; the
    // iterations not yet begun are then skipped.
    // Any number of threads may run loops on one pool at once, and an iteration may
    // itself run a loop (nested): each caller runs its own loop's items until none is
    // left, so a loop ends even when no worker is free; idle workers help whichever
    // loops have items left (the latest begun first), before any posted task.
    void parallel_for(int n, const std::function<void(int)>& fn);

    // Runs fn() once on one of the workers, later, and returns at once. Tasks start in
    // the order posted, each when no loop has items left for the worker to take. fn
    // must not throw; it may run loops on this pool. Needs a worker (workers() >= 1);
    // the tasks still waiting when the pool ends do not run, so whoever posts one
    // waits for it before the pool goes.
    void post(std::function<void()> fn);

    // Runs fn() at once on a thread of the pool's set aside for jobs that last (a
    // scene's load, a world's build, a recovery copy's write): such a job may itself
    // run loops on the pool and wait for them, so it never holds a worker that loops
    // and posted tasks need, and it never waits behind them. A thread is made when
    // every one set aside is busy, and kept for the next job. Its value (or exception)
    // comes through the Job. The pool ends after every such job has ended.
    template <class F>
    auto aside(F&& fn) -> Job<decltype(fn())> {
        using R = decltype(fn());
        auto promise = std::make_shared<std::promise<R>>();
        Job<R> job(promise->get_future());
        // The function (and all it holds) goes before its value arrives: whoever takes
        // the value finds nothing of it kept alive by the job. The job's run returns
        // the delivery of its value, made once its thread counts as free again.
        start_aside([promise, f = std::make_shared<std::decay_t<F>>(std::forward<F>(fn))]() mutable
                    -> std::function<void()> {
            try {
                if constexpr (std::is_void_v<R>) {
                    (*f)();
                    f.reset();
                    return [promise] { promise->set_value(); };
                } else {
                    auto value = std::make_shared<R>((*f)());
                    f.reset();
                    return [promise, value] { promise->set_value(std::move(*value)); };
                }
            } catch (...) {
                f.reset();
                return [promise, error = std::current_exception()] { promise->set_exception(error); };
            }
        });
        return job;
    }
    // The threads made for aside() so far (busy or idle).
    int aside_threads() const;

private:
    // One loop: every thread that joins it holds it, so a worker that wakes late
    // finds its items all taken instead of taking another loop's.
    struct Loop {
        const std::function<void(int)>* fn = nullptr;
        int n = 0;
        std::atomic<int> next{0};
        std::atomic<bool> failed{false};
        std::exception_ptr error;  // under the pool's mutex
        int busy = 0;              // workers inside it (under the pool's mutex)
        bool has_items() const {
            return next.load(std::memory_order_relaxed) < n && !failed.load(std::memory_order_relaxed);
        }
    };
    void work();
    void work_aside();
    // fn runs the job and returns the delivery of its value.
    void start_aside(std::function<std::function<void()>()> fn);
    void run_items(Loop& loop);
    // The latest begun loop with items left, or null (under mutex_).
    Loop* loop_with_items() const;

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::vector<Loop*> loops_;  // begun, their callers not yet done taking items (under mutex_)
    std::deque<std::function<void()>> tasks_;  // posted, not yet started (under mutex_)
    bool quit_ = false;
    int nice_ = 0;

    // aside(): its own threads, queue and lock, apart from the loops' and tasks'.
    mutable std::mutex aside_mutex_;
    std::condition_variable aside_wake_;
    std::vector<std::thread> aside_threads_;
    std::deque<std::function<std::function<void()>()>> aside_jobs_;  // not yet started (under aside_mutex_)
    int aside_idle_ = 0;                            // aside threads waiting for a job
    bool aside_quit_ = false;
};

// The pool the process shares: loading, BVH builds, image writing and renders run
// their parallel parts on it. Made on first use with the workers that
// set_process_threads asked for (by default one per hardware thread); it lasts as
// long as the process.
ThreadPool& process_pool();
// The workers process_pool() is to have (0: one per hardware thread). Takes effect
// only before the pool's first use; returns whether the pool has (or will have) that
// many workers.
bool set_process_threads(int workers);
// The process pool's threads (its workers and those for aside()) run `nice` steps
// below the thread that first uses it (a window's UI thread keeps its frames while
// they render and load; 0: the same). Takes effect only before the pool's first use,
// as set_process_threads.
void set_process_worker_nice(int nice);
// The hardware threads this process may use (its CPU affinity: mpirun binds each rank
// to its cores, and more threads than that only queue for them): the default number
// of workers.
int hardware_threads();

// f(0) on the caller's thread and, when `two`, f(1) at the same time on a thread of
// process_pool() (or after f(0) on the caller's, when none is free); else f(0) then f(1). An exception from either is rethrown here once both
// have ended. (The BVH builds' halves: work split once.)
template <class F>
void two_ways(bool two, F&& f) {
    if (!two) {
        f(0);
        f(1);
        return;
    }
    process_pool().parallel_for(2, [&f](int part) { f(part); });
}

}  // namespace rt
