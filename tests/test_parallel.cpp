// The thread pool behind parallel_for: every iteration runs exactly once, on the
// caller's thread and the pool's, loop after loop; a throw ends the loop and reaches
// the caller. Tasks posted to it run once each, on its workers, in order.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <new>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "parallel.h"

using rt::ThreadPool;

TEST_CASE("parallel_for runs each iteration once, on more than one thread") {
    ThreadPool pool(4);
    CHECK(pool.size() == 4);
    constexpr int n = 20000;
    std::vector<std::atomic<int>> runs(n);
    std::mutex m;
    std::set<std::thread::id> threads;
    pool.parallel_for(n, [&](int i) {
        runs[std::size_t(i)].fetch_add(1);
        // Long enough an item that the workers wake before the caller has taken all.
        if (i % 64 == 0) {
            std::lock_guard<std::mutex> lock(m);
            threads.insert(std::this_thread::get_id());
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    for (int i = 0; i < n; ++i) REQUIRE(runs[std::size_t(i)].load() == 1);
    CHECK(threads.count(std::this_thread::get_id()) == 1);  // the caller takes part
    CHECK(threads.size() > 1);
}

TEST_CASE("loop after loop: no iteration of one loop runs in the next, none is lost") {
    // Workers that wake late for a loop already finished must not take items of the
    // next one (each loop's sum would then be off).
    ThreadPool pool(3);
    for (int loop = 0; loop < 3000; ++loop) {
        const int n = 1 + loop % 7;
        std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
        pool.parallel_for(n, [&](int i) { runs[std::size_t(i)].fetch_add(1); });
        for (int i = 0; i < n; ++i) REQUIRE(runs[std::size_t(i)].load() == 1);
    }
}

TEST_CASE("a pool of one runs the loop on the caller's thread, in order") {
    ThreadPool pool(1);
    CHECK(pool.size() == 1);
    std::vector<int> order;
    const auto me = std::this_thread::get_id();
    pool.parallel_for(5, [&](int i) {
        CHECK(bool(std::this_thread::get_id() == me));
        order.push_back(i);
    });
    CHECK(order == std::vector<int>{0, 1, 2, 3, 4});
    pool.parallel_for(0, [&](int) { FAIL("no iteration of an empty loop"); });
}

TEST_CASE("a throw in an iteration (a bad_alloc on a worker) reaches the caller; the pool works on") {
    ThreadPool pool(3);
    std::atomic<int> ran{0};
    CHECK_THROWS_AS(pool.parallel_for(100000,
                                      [&](int i) {
                                          ran.fetch_add(1);
                                          if (i == 500) throw std::bad_alloc();
                                      }),
                    std::bad_alloc);
    // The items not begun when it threw were skipped.
    CHECK(ran.load() < 100000);
    std::atomic<int> after{0};
    pool.parallel_for(1000, [&](int) { after.fetch_add(1); });
    CHECK(after.load() == 1000);
}

namespace {
// Waits until `count` reaches `n` (polled under the lock the tasks count under).
void wait_count(std::mutex& m, std::condition_variable& cv, const int& count, int n) {
    std::unique_lock<std::mutex> lock(m);
    cv.wait(lock, [&] { return count >= n; });
}
}  // namespace

TEST_CASE("posted tasks run once each, on the workers, not on the caller") {
    ThreadPool pool(3);
    CHECK(pool.workers() == 2);
    constexpr int n = 2000;
    std::vector<int> runs(n, 0);
    std::mutex m;
    std::condition_variable cv;
    int count = 0;
    bool on_caller = false;
    const auto me = std::this_thread::get_id();
    for (int i = 0; i < n; ++i)
        pool.post([&, i] {
            std::lock_guard<std::mutex> lock(m);
            ++runs[std::size_t(i)];
            on_caller |= std::this_thread::get_id() == me;
            if (++count == n) cv.notify_all();
        });
    wait_count(m, cv, count, n);
    CHECK_FALSE(on_caller);
    CHECK(std::count(runs.begin(), runs.end(), 1) == n);
}

TEST_CASE("one worker runs posted tasks in the order posted, between loops") {
    ThreadPool pool(2);
    std::mutex m;
    std::condition_variable cv;
    std::vector<int> order;
    int count = 0;
    for (int i = 0; i < 100; ++i) {
        pool.post([&, i] {
            std::lock_guard<std::mutex> lock(m);
            order.push_back(i);
            ++count;
            cv.notify_all();
        });
        // A loop in between: the posted tasks wait or run around it, none is lost.
        if (i % 10 == 0) {
            std::atomic<int> items{0};
            pool.parallel_for(50, [&](int) { items.fetch_add(1); });
            REQUIRE(items.load() == 50);
        }
    }
    wait_count(m, cv, count, 100);
    std::vector<int> expected(100);
    for (int i = 0; i < 100; ++i) expected[std::size_t(i)] = i;
    CHECK(order == expected);
}
