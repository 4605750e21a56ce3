#include "redpost/kinematics/status_turn.hpp"

#include <cmath>
#include <string>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

namespace redpost {

namespace {

double arm_axis_deg(const Cell& cell, const ArmStatusModel& model, const JointVector& q,
                    int axis_number) {
  const int i = model.joint_of_axis[axis_number - 1];
  return to_axis_value(cell.joint(i), q[i]);
}

Eigen::Vector3d normal_part(const Eigen::Vector3d& v, const Eigen::Vector3d& unit_axis) {
  return v - v.dot(unit_axis) * unit_axis;
}

// The "forward" direction of the A1 frame from the A2 axis offset: the direction of the common
// perpendicular from the A1 axis to the A2 axis, normal to A1. Zero if the axes meet or are
// parallel (then the offset says nothing).
Eigen::Vector3d forward_from_offset(const KinematicsData& data, int j1, int j2) {
  const Eigen::Vector3d o1 = data.p_B_joint[static_cast<size_t>(j1)];
  const Eigen::Vector3d z1 = data.z_B_joint[static_cast<size_t>(j1)].normalized();
  const Eigen::Vector3d o2 = data.p_B_joint[static_cast<size_t>(j2)];
  const Eigen::Vector3d z2 = data.z_B_joint[static_cast<size_t>(j2)].normalized();
  const double b = z1.dot(z2);
  const double denom = 1.0 - b * b;
  if (denom < 1e-9)
    return Eigen::Vector3d::Zero();
  // Closest points o1 + s z1 and o2 + t z2 of the two lines.
  const Eigen::Vector3d w0 = o1 - o2;
  const double d = z1.dot(w0), e = z2.dot(w0);
  const double s = (b * e - d) / denom;
  const double t = (e - b * d) / denom;
  const Eigen::Vector3d offset = normal_part((o2 + t * z2) - (o1 + s * z1), z1);
  // Below a micrometre the axes meet: no usable direction.
  if (offset.norm() < 1e-3)
    return Eigen::Vector3d::Zero();
  return offset.normalized();
}

// sin of the angle from (A2 axis -> A3 axis) to (A3 axis -> wrist point) in the plane normal
// to A2, and whether the wrist lies ahead of the A3 axis (stretched rather than folded).
struct Collinearity {
  double sine = 0.0;
  bool stretched = false;
};

Collinearity collinearity(const Cell& cell, const ArmStatusModel& model, JointVector q,
                          double a3_deg, KinematicsData& data) {
  const int j3 = model.joint_of_axis[2];
  q[j3] = from_axis_value(cell.joint(j3), a3_deg);
  forward_kinematics(cell, q, data);
  const int j2 = model.joint_of_axis[1], j5 = model.joint_of_axis[4];
  const Eigen::Vector3d z2 = data.z_B_joint[static_cast<size_t>(j2)].normalized();
  const Eigen::Vector3d u = normal_part(
      data.p_B_joint[static_cast<size_t>(j3)] - data.p_B_joint[static_cast<size_t>(j2)], z2);
  const Eigen::Vector3d v = normal_part(
      data.p_B_joint[static_cast<size_t>(j5)] - data.p_B_joint[static_cast<size_t>(j3)], z2);
  Collinearity c;
  const double norms = u.norm() * v.norm();
  if (norms > 0.0) {
    c.sine = u.cross(v).dot(z2) / norms;
    c.stretched = u.dot(v) > 0.0;
  }
  return c;
}

// phi: the A3 value (deg, in (-180, 180]) at which the A2 axis, the A3 axis and the wrist point
// are collinear with the arm stretched. The sine of the fold angle changes sign there; a scan
// in 1 deg steps brackets the root and bisection refines it to far below print precision.
double find_phi_deg(const Cell& cell, const ArmStatusModel& model) {
  KinematicsData data;
  const JointVector home = cell.home();
  double lo = -180.0;
  Collinearity c_lo = collinearity(cell, model, home, lo, data);
  for (int step = 1; step <= 360; ++step) {
    const double hi = -180.0 + step;
    const Collinearity c_hi = collinearity(cell, model, home, hi, data);
    if (c_lo.stretched && c_hi.stretched && (c_lo.sine <= 0.0) != (c_hi.sine <= 0.0)) {
      double a = lo, b = hi;
      const bool rising = c_lo.sine <= 0.0;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (a + b);
        const bool below = collinearity(cell, model, home, mid, data).sine <= 0.0;
        (below == rising ? a : b) = mid;
      }
      double phi = 0.5 * (a + b);
      if (phi <= -180.0)
        phi += 360.0;
      return phi;
    }
    lo = hi;
    c_lo = c_hi;
  }
  throw Error(ErrorCode::bad_input,
              "cell '" + cell.name +
                  "': no A3 value puts the A2 axis, the A3 axis and the wrist point on one line; "
                  "the joints mapped to A2, A3 and A5 do not form a KUKA-like arm",
              SourceLocation{cell.source_file, 0, 0});
}

}  // namespace

ArmStatusModel make_arm_status_model(const Cell& cell) {
  ArmStatusModel model;
  for (int i = 0; i < cell.size(); ++i) {
    const ControllerAxis& axis = cell.joint(i).axis;
    if (axis.kind == AxisKind::arm)
      model.joint_of_axis[axis.number - 1] = i;
  }
  const SourceLocation where{cell.source_file, 0, 0};
  for (int n = 1; n <= 6; ++n) {
    const int i = model.joint_of_axis[n - 1];
    if (i < 0) {
      throw Error(ErrorCode::bad_input,
                  "cell '" + cell.name + "' maps no joint to controller axis A" +
                      std::to_string(n) + "; Status and Turn need all of A1..A6",
                  where);
    }
    if (cell.joint(i).type != JointType::revolute) {
      throw Error(ErrorCode::bad_input,
                  "cell '" + cell.name + "': joint '" + cell.joint(i).name + "' drives A" +
                      std::to_string(n) + " but is not revolute",
                  where);
    }
    // The wrist point and the reference posture below are read off a chain in which each arm
    // axis carries the ones after it.
    if (n > 1 && i <= model.joint_of_axis[n - 2]) {
      throw Error(ErrorCode::bad_input,
                  "cell '" + cell.name + "': A" + std::to_string(n) + " (joint '" +
                      cell.joint(i).name + "') comes before A" + std::to_string(n - 1) +
                      " in the chain; A1..A6 must follow the chain order",
                  where);
    }
  }

  KinematicsData data;
  forward_kinematics(cell, cell.home(), data);
  model.forward_from_a2_offset =
      !forward_from_offset(data, model.joint_of_axis[0], model.joint_of_axis[1]).isZero();
  model.phi_deg = find_phi_deg(cell, model);
  return model;
}

double wrist_x_in_a1_frame_mm(const Cell& cell, const ArmStatusModel& model, const JointVector& q) {
  const int j1 = model.joint_of_axis[0], j5 = model.joint_of_axis[4];
  KinematicsData data;
  forward_kinematics(cell, q, data);
  const Eigen::Vector3d o1 = data.p_B_joint[static_cast<size_t>(j1)];
  const Eigen::Vector3d z1 = data.z_B_joint[static_cast<size_t>(j1)].normalized();
  const Eigen::Vector3d wrist = data.p_B_joint[static_cast<size_t>(j5)];

  Eigen::Vector3d forward = Eigen::Vector3d::Zero();
  if (model.forward_from_a2_offset) {
    forward = forward_from_offset(data, j1, model.joint_of_axis[1]);
  } else {
    // No A1-A2 offset: the stretched-up posture (A2 = -90, A3 = 90) points forward (its wrist
    // x is l > 0). A2 and A3 come after A1, so the A1 axis does not move.
    JointVector q_ref = q;
    const int j2 = model.joint_of_axis[1], j3 = model.joint_of_axis[2];
    q_ref[j2] = from_axis_value(cell.joint(j2), -90.0);
    q_ref[j3] = from_axis_value(cell.joint(j3), 90.0);
    KinematicsData ref;
    forward_kinematics(cell, q_ref, ref);
    const Eigen::Vector3d w = normal_part(ref.p_B_joint[static_cast<size_t>(j5)] - o1, z1);
    if (w.norm() > 1e-3)
      forward = w.normalized();
  }
  if (forward.isZero()) {
    throw Error(ErrorCode::internal,
                "cell '" + cell.name + "': the forward direction of the A1 frame is undefined");
  }
  return (wrist - o1).dot(forward);
}

StatusTurn status_turn(const Cell& cell, const ArmStatusModel& model, const JointVector& q) {
  StatusTurn out;
  for (int n = 1; n <= 6; ++n) {
    if (arm_axis_deg(cell, model, q, n) < 0.0)
      out.turn |= 1 << (n - 1);
  }
  if (wrist_x_in_a1_frame_mm(cell, model, q) < 0.0)
    out.status |= 1;  // overhead area
  if (arm_axis_deg(cell, model, q, 3) >= model.phi_deg)
    out.status |= 2;
  // A5 = 0 counts as positive: HOME (A5 = 0) is Status 2 (PARAMETERS.md section 3).
  if (arm_axis_deg(cell, model, q, 5) < 0.0)
    out.status |= 4;
  return out;
}

}  // namespace redpost
