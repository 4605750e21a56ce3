// The second stage of a session's pipeline (PostOptions::plan_threads, docs/redundancy.md
// "Threads"): the session's own thread reads the events and plans the windows of the whole-path
// plan; this stage's thread tracks and writes the calls each window releases, in order, while
// the next window is planned. Batches go through a bounded queue, so memory stays flat.
//
// Between batches the stage's thread sleeps. It used to help with the plan's lattice loops and
// poll for them meanwhile; since the clearance check made the tracking heavier, that gained
// nothing alone (the 1M raster 3.33 s with it, 3.27 s without, --threads 2) and cost two
// conversions side by side 20 % (docs/redundancy.md, "Threads").
//
// A batch that throws fails the stage: the batches after it are dropped, and the exception is
// thrown to the planning thread at its next push() or drain(), as the serial session would have
// thrown it when it released that batch.
//
// Internal to redpost::core; not installed.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace redpost {

template <class Batch>
class DispatchStage {
 public:
  // run(batch) on the stage's thread for every batch pushed, in order.
  explicit DispatchStage(std::function<void(Batch&)> run, std::size_t max_queued = 4)
      : run_(std::move(run)), max_queued_(max_queued) {
    thread_ = std::thread([this] { loop(); });
  }

  ~DispatchStage() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    work_.notify_all();
    thread_.join();
  }

  DispatchStage(const DispatchStage&) = delete;
  DispatchStage& operator=(const DispatchStage&) = delete;

  // Queues a batch (waits while the queue is full); throws the stage's failure, if any.
  void push(Batch&& batch) {
    std::unique_lock<std::mutex> lock(mutex_);
    space_.wait(lock, [&] { return queue_.size() < max_queued_ || error_; });
    if (error_)
      std::rethrow_exception(error_);
    queue_.push_back(std::move(batch));
    lock.unlock();
    work_.notify_one();
  }

  // Waits until every batch pushed has run; throws the stage's failure, if any.
  void drain() const {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return (queue_.empty() && !busy_) || error_; });
    if (error_)
      std::rethrow_exception(error_);
  }

  // The same without throwing: whether a batch failed.
  bool drain_quietly() const {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return (queue_.empty() && !busy_) || error_; });
    return static_cast<bool>(error_);
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_)
        return;  // the session goes: what is queued goes with it
      Batch batch = std::move(queue_.front());
      queue_.pop_front();
      busy_ = true;
      lock.unlock();
      space_.notify_one();
      std::exception_ptr error;
      try {
        run_(batch);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      busy_ = false;
      if (error) {
        error_ = error;
        queue_.clear();
      }
      idle_.notify_all();
      space_.notify_all();
    }
  }

  std::function<void(Batch&)> run_;
  std::size_t max_queued_;
  mutable std::mutex mutex_;
  mutable std::condition_variable work_, space_, idle_;
  std::deque<Batch> queue_;
  bool busy_ = false;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // started once the members above exist
};

}  // namespace redpost
