// The calibration parameters: names, parsing, and their values in a cell (parameters.hpp).
// docs/calibration.md.
#include "redpost/calibration/parameters.hpp"

#include <algorithm>
#include <set>
#include <sstream>

#include "calibration/fail.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

using detail::fail_bad_input;

const char* field_name(DhField f) {
  switch (f) {
    case DhField::alpha:
      return "alpha";
    case DhField::a:
      return "a";
    case DhField::theta:
      return "theta";
    case DhField::d:
      return "d";
  }
  return "?";
}

double& field_ref(Joint& j, DhField f) {
  switch (f) {
    case DhField::alpha:
      return j.alpha_rad;
    case DhField::a:
      return j.a_mm;
    case DhField::theta:
      return j.theta_rad;
    case DhField::d:
      break;
  }
  return j.d_mm;
}

double field_value(const Joint& j, DhField f) {
  return field_ref(const_cast<Joint&>(j), f);
}

}  // namespace

std::string CalibrationParameter::name() const {
  return "link" + std::to_string(link) + "." + field_name(field);
}

CalibrationParameter parse_calibration_parameter(const std::string& name, const Cell& cell) {
  const std::string bad = "bad calibration parameter '" + name +
                          "': expected link<i>.<alpha|a|theta|d> with i in 1.." +
                          std::to_string(cell.size());
  if (name.rfind("link", 0) != 0)
    fail_bad_input(bad);
  const size_t dot = name.find('.');
  if (dot == std::string::npos || dot == 4)
    fail_bad_input(bad);
  const std::string index = name.substr(4, dot - 4), field = name.substr(dot + 1);
  if (!std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      index.size() > 3)
    fail_bad_input(bad);
  CalibrationParameter p;
  p.link = std::stoi(index);
  if (p.link < 1 || p.link > cell.size())
    fail_bad_input(bad);
  if (field == "alpha")
    p.field = DhField::alpha;
  else if (field == "a")
    p.field = DhField::a;
  else if (field == "theta")
    p.field = DhField::theta;
  else if (field == "d")
    p.field = DhField::d;
  else
    fail_bad_input(bad);
  return p;
}

std::vector<CalibrationParameter> parse_calibration_parameters(const std::string& list,
                                                               const Cell& cell) {
  std::vector<CalibrationParameter> out;
  std::set<std::string> seen;
  std::string item;
  std::istringstream in(list);
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty())
      continue;
    CalibrationParameter p = parse_calibration_parameter(item, cell);
    if (!seen.insert(p.name()).second)
      fail_bad_input("calibration parameter '" + item + "' given twice");
    out.push_back(p);
  }
  if (out.empty())
    return default_calibration_parameters();
  return out;
}

std::vector<CalibrationParameter> default_calibration_parameters() {
  return {{1, DhField::alpha}, {1, DhField::a},     {1, DhField::theta},
          {1, DhField::d},     {2, DhField::theta}, {2, DhField::d}};
}

Eigen::VectorXd parameter_values(const Cell& cell,
                                 const std::vector<CalibrationParameter>& params) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(params.size()));
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].link < 1 || params[i].link > cell.size())
      fail_bad_input("calibration parameter " + params[i].name() + ": no such link in the cell");
    v[static_cast<Eigen::Index>(i)] = field_value(cell.joint(params[i].link - 1), params[i].field);
  }
  return v;
}

Cell apply_parameters(const Cell& cell, const std::vector<CalibrationParameter>& params,
                      const Eigen::VectorXd& values) {
  if (values.size() != static_cast<Eigen::Index>(params.size()))
    throw Error(ErrorCode::internal, "apply_parameters: one value per parameter expected");
  Cell out = cell;
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].link < 1 || params[i].link > cell.size())
      fail_bad_input("calibration parameter " + params[i].name() + ": no such link in the cell");
    field_ref(out.joints[static_cast<size_t>(params[i].link - 1)], params[i].field) =
        values[static_cast<Eigen::Index>(i)];
  }
  finalize_cell(out);
  return out;
}

}  // namespace redpost
