// A fixed set of threads that share the iterations of one loop and wait for each other: the
// whole-path plan evaluates every node of a lattice layer (an IK each) this way
// (docs/redundancy.md, "Threads").
//
// Each index is run by exactly one thread, and a loop body writes only what belongs to its
// index, so the results are the same for any number of threads and any timing: the program is
// byte for byte the single-thread one.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace redpost {

// A count of threads as asked (0: one per core the machine has, at most
// WorkerPool::kMaxAutoThreads), made a count (at least 1).
int resolved_threads(int threads);

class WorkerPool {
 public:
  // `threads` in all, the calling thread among them (1: no thread is started). 0: one per core
  // the machine has, at most kMaxAutoThreads.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // body(i) for every i in [0, n), on every thread; returns when all are done. The first
  // exception a body throws is thrown here once all have stopped.
  void for_each(std::size_t n, const std::function<void(std::size_t)>& body);

  static constexpr int kMaxAutoThreads = 8;

 private:
  void work();       // a worker thread's loop
  void run_share();  // takes indices of the current loop until none are left

  std::vector<std::thread> workers_;
  std::mutex mutex_;  // for the sleepers, and the error
  std::condition_variable wake_;
  std::atomic<std::uint64_t> generation_{0};  // one per loop; workers wait for the next
  std::atomic<bool> stop_{false};
  const std::function<void(std::size_t)>* body_ = nullptr;  // published by generation_
  std::size_t n_ = 0;
  std::atomic<std::size_t> next_{0};
  std::atomic<int> running_{0};  // workers not yet done with the current loop
  std::exception_ptr error_;
};

}  // namespace redpost
