// The tracker (Andres Algorithm 1) on whole paths: tolerances, limits, jumps, the null space at
// work, reach through redundancy, chunking, and agreement with KDL's own IK.
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <random>

#include "catch_compat.hpp"
#include "kdl_chain.hpp"
#include "paths.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/redundancy/tracker.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

struct PathRun {
  std::vector<PoseResult> results;
  int failures = 0;
  int first_failure = -1;
};

PathRun run_path(Tracker& tracker, const std::vector<TcpTarget>& path) {
  PathRun run;
  const PoseResult first = tracker.solve_first_pose(path.front());
  REQUIRE(first.status == PoseStatus::converged);
  tracker.reset(first.q);
  for (size_t k = 0; k < path.size(); ++k) {
    run.results.push_back(tracker.track(path[k]));
    if (run.results.back().status != PoseStatus::converged) {
      if (run.first_failure < 0)
        run.first_failure = static_cast<int>(k);
      ++run.failures;
      break;  // a postprocessor stops at the first failure
    }
  }
  return run;
}

double weighted_distance(const Cell& cell, const JointVector& q, const JointVector& ref) {
  double s = 0.0;
  for (int i = 0; i < cell.size(); ++i)
    s += cell.joint(i).weight * (q[i] - ref[i]) * (q[i] - ref[i]);
  return std::sqrt(s);
}

}  // namespace

TEST_CASE("tracker: a 5-axis raster is tracked within tolerance, limits and the jump bound") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  Tracker tracker(cell);
  const auto path = test::raster_in_tool_plane(cell, 400, 400, 0.5, 10, 20, 20000);
  const PathRun run = run_path(tracker, path);
  REQUIRE(run.failures == 0);
  JointVector previous;
  for (size_t k = 0; k < run.results.size(); ++k) {
    const PoseResult& r = run.results[k];
    CHECK(r.position_error_mm <= 1e-4);
    CHECK(r.orientation_error_rad <= 1e-7);
    CHECK(within_limits(cell, r.q));
    // Independent check of the reported residual: FK of the returned posture.
    if (k % 97 == 0) {
      const Isometry T = tcp_pose(cell, r.q);
      CHECK((T.translation() - path[k].p_B_mm).norm() <= 1e-4);
      CHECK(std::acos(std::min(1.0, T.linear().col(2).dot(path[k].z_B))) <= 2e-7);
    }
    if (k > 0) {
      for (int i = 0; i < cell.size(); ++i) {
        const double bound = cell.joint(i).type == JointType::prismatic
                                 ? tracker.options().max_joint_step_mm
                                 : tracker.options().max_joint_step_rad;
        CHECK(std::abs(r.q[i] - previous[i]) <= bound);
      }
    }
    previous = r.q;
  }
}

TEST_CASE("tracker: the null-space goals act (centring on home) without spoiling the task") {
  // Both trackers start from the same posture, far from home in the null space: track 600 mm
  // away and the table turned by 0.3 rad, the arm solved for the first target. With h = 0 the
  // redundancy stays where it is; with centring it drifts back towards home.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const auto path = test::raster_in_tool_plane(cell, 300, 300, 1.0, 20, 15, 6000);
  TrackerOptions frozen;
  frozen.locked.set(0);
  frozen.locked.set(1);
  Tracker start(cell, frozen);
  JointVector away = cell.home();
  away[0] += 0.3;
  away[1] += 600;
  start.reset(away);
  const PoseResult first = start.solve_first_pose(path.front());
  REQUIRE(first.status == PoseStatus::converged);

  TrackerOptions with_h, without_h;
  without_h.gains.centring = 0.0;
  without_h.gains.conditioning = 0.0;
  without_h.gains.limits = 0.0;
  Tracker a(cell, with_h), b(cell, without_h);
  a.reset(first.q);
  b.reset(first.q);
  double late_a = 0.0, late_b = 0.0;

  for (size_t k = 0; k < path.size(); ++k) {
    const PoseResult ra = a.track(path[k]), rb = b.track(path[k]);
    REQUIRE(ra.status == PoseStatus::converged);
    REQUIRE(rb.status == PoseStatus::converged);
    CHECK(ra.position_error_mm <= 1e-4);
    CHECK(ra.orientation_error_rad <= 1e-7);
    if (k >= path.size() / 2) {
      late_a += weighted_distance(cell, ra.q, cell.home());
      late_b += weighted_distance(cell, rb.q, cell.home());
    }
  }

  INFO("weighted distance to home over the second half: with h " << late_a << ", without "
                                                                 << late_b);
  // The objective of the centring goal is the weighted distance sum w_i (q_i - q_ref,i)^2 over
  // all joints: it trades table and track against the arm, so no single joint need be closer.
  CHECK(late_a < 0.6 * late_b);
}

TEST_CASE("tracker: the conditioning goal keeps the arm better conditioned") {
  // A pass that stretches the arm towards its reach: the track can follow, and the
  // conditioning goal should make it do so rather than let the arm stretch.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const Isometry T0 = tcp_pose(cell, cell.home());
  // Away from the robot base: the arm faces -x of {B} at home (A1 = 0 towards the table).
  const auto path = test::straight_pass(cell, Eigen::Vector3d(-1, 0, 0), 500, 1.0);
  TrackerOptions plain, conditioned;
  plain.gains.centring = 0.0;
  plain.gains.conditioning = 0.0;
  conditioned.gains.centring = 0.0;
  conditioned.gains.conditioning_threshold = 0.6;
  conditioned.gains.conditioning_gradient = 0.5;
  Tracker a(cell, plain), b(cell, conditioned);
  const PathRun ra = run_path(a, path), rb = run_path(b, path);
  REQUIRE(ra.failures == 0);
  REQUIRE(rb.failures == 0);
  double min_a = 1.0, min_b = 1.0;
  for (size_t k = 0; k < path.size(); ++k) {
    min_a = std::min(min_a, ra.results[k].inv_condition);
    min_b = std::min(min_b, rb.results[k].inv_condition);
  }
  INFO("lowest 1/kappa_F: without the goal " << min_a << ", with " << min_b);
  CHECK(min_b > min_a + 0.02);
  (void)T0;
}

TEST_CASE("tracker: reach through redundancy (Andres Fig. 14): a 2 m pass along the track") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  // The track runs along -y of {B} at theta_M = 0 (Table 1: z1 = -y_B).
  const auto path = test::straight_pass(cell, Eigen::Vector3d(0, -1, 0), 2000, 1.0);
  const int track = cell.find_joint("d_L"), table = cell.find_joint("theta_M");

  TrackerOptions frozen;
  frozen.locked.set(static_cast<size_t>(track));
  frozen.locked.set(static_cast<size_t>(table));
  Tracker locked(cell, frozen);
  const PathRun rl = run_path(locked, path);
  CHECK(rl.failures == 1);
  INFO("with track and table frozen the pass fails at pose " << rl.first_failure);
  CHECK(rl.first_failure > 0);
  CHECK(rl.first_failure < static_cast<int>(path.size()) - 1);

  Tracker free_axes(cell);
  const PathRun rf = run_path(free_axes, path);
  REQUIRE(rf.failures == 0);
  double lo = 1e9, hi = -1e9;
  for (const PoseResult& r : rf.results) {
    lo = std::min(lo, r.q[track]);
    hi = std::max(hi, r.q[track]);
  }
  INFO("track travel " << hi - lo << " mm");
  CHECK(hi - lo > 500.0);
}

TEST_CASE("tracker: results do not depend on how the stream is chunked") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const auto path = test::raster_in_tool_plane(cell, 200, 200, 1.0, 20, 10, 3000);
  std::vector<JointVector> reference;
  {
    Tracker t(cell);
    t.reset(t.solve_first_pose(path.front()).q);
    for (const TcpTarget& target : path)
      reference.push_back(t.track(target).q);
  }
  for (size_t chunk : {size_t{1}, size_t{7}, size_t{1000}}) {
    Tracker t(cell);
    t.reset(t.solve_first_pose(path.front()).q);
    std::vector<PoseResult> results(path.size());
    for (size_t start = 0; start < path.size(); start += chunk) {
      const size_t count = std::min(chunk, path.size() - start);
      t.track(path.data() + start, count, results.data() + start);
    }
    for (size_t k = 0; k < path.size(); ++k) {
      REQUIRE(results[k].q.size() == reference[k].size());
      CHECK(results[k].q == reference[k]);  // bit for bit
    }
  }
}

TEST_CASE("tracker: KDL's ChainIkSolverPos_NR_JL reaches the same TCP poses") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const auto path = test::raster_in_tool_plane(cell, 300, 300, 2.0, 25, 20, 2000);
  Tracker tracker(cell);
  const PathRun run = run_path(tracker, path);
  REQUIRE(run.failures == 0);

  const KDL::Chain chain = test::kdl_chain_from_cell(cell);
  const int n = cell.size();
  KDL::JntArray q_min(n), q_max(n);
  for (int i = 0; i < n; ++i) {
    q_min(i) = cell.joint(i).lower;
    q_max(i) = cell.joint(i).upper;
  }
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainIkSolverVel_pinv ik_vel(chain);
  KDL::ChainIkSolverPos_NR_JL ik(chain, q_min, q_max, fk, ik_vel, 500, 1e-9);
  for (size_t k = 1; k < path.size(); k += 25) {
    const PoseResult& r = run.results[k];
    KDL::JntArray q_tracker(n), q_prev(n), q_out(n);
    for (int i = 0; i < n; ++i) {
      q_tracker(i) = r.q[i];
      q_prev(i) = run.results[k >= 25 ? k - 25 : 0].q[i];
    }
    // KDL's FK of the tracker's posture meets the CL target.
    KDL::Frame F;
    fk.JntToCart(q_tracker, F);
    const Isometry T = test::isometry_from_kdl(F);
    CHECK((T.translation() - path[k].p_B_mm).norm() <= 1e-4);
    CHECK(std::acos(std::min(1.0, T.linear().col(2).dot(path[k].z_B))) <= 2e-7);
    // KDL's IK, from an earlier posture of the path, reaches that same TCP frame.
    REQUIRE(ik.CartToJnt(q_prev, F, q_out) >= 0);
    KDL::Frame F_kdl;
    fk.JntToCart(q_out, F_kdl);
    CHECK((test::isometry_from_kdl(F_kdl).matrix() - T.matrix()).cwiseAbs().maxCoeff() < 1e-6);
  }
}

TEST_CASE("tracker: an unreachable first pose is reported, not silently approximated") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  Tracker tracker(cell);
  // 10 m above the table: beyond any reach.
  const PoseResult r =
      tracker.solve_first_pose(TcpTarget::axis({0, 0, 10000}, Eigen::Vector3d::UnitZ()));
  CHECK(r.status != PoseStatus::converged);
  CHECK(r.position_error_mm > 1000.0);
}

TEST_CASE("tracker: a pose beyond a joint limit fails with joint_limit, naming the joint") {
  // Track and table locked; the home TCP pose swung about the A1 axis by up to 270 degrees.
  // A1 spans only +-185 degrees, so the arm must stop at its limit and the pose fail there.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  TrackerOptions o;
  o.locked.set(0);
  o.locked.set(1);
  Tracker tracker(cell, o);
  KinematicsData data;
  forward_kinematics(cell, cell.home(), data);
  const Eigen::Vector3d axis_point = data.T_B_link[1].translation();  // on the A1 axis
  const Eigen::Vector3d axis_dir = data.T_B_link[1].linear().col(2);
  PoseResult last;
  int poses = 0;
  for (double deg = 0.0; deg <= 270.0; deg += 0.25, ++poses) {
    const Eigen::AngleAxisd turn(deg_to_rad(deg), axis_dir);
    const Eigen::Vector3d p = axis_point + turn * (data.T_B_tcp.translation() - axis_point);
    last = tracker.track(TcpTarget::axis(p, turn * data.T_B_tcp.linear().col(2)));
    if (last.status != PoseStatus::converged)
      break;
    REQUIRE(within_limits(cell, last.q));
  }
  INFO("failed after " << poses << " poses: " << to_string(last.status));
  CHECK(last.status == PoseStatus::joint_limit);
  CHECK(last.offending_joint == cell.find_joint("theta_1"));
  CHECK(poses > 4 * 170);              // not before A1 has used most of its range
  CHECK(within_limits(cell, last.q));  // the reported posture is the last good one
}

TEST_CASE("tracker: a jump beyond the bound is refused and the posture kept") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  TrackerOptions o;
  o.max_joint_step_rad = deg_to_rad(0.5);
  o.max_joint_step_mm = 5.0;
  Tracker tracker(cell, o);
  const Isometry T0 = tcp_pose(cell, cell.home());
  // 0.5 mm: fine. 100 mm in one pose: some joint must move more than 0.5 deg or 5 mm.
  PoseResult r = tracker.track(
      TcpTarget::axis(T0.translation() + Eigen::Vector3d(0.5, 0, 0), T0.linear().col(2)));
  REQUIRE(r.status == PoseStatus::converged);
  const JointVector before = tracker.q();
  r = tracker.track(
      TcpTarget::axis(T0.translation() + Eigen::Vector3d(100, 0, 0), T0.linear().col(2)));
  CHECK(r.status == PoseStatus::joint_jump);
  CHECK(r.offending_joint >= 0);
  CHECK(r.q == before);
  CHECK(tracker.q() == before);
}

TEST_CASE("tracker: the KR270-2 cell (modified DH, spin after a fixed frame) tracks a raster") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  Tracker tracker(cell);
  const auto path = test::raster_in_tool_plane(cell, 300, 300, 1.0, 25, 15, 5000);
  const PathRun run = run_path(tracker, path);
  REQUIRE(run.failures == 0);
  for (size_t k = 0; k < path.size(); k += 50) {
    const Isometry T = tcp_pose(cell, run.results[k].q);
    CHECK((T.translation() - path[k].p_B_mm).norm() <= 1e-4);
    CHECK(within_limits(cell, run.results[k].q));
  }
}

TEST_CASE("tracker: solve_first_pose holds locked joints at their current value") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  TrackerOptions o;
  o.locked.set(0);
  o.locked.set(1);
  Tracker tracker(cell, o);
  JointVector q = cell.home();
  q[0] = deg_to_rad(30.0);
  q[1] = 900.0;
  tracker.reset(q);
  // A target the arm reaches from there: the home TCP pose seen from the moved table and track.
  const Isometry T = tcp_pose(cell, q);
  const PoseResult r = tracker.solve_first_pose(
      TcpTarget::axis(T.translation() + Eigen::Vector3d(20, -10, -30), T.linear().col(2)));
  REQUIRE(r.status == PoseStatus::converged);
  CHECK(r.q[0] == q[0]);
  CHECK(r.q[1] == q[1]);
}

namespace {
// A pass tracked with every joint free (the "plan"), and the track and the table to hold.
struct HeldAxes {
  Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  int track = cell.find_joint("d_L"), table = cell.find_joint("theta_M");
  std::vector<TcpTarget> path;
  PathRun plan;
  std::bitset<kMaxJoints> hold;

  HeldAxes(const Eigen::Vector3d& d_B, double length_mm) {
    path = test::straight_pass(cell, d_B, length_mm, 2.0);
    Tracker free_axes(cell);
    plan = run_path(free_axes, path);
    hold.set(static_cast<std::size_t>(track));
    hold.set(static_cast<std::size_t>(table));
  }
};
}  // namespace

TEST_CASE("tracker: following a plan with the external axes held runs them exactly as planned") {
  // The plan's postures along a line (the free tracker's own, track and table nudged): followed
  // with the track and the table held, the written track and table are the plan's, to the bit,
  // and the TCP still meets every target.
  const HeldAxes h(Eigen::Vector3d(1, 0, 0), 200);
  REQUIRE(h.plan.failures == 0);
  Tracker held(h.cell);
  held.reset(h.plan.results.front().q);
  for (std::size_t k = 1; k < h.path.size(); ++k) {
    JointVector plan = h.plan.results[k].q;
    plan[h.track] += 3.0 * std::sin(0.05 * static_cast<double>(k));  // mm
    plan[h.table] += deg_to_rad(0.2) * std::cos(0.05 * static_cast<double>(k));
    held.follow(plan, 0.5, 0.2, h.hold);
    const PoseResult r = held.track(h.path[k]);
    INFO("pose " << k);
    REQUIRE(r.status == PoseStatus::converged);
    CHECK(r.q[h.track] == plan[h.track]);
    CHECK(r.q[h.table] == plan[h.table]);
  }
}

TEST_CASE("tracker: a held axis is let go where the pose cannot be met with it") {
  // A plan whose track lies 1500 mm off where the arm could reach the target from: held there,
  // the pose has no solution, so the tracker moves every joint and still converges.
  const HeldAxes h(Eigen::Vector3d(0, -1, 0), 20);
  REQUIRE(h.plan.failures == 0);
  Tracker held(h.cell);
  held.reset(h.plan.results[0].q);
  JointVector plan = h.plan.results[1].q;
  plan[h.track] += 1500.0;
  held.follow(plan, 0.5, 0.2, h.hold);
  const PoseResult r = held.track(h.path[1]);
  REQUIRE(r.status == PoseStatus::converged);
  CHECK(std::fabs(r.q[h.track] - plan[h.track]) > 1.0);
}
