// What an output path may name. redpost replaces a file by renaming a finished temporary over it,
// so a path that names something other than a regular file (a folder, a device, a FIFO, a
// symbolic link such as one to /proc/self/fd/1) would be replaced by a regular file: refused.
// A path that names one of the run's inputs, or another of its outputs, would destroy the input
// or the other output: refused before anything is read or written.
#pragma once

#include <string>
#include <vector>

namespace redpost {

// Throws Error(ErrorCode::io) naming `path` when it exists and is not a regular file (or is a
// symbolic link). `what` says which output it is ("--report", "the program file").
void check_output_target(const std::string& path, const std::string& what);

// Throws Error(ErrorCode::io) naming `path` when the folder that would hold it does not exist or
// is not writable: for an output written after others, so that it cannot fail once they are.
void check_output_folder(const std::string& path, const std::string& what);

// True when both paths name the same file: the same inode if both exist, else the same path
// once made absolute and normal (symbolic links in existing folders resolved).
bool same_file(const std::string& a, const std::string& b);

struct NamedPath {
  std::string role;  // "the CL input", "--cell", "--report"
  std::string path;  // empty: not given, skipped
};

// Every output must differ from every input and from every other output. Throws
// Error(ErrorCode::io) naming the output and the role it clashes with.
void check_distinct_files(const std::vector<NamedPath>& inputs,
                          const std::vector<NamedPath>& outputs);

}  // namespace redpost
