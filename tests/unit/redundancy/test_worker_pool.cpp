// The plan's worker threads: every index once, on every thread count and with a helper from
// outside, errors carried back.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/redundancy/worker_pool.hpp"

using namespace redpost;

TEST_CASE("worker pool: every index run exactly once, for any count of threads and indices") {
  for (int threads : {1, 2, 3, 8}) {
    WorkerPool pool(threads);
    CHECK(pool.threads() == threads);
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{8}, std::size_t{9},
                          std::size_t{1000}, std::size_t{100003}}) {
      std::vector<std::atomic<int>> runs(n);
      pool.for_each(n, [&](std::size_t i) { runs[i].fetch_add(1); });
      std::size_t once = 0;
      for (const std::atomic<int>& r : runs)
        once += r.load() == 1 ? 1 : 0;
      INFO(threads << " threads, " << n << " indices");
      CHECK(once == n);
    }
  }
  // 0: one per core, at most the cap.
  WorkerPool automatic(0);
  CHECK(automatic.threads() >= 1);
  CHECK(automatic.threads() <= WorkerPool::kMaxAutoThreads);
}

TEST_CASE("worker pool: a body's exception is thrown to the caller, and the pool goes on") {
  WorkerPool pool(3);
  std::atomic<long> done{0};
  CHECK_THROWS_AS(pool.for_each(5000,
                                [&](std::size_t i) {
                                  if (i == 1234)
                                    throw std::runtime_error("node 1234");
                                  done.fetch_add(1);
                                }),
                  std::runtime_error);
  CHECK(done.load() == 4999);  // the others still ran: every slot is written or the error said
  std::atomic<long> sum{0};
  pool.for_each(1000, [&](std::size_t i) { sum.fetch_add(static_cast<long>(i)); });
  CHECK(sum.load() == 999L * 1000L / 2L);
}

TEST_CASE("worker pool: a helper thread from outside shares the loops, every index once") {
  for (int threads : {1, 2}) {
    WorkerPool pool(threads);
    std::atomic<bool> stop{false};
    std::mutex m;
    std::condition_variable cv;
    pool.attach_helper([&] {
      std::lock_guard<std::mutex> lock(m);
      cv.notify_one();
    });
    // The helper polls, and sleeps now and then, as the session's tracking thread does.
    std::thread helper([&] {
      for (int k = 0; !stop.load(); ++k) {
        if (pool.loop_open()) {
          pool.help();
        } else if (k % 64 == 63) {
          std::unique_lock<std::mutex> lock(m);
          pool.helper_sleeping(true);
          cv.wait_for(lock, std::chrono::milliseconds(1),
                      [&] { return stop.load() || pool.loop_open(); });
          pool.helper_sleeping(false);
        } else {
          WorkerPool::poll_pause(k % 64);
        }
      }
    });
    for (int loop = 0; loop < 400; ++loop) {
      const std::size_t n = static_cast<std::size_t>(1 + (loop * 37) % 900);
      std::vector<std::atomic<int>> runs(n);
      pool.for_each(n, [&](std::size_t i) { runs[i].fetch_add(1); });
      std::size_t once = 0;
      for (const std::atomic<int>& r : runs)
        once += r.load() == 1 ? 1 : 0;
      INFO(threads << " threads, loop " << loop << ", " << n << " indices");
      REQUIRE(once == n);
    }
    if (threads == 1) {
      // The helper does join: index 0 waits (at most 10 s) until an index ran on another thread
      // than the caller's, which with one thread in the pool can only be the helper.
      const std::thread::id caller = std::this_thread::get_id();
      std::atomic<bool> elsewhere{false};
      pool.for_each(64, [&](std::size_t i) {
        if (std::this_thread::get_id() != caller)
          elsewhere.store(true);
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (i == 0 && !elsewhere.load() && std::chrono::steady_clock::now() < until)
          std::this_thread::yield();
      });
      CHECK(elsewhere.load());
    }
    stop.store(true);
    {
      std::lock_guard<std::mutex> lock(m);
      cv.notify_one();
    }
    helper.join();
    pool.attach_helper({});
  }
}
