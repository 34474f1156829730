// The thread pool behind parallel_for: every iteration runs exactly once, on the
// caller's thread and the pool's, loop after loop, loops of several callers at once
// and loops inside loops; a throw ends the loop and reaches its caller. Tasks posted
// to it run once each, on its workers, in order.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
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
    std::thread::id first;
    pool.parallel_for(n, [&](int i) {
        runs[std::size_t(i)].fetch_add(1);
        if (i == 0) first = std::this_thread::get_id();
        // Long enough an item that the workers wake before the caller has taken all.
        if (i % 64 == 0) {
            std::lock_guard<std::mutex> lock(m);
            threads.insert(std::this_thread::get_id());
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    for (int i = 0; i < n; ++i) REQUIRE(runs[std::size_t(i)].load() == 1);
    CHECK(threads.count(std::this_thread::get_id()) == 1);  // the caller takes part
    CHECK(bool(first == std::this_thread::get_id()));  // item 0 always
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
                                          // Slow enough that a thread held up right at the
                                          // throw cannot see the others finish the loop.
                                          if (i > 500) std::this_thread::sleep_for(std::chrono::microseconds(1));
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

namespace {
// Waits until pred() holds or `seconds` pass; whether it held.
template <class Pred>
bool eventually(Pred pred, double seconds = 10) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!pred()) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    return true;
}
}  // namespace

TEST_CASE("loops of several threads at once on one pool: each gets every index exactly once") {
    ThreadPool pool(3);
    constexpr int callers = 3, loops = 300;
    std::atomic<int> ready{0}, inside{0}, overlapped{0};
    std::atomic<bool> bad{false};
    std::vector<std::thread> threads;
    for (int c = 0; c < callers; ++c)
        threads.emplace_back([&, c] {
            ready.fetch_add(1);
            while (ready.load() < callers) std::this_thread::yield();
            for (int loop = 0; loop < loops; ++loop) {
                const int n = 1 + (loop * 7 + c * 13) % 97;
                std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
                inside.fetch_add(1);
                pool.parallel_for(n, [&](int i) {
                    // The first loops wait for each other: the loops do run at once.
                    if (loop == 0 && i == 0) eventually([&] { return inside.load() == callers; });
                    if (inside.load() > 1) overlapped.fetch_add(1);
                    runs[std::size_t(i)].fetch_add(1);
                });
                inside.fetch_sub(1);
                for (int i = 0; i < n; ++i)
                    if (runs[std::size_t(i)].load() != 1) bad = true;
            }
        });
    for (std::thread& t : threads) t.join();
    CHECK_FALSE(bad.load());
    CHECK(overlapped.load() > 0);  // the loops did run at the same time
}

TEST_CASE("a loop begun while the workers run posted tasks ends on its caller; they help it after") {
    // The older of two loops must still be helped once the workers are free, though a
    // newer loop began and ended meanwhile.
    ThreadPool pool(3);
    std::atomic<bool> release{false};
    std::atomic<int> holding{0};
    std::mutex m;
    std::condition_variable cv;
    int tasks_done = 0;
    for (int k = 0; k < pool.workers(); ++k)
        pool.post([&] {
            holding.fetch_add(1);
            while (!release.load()) std::this_thread::sleep_for(std::chrono::microseconds(100));
            std::lock_guard<std::mutex> lock(m);
            ++tasks_done;
            cv.notify_all();
        });
    REQUIRE(eventually([&] { return holding.load() == pool.workers(); }));

    // Loop A: its two items meet, so one of them needs a worker (run one after the
    // other, each waits in vain).
    std::atomic<int> a_inside{0}, a_runs{0}, a_saw{0};
    std::thread a([&] {
        pool.parallel_for(2, [&](int) {
            a_runs.fetch_add(1);
            a_inside.fetch_add(1);
            if (eventually([&] { return a_inside.load() == 2; })) {
                a_saw.fetch_add(1);
                eventually([&] { return a_saw.load() == 2; });
            }
            a_inside.fetch_sub(1);
        });
    });
    REQUIRE(eventually([&] { return a_inside.load() == 1; }));

    // Loop B, from here, while both workers are held and A waits: its caller runs it all.
    constexpr int n = 500;
    std::vector<std::atomic<int>> runs(n);
    std::set<std::thread::id> b_threads;
    pool.parallel_for(n, [&](int i) {
        runs[std::size_t(i)].fetch_add(1);
        std::lock_guard<std::mutex> lock(m);
        b_threads.insert(std::this_thread::get_id());
    });
    for (int i = 0; i < n; ++i) REQUIRE(runs[std::size_t(i)].load() == 1);
    CHECK(b_threads.size() == 1);

    release = true;
    a.join();
    CHECK(a_runs.load() == 2);
    CHECK(a_saw.load() == 2);
    wait_count(m, cv, tasks_done, pool.workers());
}

TEST_CASE("loops inside loops: every index of every level once, the inner loops helped") {
    ThreadPool pool(4);
    constexpr int outer = 6, middle = 5, inner = 40;
    std::vector<std::atomic<int>> runs(outer * middle * inner);
    std::mutex m;
    std::set<std::thread::id> inner_threads;
    pool.parallel_for(outer, [&](int i) {
        pool.parallel_for(middle, [&](int j) {
            pool.parallel_for(inner, [&](int k) {
                runs[std::size_t((i * middle + j) * inner + k)].fetch_add(1);
                if (k % 8 == 0) {
                    std::lock_guard<std::mutex> lock(m);
                    inner_threads.insert(std::this_thread::get_id());
                    std::this_thread::sleep_for(std::chrono::microseconds(100));
                }
            });
        });
    });
    for (std::size_t x = 0; x < runs.size(); ++x) REQUIRE(runs[x].load() == 1);
    CHECK(inner_threads.size() > 1);
}

TEST_CASE("an inner loop's throw reaches the outer loop's caller") {
    ThreadPool pool(3);
    CHECK_THROWS_WITH_AS(pool.parallel_for(8,
                                           [&](int i) {
                                               pool.parallel_for(100, [&](int j) {
                                                   if (i == 5 && j == 50) throw std::runtime_error("inner 5/50");
                                               });
                                           }),
                         "inner 5/50", std::runtime_error);
    std::atomic<int> after{0};
    pool.parallel_for(100, [&](int) { after.fetch_add(1); });
    CHECK(after.load() == 100);
}

TEST_CASE("throws in loops of several threads at once each reach their own caller") {
    ThreadPool pool(3);
    constexpr int callers = 3, rounds = 200;
    std::atomic<int> ready{0}, wrong{0}, caught{0};
    std::vector<std::thread> threads;
    for (int c = 0; c < callers; ++c)
        threads.emplace_back([&, c] {
            ready.fetch_add(1);
            while (ready.load() < callers) std::this_thread::yield();
            const std::string mine = "caller " + std::to_string(c);
            for (int r = 0; r < rounds; ++r) {
                try {
                    // Every caller's loop throws, at an item a worker may well run.
                    pool.parallel_for(64, [&](int i) {
                        if (i == 1 + (r + c) % 63) throw std::runtime_error(mine);
                    });
                    wrong.fetch_add(1);  // no throw at all
                } catch (const std::runtime_error& e) {
                    if (e.what() != mine) wrong.fetch_add(1);
                    caught.fetch_add(1);
                }
            }
        });
    for (std::thread& t : threads) t.join();
    CHECK(wrong.load() == 0);
    CHECK(caught.load() == callers * rounds);
}

TEST_CASE("posted tasks may run loops on their own pool") {
    ThreadPool pool(3);
    std::mutex m;
    std::condition_variable cv;
    int done = 0;
    std::atomic<int> bad{0};
    for (int t = 0; t < 20; ++t)
        pool.post([&] {
            std::vector<std::atomic<int>> runs(100);
            pool.parallel_for(100, [&](int i) { runs[std::size_t(i)].fetch_add(1); });
            for (auto& r : runs)
                if (r.load() != 1) bad.fetch_add(1);
            std::lock_guard<std::mutex> lock(m);
            ++done;
            cv.notify_all();
        });
    wait_count(m, cv, done, 20);
    CHECK(bad.load() == 0);
}

TEST_CASE("two_ways runs both parts on the process pool, and either part's throw reaches the caller") {
    REQUIRE(rt::process_pool().workers() >= 1);
    // Its count is fixed once it runs.
    CHECK(rt::set_process_threads(rt::process_pool().workers()));
    CHECK_FALSE(rt::set_process_threads(rt::process_pool().workers() + 1));
    for (const bool two : {false, true}) {
        std::atomic<int> ran[2] = {{0}, {0}};
        std::atomic<int> inside{0};
        std::atomic<bool> met{false};
        rt::two_ways(two, [&](int part) {
            ran[part].fetch_add(1);
            inside.fetch_add(1);
            // Side by side when two: each part sees the other begin.
            if (two && eventually([&] { return inside.load() == 2; })) met = true;
        });
        CHECK(ran[0].load() == 1);
        CHECK(ran[1].load() == 1);
        CHECK(met.load() == two);
        for (int bad : {0, 1})
            CHECK_THROWS_WITH_AS(rt::two_ways(two,
                                              [&](int part) {
                                                  if (part == bad) throw std::runtime_error("part " + std::to_string(part));
                                              }),
                                 ("part " + std::to_string(bad)).c_str(), std::runtime_error);
    }
}

TEST_CASE("a job set aside starts at once, even while every worker is held by posted tasks") {
    ThreadPool pool(2);  // one worker
    std::mutex m;
    std::condition_variable cv;
    bool release = false;
    pool.post([&] {
        std::unique_lock<std::mutex> lock(m);
        cv.wait(lock, [&] { return release; });
    });
    // The worker is held: a posted task would wait; the job set aside does not. And it
    // may run a loop on the pool (its own thread takes every item).
    rt::Job<int> job = pool.aside([&pool] {
        std::atomic<int> sum{0};
        pool.parallel_for(100, [&](int i) { sum += i; });
        return sum.load();
    });
    CHECK(job.get() == 4950);
    CHECK_FALSE(job.valid());
    {
        std::lock_guard<std::mutex> lock(m);
        release = true;
    }
    cv.notify_all();
}

TEST_CASE("jobs set aside: their values and throws arrive; their threads are kept for the next") {
    ThreadPool pool(2);
    for (int i = 0; i < 20; ++i) {
        rt::Job<int> job = pool.aside([i] { return i * i; });
        CHECK(job.get() == i * i);
    }
    // One after another: one thread did them all (it counts as free before a job's
    // value arrives).
    CHECK(pool.aside_threads() == 1);
    rt::Job<void> bad = pool.aside([] { throw std::runtime_error("no"); });
    CHECK_THROWS_AS(bad.get(), std::runtime_error);
    // Two at once get two threads: the second does not wait behind the first.
    std::atomic<bool> second_ran{false};
    rt::Job<void> first = pool.aside([&] {
        while (!second_ran.load()) std::this_thread::yield();
    });
    rt::Job<void> second = pool.aside([&] { second_ran = true; });
    first.wait();  // (it ends only once the second has run)
    CHECK(second_ran.load());
    second.wait();
    CHECK(pool.aside_threads() >= 2);
}

TEST_CASE("a Job let go waits for its job, as std::async's future does") {
    ThreadPool pool(1);
    std::atomic<bool> done{false};
    {
        rt::Job<void> job = pool.aside([&] {
            std::this_thread::yield();
            done = true;
        });
    }
    CHECK(done.load());
    done = false;
    rt::Job<void> job = pool.aside([&] { done = true; });
    job = pool.aside([] {});  // assigned over: the first has ended by then
    CHECK(done.load());
    job.wait();
    CHECK(job.ready());
}

TEST_CASE("what a job set aside holds is gone by the time its value arrives") {
    ThreadPool pool(1);
    for (int k = 0; k < 50; ++k) {
        auto held = std::make_shared<int>(k);
        std::weak_ptr<int> seen = held;
        rt::Job<int> job = pool.aside([held = std::move(held)] { return *held + 1; });
        job.wait();
        CHECK(seen.expired());
        CHECK(job.get() == k + 1);
    }
}
