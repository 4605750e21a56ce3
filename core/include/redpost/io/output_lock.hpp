// One writer per program: a second process (or session) that starts writing a program of the
// same name into the same folder while the first is still at it gets a clear error at once,
// instead of the two racing to rename their files over each other.
//
// The lock is an flock(2) on ".NAME.lock~" in the output folder, taken without waiting and held
// until the writer ends; the file is removed when the lock is released (and at exit or on a
// signal, with the temporaries). flock locks are released by the kernel when a process dies, so
// a killed run never blocks the next one.
#pragma once

#include <string>

namespace redpost {

class OutputLock {
 public:
  OutputLock() = default;
  // Throws Error(ErrorCode::io) when another writer holds the lock of `name` in `folder`, or the
  // folder cannot take the lock file.
  OutputLock(const std::string& folder, const std::string& name);
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;

 private:
  void release() noexcept;
  std::string path_;
  int fd_ = -1;
};

}  // namespace redpost
