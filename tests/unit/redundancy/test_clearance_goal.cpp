// The clearance as a null-space goal (redundancy/clearance_goal.hpp): its gradient against
// finite differences of the distance, and the tracker steering a body away from an obstacle with
// it while the TCP stays on its targets.
#include <algorithm>
#include <random>

#include "../collision/collision_support.hpp"
#include "catch_compat.hpp"
#include "redpost/collision/clearance.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/redundancy/clearance_goal.hpp"
#include "redpost/redundancy/tracker.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// The Andres cell's skeleton (its own pairs allowed) and a sphere on {B} at `obstacle`.
struct Setup {
  Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  std::unique_ptr<CollisionScene> scene;

  explicit Setup(const Eigen::Vector3d& obstacle, double radius_mm) {
    std::vector<Body> bodies = test::skeleton_bodies(cell, 60.0);
    const std::vector<std::pair<int, int>> allowed =
        test::all_pairs(static_cast<int>(bodies.size()));
    Shape s;
    s.kind = ShapeKind::sphere;
    s.radius_mm = radius_mm;
    s.T_frame_shape.translation() = obstacle;
    Body o;
    o.name = "obstacle";
    o.role = BodyRole::fixture;
    o.frame = kFrameBase;
    o.shapes.push_back(s);
    bodies.push_back(o);
    scene = std::make_unique<CollisionScene>(cell, bodies, allowed);
  }

  // The distance of every pair at q (exact).
  std::vector<double> distances(const JointVector& q) const {
    ScenePoses poses;
    KinematicsData data;
    scene->prepare(poses);
    JointVector qp = q;
    qp[cell.size() - 1] = 0.0;  // the spin: no body turns with it
    forward_kinematics(cell, qp, data);
    scene->place(data, poses);
    std::vector<double> d;
    for (std::size_t p = 0; p < scene->pairs().size(); ++p)
      d.push_back(scene->distance(static_cast<int>(p), poses, 1e9));
    return d;
  }
  double least(const JointVector& q) const {
    const std::vector<double> d = distances(q);
    return *std::min_element(d.begin(), d.end());
  }
  // The goal's potential: its gradient() is grad Phi, Phi = -sum (influence - d)^2 / (2
  // influence) over the pairs within the influence.
  double potential(const JointVector& q, double influence) const {
    double phi = 0.0;
    for (double d : distances(q)) {
      if (d < influence)
        phi -= (influence - d) * (influence - d) / (2.0 * influence);
    }
    return phi;
  }
};

}  // namespace

TEST_CASE("the clearance goal's gradient is its potential's, by finite differences",
          "[redundancy][collision]") {
  std::mt19937_64 rng(461);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Cell probe = test::shipped_cell("andres2011_kr15_track_table");
    JointVector q = probe.home();
    for (int i = 0; i < probe.size(); ++i)
      q[i] += 0.2 * u(rng) * (probe.joint(i).type == JointType::prismatic ? 500.0 : 1.0);
    // An obstacle 30 mm off the forearm's capsule, in a random direction.
    KinematicsData data;
    forward_kinematics(probe, q, data);
    const int forearm = probe.find_joint("theta_4");
    const Eigen::Vector3d on_arm = data.T_B_link[static_cast<std::size_t>(forearm)].translation();
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    Setup s(on_arm + (60.0 + 40.0 + 30.0) * dir, 40.0);
    const double d = s.least(q);
    if (!(d > 5.0 && d < 60.0))
      continue;  // another part of the arm is nearer, or the obstacle sits on it
    const double influence = 100.0;
    ClearanceGoal goal(*s.scene, influence);
    JointVector g;
    goal.gradient(q, g);
    for (int i = 0; i < s.cell.size(); ++i) {
      if (s.cell.joint(i).type == JointType::virtual_spin)
        continue;
      const double h = s.cell.joint(i).type == JointType::prismatic ? 1e-3 : 1e-6;
      JointVector qp = q, qm = q;
      qp[i] += h;
      qm[i] -= h;
      const double fd = (s.potential(qp, influence) - s.potential(qm, influence)) / (2.0 * h);
      INFO("trial " << trial << " joint " << i << " d " << d);
      CHECK(g[i] == Approx(fd).epsilon(1e-3).margin(1e-3));
    }
    ++compared;
  }
  CHECK(compared >= 10);
}

TEST_CASE("the tracker steers a link away from an obstacle with the goal, the TCP on target",
          "[redundancy][collision]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const JointVector home = cell.home();
  KinematicsData data;
  forward_kinematics(cell, home, data);
  const int forearm = cell.find_joint("theta_4");
  const Eigen::Vector3d on_arm = data.T_B_link[static_cast<std::size_t>(forearm)].translation();
  // A sphere (r 60) on the wrist's frame and an obstacle (r 50) 20 mm beside it, on the side
  // where the track and the table can take the wrist away (straight above it, no null-space
  // motion changes the distance to first order).
  Setup s(on_arm + Eigen::Vector3d(60.0 + 50.0 + 20.0, 0.0, 0.0), 50.0);
  {
    Shape ball;
    ball.kind = ShapeKind::sphere;
    ball.radius_mm = 60.0;
    Body wrist;
    wrist.name = "wrist";
    wrist.frame = forearm;
    wrist.shapes.push_back(ball);
    Body obstacle = s.scene->body(s.scene->body_count() - 1);
    s.scene = std::make_unique<CollisionScene>(s.cell, std::vector<Body>{wrist, obstacle},
                                               std::vector<std::pair<int, int>>{});
  }
  const double before = s.least(home);
  REQUIRE(before == Approx(20.0).margin(1e-6));
  ClearanceGoal goal(*s.scene, 60.0);
  goal.set_active(true);
  for (const bool with_goal : {false, true}) {
    TrackerOptions o;
    o.extra_goal = with_goal ? &goal : nullptr;
    Tracker tracker(cell, o);
    tracker.reset(home);
    const TcpTarget target =
        TcpTarget::axis(tcp_pose(cell, home).translation(), tcp_pose(cell, home).linear().col(2));
    for (int k = 0; k < 300; ++k) {
      const PoseResult r = tracker.track(target);
      REQUIRE(r.status == PoseStatus::converged);
      CHECK(r.position_error_mm < 1e-3);
    }
    const double after = s.least(tracker.q());
    INFO("with the goal: " << with_goal << ", before " << before << " mm, after " << after);
    if (with_goal)
      CHECK(after > before + 5.0);  // the redundancy moved the arm away
    else
      CHECK(after < before + 0.5);  // centring alone does not
  }
}
