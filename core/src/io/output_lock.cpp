#include "redpost/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include "redpost/io/error.hpp"
#include "redpost/io/temporaries.hpp"

namespace redpost {

OutputLock::OutputLock(const std::string& folder, const std::string& name) {
  const std::string path = (std::filesystem::path(folder) / ("." + name + ".lock~")).string();
  // A lock file unlinked by the holder between our open and our flock would give us a lock on a
  // file nobody else can see: take the lock, then check that the name still leads to it.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw Error(ErrorCode::io,
                  std::string("cannot create the lock file of the program: ") +
                      std::strerror(errno) + "; check that the output folder is writable",
                  SourceLocation{path, 0, 0});
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd);
      if (err == EWOULDBLOCK) {
        throw Error(ErrorCode::io,
                    "program '" + name +
                        "' is being written into this folder by another redpost run or session; "
                        "wait for it to end, or choose another program name or output folder",
                    SourceLocation{folder, 0, 0});
      }
      throw Error(ErrorCode::io, std::string("cannot lock the program: ") + std::strerror(err),
                  SourceLocation{path, 0, 0});
    }
    struct stat by_fd {
    }, by_name{};
    if (::fstat(fd, &by_fd) == 0 && ::lstat(path.c_str(), &by_name) == 0 &&
        by_fd.st_dev == by_name.st_dev && by_fd.st_ino == by_name.st_ino) {
      path_ = path;
      fd_ = fd;
      register_temporary(path_);
      return;
    }
    ::close(fd);
  }
  throw Error(ErrorCode::io, "cannot lock the program: its lock file keeps changing",
              SourceLocation{path, 0, 0});
}

OutputLock::~OutputLock() {
  release();
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : path_(std::exchange(other.path_, {})), fd_(std::exchange(other.fd_, -1)) {}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    path_ = std::exchange(other.path_, {});
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

// Unlinked while still locked: a writer waiting to open the name either opens this inode (and
// sees it unlinked after its flock) or creates a new file.
void OutputLock::release() noexcept {
  if (fd_ < 0)
    return;
  remove_temporary(path_);
  ::close(fd_);
  fd_ = -1;
}

}  // namespace redpost
