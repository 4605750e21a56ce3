// The readings file of the calibration (issue 7): a CSV with a header row, one row per point.
//
//   plane,distance,x,y,z,a,b,c,q1,q2     the commanded TCP pose (mm, KRL ABC in deg) and the
//                                        cell's external joints in DH units (rad or mm) under
//                                        their chain-order names q<i>; the other joints are
//                                        solved on the NOMINAL cell (joints_for_commanded_frame)
//   plane,distance,q1,...,qn             every joint of the chain in DH units (rad or mm)
//
// `plane` is x, y or z; `distance` is the laser reading in mm; an optional `point` column (the
// plan's point number) is ignored. Columns are named by the header
// (case-insensitive, any order, each exactly once). Blank lines and lines starting with '#' are
// skipped. Every problem is an Error(bad_input) located at the file and line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

enum class ReadingsForm {
  commanded_pose,  // plane,distance,x,y,z,a,b,c + the external joints
  joints,          // plane,distance,q1..qn
};

struct ReadingsReadOptions {
  // Passed to joints_for_commanded_frame for rows in the commanded-pose form.
  int perturbed_starts = 24;
  std::uint64_t seed = 1;
};

// Parses a readings file's text; `source_name` is used in messages. Each point's q is the full
// joint vector; `configuration` numbers the distinct external-joint value sets in order of
// first appearance (commanded-pose form) and is 0 in the joints form. Throws Error(bad_input).
std::vector<CalibrationPoint> parse_readings_csv(const std::string& text,
                                                 const std::string& source_name,
                                                 const Cell& nominal,
                                                 const ReadingsReadOptions& options = {});

// Reads a readings file. Throws Error (io or bad_input).
std::vector<CalibrationPoint> load_readings_csv(const std::string& path, const Cell& nominal,
                                                const ReadingsReadOptions& options = {});

struct ReadingsWriteOptions {
  ReadingsForm form = ReadingsForm::commanded_pose;
  // Chain indices (0-based) of the external joints written in the commanded-pose form.
  std::vector<int> external_joints{0, 1};
  // true: the distance column is left empty, a template to fill in on the shop floor.
  bool blank_distances = false;
  // true: a '#' comment line before the header saying what the file is.
  bool comment = true;
  // true: a first column 'point' numbering the rows 1..n, as the plan's KRL program's comments
  // do (the reader accepts and ignores it).
  bool point_numbers = false;
};

// Writes points as a readings file (numbers in the shortest form that reads back exactly).
std::string format_readings_csv(const Cell& cell, const std::vector<CalibrationPoint>& points,
                                const ReadingsWriteOptions& options = {});

}  // namespace redpost

namespace redpost {

// The calibrated cell file: `xml_text` (the nominal cell's file, named `source_name` in
// messages) with only the <dh> attributes of the identified parameters rewritten (angles in
// deg, lengths in mm, shortest exact form) and `comment` inserted as an XML comment on its own
// line before the <cell> element; every other byte is kept. The result is parsed back and
// checked to give `values`. Throws Error(bad_input) when a joint's <dh> cannot be found.
std::string calibrated_cell_xml(const std::string& xml_text, const std::string& source_name,
                                const std::vector<CalibrationParameter>& params,
                                const Eigen::VectorXd& values, const std::string& comment);

}  // namespace redpost
