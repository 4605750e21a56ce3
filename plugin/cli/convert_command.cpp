// `redpost convert`: a CL file (APT/CLDATA or NX CLSF) in, a KRL program out.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "commands.hpp"
#include "definitions.hpp"
#include "redpost/cell_xml.hpp"
#include "redpost/cl_reader.hpp"
#include "redpost/controller_axes.hpp"
#include "redpost/error.hpp"
#include "redpost/krl_template.hpp"
#include "redpost/kuka_abc.hpp"
#include "redpost/post_session.hpp"
#include "redpost/text_file.hpp"

namespace redpost::cli {

namespace {

struct ConvertOptions {
  std::string input;
  std::string cell_path;
  std::string krl_path;
  std::string output_dir;
  std::string name;
  std::string joints_csv;
  std::string placement;  // "x,y,z,a,b,c" of the CL frame in the cell's {B}
  std::string base = "BASE_DATA[1]";
  std::string tool = "TOOL_DATA[1]";
  double apo_mm = 0.5;
  int split = 0;
  int cl_line_every = 50;
  double chordal_tolerance_mm = 0.01;
  bool quiet = false;
};

// A KRL identifier from a file name: letters, digits and '_', a letter first, short enough to
// take the _P001 suffix of a split program.
std::string program_name_from(const std::string& path) {
  std::string stem = std::filesystem::path(path).stem().string(), out;
  for (char c : stem) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    out += ok ? c : '_';
  }
  if (out.empty() || !std::isalpha(static_cast<unsigned char>(out[0])))
    out = "P" + out;
  if (out.size() > 19)
    out.resize(19);
  return out;
}

Isometry parse_placement(const std::string& text) {
  double v[6];
  int n = 0;
  size_t i = 0;
  while (i <= text.size() && n < 7) {
    const size_t j = text.find(',', i);
    const std::string token = text.substr(i, j == std::string::npos ? std::string::npos : j - i);
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (token.empty() || end == token.c_str() || *end != '\0' || !std::isfinite(x) || n == 6) {
      throw Error(ErrorCode::bad_input,
                  "--placement takes six numbers x,y,z,a,b,c (mm and deg), got '" + text + "'");
    }
    v[n++] = x;
    if (j == std::string::npos)
      break;
    i = j + 1;
  }
  if (n != 6) {
    throw Error(ErrorCode::bad_input,
                "--placement takes six numbers x,y,z,a,b,c (mm and deg), got '" + text + "'");
  }
  return frame_from_xyzabc(v[0], v[1], v[2], KukaAbc{v[3], v[4], v[5]});
}

// Values as the robot programmer reads them: controller units for mapped joints (A2 -90 deg),
// DH degrees or mm otherwise.
std::string joint_value_text(const Joint& j, double v) {
  const double shown = j.axis.mapped()                  ? to_axis_value(j, v)
                       : j.type == JointType::prismatic ? v
                                                        : rad_to_deg(v);
  return fmt::format(j.type == JointType::prismatic ? "{:.1f} mm" : "{:.2f} deg", shown);
}

// A distance (a margin), in the joint's unit.
std::string joint_distance_text(const Joint& j, double d) {
  return j.type == JointType::prismatic ? fmt::format("{:.1f} mm", d)
                                        : fmt::format("{:.2f} deg", rad_to_deg(d));
}

void print_summary(const Cell& cell, const PostSummary& s, double seconds) {
  fmt::print("poses {} (motions written {}), {:.2f} s, {:.0f} poses/s\n", s.poses, s.motions,
             seconds, seconds > 0 ? s.poses / seconds : 0.0);
  fmt::print("lowest 1/kappa_F of the arm: {:.3f} (CL line {})\n", s.lowest_inv_condition,
             s.lowest_inv_condition_line);
  fmt::print("{:<12} {:>6} {:>26} {:>26}\n", "joint", "axis", "range used",
             "smallest margin (low/high)");
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const JointRange& r = s.joints[static_cast<size_t>(i)];
    // A negative sign swaps the ends of the range in controller units.
    std::string lo = joint_value_text(j, r.lowest), hi = joint_value_text(j, r.highest);
    std::string m_lo = joint_distance_text(j, r.margin_lower),
                m_hi = joint_distance_text(j, r.margin_upper);
    if (j.axis.mapped() && j.axis.sign < 0) {
      std::swap(lo, hi);
      std::swap(m_lo, m_hi);
    }
    fmt::print("{:<12} {:>6} {:>26} {:>26}\n", j.name, axis_name(j.axis), lo + " .. " + hi,
               m_lo + " / " + m_hi);
  }
  for (const std::string& f : s.files)
    fmt::print("wrote {}\n", f);
}

int run_convert(const ConvertOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const Cell cell = load_cell(opt.cell_path);
  const KrlTemplateSet templates =
      load_krl_templates(opt.krl_path.empty() ? default_krl_template() : opt.krl_path);

  PostOptions post;
  post.program.name = opt.name.empty() ? program_name_from(opt.input) : opt.name;
  post.program.output_dir = opt.output_dir;
  post.program.base = opt.base;
  post.program.tool = opt.tool;
  post.program.apo_mm = opt.apo_mm;
  post.program.motions_per_file = opt.split;
  post.program.cl_line_every = opt.cl_line_every;
  post.program.header_comment = fmt::format("redpost 0.1.0, cell {}, from {}", cell.name,
                                            std::filesystem::path(opt.input).filename().string());
  post.source_name = opt.input;
  post.joints_csv_path = opt.joints_csv;
  if (!opt.placement.empty())
    post.T_B_part = parse_placement(opt.placement);

  std::ifstream in = open_text_stream(opt.input);
  ClReaderOptions reader_options;
  reader_options.chordal_tolerance_mm = opt.chordal_tolerance_mm;
  ClReader reader(in, opt.input, reader_options);
  PostSession session(cell, templates, post);

  const bool progress = !opt.quiet && ::isatty(STDERR_FILENO) == 1;
  auto last_report = std::chrono::steady_clock::now();
  ClEvent event;
  long events = 0;
  while (reader.next(event)) {
    session.handle(event);
    if (progress && (++events & 1023) == 0) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report > std::chrono::milliseconds(500)) {
        fmt::print(stderr, "\r{} poses, CL line {}   ", session.summary().poses, event.line);
        std::fflush(stderr);
        last_report = now;
      }
    }
  }
  if (progress)
    fmt::print(stderr, "\r{:40}\r", "");
  for (const std::string& w : reader.warnings())
    fmt::print(stderr, "warning: {}\n", w);
  const PostSummary& summary = session.finish();
  for (const std::string& w : summary.warnings)
    fmt::print(stderr, "warning: {}\n", w);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!opt.quiet)
    print_summary(cell, summary, seconds);
  return kExitOk;
}

}  // namespace

Runner add_convert_command(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  CLI::App* c = app.add_subcommand(
      "convert", "Convert a CL file (APT/CLDATA or NX CLSF) into a KRL program (.src/.dat).");
  c->add_option("input", opt->input, "CL file")->required();
  c->add_option("--cell", opt->cell_path, "Cell definition (XML)")->required();
  c->add_option("--krl", opt->krl_path, "KRL template set (XML); default krc4_lin");
  c->add_option("-o,--output", opt->output_dir, "Output directory (must exist)")->required();
  c->add_option("--name", opt->name,
                "Program name (KRL identifier, at most 24 characters); default from the input");
  c->add_option("--joints-csv", opt->joints_csv,
                "Write one row per motion: pose, CL line, joints (DH units), controller axes");
  c->add_option("--placement", opt->placement,
                "Where the CL frame lies in the cell's base frame: x,y,z,a,b,c (mm, deg)");
  c->add_option("--base", opt->base, "Right-hand side of $BASE = (default BASE_DATA[1])");
  c->add_option("--tool", opt->tool, "Right-hand side of $TOOL = (default TOOL_DATA[1])");
  c->add_option("--apo", opt->apo_mm, "Blending distance $APO.CDIS in mm (default 0.5)");
  c->add_option("--split", opt->split, "Motions per file; 0 keeps one file (default 0)");
  c->add_option("--cl-line-every", opt->cl_line_every,
                "A comment with the CL line every N motions (default 50, 0: never)");
  c->add_option("--chordal-tol", opt->chordal_tolerance_mm,
                "Chordal tolerance for arcs and NURBS in mm (default 0.01)");
  c->add_flag("-q,--quiet", opt->quiet, "No progress and no summary");
  return [opt] { return run_convert(*opt); };
}

}  // namespace redpost::cli
