// The pool behind parallel_for (see parallel.h).
#include "parallel.h"

#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <memory>

namespace rt {

namespace {

// The calling thread's priority, `steps` below what it was (a thread's nice value is
// its own on Linux).
void lower_this_thread(int steps) {
    if (steps <= 0) return;
    errno = 0;
    const pid_t self = pid_t(syscall(SYS_gettid));
    const int now = getpriority(PRIO_PROCESS, self);
    if (errno == 0) setpriority(PRIO_PROCESS, self, std::min(19, now + steps));
}

}  // namespace

ThreadPool::ThreadPool(int threads, int nice) : nice_(nice) {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
    {
        // Jobs set aside end first: one may be running a loop on the workers.
        std::lock_guard<std::mutex> lock(aside_mutex_);
        aside_quit_ = true;
    }
    aside_wake_.notify_all();
    for (std::thread& t : aside_threads_) t.join();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        quit_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void ThreadPool::run_items(Loop& loop) {
    for (;;) {
        const int i = loop.next.fetch_add(1, std::memory_order_relaxed);
        if (i >= loop.n || loop.failed.load(std::memory_order_relaxed)) return;
        try {
            (*loop.fn)(i);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!loop.error) loop.error = std::current_exception();
            loop.failed = true;
        }
    }
}

ThreadPool::Loop* ThreadPool::loop_with_items() const {
    for (auto it = loops_.rbegin(); it != loops_.rend(); ++it)
        if ((*it)->has_items()) return *it;
    return nullptr;
}

void ThreadPool::work() {
    lower_this_thread(nice_);
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        Loop* loop = nullptr;
        wake_.wait(lock, [&] { return quit_ || (loop = loop_with_items()) != nullptr || !tasks_.empty(); });
        if (quit_) return;
        if (loop) {
            // A loop first: its caller waits for it. The loop stays while busy > 0.
            ++loop->busy;
            lock.unlock();
            run_items(*loop);
            lock.lock();
            if (--loop->busy == 0) done_.notify_all();
            continue;
        }
        std::function<void()> task = std::move(tasks_.front());
        tasks_.pop_front();
        lock.unlock();
        task();
        task = nullptr;  // what it holds goes before the next wait
        lock.lock();
    }
}

void ThreadPool::post(std::function<void()> fn) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        tasks_.push_back(std::move(fn));
    }
    wake_.notify_one();
}

void ThreadPool::start_aside(std::function<std::function<void()>()> fn) {
    std::lock_guard<std::mutex> lock(aside_mutex_);
    aside_jobs_.push_back(std::move(fn));
    // Every job starts at once: an idle thread takes it, or a new one.
    if (aside_idle_ >= int(aside_jobs_.size()))
        aside_wake_.notify_one();
    else
        aside_threads_.emplace_back([this] { work_aside(); });
}

void ThreadPool::work_aside() {
    lower_this_thread(nice_);
    std::unique_lock<std::mutex> lock(aside_mutex_);
    ++aside_idle_;
    for (;;) {
        aside_wake_.wait(lock, [&] { return aside_quit_ || !aside_jobs_.empty(); });
        // The queue is emptied before quitting: a Job's holder waits for its job.
        if (aside_jobs_.empty()) return;
        --aside_idle_;
        std::function<std::function<void()>()> job = std::move(aside_jobs_.front());
        aside_jobs_.pop_front();
        lock.unlock();
        std::function<void()> deliver = job();
        job = nullptr;  // what it holds goes before its value arrives
        lock.lock();
        // Free from here on, before the value arrives: a job its holder starts next
        // finds this thread (it takes the job once back in the wait above).
        ++aside_idle_;
        lock.unlock();
        deliver();
        deliver = nullptr;
        lock.lock();
    }
}

int ThreadPool::aside_threads() const {
    std::lock_guard<std::mutex> lock(aside_mutex_);
    return int(aside_threads_.size());
}

void ThreadPool::parallel_for(int n, const std::function<void(int)>& fn) {
    if (n <= 0) return;
    if (workers_.empty() || n == 1) {
        for (int i = 0; i < n; ++i) fn(i);
        return;
    }
    Loop loop;
    loop.fn = &fn;
    loop.n = n;
    loop.next = 1;  // item 0 is the caller's
    {
        std::lock_guard<std::mutex> lock(mutex_);
        loops_.push_back(&loop);
    }
    // Enough workers for the items besides the caller's.
    if (n - 1 >= workers())
        wake_.notify_all();
    else
        for (int k = 0; k < n - 1; ++k) wake_.notify_one();
    try {
        fn(0);
    } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        loop.error = std::current_exception();
        loop.failed = true;
    }
    run_items(loop);
    std::exception_ptr error;
    {
        // Every item is taken: no worker joins from now on. Wait for those still
        // running one.
        std::unique_lock<std::mutex> lock(mutex_);
        loops_.erase(std::find(loops_.begin(), loops_.end(), &loop));
        done_.wait(lock, [&] { return loop.busy == 0; });
        error = loop.error;
    }
    if (error) std::rethrow_exception(error);
}

namespace {

std::mutex process_mutex;
int process_workers = 0;  // asked for (0: one per hardware thread); under process_mutex
std::atomic<int> process_worker_nice{0};
std::atomic<ThreadPool*> process{nullptr};

int workers_for(int asked) { return asked > 0 ? asked : hardware_threads(); }

}  // namespace

int hardware_threads() {
#ifdef CPU_COUNT
    // The processors this process may run on (a container or taskset may allow fewer
    // than the machine has).
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
#endif
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

ThreadPool& process_pool() {
    if (ThreadPool* p = process.load(std::memory_order_acquire)) return *p;
    std::lock_guard<std::mutex> lock(process_mutex);
    ThreadPool* p = process.load(std::memory_order_relaxed);
    if (!p) {
        // Never deleted: a thread still in a loop when the process exits keeps it.
        p = new ThreadPool(workers_for(process_workers) + 1, process_worker_nice.load());
        process.store(p, std::memory_order_release);
    }
    return *p;
}

void set_process_worker_nice(int nice) { process_worker_nice.store(std::max(0, nice)); }

bool set_process_threads(int workers) {
    std::lock_guard<std::mutex> lock(process_mutex);
    if (ThreadPool* p = process.load(std::memory_order_relaxed)) return p->workers() == workers_for(workers);
    process_workers = workers;
    return true;
}

}  // namespace rt
