// The plan's worker threads: every index once, on every thread count, errors carried back.
#include <atomic>
#include <stdexcept>
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
