// The temporaries of output files: each one unique, created where nothing stood (never through a
// symbolic link or into another process's file), and removed when the process ends before it
// was renamed: at exit(), and from a signal handler the host installs (docs/reliability.md).
//
// Two writers of the same final name get two temporaries: they cannot write into each other's
// bytes, whatever else they do. A temporary is ".NAME.XXXXXXXX.part~" beside its final name, so
// that the rename stays within one file system and the name is never one a controller loads.
#pragma once

#include <signal.h>

#include <cstdio>
#include <string>

namespace redpost {

struct Temporary {
  std::string path;
  std::FILE* file = nullptr;  // open for writing, fully buffered
};

// Creates a new temporary for `final_path` with O_CREAT | O_EXCL | O_NOFOLLOW and registers it
// for clean-up. Throws Error(ErrorCode::io) naming `final_path` when the folder cannot take it.
Temporary create_temporary(const std::string& final_path);

// Creates a new, empty file with O_CREAT | O_EXCL | O_NOFOLLOW beside `final_path`, named
// ".NAME.XXXXXXXX<suffix>"; returns its path and leaves it closed (not registered).
std::string create_unique_beside(const std::string& final_path, const char* suffix);

// Registers a path made otherwise (a lock file) for clean-up.
void register_temporary(const std::string& path);

// The temporary was renamed or removed by its owner: it is no longer cleaned up.
void forget_temporary(const std::string& path) noexcept;

// Removes the file and forgets it.
void remove_temporary(const std::string& path) noexcept;

// Removes every registered temporary that still exists. Async-signal-safe: it only walks a
// list that is never freed and calls unlink(2), so a host's SIGTERM handler may call it (the
// C ABI exports it as rp_remove_temporaries). Also run at exit().
void remove_all_temporaries() noexcept;

// A stretch of this thread in which a stop request must not land: creating and registering a
// temporary, swapping a program's files in. SIGTERM, SIGINT and SIGHUP are held back in this
// thread meanwhile, and stop_and_remove_temporaries(), on whichever thread a stop signal's
// handler runs, waits for every section under way to end. Once a stop was requested, a thread
// that would enter a section waits for the process to end instead: with several threads writing
// (the pipeline), a temporary made after the handler's clean-up would otherwise be left behind.
class FileSection {
 public:
  FileSection();
  ~FileSection();
  FileSection(const FileSection&) = delete;
  FileSection& operator=(const FileSection&) = delete;

 private:
  sigset_t old_;
};

// For a stop signal's handler, before the process ends: no section begins from now on, the
// sections under way are waited for (at most 5 s: a swap's renames), then every registered
// temporary is removed. Async-signal-safe (atomics, nanosleep(2), unlink(2)).
void stop_and_remove_temporaries() noexcept;

}  // namespace redpost
