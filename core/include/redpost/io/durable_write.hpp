// Output that is never half-written, never a mix of an old and a new set of files, and survives
// a power cut once redpost says it is done.
//
// Every file goes to a unique temporary beside its final name (temporaries.hpp), is flushed to
// the disk with fsync, and only then renamed into place; after the renames the folder itself is
// synced, so the new names are durable too. The renames of a set of files (a split program) are
// one transaction: the old files are moved aside first, and if any rename fails they are put
// back, so a run that cannot complete keeps the old set whole (docs/reliability.md).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace redpost {

// fflush + fsync of an open file. Throws Error(ErrorCode::io) naming `path_for_message` (a full
// disk and a failing device surface here at the latest).
void flush_to_disk(std::FILE* file, const std::string& path_for_message);

// fsync of a folder, so that renames and removals in it are durable. File systems that cannot
// sync a folder (EINVAL) are accepted silently; any other failure throws Error(ErrorCode::io).
void sync_directory(const std::string& dir);

struct Replacement {
  std::string temp;        // a finished, flushed temporary (create_temporary)
  std::string final_path;  // the name it gets
};

// Renames every temporary to its final name, all or nothing:
//  1. every final name must be free or a regular file (check_output_target);
//  2. the existing files are moved aside to ".NAME.XXXXXXXX.old~", the last one first;
//  3. the temporaries are renamed in, in the given order (put the file that makes the set
//     usable, such as a program's main .src, last);
//  4. the files moved aside are removed, and the folders synced.
// When a step fails, the new files are taken out, the old ones put back, every temporary is
// removed, and Error(ErrorCode::io) names the file and says that the old files were kept.
// SIGTERM, SIGINT and SIGHUP are held back for the few microseconds of steps 2-4, so that a
// stop request lands before or after the swap, never inside it; a SIGKILL there leaves the
// set without its last file (nothing that runs) and the old files under their ".old~" names.
void replace_files(const std::vector<Replacement>& files);

struct TextOutput {
  std::string path;
  std::string text;
};

// A set of text files written to their temporaries and flushed, not yet renamed: commit() gives
// them their names (replace_files); destroying it uncommitted removes the temporaries.
class PreparedTexts {
 public:
  explicit PreparedTexts(const std::vector<TextOutput>& files);
  ~PreparedTexts();
  PreparedTexts(const PreparedTexts&) = delete;
  PreparedTexts& operator=(const PreparedTexts&) = delete;
  void commit();

 private:
  std::vector<Replacement> files_;
};

// Writes every text to its temporary and flushes it to the disk; only when all of them are
// written does it rename them into place (replace_files). Throws Error(ErrorCode::io) naming
// the file and what to check.
void write_text_files(const std::vector<TextOutput>& files);

inline void write_text_file(const std::string& path, std::string_view text) {
  write_text_files({TextOutput{path, std::string(text)}});
}

}  // namespace redpost
