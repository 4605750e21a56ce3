// The plan's worker threads (redundancy/worker_pool.hpp).
//
// A keyframe's nodes take tens of microseconds to solve, about what putting a thread to sleep
// and waking it costs: the workers therefore poll for a while between loops before they sleep
// (first spinning, then yielding the core), and the caller polls while the last chunks finish. A
// worker asleep (the session tracked and wrote for a while) costs one wake-up at the next loop.
#include "redpost/redundancy/worker_pool.hpp"

#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace redpost {

namespace {

// Indices taken at a time: a few IK solutions, so that the shared counter is not the bottleneck
// and a layer of a hundred nodes still spreads over every thread.
constexpr std::size_t kChunk = 8;
// Polls of a waiting worker before it sleeps: the first with a pause instruction (a few
// microseconds), the rest giving the core away (sched_yield), so that a machine with more
// threads than cores (tests run side by side, another process) loses little to the waiting.
constexpr int kPauses = 256;
constexpr int kYields = 200;

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

int resolved_threads(int threads) {
  if (threads > 0)
    return threads;
  return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1,
                    WorkerPool::kMaxAutoThreads);
}

WorkerPool::WorkerPool(int threads) {
  threads = resolved_threads(threads);
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t)
    workers_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
  for (std::thread& t : workers_)
    t.join();
}

void WorkerPool::run_share() {
  const std::size_t n = n_;
  for (;;) {
    const std::size_t first = next_.fetch_add(kChunk);
    if (first >= n)
      return;
    const std::size_t last = std::min(n, first + kChunk);
    for (std::size_t i = first; i < last; ++i) {
      try {
        (*body_)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!error_)
          error_ = std::current_exception();
      }
    }
  }
}

void WorkerPool::work() {
  std::uint64_t seen = 0;
  for (;;) {
    for (int k = 0; k < kPauses + kYields && generation_.load(std::memory_order_acquire) == seen &&
                    !stop_.load(std::memory_order_relaxed);
         ++k) {
      if (k < kPauses)
        relax();
      else
        std::this_thread::yield();
    }
    if (generation_.load(std::memory_order_acquire) == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] {
        return stop_.load() || generation_.load(std::memory_order_acquire) != seen;
      });
    }
    if (stop_.load())
      return;
    // The loop's body and size were written before the generation (release, acquire above).
    seen = generation_.load(std::memory_order_acquire);
    run_share();
    running_.fetch_sub(1, std::memory_order_release);
  }
}

void WorkerPool::for_each(std::size_t n, const std::function<void(std::size_t)>& body) {
  if (workers_.empty() || n <= kChunk) {
    for (std::size_t i = 0; i < n; ++i)
      body(i);
    return;
  }
  body_ = &body;
  n_ = n;
  next_.store(0, std::memory_order_relaxed);
  running_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
  {
    // Under the lock, so that a worker between its last check and its sleep is not missed.
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  run_share();
  // Every worker has finished with this loop (its last chunk, or a look at an empty counter)
  // before the body goes out of scope.
  for (int k = 0; running_.load(std::memory_order_acquire) != 0; ++k) {
    if (k < kPauses)
      relax();
    else
      std::this_thread::yield();
  }
  body_ = nullptr;
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    error = std::exchange(error_, nullptr);
  }
  if (error)
    std::rethrow_exception(error);
}

}  // namespace redpost
