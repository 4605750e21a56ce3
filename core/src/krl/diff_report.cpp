// The KRL diff's reports (redpost/krl/diff.hpp): the differences and statistics as text, and
// the whole result as JSON.
#include "redpost/krl/diff.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "krl/diff_path.hpp"

namespace redpost {

namespace {

std::string num(double v) {
  if (!std::isfinite(v))
    return "nan";
  if (v == 0.0)
    v = 0.0;
  return fmt::format("{:.6g}", v);
}

std::string tolerance_of(KrlQuantity q, const KrlDiffOptions& o) {
  switch (q) {
    case KrlQuantity::position:
    case KrlQuantity::aux_position:
    case KrlQuantity::apo_cdis:
      return num(o.pos_tol_mm);
    case KrlQuantity::orientation:
    case KrlQuantity::path_orientation:
      return num(o.ang_tol_deg);
    case KrlQuantity::vel_cp:
      return num(o.vel_tol_m_per_s);
    case KrlQuantity::path:
      return num(o.path_tol_mm);
    case KrlQuantity::status:
    case KrlQuantity::turn:
    case KrlQuantity::keyword:
    case KrlQuantity::target_kind:
    case KrlQuantity::ptp_velocity:
    case KrlQuantity::tool:
    case KrlQuantity::base:
      return "exact";
    default:
      return num(o.axis_tol);
  }
}

std::string where(const std::string& file, int line, int last_line) {
  if (last_line != line && last_line != 0)
    return fmt::format("{}:{}-{}", file, line, last_line);
  return fmt::format("{}:{}", file, line);
}

std::string deviation_text(const KrlDeviation& d) {
  const std::string name = krl_quantity_name(d.quantity);
  if (!d.detail.empty())
    return name + " " + d.detail;
  const std::string unit = krl_quantity_unit(d.quantity);
  return name + " " + num(d.value) + (unit == "axis" ? "" : " " + unit);
}

void json_string(std::string& out, const std::string& s) {
  out += '"';
  for (char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      default:
        if (c < 0x20)
          out += fmt::format("\\u{:04x}", c);
        else
          out += ch;
    }
  }
  out += '"';
}

std::string json_number(double v) {
  if (!std::isfinite(v))
    return "null";
  if (v == 0.0)
    v = 0.0;
  return fmt::format("{:.9g}", v);
}

}  // namespace

std::string format_krl_diff_text(const KrlDiffResult& r, const KrlDiffOptions& o) {
  std::string out;
  for (const std::string& u : r.unmatched)
    out += u + "\n";
  size_t n = 0;
  for (const KrlDifference& d : r.differences) {
    ++n;
    switch (d.kind) {
      case KrlDifference::Kind::changed: {
        out += fmt::format("{} <-> {}: {} / {}:", where(d.file_a, d.line_a, 0),
                           where(d.file_b, d.line_b, 0), d.keyword_a, d.keyword_b);
        for (size_t i = 0; i < d.deviations.size(); ++i)
          out += (i ? ", " : " ") + deviation_text(d.deviations[i]);
        out += "\n";
        break;
      }
      case KrlDifference::Kind::inserted:
        out += fmt::format("{}: inserted in B: {} motion{} ({} ...)\n",
                           where(d.file_b, d.line_b, d.last_line_b), d.count,
                           d.count == 1 ? "" : "s", d.keyword_b);
        break;
      case KrlDifference::Kind::removed:
        out += fmt::format("{}: removed from A: {} motion{} ({} ...)\n",
                           where(d.file_a, d.line_a, d.last_line_a), d.count,
                           d.count == 1 ? "" : "s", d.keyword_a);
        break;
    }
  }
  const size_t listed = r.differences.size() + r.summaries.size();
  if (r.difference_count > listed)
    out += fmt::format("... {} more difference(s) not shown (--max-shown)\n",
                       r.difference_count - listed);
  // Program-wide differences, once each: a setting or a motion kind that differs at many
  // motions, or the paths as curves (--as-curves).
  for (const KrlSummaryDifference& d : r.summaries) {
    const std::string at =
        d.file_b.empty()   ? where(d.file_a, d.line_a, 0)
        : d.file_a.empty() ? where(d.file_b, d.line_b, 0)
                           : where(d.file_a, d.line_a, 0) + " <-> " + where(d.file_b, d.line_b, 0);
    out += fmt::format("{} differs at {} motion{}: {} (first: {})\n", krl_quantity_name(d.quantity),
                       d.count, d.count == 1 ? "" : "s", d.detail, at);
  }
  if (r.statistics[static_cast<size_t>(KrlQuantity::path)].compared > 0) {
    out += fmt::format(
        "paths as curves: the largest distance from a point of one program to the other's path "
        "is {}{} mm{} (tolerance {} mm{})\n",
        r.path_exact ? "" : "more than ", num(r.path_distance_mm),
        r.path_file.empty() ? "" : ", at " + where(r.path_file, r.path_line, 0), num(o.path_tol_mm),
        o.as_curves ? "" : "; --as-curves compares by it");
    if (r.path_capped > 0) {
      out += fmt::format(
          "paths as curves: {} point{} in a crowd (more than {} segments of the other path near "
          "them that are not duplicates of each other): the distance there is the least over "
          "the {} examined, an upper bound\n",
          r.path_capped, r.path_capped == 1 ? "" : "s", krl::PathWindow::kMaxExamined,
          krl::PathWindow::kMaxExamined);
    }
  }
  if (r.unaligned_regions > 0)
    out += fmt::format(
        "alignment: {} region{} where no motion had a partner within the window of {} motions, "
        "the first from {} and {} on; {} paired in order.{}\n",
        r.unaligned_regions, r.unaligned_regions == 1 ? "" : "s", r.window,
        where(r.unaligned_file_a, r.unaligned_line_a, 0),
        where(r.unaligned_file_b, r.unaligned_line_b, 0),
        r.unaligned_regions == 1 ? "its motions were" : "their motions were",
        // Past the work budget the programs differ nearly everywhere: no window would help.
        r.budget_exhausted         ? ""
        : r.unaligned_regions == 1 ? " A larger --window may align it."
                                   : " A larger --window may align them.");
  if (r.budget_exhausted)
    out +=
        "alignment: the work budget ran out (programs with very many differences); the rest "
        "of that region was paired in order\n";
  out += fmt::format(
      "{}: {} motions in A, {} in B, {} compared ({}), {} changed, {} inserted, {} removed\n",
      r.equal ? "equal" : "different", r.motions_a, r.motions_b, r.compared,
      r.aligned_by_cl_line ? "aligned by CL line" : "aligned by position", r.changed, r.inserted,
      r.removed);
  out += fmt::format("{:<13} {:>10} {:>10} {:>12} {:>12} {:>10}\n", "quantity", "compared",
                     "over tol", "max", "mean", "tolerance");
  for (int q = 0; q < kKrlQuantityCount; ++q) {
    const KrlQuantityStats& s = r.statistics[static_cast<size_t>(q)];
    if (s.compared == 0)
      continue;
    out += fmt::format("{:<13} {:>10} {:>10} {:>12} {:>12} {:>10}\n",
                       krl_quantity_name(static_cast<KrlQuantity>(q)), s.compared, s.over_tolerance,
                       num(s.max), num(s.mean()), tolerance_of(static_cast<KrlQuantity>(q), o));
  }
  return out;
}

std::string format_krl_diff_json(const KrlDiffResult& r, const KrlDiffOptions& o) {
  std::string out = "{";
  out += fmt::format(
      "\"equal\": {}, \"motions_a\": {}, \"motions_b\": {}, \"compared\": {}, \"changed\": {}, "
      "\"inserted\": {}, \"removed\": {}, \"difference_count\": {}, \"aligned_by\": \"{}\", ",
      r.equal ? "true" : "false", r.motions_a, r.motions_b, r.compared, r.changed, r.inserted,
      r.removed, r.difference_count, r.aligned_by_cl_line ? "cl_line" : "position");
  out += fmt::format(
      "\"tolerances\": {{\"position_mm\": {}, \"orientation_deg\": {}, \"axis\": {}, "
      "\"vel_cp_m_per_s\": {}, \"path_mm\": {}}}, \"as_curves\": {}, ",
      json_number(o.pos_tol_mm), json_number(o.ang_tol_deg), json_number(o.axis_tol),
      json_number(o.vel_tol_m_per_s), json_number(o.path_tol_mm), o.as_curves ? "true" : "false");
  out += fmt::format("\"window\": {}, \"budget_exhausted\": {}, \"unaligned\": {{\"regions\": {}, ",
                     r.window, r.budget_exhausted ? "true" : "false", r.unaligned_regions);
  out += "\"a\": {\"file\": ";
  json_string(out, r.unaligned_file_a);
  out += fmt::format(", \"line\": {}}}, \"b\": {{\"file\": ", r.unaligned_line_a);
  json_string(out, r.unaligned_file_b);
  out += fmt::format(", \"line\": {}}}}}, ", r.unaligned_line_b);
  out += fmt::format(
      "\"path\": {{\"distance_mm\": {}, \"exact\": {}, \"capped\": {}, "
      "\"examined\": {}, \"file\": ",
      json_number(r.path_distance_mm), r.path_exact ? "true" : "false", r.path_capped,
      r.path_examined);
  json_string(out, r.path_file);
  out += fmt::format(", \"line\": {}}}, \"summaries\": [", r.path_line);
  for (size_t i = 0; i < r.summaries.size(); ++i) {
    const KrlSummaryDifference& d = r.summaries[i];
    out += fmt::format("{}{{\"quantity\": \"{}\", \"count\": {}, \"detail\": ", i ? ", " : "",
                       krl_quantity_name(d.quantity), d.count);
    json_string(out, d.detail);
    out += ", \"a\": {\"file\": ";
    json_string(out, d.file_a);
    out += fmt::format(", \"line\": {}}}, \"b\": {{\"file\": ", d.line_a);
    json_string(out, d.file_b);
    out += fmt::format(", \"line\": {}}}}}", d.line_b);
  }
  out += "], ";
  out += "\"unmatched\": [";
  for (size_t i = 0; i < r.unmatched.size(); ++i) {
    if (i)
      out += ", ";
    json_string(out, r.unmatched[i]);
  }
  out += "], \"differences\": [";
  auto side = [&](const char* key, const std::string& file, int line, int last,
                  const std::string& kw) {
    out += fmt::format("\"{}\": {{\"file\": ", key);
    json_string(out, file);
    out += fmt::format(", \"line\": {}, \"last_line\": {}, \"keyword\": ", line, last);
    json_string(out, kw);
    out += "}";
  };
  for (size_t i = 0; i < r.differences.size(); ++i) {
    const KrlDifference& d = r.differences[i];
    if (i)
      out += ", ";
    const char* kind = d.kind == KrlDifference::Kind::changed    ? "changed"
                       : d.kind == KrlDifference::Kind::inserted ? "inserted"
                                                                 : "removed";
    out += fmt::format("{{\"kind\": \"{}\", \"count\": {}, ", kind, d.count);
    if (d.kind != KrlDifference::Kind::inserted) {
      side("a", d.file_a, d.line_a, d.last_line_a, d.keyword_a);
      out += ", ";
    }
    if (d.kind != KrlDifference::Kind::removed) {
      side("b", d.file_b, d.line_b, d.last_line_b, d.keyword_b);
      out += ", ";
    }
    out += "\"deviations\": [";
    for (size_t k = 0; k < d.deviations.size(); ++k) {
      const KrlDeviation& v = d.deviations[k];
      if (k)
        out += ", ";
      out += fmt::format("{{\"quantity\": \"{}\", \"value\": {}, \"unit\": \"{}\", \"detail\": ",
                         krl_quantity_name(v.quantity), json_number(v.value),
                         krl_quantity_unit(v.quantity));
      json_string(out, v.detail);
      out += "}";
    }
    out += "]}";
  }
  out += "], \"statistics\": {";
  bool first = true;
  for (int q = 0; q < kKrlQuantityCount; ++q) {
    const KrlQuantityStats& s = r.statistics[static_cast<size_t>(q)];
    if (s.compared == 0)
      continue;
    if (!first)
      out += ", ";
    first = false;
    out += fmt::format(
        "\"{}\": {{\"compared\": {}, \"over_tolerance\": {}, \"max\": {}, \"mean\": {}, "
        "\"unit\": \"{}\"}}",
        krl_quantity_name(static_cast<KrlQuantity>(q)), s.compared, s.over_tolerance,
        json_number(s.max), json_number(s.mean()), krl_quantity_unit(static_cast<KrlQuantity>(q)));
  }
  out += "}}\n";
  return out;
}

}  // namespace redpost
