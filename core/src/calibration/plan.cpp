// The measurement plan of the calibration (plan.hpp): the commanded frames of eqs. 2-4, the
// joints that reach them on the nominal model, and simulated readings. docs/calibration.md.
#include "redpost/calibration/plan.hpp"

#include <bitset>
#include <random>
#include <sstream>
#include <string>

#include "calibration/fail.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/redundancy/tracker.hpp"

namespace redpost {

namespace {

using detail::fail_bad_input;

}  // namespace

std::vector<int> external_joint_indices(const Cell& cell) {
  std::vector<int> out;
  for (int i = 0; i < cell.size(); ++i)
    if (cell.joint(i).axis.kind == AxisKind::external)
      out.push_back(i);
  return out;
}

Isometry commanded_frame(PlaneAxis plane, const Eigen::Vector3d& p_on_plane, double stand_off_mm) {
  KukaAbc abc;  // eqs. 2-4
  if (plane == PlaneAxis::x)
    abc = {0.0, -90.0, 0.0};
  else if (plane == PlaneAxis::y)
    abc = {0.0, 0.0, -90.0};
  Isometry T = frame_from_xyzabc(p_on_plane.x(), p_on_plane.y(), p_on_plane.z(), abc);
  // The beam is -z: the TCP stands off the plane by stand_off against the beam, along +z.
  T.translation() += stand_off_mm * T.linear().col(2);
  return T;
}

namespace {

// The tracker stops within 1e-4 mm and 1e-7 rad of its target: enough to run a path, not to
// model a reading. A controller reaches the commanded frame with its exact inverse kinematics,
// so the joints the reading is modelled at must give that frame to rounding, or the
// identification inherits the solver's tolerance (parameters off by some 1e-6 mm on noise-free
// data). A few Newton steps over the joints that are not locked, minimum-norm (the spin about
// the beam stays where the tracker left it as far as the frame allows), take the error from
// 1e-4 mm to 1e-13 mm: the convergence is quadratic.
void polish_to_frame(const Cell& cell, const std::bitset<kMaxJoints>& locked, const Isometry& T,
                     JointVector& q) {
  KinematicsData data;
  Jacobian J(6, cell.size());
  for (int it = 0; it < 8; ++it) {
    forward_kinematics(cell, q, data);
    const Eigen::AngleAxisd rotation(T.linear() * data.T_B_tcp.linear().transpose());
    Eigen::Matrix<double, 6, 1> e;  // [omega; v], as the Jacobian's rows
    e.head<3>() = rotation.angle() * rotation.axis();
    e.tail<3>() = T.translation() - data.T_B_tcp.translation();
    if (e.tail<3>().norm() < 1e-12 && e.head<3>().norm() < 1e-15)
      return;
    tcp_jacobian(cell, data, J);
    // Locked joints stay; so does a joint the tracker left on a limit (the others, seven for
    // six, still span the frame).
    for (int j = 0; j < cell.size(); ++j) {
      const Joint& joint = cell.joint(j);
      const bool on_limit = q[j] - joint.lower < 1e-9 || joint.upper - q[j] < 1e-9;
      if (locked.test(static_cast<size_t>(j)) || on_limit)
        J.col(j).setZero();
    }
    const Eigen::MatrixXd Jd = J;
    const Eigen::VectorXd dq = Jd.completeOrthogonalDecomposition().solve(e);
    q += dq;
    if (dq.cwiseAbs().maxCoeff() < 1e-15)
      return;
  }
}

}  // namespace

JointVector joints_for_commanded_frame(const Cell& nominal, const std::vector<int>& external_joints,
                                       const std::vector<double>& external_values,
                                       const Isometry& T_B_commanded, int perturbed_starts,
                                       std::uint64_t seed) {
  if (external_values.size() != external_joints.size())
    fail_bad_input("calibration: " + std::to_string(external_values.size()) + " values for " +
                   std::to_string(external_joints.size()) + " external joints");
  // Tracker::solve_first_pose starts from the cell's home (with the locked joints at their home
  // values too), so the solver's cell gets the external values as those joints' home. The
  // geometry is the nominal one, untouched.
  Cell solver_cell = nominal;
  TrackerOptions topt;
  for (size_t e = 0; e < external_joints.size(); ++e) {
    const int idx = external_joints[e];
    if (idx < 0 || idx >= nominal.size())
      fail_bad_input("calibration: external joint index " + std::to_string(idx) + " out of range");
    topt.locked.set(static_cast<size_t>(idx));
    solver_cell.joints[static_cast<size_t>(idx)].home = external_values[e];
  }
  const JointVector start = solver_cell.home();
  if (!within_limits(nominal, start))
    fail_bad_input("calibration: external joint values beyond the joints' limits");
  topt.q_ref = start;
  Tracker tracker(solver_cell, topt);
  tracker.reset(start);
  const PoseResult r =
      tracker.solve_first_pose(TcpTarget::frame(T_B_commanded), perturbed_starts, seed);
  if (r.status != PoseStatus::converged) {
    const Eigen::Vector3d p = T_B_commanded.translation();
    std::ostringstream m;
    m << "the commanded frame at " << p.x() << ", " << p.y() << ", " << p.z()
      << " mm cannot be reached: " << to_string(r.status);
    throw Error(ErrorCode::unreachable, m.str());
  }
  // The first solution may sit on a joint limit (a joint is locked there when the solver meets
  // it). The spin about the beam is free (the reading does not depend on it), so let the
  // null-space goals (centring, limit avoidance) move the posture off the limits while the TCP
  // stays on the commanded frame: track the same target until the posture settles.
  // Only postures near a limit need it (the others are left as solved, which is also fast).
  auto near_limit = [&nominal, &topt](const JointVector& q) {
    for (int j = 0; j < nominal.size(); ++j) {
      const Joint& jt = nominal.joint(j);
      if (topt.locked.test(static_cast<size_t>(j)) || jt.type == JointType::virtual_spin)
        continue;
      const double margin = jt.type == JointType::prismatic ? 5.0 : deg_to_rad(5.0);
      if (q[j] - jt.lower < margin || jt.upper - q[j] < margin)
        return true;
    }
    return false;
  };
  tracker.reset(r.q);
  JointVector q = r.q;
  for (int k = 0; k < 400 && near_limit(q); ++k) {
    const PoseResult s = tracker.track(TcpTarget::frame(T_B_commanded));
    if (s.status != PoseStatus::converged)
      break;
    const double moved = (s.q - q).cwiseAbs().maxCoeff();
    q = s.q;
    if (moved < 1e-9)
      break;
  }
  // A posture on a limit may be pushed past it by the polish's 1e-4 mm: it keeps the tracker's.
  JointVector polished = q;
  polish_to_frame(nominal, topt.locked, T_B_commanded, polished);
  return within_limits(nominal, polished) ? polished : q;
}

std::vector<CalibrationPoint> plan_calibration(const Cell& nominal,
                                               const CalibrationPlanOptions& options) {
  if (options.grid < 1)
    fail_bad_input("calibration plan: the grid needs at least 1 x 1 points");
  std::vector<CalibrationPoint> points;
  const int n = options.grid;
  auto lerp = [n](double lo, double hi, int i) {
    return n == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * i / (n - 1);
  };
  const double w = options.half_width_mm;
  const auto& off = options.model.plane_offset_mm;
  for (size_t c = 0; c < options.configurations.size(); ++c) {
    const auto& config = options.configurations[c];
    for (int k = 0; k < 3; ++k) {
      if (!options.planes[static_cast<size_t>(k)])
        continue;
      const auto plane = static_cast<PlaneAxis>(k);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          if (options.alternate_configurations &&
              static_cast<size_t>(i + j) % options.configurations.size() != c)
            continue;
          Eigen::Vector3d p;
          const double u = lerp(-w, w, i);
          if (plane == PlaneAxis::x)
            p = {off[0], u, lerp(options.z_min_mm, options.z_max_mm, j)};
          else if (plane == PlaneAxis::y)
            p = {u, off[1], lerp(options.z_min_mm, options.z_max_mm, j)};
          else
            p = {u, lerp(-w, w, j), off[2]};
          CalibrationPoint pt;
          pt.plane = plane;
          pt.configuration = static_cast<int>(c);
          pt.T_B_commanded = commanded_frame(plane, p, options.stand_off_mm);
          try {
            pt.q = joints_for_commanded_frame(nominal, options.external_joints, config,
                                              pt.T_B_commanded, options.perturbed_starts,
                                              options.seed);
          } catch (const Error& e) {
            throw Error(e.code(), "calibration plan: point " + std::to_string(points.size() + 1) +
                                      " (configuration " + std::to_string(c + 1) + ", plane " +
                                      to_string(plane) + "): " + e.message());
          }
          pt.reading_mm = options.stand_off_mm;  // the nominal reading
          points.push_back(pt);
        }
    }
  }
  return points;
}

void simulate_readings(const Cell& true_cell, std::vector<CalibrationPoint>& points,
                       double sigma_mm, std::uint64_t seed, const MeasurementModel& model) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (auto& pt : points) {
    const double e = noise(rng);
    pt.reading_mm = laser_reading(tcp_pose(true_cell, pt.q), pt.plane, model) + sigma_mm * e;
  }
}

}  // namespace redpost
