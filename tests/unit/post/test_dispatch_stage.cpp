// The pipeline's tracking stage (post/dispatch_stage.hpp): batches run in order on its thread,
// and a failure stops it and reaches the pushing thread.
#include <atomic>
#include <stdexcept>
#include <vector>

#include "catch_compat.hpp"
#include "post/dispatch_stage.hpp"

using namespace redpost;

TEST_CASE("dispatch stage: every batch run once, in order, drain waits for all") {
  std::vector<int> seen;  // written by the stage's thread only, read after drain()
  DispatchStage<int> stage([&](int& b) { seen.push_back(b); }, 2);
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
      3);
  for (int b = 0; b < 8; ++b)
    stage.push(int{b});
  CHECK(stage.drain_quietly());
  CHECK_THROWS_AS(stage.drain(), std::runtime_error);
  CHECK_THROWS_AS(stage.push(int{8}), std::runtime_error);
  CHECK(ran.load() == 7);
}
