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
#include "redpost/io/output_target.hpp"
#include "redpost/io/temporaries.hpp"

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
  // Every line ends without trailing blanks (an empty {tool_name} must not leave one).
  converted.clear();
  const auto end_line = [&] {
    while (!converted.empty() && (converted.back() == ' ' || converted.back() == '\t'))
      converted.pop_back();
    converted += krl::kEol;
  };
  for (char ch : text) {
    if (ch == '\n')
      end_line();
    else
      converted += ch;
  }
  end_line();
  if (std::fwrite(converted.data(), 1, converted.size(), f) != converted.size()) {
    throw Error(ErrorCode::io, write_failure_text(),
                SourceLocation{files[file_index].final_path, 0, 0});
  }
  if (f == src_out)
    module_bytes += static_cast<long>(converted.size());
}

// The bytes `text` takes in a file: every line with its CRLF.
long KrlWriter::Impl::count_bytes(std::string_view text) const {
  if (text.empty())
    return 0;
  long n = static_cast<long>(text.size()) + static_cast<long>(krl::kEol.size());
  for (char ch : text)
    n += ch == '\n' ? static_cast<long>(krl::kEol.size()) - 1 : 0;
  return n;
}

size_t KrlWriter::Impl::create(const std::string& file_name, std::FILE*& f) {
  File file;
  file.final_path = (fs::path(info.output_dir) / file_name).string();
  // A folder, a device or a link under a final name shows now, not after the whole path.
  check_output_target(file.final_path, "the program file");
  Temporary temp = create_temporary(file.final_path);
  file.temp = std::move(temp.path);
  f = temp.file;
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
    if (sk[i].block == Ph::frames) {
      put(f, file_index, frames_text(header_tool));
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
    if (f == src_out)
      module_bytes += static_cast<long>(converted.size());
  }
  return sk.size();
}

std::string KrlWriter::Impl::frames_text(const ToolInForce& tool) {
  Values v;
  std::string out = render(info.base_coupled ? Stmt::base_coupled : Stmt::base_static, v);
  v.tool = tool.tool;
  v.tool_data = tool.tool_data;
  v.load_data = tool.load_data;
  const std::string select = render(Stmt::tool_select, v);
  if (!out.empty() && !select.empty())
    out += '\n';
  return out + select;
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

void KrlWriter::Impl::open_module(const std::string& name, bool continued) {
  write_dat(name, tpl.dat, "file dat");
  module = name;
  header_tool = current_tool;
  module_src = continued ? &tpl.continued_src : &tpl.src;
  const krl::Skeleton& sk = *module_src;
  out_index = create(name + ".src", src_out);
  module_bytes = 0;
  put_skeleton(src_out, out_index, sk, 0, continued ? "file continued_src" : "file src", [](Ph) {});
  header_bytes = module_bytes;
  // What close_module() will add: the skeleton after {body} (it names only this module).
  footer_bytes = 0;
  for (size_t i = body_line(sk) + 1; i < sk.size(); ++i) {
    line.clear();
    if (sk[i].block == Ph::frames) {
      line = frames_text(header_tool);
    } else {
      current = "file src";
      render_into(line, sk[i].text, Values{});
    }
    footer_bytes += static_cast<long>(line.size() + krl::kEol.size());
  }
  motions_in_module = 0;
}

void KrlWriter::Impl::close_module() {
  end_spline();
  put_skeleton(src_out, out_index, *module_src, body_line(*module_src) + 1, "file src", [](Ph) {});
  close(src_out, out_index);
}

void KrlWriter::Impl::next_part(bool continued) {
  if (static_cast<int>(parts.size()) == krl::kMaxParts) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}' needs more than {} parts ({} motions or {} bytes "
                            "each); raise motions_per_file or max_file_bytes",
                            info.name, krl::kMaxParts, info.motions_per_file, budget));
  }
  parts.push_back(fmt::format("{}{}{:03}", info.name, krl::kPartInfix, parts.size() + 1));
  open_module(parts.back(), continued);
}

// A part ends before `needed` more bytes would take its .src beyond the budget. The slack covers
// the restated state and a spline block's end, written after the check.
void KrlWriter::Impl::ensure_room(long needed) {
  constexpr long kSlack = 512;
  if (budget <= 0 || !have_last)
    return;
  if (module_bytes + needed + footer_bytes + kSlack <= budget)
    return;
  // No place out of the material came in the budget's last quarter: the part ends here, after a
  // motion that may end in the cut (end_part() continues the cut if the set can).
  end_part();
}

bool KrlWriter::Impl::part_nearly_full() const {
  return budget > 0 && have_last && 4 * (module_bytes + footer_bytes) >= 3 * budget;
}

// After a motion out of the material the next part starts as a program of its own: it restates
// the tool, spindle and coolant and starts with its BCO run, a PTP to where the robot stands (an
// exact stop, out of the cut). After a motion that may end in the cut it continues the cut: with
// the set's continued_src, no BCO run and nothing that stops the advance run, so the controller
// blends across the call; without one, as a program of its own (a stop in the cut).
void KrlWriter::Impl::end_part() {
  const bool in_cut = !last_in_air;
  const bool continued = in_cut && !tpl.continued_src.empty();
  if (in_cut) {
    if (split.mid_cut_lines.size() < 10)
      split.mid_cut_lines.push_back(last_cl_line);
    ++split.mid_cut;
    split.continued += continued ? 1 : 0;
  }
  if (parts.empty())
    promote_first_module();
  close_module();
  next_part(continued);
  restate(continued);
}

// The program outgrew one file: what was written as NAME becomes its first part, NAME_P001.
// The statements after the header are copied into a file with the part's header (at most one
// budget of bytes, once); the main program is written at finish() as with motions_per_file.
void KrlWriter::Impl::promote_first_module() {
  if (info.name.size() + krl::kPartSuffixLength > krl::kMaxIdentifierLength) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("program '{}' is larger than {} bytes and must be split, but its name has {} "
                    "characters: its parts would be named {}{}001, longer than a KRL name's {}; "
                    "use a name of at most {} characters, or raise the byte limit",
                    info.name, budget, info.name.size(), info.name, krl::kPartInfix,
                    krl::kMaxIdentifierLength, krl::kMaxIdentifierLength - krl::kPartSuffixLength));
  }
  if (std::fflush(src_out) != 0) {
    throw Error(ErrorCode::io, write_failure_text(),
                SourceLocation{files[out_index].final_path, 0, 0});
  }
  std::fclose(src_out);
  src_out = nullptr;
  const File old_src = files[out_index];
  const File old_dat = files[out_index - 1];
  files.erase(files.begin() + static_cast<long>(out_index) - 1, files.end());
  remove_temporary(old_dat.temp);

  const long first_header = header_bytes;
  const ToolInForce tool_now = current_tool;
  current_tool = header_tool;  // the part's header sets the tool the program started with
  parts.push_back(fmt::format("{}{}{:03}", info.name, krl::kPartInfix, 1));
  open_module(parts.back());
  current_tool = tool_now;

  std::FILE* in = std::fopen(old_src.temp.c_str(), "rb");
  bool ok = in && std::fseek(in, first_header, SEEK_SET) == 0;
  char buffer[1 << 16];
  while (ok) {
    const size_t n = std::fread(buffer, 1, sizeof buffer, in);
    if (n == 0) {
      ok = !std::ferror(in);
      break;
    }
    ok = std::fwrite(buffer, 1, n, src_out) == n;
    module_bytes += static_cast<long>(n);
  }
  if (in)
    std::fclose(in);
  remove_temporary(old_src.temp);
  if (!ok) {
    throw Error(ErrorCode::io, write_failure_text(),
                SourceLocation{files[out_index].final_path, 0, 0});
  }
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

// Only now do the files get their names, as one swap (replace_files): the old program of the
// same name is moved aside, its main .src first, and put back whole if any file cannot be
// renamed in; the new main .src comes last. A kill inside the swap leaves new parts or a new
// .dat without any main .src, never an old main .src that would run beside (or call) new files.
void KrlWriter::Impl::rename_files() {
  std::vector<Replacement> swap;
  swap.reserve(files.size());
  for (const File& f : files)
    swap.push_back(Replacement{f.temp, f.final_path});
  for (File& f : files)
    f.renamed = true;  // replace_files() owns the temporaries now, and removes them on failure
  replace_files(swap);
}

}  // namespace redpost
