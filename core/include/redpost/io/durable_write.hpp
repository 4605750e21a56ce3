// Output that is never half-written and survives a power cut once redpost says it is done.
//
// Every file goes to a temporary beside its final name (".NAME.part~", hidden, never a name a
// controller or a CAM system loads), is flushed to the disk with fsync, and only then renamed
// into place; after the renames the folder itself is synced, so the new names are durable too.
// A process killed at any moment leaves either the old file or the complete new one under the
// final name, never a truncated one (docs/reliability.md).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace redpost {

// The temporary a final path is written through: ".NAME.part~" in the same folder, so that the
// rename stays within one file system.
std::string temporary_path(const std::string& final_path);

// fflush + fsync of an open file. Throws Error(ErrorCode::io) naming `path_for_message` (a full
// disk and a failing device surface here at the latest).
void flush_to_disk(std::FILE* file, const std::string& path_for_message);

// fsync of a folder, so that renames and removals in it are durable. File systems that cannot
// sync a folder (EINVAL) are accepted silently; any other failure throws Error(ErrorCode::io).
void sync_directory(const std::string& dir);

struct TextOutput {
  std::string path;
  std::string text;
};

// Writes every text to its temporary and flushes it to the disk; only when all of them are
// written does it rename them into place, in the given order (put the file that makes the set
// usable, such as a program's main .src, last), and sync their folders. On a failure before the
// renames, every temporary is removed and no final name is touched. Throws Error(ErrorCode::io)
// naming the file and what to check.
void write_text_files(const std::vector<TextOutput>& files);

inline void write_text_file(const std::string& path, std::string_view text) {
  write_text_files({TextOutput{path, std::string(text)}});
}

}  // namespace redpost
