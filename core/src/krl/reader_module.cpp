// The KRL reader's lines and modules: splitting lines and comments, and the index of a module
// (its DEFs, and the points declared in it and in the .dat beside it).
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <unordered_map>

#include "io/text_util.hpp"
#include "krl/reader_parse.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"

namespace redpost::krl {

namespace fs = std::filesystem;
using detail::trim;

// --- lines -----------------------------------------------------------------------------------

// Splits on LF, CRLF or CR: views into `text`, which must outlive them.
std::vector<std::string_view> split_lines(const std::string& text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\r' || c == '\n') {
      lines.emplace_back(text.data() + start, i - start);
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n')
        ++i;
      start = i + 1;
    }
  }
  if (start < text.size())
    lines.emplace_back(text.data() + start, text.size() - start);
  return lines;
}

// The whole file, its bytes as they are (CRLF, LF or CR line ends), with the limits of
// for_each_krl_line: a line longer than any KRL line is refused as soon as it is seen (memory
// stays bounded on a file that is no program), and the whole file at kMaxKrlFileBytes.
std::string read_krl_text(const std::string& path) {
  std::string text;
  for_each_krl_line(path, [&](int, const std::string& line, std::string_view ending) {
    text += line;
    text += ending;
    return true;
  });
  return text;
}

std::size_t for_each_krl_line(const std::string& path, const KrlLineVisitor& visit) {
  std::ifstream in = open_text_stream(path);
  std::streambuf* buf = in.rdbuf();
  std::string line_text;
  int line = 1;
  std::size_t bytes = 0;
  for (int c = buf->sbumpc();; c = buf->sbumpc()) {
    if (c == std::char_traits<char>::eof()) {
      if (!line_text.empty())
        visit(line, line_text, "");
      break;
    }
    ++bytes;
    if (c == '\r' || c == '\n') {
      std::string_view ending = "\n";
      if (c == '\r') {
        if (buf->sgetc() == '\n') {
          buf->sbumpc();
          ++bytes;
          ending = "\r\n";
        } else {
          ending = "\r";
        }
      }
      if (!visit(line, line_text, ending))
        return bytes;
      line_text.clear();
      ++line;
      continue;
    }
    line_text += static_cast<char>(c);
    if (line_text.size() > kMaxKrlLineBytes) {
      throw Error(ErrorCode::bad_input,
                  "a line longer than " + std::to_string(kMaxKrlLineBytes) +
                      " bytes: no KRL program has one (is it the right file?)",
                  SourceLocation{path, line, 0});
    }
    if (bytes > kMaxKrlFileBytes) {
      throw Error(ErrorCode::io,
                  "file has more than " + std::to_string(kMaxKrlFileBytes) +
                      " bytes, far beyond any controller's program: is it the right file?",
                  SourceLocation{path, 0, 0});
    }
  }
  if (in.bad()) {
    throw Error(ErrorCode::io, "read error: is it a readable regular file?",
                SourceLocation{path, line, 0});
  }
  return bytes;
}

// Splits a line into code and comment at the first ';' outside a "..." string.
void split_comment(std::string_view line, std::string& code, std::string& comment) {
  const auto trimmed = [](std::string_view v) {
    std::size_t b = 0, e = v.size();
    while (b < e && std::isspace(static_cast<unsigned char>(v[b])))
      ++b;
    while (e > b && std::isspace(static_cast<unsigned char>(v[e - 1])))
      --e;
    return std::string(v.substr(b, e - b));
  };
  bool in_string = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '"')
      in_string = !in_string;
    if (line[i] == ';' && !in_string) {
      code = trimmed(line.substr(0, i));
      comment.assign(line.substr(i + 1));
      return;
    }
  }
  code = trimmed(line);
  comment.clear();
}

// The leading identifier of `s` (letters, digits, '_', '$'), upper case.
std::string leading_word(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && ident_char(s[i]))
    ++i;
  return upper(s.substr(0, i));
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& msg) {
  throw Error(ErrorCode::bad_input, msg, SourceLocation{file, line, 0});
}

const std::set<std::string>& motion_keywords() {
  static const std::set<std::string> k{"PTP",      "LIN",      "CIRC",     "SPTP",    "SLIN",
                                       "SCIRC",    "SPL",      "LIN_REL",  "PTP_REL", "CIRC_REL",
                                       "SPTP_REL", "SLIN_REL", "SCIRC_REL"};
  return k;
}

bool is_motion_keyword(const std::string& w) {
  return motion_keywords().count(w) != 0;
}

// --- modules ---------------------------------------------------------------------------------

namespace {

// The file names of a folder in upper case, listed once and again only when the folder changes
// (its modification time or inode): a folder of 20 000 programs is listed once, not once per
// lookup, which made `redpost check` on it quadratic. One folder per thread is kept: the
// lookups of one program or one check are in one folder.
struct FolderNames {
  std::string dir;
  struct stat st {};
  std::unordered_map<std::string, std::string> by_upper_name;  // upper-case name -> path
};

const std::unordered_map<std::string, std::string>& folder_names(const fs::path& dir) {
  thread_local FolderNames cache;
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    cache = FolderNames{};
    return cache.by_upper_name;
  }
  if (cache.dir == dir.string() && cache.st.st_ino == st.st_ino && cache.st.st_dev == st.st_dev &&
      cache.st.st_mtim.tv_sec == st.st_mtim.tv_sec &&
      cache.st.st_mtim.tv_nsec == st.st_mtim.tv_nsec) {
    return cache.by_upper_name;
  }
  cache = FolderNames{dir.string(), st, {}};
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    cache.by_upper_name.emplace(upper(it->path().filename().string()), it->path().string());
  return cache.by_upper_name;
}

}  // namespace

// Finds `stem.ext` in `dir` regardless of case; "" if absent.
std::string find_file_nocase(const fs::path& dir, const std::string& stem, const std::string& ext) {
  std::error_code ec;
  fs::path exact = dir / (stem + "." + ext);
  if (fs::is_regular_file(exact, ec))
    return exact.string();
  const auto& names = folder_names(dir);
  const auto it = names.find(upper(stem + "." + ext));
  if (it != names.end() && fs::is_regular_file(it->second, ec))
    return it->second;
  return "";
}

namespace {

// A DECL line (in the .dat or a DEF): "[DECL] [GLOBAL] TYPE NAME = {...}" or
// "NAME[i] = {...}" for an element of a declared point array. Other DECLs are skipped.
void read_decl(const std::string& code, const std::string& file, int line_no, Module& m) {
  std::string rest = code;
  std::string w = leading_word(rest);
  auto drop_word = [&](const std::string& word) { rest = trim(rest.substr(word.size())); };
  bool had_decl = false;
  if (w == "DECL") {
    drop_word(w);
    had_decl = true;
    w = leading_word(rest);
  }
  if (w == "GLOBAL") {
    drop_word(w);
    w = leading_word(rest);
  }
  if (w == "CONST") {
    drop_word(w);
    w = leading_word(rest);
  }
  std::string type;
  if (point_types().count(w)) {
    type = w;
    drop_word(w);
  } else if (!had_decl && m.array_types.count(w) && rest.size() > w.size() &&
             trim(rest.substr(w.size())).rfind('[', 0) == 0) {
    // NAME[i]={...}
    std::size_t eq = rest.find('=');
    if (eq == std::string::npos)
      return;
    std::string name = upper(trim(rest.substr(0, eq)));
    name.erase(std::remove_if(name.begin(), name.end(),
                              [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }),
               name.end());
    Cursor c{rest, eq + 1, file, line_no};
    KrlAggregate a = parse_aggregate(c);
    if (a.type.empty())
      a.type = m.array_types[w];
    m.points[name] = a;
    return;
  } else {
    return;  // not a point declaration
  }
  std::string name = leading_word(rest);
  if (name.empty())
    return;
  drop_word(name);
  if (!rest.empty() && rest[0] == '[') {  // an array declaration: DECL E6POS XP[10]
    m.array_types[name] = type;
    return;
  }
  if (rest.empty() || rest[0] != '=')
    return;  // declared without a value
  if (trim(rest.substr(1)).rfind('{', 0) != 0)
    return;  // "= P1" or an expression: not a literal
  Cursor c{rest, 1, file, line_no};
  KrlAggregate a = parse_aggregate(c);
  if (a.type.empty())
    a.type = type;
  m.points[name] = a;
}

// The DEFs of a module and their ENDs; the first line of code outside any DEF.
void index_defs(Module& m) {
  const std::string& file = m.src_path;
  int open = -1;
  std::string open_name;
  bool open_is_fct = false;
  for (int i = 0; i < static_cast<int>(m.lines.size()); ++i) {
    std::string code, comment;
    split_comment(m.lines[i], code, comment);
    std::string w = leading_word(code);
    if (w == "GLOBAL")
      w = leading_word(trim(code.substr(6)));
    if (w == "DEF" || w == "DEFFCT") {
      if (open >= 0)
        fail(file, open + 1,
             "missing END: " + std::string(open_is_fct ? "DEFFCT " : "DEF ") + open_name +
                 " is not closed before the " + w + " at line " + std::to_string(i + 1));
      open = i;
      open_is_fct = w == "DEFFCT";
      std::string after = trim(code.substr(code.find_first_of(" \t") == std::string::npos
                                               ? code.size()
                                               : code.find_first_of(" \t")));
      if (upper(leading_word(code)) == "GLOBAL")
        after = trim(after.substr(after.find(' ') + 1));
      if (open_is_fct)
        after = trim(after.substr(leading_word(after).size()));  // the type
      open_name = leading_word(after);
      if (open_name.empty())
        fail(file, i + 1, "DEF without a name");
    } else if (open < 0 && !code.empty() && code[0] != '&') {
      if (is_motion_keyword(w))
        fail(file, i + 1, "motion outside DEF");
      if (!m.stray_line)
        m.stray_line = i + 1;
    } else if (w == "END" || w == "ENDFCT") {
      if (open < 0)
        fail(file, i + 1, w + " without DEF");
      if ((w == "ENDFCT") != open_is_fct)
        fail(file, i + 1, w + " closes " + (open_is_fct ? "DEFFCT " : "DEF ") + open_name);
      if (!open_is_fct)
        m.defs.push_back(DefRange{open_name, open, i});
      open = -1;
    }
  }
  if (open >= 0)
    fail(file, open + 1,
         "missing END: " + std::string(open_is_fct ? "DEFFCT " : "DEF ") + open_name +
             " is not closed before the end of the file");
  if (m.defs.empty())
    fail(file, 0, "no DEF in the file");
}

// The point DECLs between DEFDAT and ENDDAT of the module's .dat.
void read_dat(Module& m, const std::string& dat_text) {
  const std::vector<std::string_view> dat = split_lines(dat_text);
  bool in_defdat = false;
  for (int i = 0; i < static_cast<int>(dat.size()); ++i) {
    std::string code, comment;
    split_comment(dat[i], code, comment);
    if (code.empty() || code[0] == '&')
      continue;
    std::string w = leading_word(code);
    if (w == "DEFDAT") {
      in_defdat = true;
      continue;
    }
    if (w == "ENDDAT") {
      in_defdat = false;
      continue;
    }
    if (in_defdat)
      read_decl(code, m.dat_path, i + 1, m);
  }
}

}  // namespace

Module load_module(const std::string& src_path, const KrlTextSink* text) {
  Module m;
  m.src_path = src_path;
  // The .dat beside it is read first (its names are the .src's), parsed last (the .src's
  // errors come first).
  const fs::path p(src_path);
  m.dat_path = find_file_nocase(p.parent_path().empty() ? fs::path(".") : p.parent_path(),
                                p.stem().string(), "dat");
  std::string dat_text;
  if (!m.dat_path.empty()) {
    dat_text = read_krl_text(m.dat_path);
    if (text)
      (*text)(m.dat_path, dat_text);
  }
  m.text = std::make_unique<const std::string>(read_krl_text(src_path));
  if (text)
    (*text)(src_path, *m.text);
  m.lines = split_lines(*m.text);
  index_defs(m);

  // local point DECLs in the DEFs
  for (int i = 0; i < static_cast<int>(m.lines.size()); ++i) {
    std::string code, comment;
    split_comment(m.lines[i], code, comment);
    if (leading_word(code) == "DECL")
      read_decl(code, src_path, i + 1, m);
  }

  if (!m.dat_path.empty())
    read_dat(m, dat_text);
  return m;
}

}  // namespace redpost::krl
