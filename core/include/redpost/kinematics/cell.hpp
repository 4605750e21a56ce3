// The kinematic model of a serial cell: table, track, arm and tool spin in one chain.
//
// A Cell is plain data, loaded once (see cell_xml.hpp) and then only read. The chain runs from
// the base frame {B} (for the reference cell: the workpiece/table frame, Andres Table 1) to the
// TCP. Each joint carries its DH link, limits, home value, solver weight, optional stiffness
// and its mapping to a controller axis.
//
// Conventions (docs/conventions.md):
//   standard DH link  : Rz(theta) Tz(d) Tx(a) Rx(alpha)
//   modified DH link  : Rx(alpha) Tx(a) Rz(theta) Tz(d)        (Khalil-Kleinfinger)
//   revolute / virtual: theta = theta_offset + q   (q in rad)
//   prismatic         : d     = d_offset + q       (q in mm)
//   controller axis   : value = sign * q + offset  (deg for revolute, mm for prismatic)
#pragma once

#include <array>
#include <optional>
#include <string>

#include "redpost/kinematics/tool_table.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

enum class JointType {
  revolute,
  prismatic,
  virtual_spin,  // the tool's free spin about its axis: solved for, never sent to a controller
};

enum class DhConvention { standard, modified };

// Controller axes: A1..A6 of the arm, E1..E6 external axes.
enum class AxisKind { none, arm, external };

struct ControllerAxis {
  AxisKind kind = AxisKind::none;
  int number = 0;       // 1..6
  double sign = 1.0;    // +1 or -1
  double offset = 0.0;  // controller units: deg (revolute) or mm (prismatic)

  bool mapped() const { return kind != AxisKind::none; }
};

// "A1".."A6", "E1".."E6", or "none".
std::string axis_name(const ControllerAxis& axis);

struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  DhConvention convention = DhConvention::standard;

  // DH parameters. For a revolute/virtual joint theta_rad is the constant offset added to q; for
  // a prismatic joint d_mm is.
  double alpha_rad = 0.0;
  double a_mm = 0.0;
  double theta_rad = 0.0;
  double d_mm = 0.0;

  // A fixed transform applied before this link (from <fixed> elements of the chain).
  Isometry T_prev_link = Isometry::Identity();
  bool has_fixed_before = false;

  // Limits and home in DH units (rad or mm).
  double lower = 0.0;
  double upper = 0.0;
  double home = 0.0;

  // Solver metric: a unit motion of this joint (1 rad or 1 mm) costs weight * 1^2.
  double weight = 1.0;

  ControllerAxis axis;

  // Joint stiffness: N*mm/rad for revolute joints, N/mm for prismatic ones (internal units).
  std::optional<double> stiffness;

  // The axis's speed limits (<speed>), per second in DH units: rad/s and rad/s^2 for a revolute
  // joint, mm/s and mm/s^2 for a prismatic one. 0: not given (a virtual joint never has them).
  double max_velocity = 0.0;
  double max_acceleration = 0.0;

  // Where in the definition file the joint is declared, for messages.
  int source_line = 0;

  bool has_speed() const { return max_velocity > 0.0; }
};

// Which joints form the arm whose conditioning is watched (Andres Algorithm 1 step 8), and the
// characteristic length that makes its Jacobian dimensionally homogeneous.
struct ConditioningSpec {
  int first = -1;  // chain index of the first arm joint, -1 if not declared
  int last = -1;   // chain index of the last arm joint (inclusive)
  double characteristic_length_mm = 1.0;

  bool declared() const { return first >= 0; }
  int count() const { return last - first + 1; }
};

// How the cell's external axes are known to the controller (docs/cell-format.md, <controller>):
// which kinematic the base turns with, and the data the program's base and tool changes name.
struct ControllerSettings {
  int base_data = 1;  // BASE_DATA index: $BASE, or the offset base of a coupled kinematic
  // Chain index of the joint (a turntable) that carries the base as a mathematically coupled
  // kinematic (KUKA #EASYS, $BASE = EK(...)); -1: the base is static.
  int coupled_base_joint = -1;
  int machine_def = 2;  // MACHINE_DEF index of that kinematic (KSS 8)
  int ex_ax_data = 1;   // EX_AX_DATA index of that kinematic (KSS 5: ET1 .. ET6)
  // Chain index of a linear track that carries the robot as a ROBROOT kinematic (#ERSYS); -1:
  // none. Informational: the controller moves $ROBROOT with it, the program only sets E1.
  int robroot_joint = -1;
  std::string tool_change_routine;  // a KRL routine of the cell, called with the tool number
  // LOAD_DATA index ($LOAD) of every tool the tool table gives none for; 0: the tool's TOOL_DATA
  // index (docs/tools.md, "Load data").
  int load_data = 0;
};

struct Cell {
  std::string name;
  std::string source_file;

  Isometry T_B_0 = Isometry::Identity();       // {B} -> frame 0 of the first link (<base>)
  Isometry T_last_tcp = Isometry::Identity();  // last link frame -> TCP

  std::array<Joint, kMaxJoints> joints{};
  int joint_count = 0;

  ConditioningSpec conditioning;
  ControllerSettings controller;
  // The tools (tool_table.hpp): the reference length of the chain's TCP and, optionally, a table.
  ToolTable tools;

  // Precomputed per-link constants, filled by finalize_cell().
  struct LinkConstants {
    // Most links twist by 0 or +-90 deg; forward kinematics turns those into plain moves.
    enum class Twist : unsigned char { zero, plus_quarter, minus_quarter, general };
    Twist twist = Twist::general;
    double cos_alpha = 1.0, sin_alpha = 0.0;
    double cos_theta0 = 1.0, sin_theta0 = 0.0;  // for prismatic joints (theta is constant)
  };
  std::array<LinkConstants, kMaxJoints> link{};
  bool has_tcp_frame = false;  // T_last_tcp differs from the identity

  int size() const { return joint_count; }
  const Joint& joint(int i) const { return joints[static_cast<size_t>(i)]; }

  JointVector home() const;
  JointVector lower_limits() const;
  JointVector upper_limits() const;
  JointVector weights() const;

  // Chain index of the joint with this name, or -1.
  int find_joint(const std::string& name) const;

  // True when the cell gives the speed limits of its axes (every joint but the virtual ones has
  // a <speed>; load_cell() refuses a cell where only some have one).
  bool has_axis_speeds() const;
};

// Computes the per-link constants and checks the invariants a loaded cell must hold. Call after
// building a Cell by hand; load_cell() calls it.
void finalize_cell(Cell& cell);

// True when q (DH units) lies within every joint's limits, with `tolerance` of slack.
bool within_limits(const Cell& cell, const JointVector& q, double tolerance = 0.0);

}  // namespace redpost
