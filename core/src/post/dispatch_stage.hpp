// The second stage of a session's pipeline (PostOptions::plan_threads, docs/redundancy.md
// "Threads"): the session's own thread reads the events and plans the windows of the whole-path
// plan; this stage's thread tracks and writes the calls each window releases, in order, while
// the next window is planned. Batches go through a bounded queue, so memory stays flat.
//
// Between batches the stage's thread helps with the plan's loops (WorkerPool::help), if it is
// given the pool: on two cores the planning thread has the other core for a lattice layer's
// nodes whenever the tracking has caught up. It polls for a while before it sleeps.
//
// A batch that throws fails the stage: the batches after it are dropped, and the exception is
// thrown to the planning thread at its next push() or drain(), as the serial session would have
// thrown it when it released that batch.
//
// Internal to redpost::core; not installed.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include "redpost/redundancy/worker_pool.hpp"

namespace redpost {

template <class Batch>
class DispatchStage {
 public:
  // run(batch) on the stage's thread for every batch pushed, in order; between batches the
  // thread helps `pool` (nullptr: none; it must outlive the stage).
  explicit DispatchStage(std::function<void(Batch&)> run, WorkerPool* pool = nullptr,
                         std::size_t max_queued = 4)
      : run_(std::move(run)), pool_(pool), max_queued_(max_queued) {
    if (pool_) {
      pool_->attach_helper([this] {
        std::lock_guard<std::mutex> lock(mutex_);
        work_.notify_one();
      });
    }
    thread_ = std::thread([this] { loop(); });
  }

  ~DispatchStage() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      stopping_.store(true);
    }
    work_.notify_all();
    thread_.join();
    if (pool_)
      pool_->attach_helper({});
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
    queued_.store(queue_.size());
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
  // Until a batch comes (or the stage stops): the pool's loops meanwhile. Called and returns
  // with the lock held; polls without it.
  void help_until_work(std::unique_lock<std::mutex>& lock) {
    lock.unlock();
    int k = 0;
    while (queued_.load() == 0 && !stopping_.load()) {
      if (pool_->loop_open()) {
        pool_->help();
        k = 0;
      } else if (k < WorkerPool::kPollsBeforeSleep) {
        WorkerPool::poll_pause(k++);
      } else {
        lock.lock();
        pool_->helper_sleeping(true);
        work_.wait(lock, [&] { return stop_ || !queue_.empty() || pool_->loop_open(); });
        pool_->helper_sleeping(false);
        lock.unlock();
        k = 0;
      }
    }
    lock.lock();
  }

  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (pool_)
        help_until_work(lock);
      work_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_)
        return;  // the session goes: what is queued goes with it
      Batch batch = std::move(queue_.front());
      queue_.pop_front();
      queued_.store(queue_.size());
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
        queued_.store(0);
      }
      idle_.notify_all();
      space_.notify_all();
    }
  }

  std::function<void(Batch&)> run_;
  WorkerPool* pool_;
  std::size_t max_queued_;
  mutable std::mutex mutex_;
  mutable std::condition_variable work_, space_, idle_;
  std::deque<Batch> queue_;
  bool busy_ = false;
  bool stop_ = false;
  std::atomic<std::size_t> queued_{0};  // queue_.size(), and stop_, for the polls without the lock
  std::atomic<bool> stopping_{false};
  std::exception_ptr error_;
  std::thread thread_;  // started once the members above exist
};

}  // namespace redpost
