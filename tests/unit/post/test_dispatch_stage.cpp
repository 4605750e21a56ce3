// The pipeline's tracking stage (post/dispatch_stage.hpp): batches run in order on its thread,
// a failure stops it and reaches the pushing thread, and a pool's loops are shared with it.
#include <atomic>
#include <stdexcept>
#include <vector>

#include "catch_compat.hpp"
#include "post/dispatch_stage.hpp"

using namespace redpost;

TEST_CASE("dispatch stage: every batch run once, in order, drain waits for all") {
  std::vector<int> seen;  // written by the stage's thread only, read after drain()
  DispatchStage<int> stage([&](int& b) { seen.push_back(b); }, nullptr, 2);
  for (int b = 0; b < 1000; ++b)
    stage.push(int{b});
  stage.drain();
  REQUIRE(seen.size() == 1000);
  for (int b = 0; b < 1000; ++b)
    CHECK(seen[static_cast<std::size_t>(b)] == b);
}

TEST_CASE("dispatch stage: a failing batch drops the rest and is thrown to the pusher") {
  std::atomic<int> ran{0};
  DispatchStage<int> stage(
      [&](int& b) {
        if (b == 7)
          throw std::runtime_error("batch 7");
        ran.fetch_add(1);
      },
      nullptr, 3);
  for (int b = 0; b < 8; ++b)
    stage.push(int{b});
  CHECK(stage.drain_quietly());
  CHECK_THROWS_AS(stage.drain(), std::runtime_error);
  CHECK_THROWS_AS(stage.push(int{8}), std::runtime_error);
  CHECK(ran.load() == 7);
}

TEST_CASE("dispatch stage: between batches its thread shares the pool's loops") {
  WorkerPool pool(1);  // the calling thread alone, and the stage's
  std::atomic<long> batches{0};
  {
    DispatchStage<int> stage([&](int&) { batches.fetch_add(1); }, &pool);
    long sum = 0;
    for (int loop = 0; loop < 300; ++loop) {
      std::vector<std::atomic<int>> runs(512);
      pool.for_each(runs.size(), [&](std::size_t i) { runs[i].fetch_add(1); });
      for (const std::atomic<int>& r : runs)
        sum += r.load();
      if (loop % 10 == 0)
        stage.push(int{loop});
    }
    stage.drain();
    CHECK(sum == 300L * 512L);
  }
  CHECK(batches.load() == 30);
  // The stage detached itself: the pool runs alone again.
  std::atomic<long> after{0};
  pool.for_each(100, [&](std::size_t) { after.fetch_add(1); });
  CHECK(after.load() == 100);
}
