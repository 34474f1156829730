// The pool behind parallel_for (see parallel.h).
#include "parallel.h"

namespace rt {

ThreadPool::ThreadPool(int threads) {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
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

void ThreadPool::work() {
    std::shared_ptr<Loop> seen;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [&] { return quit_ || loop_ != seen || !tasks_.empty(); });
        if (quit_) return;
        if (loop_ != seen) {
            // A loop first: its caller waits for it.
            seen = loop_;
            ++seen->busy;
            lock.unlock();
            run_items(*seen);
            lock.lock();
            if (--seen->busy == 0) done_.notify_all();
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

void ThreadPool::parallel_for(int n, const std::function<void(int)>& fn) {
    if (n <= 0) return;
    if (workers_.empty() || n == 1) {
        for (int i = 0; i < n; ++i) fn(i);
        return;
    }
    auto loop = std::make_shared<Loop>();
    loop->fn = &fn;
    loop->n = n;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        loop_ = loop;
    }
    wake_.notify_all();
    run_items(*loop);
    std::exception_ptr error;
    {
        // Every item is taken; wait for the workers still running one. A worker that
        // wakes only now finds nothing left and leaves at once.
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [&] { return loop->busy == 0; });
        error = loop->error;
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace rt
