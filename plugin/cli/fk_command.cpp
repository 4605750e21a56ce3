// `redpost fk`: forward kinematics (or the Jacobian) for joint vectors read from stdin.
#include <charconv>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"

namespace redpost::cli {

namespace {

struct FkOptions {
  std::string cell_path;
  bool jacobian = false;
  bool axes = false;
};

// 12 significant digits; -0 prints as 0 so that output does not depend on rounding noise.
std::string sig12(double v) {
  if (v == 0.0)
    v = 0.0;
  std::string s = fmt::format("{:.12g}", v);
  return s == "-0" ? "0" : s;
}

std::string joint_list(const Cell& cell, bool axes) {
  std::string s;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (!s.empty())
      s += ", ";
    s += j.name;
    if (axes) {
      s += j.axis.mapped() ? " (" + axis_name(j.axis) + ")" : " (deg)";
    }
  }
  return s;
}

// A joint vector is a few hundred bytes: a longer line is not one (or stdin is not a text of
// joint vectors, such as /dev/zero), and is refused before it fills the memory.
constexpr size_t kMaxLineBytes = 64 * 1024;

// std::getline with a bound: false at the end of the input, and throws at a line longer than
// kMaxLineBytes.
bool read_line(std::istream& in, std::string& line, int line_no) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof())
      return !line.empty();
    if (c == '\n')
      return true;
    if (line.size() == kMaxLineBytes) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("a line longer than {} bytes: fk reads one joint vector per line "
                              "(is stdin the right input?)",
                              kMaxLineBytes),
                  SourceLocation{"<stdin>", line_no, 0});
    }
    line += static_cast<char>(c);
  }
}

// A token for a message: at most 40 characters of it.
std::string shown(const std::string& token) {
  return token.size() <= 40 ? token : token.substr(0, 40) + "...";
}

// Splits a line on commas and white space; '#' starts a comment.
bool parse_values(const std::string& line, std::vector<double>& out, std::string& error) {
  out.clear();
  const std::string body = line.substr(0, line.find('#'));
  size_t i = 0;
  while (i < body.size()) {
    while (i < body.size() && (std::isspace(static_cast<unsigned char>(body[i])) || body[i] == ','))
      ++i;
    if (i >= body.size())
      break;
    size_t j = i;
    while (j < body.size() && !std::isspace(static_cast<unsigned char>(body[j])) && body[j] != ',')
      ++j;
    const std::string token = body.substr(i, j - i);
    const char* first = token.data();
    if (*first == '+' && token.size() > 1 && token[1] != '-')
      ++first;
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
    if (ec != std::errc() || ptr != token.data() + token.size()) {
      error = "'" + shown(token) + "' is not a number";
      return false;
    }
    if (!std::isfinite(v)) {
      error = "'" + shown(token) + "' is not a finite number";
      return false;
    }
    out.push_back(v);
    i = j;
  }
  return true;
}

int run_fk(const FkOptions& opt) {
  const Cell cell = load_cell(opt.cell_path);
  const int n = cell.size();
  KinematicsData data;
  Jacobian J(6, n);
  JointVector q(n);
  std::vector<double> values;
  std::string line, error;
  int line_no = 0;
  std::string out;
  while (read_line(std::cin, line, ++line_no)) {
    if (!parse_values(line, values, error)) {
      throw Error(ErrorCode::bad_input, error, SourceLocation{"<stdin>", line_no, 0});
    }
    if (values.empty())
      continue;
    if (static_cast<int>(values.size()) != n) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("expected {} values ({}{}), got {}", n,
                              opt.axes ? "controller units, chain order: " : "rad and mm: ",
                              joint_list(cell, opt.axes), values.size()),
                  SourceLocation{"<stdin>", line_no, 0});
    }
    for (int i = 0; i < n; ++i) {
      q[i] = opt.axes ? from_axis_value(cell.joint(i), values[static_cast<size_t>(i)])
                      : values[static_cast<size_t>(i)];
    }
    forward_kinematics(cell, q, data);
    out.clear();
    if (opt.jacobian) {
      tcp_jacobian(cell, data, J);
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < n; ++c) {
          if (r + c > 0)
            out += ' ';
          out += sig12(J(r, c));
        }
      }
    } else {
      const Eigen::Vector3d p = data.T_B_tcp.translation();
      const Eigen::Matrix3d R = data.T_B_tcp.linear();
      out = sig12(p.x()) + ' ' + sig12(p.y()) + ' ' + sig12(p.z());
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          out += ' ' + sig12(R(r, c));
    }
    out += '\n';
    std::fwrite(out.data(), 1, out.size(), stdout);
  }
  return kExitOk;
}

}  // namespace

Runner add_fk_command(CLI::App& app) {
  auto opt = std::make_shared<FkOptions>();
  CLI::App* fk = app.add_subcommand(
      "fk",
      "Forward kinematics: reads joint vectors from stdin (one per line, chain order, commas or "
      "spaces, '#' comments) and prints 'x y z r11 r12 r13 r21 r22 r23 r31 r32 r33' of the TCP "
      "in the cell's base frame (mm).");
  fk->add_option("--cell", opt->cell_path, "Cell definition (XML)")->required();
  fk->add_flag("--jacobian", opt->jacobian,
               "Print the 6 x n Jacobian at the TCP, row-major, rows [omega; v], instead");
  fk->add_flag("--axes", opt->axes,
               "Input is in controller units (deg, mm; virtual joint in deg) instead of DH units "
               "(rad, mm)");
  return [opt] { return run_fk(*opt); };
}

}  // namespace redpost::cli
