// The readings file of the calibration (issue 7).
#include "redpost/calibration/readings_csv.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <exception>
#include <map>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "io/text_util.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost {

namespace {

using detail::trim;

std::string lower(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string::npos ? comma : comma - start)));
    if (comma == std::string::npos)
      break;
    start = comma + 1;
  }
  return out;
}

// Shortest text that reads back to the same double; -0 prints as 0.
std::string num(double v) {
  if (v == 0.0)
    v = 0.0;
  return fmt::format("{}", v);
}

// Pose values are snapped to 1e-9 (mm, deg) so that a template reads -90, not
// -89.99999999999999: far below any robot's resolution.
std::string pose_num(double v) {
  if (std::abs(v) < 1e6)
    v = std::round(v * 1e9) / 1e9;
  return num(v);
}

// Parses "q<i>" into a 0-based index; -1 if the name is not of that form.
int joint_column_index(const std::string& name) {
  if (name.size() < 2 || name[0] != 'q')
    return -1;
  int i = 0;
  auto [ptr, ec] = std::from_chars(name.data() + 1, name.data() + name.size(), i);
  if (ec != std::errc() || ptr != name.data() + name.size() || i < 1 || name[1] == '0')
    return -1;
  return i - 1;
}

const char* const kPoseColumns[6] = {"x", "y", "z", "a", "b", "c"};

struct Header {
  ReadingsForm form = ReadingsForm::joints;
  int plane = -1, distance = -1;
  int pose[6] = {-1, -1, -1, -1, -1, -1};
  std::vector<std::pair<int, int>> joints;  // (chain index, column), in chain order
  size_t columns = 0;
};

Header parse_header(const std::string& line, const SourceLocation& where, const Cell& cell) {
  Header h;
  const std::vector<std::string> names = split_fields(line);
  h.columns = names.size();
  std::map<std::string, int> seen;
  for (size_t c = 0; c < names.size(); ++c) {
    const std::string name = lower(names[c]);
    if (name.empty())
      throw Error(ErrorCode::bad_input,
                  fmt::format("header: column {} has no name (expected plane, distance, then "
                              "x,y,z,a,b,c and the external joints, or q1..q{})",
                              c + 1, cell.size()),
                  where);
    if (!seen.emplace(name, static_cast<int>(c)).second)
      throw Error(ErrorCode::bad_input, fmt::format("header: column '{}' appears twice", name),
                  where);
    const int col = static_cast<int>(c);
    if (name == "plane") {
      h.plane = col;
      continue;
    }
    if (name == "distance") {
      h.distance = col;
      continue;
    }
    if (name == "point")  // the point number of the plan (the KRL comments'); informational
      continue;
    bool pose = false;
    for (int k = 0; k < 6; ++k) {
      if (name == kPoseColumns[k]) {
        h.pose[k] = col;
        pose = true;
      }
    }
    if (pose)
      continue;
    const int q = joint_column_index(name);
    if (q < 0)
      throw Error(ErrorCode::bad_input,
                  fmt::format("header: unknown column '{}' (expected point, plane, distance, x, y, "
                              "z, a, b, c or q1..q{})",
                              names[c], cell.size()),
                  where);
    if (q >= cell.size())
      throw Error(ErrorCode::bad_input,
                  fmt::format("header: column '{}': the cell has {} joints (q1..q{})", names[c],
                              cell.size(), cell.size()),
                  where);
    h.joints.emplace_back(q, col);
  }
  if (h.plane < 0)
    throw Error(ErrorCode::bad_input, "header: no 'plane' column", where);
  if (h.distance < 0)
    throw Error(ErrorCode::bad_input, "header: no 'distance' column", where);
  std::sort(h.joints.begin(), h.joints.end());
  int pose_columns = 0;
  for (int k = 0; k < 6; ++k)
    pose_columns += h.pose[k] >= 0 ? 1 : 0;
  if (pose_columns > 0) {
    if (pose_columns < 6) {
      std::string missing;
      for (int k = 0; k < 6; ++k)
        if (h.pose[k] < 0)
          missing += std::string(missing.empty() ? "" : ", ") + kPoseColumns[k];
      throw Error(ErrorCode::bad_input,
                  "header: the commanded pose needs x, y, z, a, b and c; missing " + missing,
                  where);
    }
    if (h.joints.empty())
      throw Error(ErrorCode::bad_input,
                  "header: the commanded-pose form needs the external joints' columns (q1, q2 "
                  "for a table and a track first in the chain)",
                  where);
    if (static_cast<int>(h.joints.size()) >= cell.size())
      throw Error(ErrorCode::bad_input,
                  "header: with x,y,z,a,b,c give only the external joints, not every joint", where);
    h.form = ReadingsForm::commanded_pose;
  } else {
    h.form = ReadingsForm::joints;
    if (static_cast<int>(h.joints.size()) != cell.size()) {
      std::string missing;
      size_t k = 0;
      for (int q = 0; q < cell.size(); ++q) {
        if (k < h.joints.size() && h.joints[k].first == q) {
          ++k;
          continue;
        }
        missing += (missing.empty() ? "q" : ", q") + std::to_string(q + 1);
      }
      throw Error(ErrorCode::bad_input,
                  "header: without the commanded pose x,y,z,a,b,c every joint q1..q" +
                      std::to_string(cell.size()) + " is needed; missing " + missing,
                  where);
    }
  }
  return h;
}

double parse_number(const std::string& field, const char* column, const SourceLocation& where) {
  if (field.empty())
    throw Error(ErrorCode::bad_input, fmt::format("column '{}' is empty", column), where);
  const char* first = field.data();
  const char* last = field.data() + field.size();
  if (*first == '+' && field.size() > 1 && field[1] != '-')
    ++first;
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last)
    throw Error(ErrorCode::bad_input,
                fmt::format("column '{}': '{}' is not a number", column, field), where);
  if (!std::isfinite(v))
    throw Error(ErrorCode::bad_input,
                fmt::format("column '{}': '{}' is not a finite number", column, field), where);
  return v;
}

}  // namespace

namespace {

// A commanded-pose row whose arm joints are still to be solved on the nominal model.
struct PendingSolve {
  size_t point = 0;
  std::vector<int> external;
  std::vector<double> values;
  SourceLocation where;
};

// Solves the arm joints of the commanded-pose rows, on two threads: each row is independent and
// deterministic, so the result does not depend on the split. The error reported is that of the
// first failing row in file order.
void solve_rows(const Cell& nominal, const ReadingsReadOptions& options,
                const std::vector<PendingSolve>& pending, std::vector<CalibrationPoint>& points) {
  std::vector<std::exception_ptr> errors(pending.size());
  auto work = [&](size_t begin, size_t step) {
    for (size_t k = begin; k < pending.size(); k += step) {
      const PendingSolve& p = pending[k];
      CalibrationPoint& pt = points[p.point];
      try {
        pt.q = joints_for_commanded_frame(nominal, p.external, p.values, pt.T_B_commanded,
                                          options.perturbed_starts, options.seed);
      } catch (const Error& e) {
        const char* what = e.code() == ErrorCode::unreachable
                               ? "the commanded pose cannot be reached on the nominal cell: "
                               : "";
        errors[k] =
            std::make_exception_ptr(Error(ErrorCode::bad_input, what + e.message(), p.where));
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  };
  if (pending.size() >= 8) {
    std::thread other(work, size_t{1}, size_t{2});
    work(0, 2);
    other.join();
  } else {
    work(0, 1);
  }
  for (const std::exception_ptr& e : errors)
    if (e)
      std::rethrow_exception(e);
}

}  // namespace

std::vector<CalibrationPoint> parse_readings_csv(const std::string& text,
                                                 const std::string& source_name,
                                                 const Cell& nominal,
                                                 const ReadingsReadOptions& options) {
  std::vector<CalibrationPoint> points;
  std::optional<Header> header;
  std::vector<std::vector<double>> configurations;
  std::vector<PendingSolve> pending;  // commanded-pose rows, solved after parsing
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    if (!raw.empty() && raw.back() == '\r')
      raw.pop_back();
    // A UTF-8 byte order mark (Excel writes one to a CSV) is not part of the first line.
    if (line_no == 1 && raw.compare(0, 3, "\xEF\xBB\xBF") == 0)
      raw.erase(0, 3);
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#')
      continue;
    const SourceLocation where{source_name, line_no, 0};
    if (!header) {
      header = parse_header(line, where, nominal);
      continue;
    }
    const Header& h = *header;
    const std::vector<std::string> fields = split_fields(line);
    if (fields.size() != h.columns)
      throw Error(
          ErrorCode::bad_input,
          fmt::format("expected {} fields as in the header, got {}", h.columns, fields.size()),
          where);
    CalibrationPoint pt;
    const std::string plane = lower(fields[static_cast<size_t>(h.plane)]);
    if (plane == "x")
      pt.plane = PlaneAxis::x;
    else if (plane == "y")
      pt.plane = PlaneAxis::y;
    else if (plane == "z")
      pt.plane = PlaneAxis::z;
    else
      throw Error(ErrorCode::bad_input,
                  fmt::format("column 'plane': '{}' is not x, y or z",
                              fields[static_cast<size_t>(h.plane)]),
                  where);
    pt.reading_mm = parse_number(fields[static_cast<size_t>(h.distance)], "distance", where);
    std::vector<int> external;
    std::vector<double> values;
    for (const auto& [q, col] : h.joints) {
      const std::string name = "q" + std::to_string(q + 1);
      external.push_back(q);
      values.push_back(parse_number(fields[static_cast<size_t>(col)], name.c_str(), where));
    }
    if (h.form == ReadingsForm::joints) {
      pt.q = JointVector(nominal.size());
      for (size_t k = 0; k < values.size(); ++k)
        pt.q[external[k]] = values[k];
      pt.configuration = 0;
    } else {
      double pose[6];
      for (int k = 0; k < 6; ++k)
        pose[k] = parse_number(fields[static_cast<size_t>(h.pose[k])], kPoseColumns[k], where);
      pt.T_B_commanded = frame_from_xyzabc(pose[0], pose[1], pose[2], {pose[3], pose[4], pose[5]});
      pending.push_back({points.size(), external, values, where});
      auto it = std::find(configurations.begin(), configurations.end(), values);
      pt.configuration = static_cast<int>(it - configurations.begin());
      if (it == configurations.end())
        configurations.push_back(values);
    }
    points.push_back(std::move(pt));
  }
  if (!header)
    throw Error(ErrorCode::bad_input,
                "no header row (expected e.g. 'plane,distance,x,y,z,a,b,c,q1,q2')",
                SourceLocation{source_name, line_no, 0});
  if (points.empty())
    throw Error(ErrorCode::bad_input, "no readings after the header",
                SourceLocation{source_name, line_no, 0});
  solve_rows(nominal, options, pending, points);
  return points;
}

std::vector<CalibrationPoint> load_readings_csv(const std::string& path, const Cell& nominal,
                                                const ReadingsReadOptions& options) {
  return parse_readings_csv(read_text_file(path), path, nominal, options);
}

std::string format_readings_csv(const Cell& cell, const std::vector<CalibrationPoint>& points,
                                const ReadingsWriteOptions& options) {
  std::string out;
  const bool pose = options.form == ReadingsForm::commanded_pose;
  std::vector<int> external = options.external_joints;
  std::sort(external.begin(), external.end());
  for (int q : external)
    if (q < 0 || q >= cell.size())
      throw Error(
          ErrorCode::bad_input,
          fmt::format("external joint index {} outside the chain of {} joints", q, cell.size()));
  if (options.comment) {
    out += fmt::format(
        "# redpost calibration readings for cell '{}': distance in mm along the "
        "beam (-z of the TCP), positive beyond the TCP; ",
        cell.name);
    if (pose) {
      out += "x,y,z mm and a,b,c deg (KRL) of the commanded TCP; ";
      for (int q : external)
        out += fmt::format("q{} = {} ({}), ", q + 1, cell.joint(q).name,
                           cell.joint(q).type == JointType::prismatic ? "mm" : "rad");
      out += "DH units\n";
    } else {
      out += "q1..qn every joint in DH units (rad, mm)\n";
    }
  }
  if (options.point_numbers)
    out += "point,";
  out += "plane,distance";
  if (pose) {
    out += ",x,y,z,a,b,c";
    for (int q : external)
      out += ",q" + std::to_string(q + 1);
  } else {
    for (int q = 0; q < cell.size(); ++q)
      out += ",q" + std::to_string(q + 1);
  }
  out += '\n';
  int number = 0;
  for (const CalibrationPoint& pt : points) {
    ++number;
    if (options.point_numbers)
      out += std::to_string(number) + ',';
    if (pt.q.size() != cell.size())
      throw Error(ErrorCode::internal, fmt::format("a calibration point has {} joints, the cell {}",
                                                   pt.q.size(), cell.size()));
    out += to_string(pt.plane);
    out += ',';
    if (!options.blank_distances)
      out += num(pt.reading_mm);
    if (pose) {
      const Eigen::Vector3d p = pt.T_B_commanded.translation();
      const KukaAbc abc = abc_from_rotation(pt.T_B_commanded.linear());
      for (double v : {p.x(), p.y(), p.z(), abc.a_deg, abc.b_deg, abc.c_deg})
        out += ',' + pose_num(v);
      for (int q : external)
        out += ',' + num(pt.q[q]);
    } else {
      for (int q = 0; q < cell.size(); ++q)
        out += ',' + num(pt.q[q]);
    }
    out += '\n';
  }
  return out;
}

namespace {

// Position of the next `token` in `text` from `pos` outside XML comments; npos if none.
size_t find_outside_comments(const std::string& text, const std::string& token, size_t pos,
                             size_t end) {
  while (pos < end) {
    const size_t hit = text.find(token, pos);
    const size_t comment = text.find("<!--", pos);
    if (hit == std::string::npos || hit >= end)
      return std::string::npos;
    if (comment != std::string::npos && comment < hit) {
      const size_t close = text.find("-->", comment + 4);
      if (close == std::string::npos)
        return std::string::npos;
      pos = close + 3;
      continue;
    }
    return hit;
  }
  return std::string::npos;
}

// Position of the next start tag `<name` (followed by white space, '/' or '>').
size_t find_start_tag(const std::string& text, const std::string& name, size_t pos, size_t end) {
  const std::string token = "<" + name;
  while (true) {
    const size_t hit = find_outside_comments(text, token, pos, end);
    if (hit == std::string::npos)
      return hit;
    const size_t after = hit + token.size();
    if (after < text.size() && (std::isspace(static_cast<unsigned char>(text[after])) ||
                                text[after] == '/' || text[after] == '>'))
      return hit;
    pos = after;
  }
}

}  // namespace

std::string calibrated_cell_xml(const std::string& xml_text, const std::string& source_name,
                                const std::vector<CalibrationParameter>& params,
                                const Eigen::VectorXd& values, const std::string& comment) {
  const Cell nominal = parse_cell(xml_text, source_name);
  std::string out = xml_text;
  // Edit from the last joint to the first so that earlier offsets stay valid.
  std::vector<size_t> order(params.size());
  for (size_t j = 0; j < order.size(); ++j)
    order[j] = j;
  std::sort(order.begin(), order.end(),
            [&](size_t l, size_t r) { return params[l].link > params[r].link; });
  for (size_t j : order) {
    const CalibrationParameter& p = params[j];
    const SourceLocation where{source_name, 0, 0};
    size_t joint = 0;
    for (int k = 0; k < p.link; ++k) {
      joint = find_start_tag(out, "joint", k == 0 ? 0 : joint + 1, out.size());
      if (joint == std::string::npos)
        throw Error(ErrorCode::bad_input, fmt::format("no <joint> element for {}", p.name()),
                    where);
    }
    size_t joint_end = find_outside_comments(out, "</joint>", joint, out.size());
    if (joint_end == std::string::npos)
      joint_end = out.size();
    const size_t dh = find_start_tag(out, "dh", joint, joint_end);
    if (dh == std::string::npos)
      throw Error(ErrorCode::bad_input, fmt::format("no <dh> element for {}", p.name()), where);
    const size_t tag_end = out.find('>', dh);
    const char* attr = p.field == DhField::alpha   ? "alpha"
                       : p.field == DhField::a     ? "a"
                       : p.field == DhField::theta ? "theta"
                                                   : "d";
    // The attribute: white space, the name, optional white space, '=', a quoted value.
    size_t pos = dh + 3, value_begin = std::string::npos, value_end = std::string::npos;
    while (pos < tag_end) {
      const size_t hit = out.find(attr, pos);
      if (hit == std::string::npos || hit >= tag_end)
        break;
      size_t k = hit + std::string(attr).size();
      pos = hit + 1;
      if (!std::isspace(static_cast<unsigned char>(out[hit - 1])))
        continue;
      while (k < tag_end && std::isspace(static_cast<unsigned char>(out[k])))
        ++k;
      if (k >= tag_end || out[k] != '=')
        continue;
      ++k;
      while (k < tag_end && std::isspace(static_cast<unsigned char>(out[k])))
        ++k;
      if (k >= tag_end || (out[k] != '"' && out[k] != '\''))
        continue;
      value_begin = k + 1;
      value_end = out.find(out[k], value_begin);
      break;
    }
    if (value_begin == std::string::npos || value_end == std::string::npos || value_end > tag_end)
      throw Error(ErrorCode::bad_input,
                  fmt::format("no {} attribute in the <dh> element of {}", attr, p.name()), where);
    const double v = values[static_cast<Eigen::Index>(j)];
    const std::string text = p.is_angle() ? num(rad_to_deg(v)) : num(v);
    out.replace(value_begin, value_end - value_begin, text);
  }
  if (!comment.empty()) {
    const size_t cell = find_start_tag(out, "cell", 0, out.size());
    if (cell == std::string::npos)
      throw Error(ErrorCode::bad_input, "no <cell> element", SourceLocation{source_name, 0, 0});
    std::string safe = comment;
    for (size_t k = safe.find("--"); k != std::string::npos; k = safe.find("--"))
      safe.replace(k, 2, "- -");
    out.insert(cell, "<!-- " + safe + " -->\n");
  }
  // The result must give the identified values and leave every other parameter alone.
  const Cell check = parse_cell(out, source_name);
  const Eigen::VectorXd got = parameter_values(check, params);
  if (check.size() != nominal.size() || (got - values).cwiseAbs().maxCoeff() > 1e-9)
    throw Error(ErrorCode::internal,
                "the calibrated cell does not read back with the identified "
                "values");
  return out;
}

}  // namespace redpost
