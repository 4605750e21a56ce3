// Where `redpost diff` takes each program's motions from (docs/krl-diff.md): a program already
// read, or a .src read as it is compared, on a thread of its own, through a bounded queue, so
// that the two programs are read side by side and neither is ever held whole.
//
// Internal to redpost::core; not installed.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "krl/diff_pose.hpp"
#include "redpost/krl/reader.hpp"

namespace redpost::krl {

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // The next motion in execution order; false at the end. Throws the reader's Error (file:line)
  // once every motion before the error has been taken.
  virtual bool next(DiffPose& out) = 0;
};

class ProgramPoseSource final : public PoseSource {
 public:
  explicit ProgramPoseSource(const KrlProgram& p) : program_(p) {}
  bool next(DiffPose& out) override;

 private:
  const KrlProgram& program_;
  PoseCompleter completer_;
  std::size_t next_ = 0;
};

class FilePoseSource final : public PoseSource {
 public:
  explicit FilePoseSource(std::string src_path);
  ~FilePoseSource() override;  // stops the reader if it is still running
  FilePoseSource(const FilePoseSource&) = delete;
  FilePoseSource& operator=(const FilePoseSource&) = delete;
  bool next(DiffPose& out) override;

 private:
  void produce();
  void publish(std::vector<DiffPose>& batch);

  std::string path_;
  PoseCompleter completer_;  // the reader thread's; the poses' strings live here
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<DiffPose>> ready_;  // batches read, not yet taken
  bool done_ = false, stop_ = false;
  std::exception_ptr error_;
  std::vector<DiffPose> current_;  // the batch being taken (the consumer's)
  std::size_t taken_ = 0;
  std::thread thread_;  // last: started once everything above is built
};

}  // namespace redpost::krl
