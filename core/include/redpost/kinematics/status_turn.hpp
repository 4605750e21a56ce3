// KUKA Status and Turn of an arm posture (shared/PARAMETERS.md section 3).
//
//   Turn   bit i-1 = 1 if A_i < 0                                  (A1 -> bit 0 ... A6 -> bit 5)
//   Status bit 0   = 1 if the wrist root point lies behind the A1 axis (x < 0 in the A1 frame:
//                    overhead area)
//          bit 1   = 1 if A3 >= phi, phi the A3 value at which the A2 axis, the A3 axis and the
//                    wrist point are collinear (0 for an arm without A3-A4 offset)
//          bit 2   = 1 if A5 < 0
#pragma once

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/controller_axes.hpp"

namespace redpost {

struct StatusTurn {
  int status = 0;
  int turn = 0;
};

// What the computation needs from a cell: which joints are A1..A6, and phi. Built once.
struct ArmStatusModel {
  int joint_of_axis[6] = {-1, -1, -1, -1, -1, -1};  // chain index of A1..A6
  double phi_deg = 0.0;                             // A3 of the collinear posture (bit 1)
  // How the x axis of the A1 frame ("forward") is found (bit 0): along the common perpendicular
  // from the A1 axis to the A2 axis (the a1 offset of every KUKA arm), or, for an arm whose A2
  // axis meets the A1 axis, towards the wrist point of the posture A2 = -90, A3 = 90 deg (the
  // arm stretched up and forward, as at KUKA HOME) with the same A1.
  bool forward_from_a2_offset = true;
};

// Throws Error(bad_input) if the cell does not map all of A1..A6.
ArmStatusModel make_arm_status_model(const Cell& cell);

StatusTurn status_turn(const Cell& cell, const ArmStatusModel& model, const JointVector& q);

// The x coordinate (mm) of the wrist root point (where the A4, A5 and A6 axes meet) in the A1
// frame: Status bit 0 is set when it is < 0. Exposed for tests and diagnostics.
double wrist_x_in_a1_frame_mm(const Cell& cell, const ArmStatusModel& model, const JointVector& q);

}  // namespace redpost
