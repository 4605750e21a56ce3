// Checking and compiling a template set for the KRL writer (krl/writer_templates.hpp).
#include "krl/writer_templates.hpp"

#include <string>

#include <fmt/format.h>

#include "redpost/io/error.hpp"

namespace redpost::krl {

namespace {

// Refuses a placeholder that is unknown or not in `allowed` for `what`.
void check_placeholders(const KrlTemplateSet& templates, std::string_view text, PhMask allowed,
                        const std::string& what) {
  for (const PlaceholderUse& u : scan_placeholders(text)) {
    if (u.ph == Ph::count_ || !(allowed & bit(u.ph))) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("template set '{}': placeholder {{{}}} is {} in {}", templates.name,
                              u.name, u.ph == Ph::count_ ? "unknown" : "not allowed", what),
                  SourceLocation{templates.source_file, 0, 0});
    }
  }
}

void compile_statements(const KrlTemplateSet& templates, CompiledTemplates& out) {
  const SourceLocation where{templates.source_file, 0, 0};
  for (size_t i = 0; i < static_cast<size_t>(Stmt::count_); ++i) {
    const StatementSpec* spec = find_statement(kStmtNames[i]);
    const auto it = templates.statements.find(std::string(kStmtNames[i]));
    if (it == templates.statements.end()) {
      if (!spec->required(templates.spline))
        continue;
      throw Error(
          ErrorCode::bad_input,
          fmt::format("template set '{}' has no statement '{}'", templates.name, kStmtNames[i]),
          where);
    }
    check_placeholders(templates, it->second, spec->allowed,
                       "statement '" + std::string(kStmtNames[i]) + "'");
    out.stmt[i] = compile(it->second);
    out.present[i] = true;
  }
}

// One line of a skeleton: a block line ({body} or {decls} alone on it) or text.
SkeletonLine compile_skeleton_line(const KrlTemplateSet& templates, std::string_view l,
                                   const SkeletonSpec& spec, std::string_view kind,
                                   bool& wants_date) {
  SkeletonLine sl;
  const size_t b = l.find_first_not_of(" \t"), e = l.find_last_not_of(" \t");
  const std::string_view core = b == l.npos ? l : l.substr(b, e - b + 1);
  if (core == "{body}" || core == "{decls}" || core == "{frames}") {
    sl.block = core == "{body}" ? Ph::body : core == "{decls}" ? Ph::decls : Ph::frames;
  } else {
    // Block placeholders elsewhere than alone on their line are refused here too.
    check_placeholders(templates, l,
                       spec.allowed & ~(bit(Ph::body) | bit(Ph::decls) | bit(Ph::frames)),
                       "file '" + std::string(kind) + "'");
    sl.text = compile(l);
    wants_date = wants_date || (sl.text.used & bit(Ph::date));
  }
  if (sl.block != Ph::count_ && !(spec.allowed & bit(sl.block))) {
    throw Error(ErrorCode::bad_input,
                fmt::format("template set '{}': {{{}}} is not allowed in file '{}'", templates.name,
                            placeholder_name(sl.block), kind),
                SourceLocation{templates.source_file, 0, 0});
  }
  return sl;
}

Skeleton compile_skeleton(const KrlTemplateSet& templates, const std::string& text,
                          std::string_view kind, bool& wants_date) {
  const SkeletonSpec* spec = find_skeleton(kind);
  Skeleton out;
  int bodies = 0;
  size_t pos = 0;
  while (true) {
    const size_t nl = text.find('\n', pos);
    const std::string_view l(text.data() + pos, (nl == std::string::npos ? text.size() : nl) - pos);
    SkeletonLine sl = compile_skeleton_line(templates, l, *spec, kind, wants_date);
    bodies += sl.block == Ph::body;
    out.push_back(std::move(sl));
    if (nl == std::string::npos)
      break;
    pos = nl + 1;
  }
  if (spec->needs_body && bodies != 1) {
    throw Error(ErrorCode::bad_input,
                fmt::format("template set '{}': file '{}' needs exactly one line {{body}}",
                            templates.name, kind),
                SourceLocation{templates.source_file, 0, 0});
  }
  return out;
}

}  // namespace

CompiledTemplates compile_templates(const KrlTemplateSet& templates) {
  CompiledTemplates out;
  compile_statements(templates, out);
  if (templates.max_spline_points < 1) {
    throw Error(ErrorCode::bad_input,
                "template set '" + templates.name + "': max_spline_points must be >= 1",
                SourceLocation{templates.source_file, 0, 0});
  }
  out.src = compile_skeleton(templates, templates.src_file, "src", out.wants_date);
  out.dat = compile_skeleton(templates, templates.dat_file, "dat", out.wants_date);
  out.main_src = compile_skeleton(templates, templates.main_src_file, "main_src", out.wants_date);
  out.main_dat = compile_skeleton(templates, templates.main_dat_file, "main_dat", out.wants_date);
  if (!templates.continued_src_file.empty()) {
    // A set built by hand is held to what the loader refuses (template.cpp).
    if (const auto [line, what] = continued_problem(templates.continued_src_file); line >= 0) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("template set '{}': file 'continued_src', line {}: it is called "
                              "between two blended motions and may not hold {}",
                              templates.name, line + 1, what),
                  SourceLocation{templates.source_file, 0, 0});
    }
    out.continued_src =
        compile_skeleton(templates, templates.continued_src_file, "continued_src", out.wants_date);
  }
  return out;
}

}  // namespace redpost::krl
