// Shared helpers of the unit tests: where the shipped definitions are, seeded random postures.
#pragma once

#include <initializer_list>
#include <random>
#include <string>
#include <utility>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost::test {

inline std::string source_path(const std::string& relative) {
  return std::string(REDPOST_SOURCE_DIR) + "/" + relative;
}

inline Cell shipped_cell(const std::string& name) {
  return load_cell(source_path("definitions/cells/" + name + ".xml"));
}

inline const char* const kShippedCells[] = {"andres2011_kr15_track_table", "kr15_2",
                                            "caro2014_kr270_table"};

// A posture drawn uniformly within the joint limits.
inline JointVector random_posture(const Cell& cell, std::mt19937_64& rng) {
  JointVector q(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    std::uniform_real_distribution<double> u(cell.joint(i).lower, cell.joint(i).upper);
    q[i] = u(rng);
  }
  return q;
}

// One row of a hand-built chain: a joint's DH parameters (deg, mm), limits (rad or mm) and
// stiffness (N*mm/rad or N/mm; 0: rigid).
struct DhRow {
  JointType type;
  DhConvention convention;
  double alpha_deg, a_mm, theta_deg, d_mm;
  double lower, upper;
  double stiffness = 0.0;
};

// A fixed frame before chain joint `joint` (x y z in mm, A B C in deg).
struct FixedFrameRow {
  int joint;
  double x_mm, y_mm, z_mm, a_deg, b_deg, c_deg;
};

// A cell built in code rather than read from XML, for the branches the shipped cells leave out
// (modified DH, prismatic joints in both conventions, fixed frames): joints j1.. with home at
// mid-range, then finalize_cell().
inline Cell hand_built_cell(std::string name, const Isometry& T_B_0, const Isometry& T_last_tcp,
                            std::initializer_list<DhRow> rows,
                            std::initializer_list<FixedFrameRow> fixed_frames) {
  Cell cell;
  cell.name = std::move(name);
  cell.T_B_0 = T_B_0;
  cell.T_last_tcp = T_last_tcp;
  int i = 0;
  for (const DhRow& r : rows) {
    Joint& j = cell.joints[static_cast<size_t>(i)];
    j.name = "j" + std::to_string(i + 1);
    j.type = r.type;
    j.convention = r.convention;
    j.alpha_rad = deg_to_rad(r.alpha_deg);
    j.a_mm = r.a_mm;
    j.theta_rad = deg_to_rad(r.theta_deg);
    j.d_mm = r.d_mm;
    j.lower = r.lower;
    j.upper = r.upper;
    j.home = 0.5 * (r.lower + r.upper);
    if (r.stiffness > 0.0)
      j.stiffness = r.stiffness;
    ++i;
  }
  cell.joint_count = i;
  for (const FixedFrameRow& f : fixed_frames) {
    Joint& j = cell.joints[static_cast<size_t>(f.joint)];
    j.T_prev_link = frame_from_xyzabc(f.x_mm, f.y_mm, f.z_mm, {f.a_deg, f.b_deg, f.c_deg});
    j.has_fixed_before = true;
  }
  finalize_cell(cell);
  return cell;
}

}  // namespace redpost::test
