// The directory side of `redpost diff` (docs/krl-diff.md): the main programs of a folder, found
// by their calls, matched by name between two folders, and their results merged.
#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "krl/diff_source.hpp"
#include "krl/diff_stream.hpp"
#include "krl/reader_parse.hpp"
#include "krl/text.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/krl/diff.hpp"

namespace redpost {

namespace fs = std::filesystem;
using krl::ident_char;
using krl::ident_start;
using krl::upper;

namespace {

void merge(KrlDiffResult& total, const KrlDiffResult& r, const KrlDiffOptions& o) {
  total.equal = total.equal && r.equal;
  total.motions_a += r.motions_a;
  total.motions_b += r.motions_b;
  total.compared += r.compared;
  total.changed += r.changed;
  total.inserted += r.inserted;
  total.removed += r.removed;
  total.difference_count += r.difference_count;
  total.aligned_by_cl_line = total.aligned_by_cl_line || r.aligned_by_cl_line;
  total.window = r.window;
  if (r.unaligned_regions > 0 && total.unaligned_regions == 0) {
    total.unaligned_file_a = r.unaligned_file_a;
    total.unaligned_line_a = r.unaligned_line_a;
    total.unaligned_file_b = r.unaligned_file_b;
    total.unaligned_line_b = r.unaligned_line_b;
  }
  total.unaligned_regions += r.unaligned_regions;
  total.budget_exhausted = total.budget_exhausted || r.budget_exhausted;
  for (const KrlDifference& d : r.differences)
    if (total.differences.size() < o.max_shown)
      total.differences.push_back(d);
  for (const KrlSummaryDifference& s : r.summaries) {
    auto it = std::find_if(total.summaries.begin(), total.summaries.end(),
                           [&](const KrlSummaryDifference& t) { return t.quantity == s.quantity; });
    if (it == total.summaries.end()) {
      total.summaries.push_back(s);
    } else {
      it->count += s.count;
      --total.difference_count;  // one program-wide difference, counted once
    }
  }
  total.path_capped += r.path_capped;
  total.path_examined += r.path_examined;
  if (r.path_distance_mm > total.path_distance_mm || !r.path_exact) {
    if (r.path_distance_mm >= total.path_distance_mm) {
      total.path_distance_mm = r.path_distance_mm;
      total.path_file = r.path_file;
      total.path_line = r.path_line;
    }
    total.path_exact = total.path_exact && r.path_exact;
  }
  for (size_t q = 0; q < total.statistics.size(); ++q) {
    KrlQuantityStats& t = total.statistics[q];
    const KrlQuantityStats& s = r.statistics[q];
    t.compared += s.compared;
    t.over_tolerance += s.over_tolerance;
    t.sum += s.sum;
    t.max = std::max(t.max, s.max);
  }
}

// Both programs read side by side, each on a thread of its own (krl/diff_source.hpp).
KrlDiffResult diff_krl_files(const std::string& a, const std::string& b, const KrlDiffOptions& o) {
  krl::FilePoseSource sa(a), sb(b);
  return krl::diff_pose_streams(sa, sb, o);
}

bool is_src(const fs::path& p) {
  return upper(p.extension().string()) == ".SRC";
}

// Names called as subprograms in a .src: statements of the form NAME( ... ).
std::set<std::string> called_names(const std::string& text) {
  static const std::set<std::string> keywords = {
      "IF",     "WHILE", "FOR",    "REPEAT", "UNTIL",     "SWITCH",  "WAIT",
      "RETURN", "DEF",   "DEFFCT", "GLOBAL", "INTERRUPT", "TRIGGER", "ANIN",
      "ANOUT",  "EXT",   "EXTFCT", "DECL",   "ELSE"};
  std::set<std::string> out;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos)
      eol = text.size();
    size_t i = pos;
    while (i < eol && (text[i] == ' ' || text[i] == '\t'))
      ++i;
    if (i < eol && ident_start(text[i])) {
      size_t j = i;
      while (j < eol && ident_char(text[j]))
        ++j;
      size_t k = j;
      while (k < eol && (text[k] == ' ' || text[k] == '\t'))
        ++k;
      if (k < eol && text[k] == '(') {
        std::string name = upper(text.substr(i, j - i));
        if (!keywords.count(name))
          out.insert(name);
      }
    }
    pos = eol + 1;
  }
  return out;
}

}  // namespace

std::vector<std::string> krl_main_programs(const std::string& directory) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file() && is_src(it->path()))
      files.push_back(it->path());
  }
  if (ec)
    throw Error(ErrorCode::io, "cannot list the directory: " + ec.message(),
                SourceLocation{directory, 0, 0});
  std::set<std::string> called;
  for (const fs::path& f : files) {
    const std::string self = upper(f.stem().string());
    for (const std::string& n : called_names(krl::read_krl_text(f.string())))
      if (n != self)
        called.insert(n);
  }
  std::vector<std::string> out;
  for (const fs::path& f : files)
    if (!called.count(upper(f.stem().string())))
      out.push_back(f.string());
  std::sort(out.begin(), out.end());
  return out;
}

KrlDiffResult diff_krl_paths(const std::string& path_a, const std::string& path_b,
                             const KrlDiffOptions& options) {
  std::error_code ec;
  const bool dir_a = fs::is_directory(path_a, ec), dir_b = fs::is_directory(path_b, ec);
  if (dir_a != dir_b)
    throw Error(ErrorCode::bad_input,
                "cannot compare a directory with a file: '" + path_a + "' and '" + path_b + "'");
  if (!dir_a)
    return diff_krl_files(path_a, path_b, options);

  std::map<std::string, std::string> ma, mb;
  for (const std::string& p : krl_main_programs(path_a))
    ma[upper(fs::path(p).filename().string())] = p;
  for (const std::string& p : krl_main_programs(path_b))
    mb[upper(fs::path(p).filename().string())] = p;
  KrlDiffResult total;
  for (const auto& [name, pa] : ma) {
    auto it = mb.find(name);
    if (it == mb.end()) {
      total.unmatched.push_back("only in A: " + pa);
      continue;
    }
    merge(total, diff_krl_files(pa, it->second, options), options);
  }
  for (const auto& [name, pb] : mb)
    if (!ma.count(name))
      total.unmatched.push_back("only in B: " + pb);
  if (!total.unmatched.empty())
    total.equal = false;
  return total;
}

}  // namespace redpost
