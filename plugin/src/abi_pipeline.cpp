// The pipeline of a session (rp_options.pipeline): the host's thread makes the events (reads a
// CL file, runs NX's handlers) and expands and reduces them (PostSession::front), while a thread
// of the session's own plans, tracks and writes what comes out, in order (route_front). The
// items go in batches through a bounded queue, so memory stays flat and the program is the one
// the same events give without the pipeline, byte for byte, with the same warnings.
//
// An event that fails on the session's thread fails the session; the host's next call (an
// event, rp_prepare, rp_close) returns that event's status and message, as the event itself
// would have. Every query waits for the queue to be empty first, so it sees every event sent.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "abi_internal.hpp"

namespace redpost::abi {

struct Pipeline {
  struct Job {
    redpost::PostSession::FrontItem item;
    long index = 0;  // the number of the event that gave it, for "event N: " in a message
  };
  static constexpr std::size_t kBatch = 256;      // events per hand-over
  static constexpr std::size_t kMaxBatches = 32;  // queued at most: memory stays flat

  std::mutex m;
  std::condition_variable work, space, idle;
  std::deque<std::vector<Job>> queue;
  std::vector<Job> open;  // the host's batch being filled
  bool busy = false;      // the thread is tracking a batch
  bool stop = false;
  // The first failure on the thread; the rest of the events are dropped after it.
  bool failed = false;
  std::atomic<bool> failed_flag{false};  // the same, for the host's check at every event
  bool told = false;
  rp_status status = RP_OK;
  std::string message;
  int line = 0;
  std::thread thread;

  ~Pipeline() {
    {
      std::lock_guard<std::mutex> lock(m);
      stop = true;
    }
    work.notify_all();
    if (thread.joinable())
      thread.join();
  }

  void hand_over() {
    if (open.empty())
      return;
    std::unique_lock<std::mutex> lock(m);
    space.wait(lock, [&] { return queue.size() < kMaxBatches || failed; });
    if (!failed)
      queue.push_back(std::move(open));
    lock.unlock();
    work.notify_one();
    open.clear();
    open.reserve(kBatch);
  }

  void wait_idle() {
    hand_over();
    std::unique_lock<std::mutex> lock(m);
    idle.wait(lock, [&] { return queue.empty() && !busy; });
  }

  void run(rp_session* session) {
    for (;;) {
      std::vector<Job> batch;
      {
        std::unique_lock<std::mutex> lock(m);
        work.wait(lock, [&] { return stop || !queue.empty(); });
        if (stop)
          return;
        batch = std::move(queue.front());
        queue.pop_front();
        busy = true;
      }
      space.notify_one();
      for (Job& job : batch) {
        if (failed)
          break;
        std::string error;
        int error_line = 0;
        const rp_status st = guard(error, "event " + std::to_string(job.index) + ": ", [&] {
          try {
            session->post->route_front(job.item);
          } catch (const Error& e) {
            error_line = e.where().line;
            throw;
          }
        });
        if (st != RP_OK) {
          std::lock_guard<std::mutex> lock(m);
          failed = true;
          failed_flag = true;
          status = st;
          message = std::move(error);
          line = error_line;
        }
      }
      {
        std::lock_guard<std::mutex> lock(m);
        busy = false;
        if (failed)
          queue.clear();
      }
      idle.notify_all();
      space.notify_all();
    }
  }
};

}  // namespace redpost::abi

using redpost::abi::Pipeline;

rp_session::rp_session() = default;

rp_session::~rp_session() {
  pipeline.reset();
}

void rp_session::start_pipeline() {
  pipeline = std::make_unique<Pipeline>();
  pipeline->open.reserve(Pipeline::kBatch);
  // The thread gets the pipeline itself: rp_free may come before it first runs, and the
  // pointer member is cleared before the pipeline is destroyed.
  Pipeline* p = pipeline.get();
  p->thread = std::thread([p, this] { p->run(this); });
}

void rp_session::submit(redpost::ClEvent&& e) {
  if (!pipeline) {
    post->handle(e);
    return;
  }
  Pipeline& p = *pipeline;
  front_items.clear();
  const auto queue = [&] {
    for (redpost::PostSession::FrontItem& item : front_items) {
      p.open.push_back(Pipeline::Job{std::move(item), events});
      if (p.open.size() >= Pipeline::kBatch)
        p.hand_over();
    }
  };
  try {
    post->front(e, front_items);
  } catch (...) {
    // What came before the error is tracked first, as handle() would have; a failure there, or
    // on the plan's tracking thread, is the error (rethrow_earlier), as without the pipeline.
    queue();
    p.wait_idle();
    if (p.failed_flag.load(std::memory_order_acquire))
      return;  // the next call (or rp_prepare) tells it
    post->rethrow_earlier();
    throw;
  }
  queue();
}

void rp_session::sync() const {
  if (pipeline)
    pipeline->wait_idle();
}

rp_status rp_session::take_pipeline_failure() {
  if (!pipeline)
    return RP_OK;
  Pipeline& p = *pipeline;
  if (!p.failed_flag.load(std::memory_order_acquire))
    return RP_OK;
  {
    std::lock_guard<std::mutex> lock(p.m);
    if (!p.failed || p.told)
      return RP_OK;
    p.told = true;
  }
  p.wait_idle();
  state = State::failed;
  error = p.message;
  failure = p.message;
  error_line = p.line;
  return p.status;
}
