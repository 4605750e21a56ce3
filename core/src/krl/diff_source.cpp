// The programs `redpost diff` compares, as streams of motions (krl/diff_source.hpp).
#include "krl/diff_source.hpp"

#include <utility>

namespace redpost::krl {

namespace {

// 512 motions a batch, at most 8 batches waiting: about 1 MB of poses per program in flight,
// and the lock taken once per 512 motions.
constexpr std::size_t kBatch = 512;
constexpr std::size_t kMaxWaiting = 8;

// Thrown through the reader to stop it when the diff ends early (an error on the other side).
struct Stopped {};

}  // namespace

bool ProgramPoseSource::next(DiffPose& out) {
  if (next_ >= program_.motions.size())
    return false;
  out = completer_.complete(program_.motions[next_++]);
  return true;
}

FilePoseSource::FilePoseSource(std::string src_path) : path_(std::move(src_path)) {
  thread_ = std::thread([this] { produce(); });
}

FilePoseSource::~FilePoseSource() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void FilePoseSource::publish(std::vector<DiffPose>& batch) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return ready_.size() < kMaxWaiting || stop_; });
  if (stop_)
    throw Stopped{};
  ready_.push_back(std::move(batch));
  lock.unlock();
  changed_.notify_all();
  batch.clear();
  batch.reserve(kBatch);
}

void FilePoseSource::produce() {
  std::exception_ptr error;
  try {
    std::vector<DiffPose> batch;
    batch.reserve(kBatch);
    read_krl_program(path_, [&](const KrlMotionRecord& m) {
      batch.push_back(completer_.complete(m));
      if (batch.size() == kBatch)
        publish(batch);
    });
    if (!batch.empty())
      publish(batch);
  } catch (const Stopped&) {
  } catch (...) {
    error = std::current_exception();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = error;
    done_ = true;
  }
  changed_.notify_all();
}

bool FilePoseSource::next(DiffPose& out) {
  if (taken_ < current_.size()) {
    out = current_[taken_++];
    return true;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return !ready_.empty() || done_; });
  if (!ready_.empty()) {
    current_ = std::move(ready_.front());
    ready_.pop_front();
    lock.unlock();
    changed_.notify_all();
    taken_ = 0;
    out = current_[taken_++];
    return true;
  }
  if (error_) {
    std::exception_ptr e = std::exchange(error_, nullptr);
    std::rethrow_exception(e);
  }
  return false;
}

}  // namespace redpost::krl
