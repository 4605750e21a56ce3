// The program files of the KRL writer: temporary files written line by line, the skeleton
// around each program's statements, the parts of a split program and its main program, and the
// renames that give the files their final names only once the whole program is written.
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "krl/writer_impl.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace fs = std::filesystem;
using krl::Ph;
using krl::Stmt;

namespace krl {

std::string errno_text() {
  return std::strerror(errno);
}

}  // namespace krl

namespace {

// A failed write of a program file (nothing gets a final name: see finish()).
std::string write_failure_text() {
  return "cannot write: " + krl::errno_text() +
         "; check the free space and the file size limit (ulimit -f); no program was written";
}

}  // namespace

// --- output ----------------------------------------------------------------------------------
void KrlWriter::Impl::put(std::FILE* f, size_t file_index, std::string_view text) {
  if (text.empty())
    return;
  if (!f) {
    throw Error(ErrorCode::internal,
                "KRL writer: no file open (an earlier error or finish() ended this program)");
  }
  converted.clear();
  for (char ch : text) {
    if (ch == '\n')
      converted += krl::kEol;
    else
      converted += ch;
  }
  converted += krl::kEol;
  if (std::fwrite(converted.data(), 1, converted.size(), f) != converted.size()) {
    throw Error(ErrorCode::io, write_failure_text(),
                SourceLocation{files[file_index].final_path, 0, 0});
  }
}

size_t KrlWriter::Impl::create(const std::string& file_name, std::FILE*& f) {
  File file;
  file.final_path = (fs::path(info.output_dir) / file_name).string();
  file.temp = (fs::path(info.output_dir) / ("." + file_name + ".part~")).string();
  f = std::fopen(file.temp.c_str(), "wb");
  if (!f) {
    throw Error(ErrorCode::io, "cannot create a file in the output directory: " + krl::errno_text(),
                SourceLocation{file.final_path, 0, 0});
  }
  std::setvbuf(f, nullptr, _IOFBF, 1 << 16);
  files.push_back(std::move(file));
  return files.size() - 1;
}

// Closes a finished file, flushed to the disk first (durable_write.hpp): its rename in
// finish() must never give a final name to data still in the page cache.
void KrlWriter::Impl::close(std::FILE*& f, size_t file_index) {
  std::FILE* file = f;
  f = nullptr;
  const bool failed = std::ferror(file) != 0;
  if (!failed) {
    try {
      flush_to_disk(file, files[file_index].final_path);
    } catch (...) {
      std::fclose(file);
      throw;
    }
  }
  const int rc = std::fclose(file);
  if (failed || rc != 0) {
    throw Error(ErrorCode::io, write_failure_text(),
                SourceLocation{files[file_index].final_path, 0, 0});
  }
}

template <class Block>
size_t KrlWriter::Impl::put_skeleton(std::FILE* f, size_t file_index, const krl::Skeleton& sk,
                                     size_t from, std::string_view file_kind, Block&& block) {
  for (size_t i = from; i < sk.size(); ++i) {
    if (sk[i].block == Ph::body)
      return i;
    if (sk[i].block == Ph::decls) {
      block(Ph::decls);
      continue;
    }
    current = file_kind;
    line.clear();
    render_into(line, sk[i].text, Values{});
    // A skeleton line is written even when empty: blank lines are part of the layout.
    converted.assign(line);
    converted += krl::kEol;
    if (std::fwrite(converted.data(), 1, converted.size(), f) != converted.size()) {
      throw Error(ErrorCode::io, write_failure_text(),
                  SourceLocation{files[file_index].final_path, 0, 0});
    }
  }
  return sk.size();
}

// --- modules ---------------------------------------------------------------------------------
void KrlWriter::Impl::write_dat(const std::string& name, const krl::Skeleton& sk,
                                std::string_view kind) {
  module = name;
  std::FILE* f = nullptr;
  const size_t idx = create(name + ".dat", f);
  try {
    put_skeleton(f, idx, sk, 0, kind, [](Ph) {});
    close(f, idx);
  } catch (...) {
    if (f)
      std::fclose(f);
    throw;
  }
}

size_t KrlWriter::Impl::body_line(const krl::Skeleton& sk) const {
  for (size_t i = 0; i < sk.size(); ++i) {
    if (sk[i].block == Ph::body)
      return i;
  }
  return sk.size();
}

void KrlWriter::Impl::open_module(const std::string& name) {
  write_dat(name, tpl.dat, "file dat");
  module = name;
  out_index = create(name + ".src", src_out);
  put_skeleton(src_out, out_index, tpl.src, 0, "file src", [](Ph) {});
  motions_in_module = 0;
}

void KrlWriter::Impl::close_module() {
  end_spline();
  put_skeleton(src_out, out_index, tpl.src, body_line(tpl.src) + 1, "file src", [](Ph) {});
  close(src_out, out_index);
}

void KrlWriter::Impl::next_part() {
  if (static_cast<int>(parts.size()) == krl::kMaxParts) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}' needs more than {} parts of {} motions; raise "
                            "motions_per_file",
                            info.name, krl::kMaxParts, info.motions_per_file));
  }
  parts.push_back(fmt::format("{}{}{:03}", info.name, krl::kPartInfix, parts.size() + 1));
  open_module(parts.back());
}

// The main program of a split program: calls the parts in order.
void KrlWriter::Impl::write_main_program() {
  write_dat(info.name, tpl.main_dat, "file main_dat");
  module = info.name;
  std::FILE* f = nullptr;
  const size_t idx = create(info.name + ".src", f);
  try {
    const auto calls = [&](Stmt s) {
      for (const std::string& part : parts) {
        Values v;
        v.callee = part;
        put(f, idx, render(s, v));
      }
    };
    const size_t body =
        put_skeleton(f, idx, tpl.main_src, 0, "file main_src", [&](Ph) { calls(Stmt::call_decl); });
    calls(Stmt::call);
    module = info.name;
    put_skeleton(f, idx, tpl.main_src, body + 1, "file main_src",
                 [&](Ph) { calls(Stmt::call_decl); });
    close(f, idx);
  } catch (...) {
    if (f)
      std::fclose(f);
    throw;
  }
}

// Only now do the files get their names, the main .src last. An older program of the same
// name loses its main .src first: a kill between two renames then leaves new parts or a new
// .dat without any main .src, never an old main .src that would run beside (or call) new files.
void KrlWriter::Impl::rename_files() {
  const std::string& main_src = files.back().final_path;
  if (std::remove(main_src.c_str()) != 0 && errno != ENOENT) {
    throw Error(ErrorCode::io, "cannot replace the existing program: " + krl::errno_text(),
                SourceLocation{main_src, 0, 0});
  }
  for (File& f : files) {
    if (std::rename(f.temp.c_str(), f.final_path.c_str()) != 0) {
      throw Error(ErrorCode::io,
                  "cannot rename " + f.temp + " to its final name: " + krl::errno_text(),
                  SourceLocation{f.final_path, 0, 0});
    }
    f.renamed = true;
  }
  sync_directory(info.output_dir);
}

}  // namespace redpost
