// Closed-form inverse kinematics of the arm (issue 8) against forward kinematics (round trips
// from seeded random postures), status_turn() (the posture numbering), brute force (the
// 2*pi-equivalent nearest q_near) and hand-made cells outside the KUKA class.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

constexpr double kTwoPi = 2.0 * kPi;

double wrap_pi(double x) {
  return x - kTwoPi * std::round(x / kTwoPi);
}

struct PoseError {
  double position_mm = 0.0;
  double rotation_rad = 0.0;
};

// Position error and rotation angle between the TCP of q and a target.
PoseError pose_error(const Cell& cell, const JointVector& q, const Isometry& T) {
  const Isometry T_q = tcp_pose(cell, q);
  PoseError e;
  e.position_mm = (T_q.translation() - T.translation()).norm();
  const Eigen::AngleAxisd rel(T_q.linear().transpose() * T.linear());
  e.rotation_rad = std::abs(rel.angle());
  return e;
}

bool arm_within_limits(const Cell& cell, const std::array<int, 6>& arm, const JointVector& q) {
  for (const int i : arm) {
    if (!(q[i] >= cell.joint(i).lower && q[i] <= cell.joint(i).upper))
      return false;
  }
  return true;
}

// True when no other 2*pi-equivalent of q[i] within the limits is nearer to near[i].
bool nearest_within_limits(const Cell& cell, int i, const JointVector& q, const JointVector& near) {
  const Joint& j = cell.joint(i);
  for (int k = -3; k <= 3; ++k) {
    const double v = q[i] + kTwoPi * k;
    if (k != 0 && v >= j.lower && v <= j.upper &&
        std::abs(v - near[i]) < std::abs(q[i] - near[i]) - 1e-12)
      return false;
  }
  return true;
}

// The shipped KR15/2 file with one DH line replaced, for cells outside the class.
std::string kr15_with(const std::string& from, const std::string& to) {
  std::string xml = read_text_file(test::source_path("definitions/cells/kr15_2.xml"));
  const size_t at = xml.find(from);
  REQUIRE(at != std::string::npos);
  xml.replace(at, from.size(), to);
  return xml;
}

}  // namespace

TEST_CASE("arm_ik: random postures of every shipped cell come back in their own posture",
          "[arm_ik]") {
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    const ArmStatusModel& model = ik.status_model();
    const std::array<int, 6>& arm = ik.arm_joints();
    std::mt19937_64 rng(20240808);
    const int kPoses = 10000;
    int own_missing = 0, own_not_valid = 0, own_mismatch = 0, status_mismatch = 0,
        round_trip_bad = 0, valid_mismatch = 0, others_changed = 0, not_nearest = 0;
    int all_eight = 0;
    std::array<int, 8> found{};
    double worst_q = 0.0, worst_mm = 0.0, worst_rad = 0.0;
    for (int n = 0; n < kPoses; ++n) {
      // Every joint random, externals and the virtual spin included: they go in as q_other.
      const JointVector q = test::random_posture(cell, rng);
      const Isometry T = tcp_pose(cell, q);
      const JointVector* near = (n % 2 == 0) ? nullptr : &q;
      const JointVector home = cell.home();
      const JointVector& q_near = near != nullptr ? *near : home;
      const ArmIkSolutions sol = ik.solve(T, q, near);

      const int mu = status_turn(cell, model, q).status;
      if (!sol.exists[static_cast<size_t>(mu)]) {
        ++own_missing;
        continue;
      }
      if (!sol.valid[static_cast<size_t>(mu)])
        ++own_not_valid;
      for (int k = 0; k < 6; ++k) {
        const int i = arm[static_cast<size_t>(k)];
        const double dq = std::abs(wrap_pi(sol.q[static_cast<size_t>(mu)][i] - q[i]));
        worst_q = std::max(worst_q, dq);
        if (dq > 1e-7)
          ++own_mismatch;
      }

      int exists = 0;
      for (int s = 0; s < 8; ++s) {
        if (!sol.exists[static_cast<size_t>(s)])
          continue;
        ++exists;
        ++found[static_cast<size_t>(s)];
        const JointVector& qs = sol.q[static_cast<size_t>(s)];
        if (status_turn(cell, model, qs).status != s)
          ++status_mismatch;
        const PoseError e = pose_error(cell, qs, T);
        worst_mm = std::max(worst_mm, e.position_mm);
        worst_rad = std::max(worst_rad, e.rotation_rad);
        const bool round_trip = e.position_mm < 1e-6 && e.rotation_rad < 1e-9;
        if (!round_trip)
          ++round_trip_bad;
        if (sol.valid[static_cast<size_t>(s)] != (round_trip && arm_within_limits(cell, arm, qs)))
          ++valid_mismatch;
        for (int i = 0; i < cell.size(); ++i) {
          const bool is_arm = std::find(arm.begin(), arm.end(), i) != arm.end();
          if (!is_arm && qs[i] != q[i])
            ++others_changed;
        }
        if (sol.valid[static_cast<size_t>(s)]) {
          for (const int i : arm) {
            if (!nearest_within_limits(cell, i, qs, q_near))
              ++not_nearest;
          }
        }
      }
      if (exists == 8)
        ++all_eight;
    }
    INFO(name << ": all eight postures for " << all_eight << " of " << kPoses
              << " poses; worst |dq| " << worst_q << " rad, round trip " << worst_mm << " mm "
              << worst_rad << " rad");
    if (std::getenv("REDPOST_ARM_IK_STATS") != nullptr) {
      WARN(name << ": all eight postures for " << all_eight << " of " << kPoses
                << " poses; worst |dq| " << worst_q << " rad, round trip " << worst_mm << " mm "
                << worst_rad << " rad");
    }
    CHECK(own_missing == 0);
    CHECK(own_not_valid == 0);
    CHECK(own_mismatch == 0);
    CHECK(status_mismatch == 0);
    CHECK(round_trip_bad == 0);
    CHECK(valid_mismatch == 0);
    CHECK(others_changed == 0);
    CHECK(not_nearest == 0);
    // Postures drawn within the limits are mostly inside the reach of both shoulder branches
    // (52 to 65 % of them in the shipped cells); every one of the eight slots is met.
    CHECK(all_eight > kPoses * 2 / 5);
    for (int s = 0; s < 8; ++s)
      CHECK(found[static_cast<size_t>(s)] > 0);
  }
}

TEST_CASE("arm_ik: one posture asked is bit for bit that posture of the full solve", "[arm_ik]") {
  // The whole-path planner asks for one Status at a time (only_status), and the solver skips the
  // shoulder and elbow branches that cannot give it: the answer must not change.
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    std::mt19937_64 rng(20261202);
    int compared = 0, differ = 0;
    for (int n = 0; n < 2000; ++n) {
      const JointVector q = test::random_posture(cell, rng);
      const Isometry T = tcp_pose(cell, q);
      const ArmIkSolutions all = ik.solve(T, q, nullptr);
      for (int s = 0; s < 8; ++s) {
        const auto su = static_cast<size_t>(s);
        const ArmIkSolutions one = ik.solve(T, q, nullptr, s);
        if (one.valid[su] != all.valid[su] || one.exists[su] != all.exists[su])
          ++differ;
        else if (all.exists[su] && one.q[su] != all.q[su])
          ++differ;
        for (int o = 0; o < 8; ++o)
          differ += (o != s && one.valid[static_cast<size_t>(o)]) ? 1 : 0;
        compared += all.exists[su] ? 1 : 0;
      }
    }
    INFO(name << ": " << compared << " postures compared");
    CHECK(compared > 5000);
    CHECK(differ == 0);
  }
}

TEST_CASE(
    "arm_ik: surroundings composed beforehand give the same postures, and the round trip "
    "never fails where a posture exists within the limits",
    "[arm_ik]") {
  // The whole-path planner composes the links around the arm once per setting of the table,
  // track and spin (before_arm, after_arm) and skips the round trip (RoundTrip::skip): the
  // postures must be bit for bit the plain solve's, and the check must be one that never fails
  // where it is skipped. Targets: the TCP of random postures (exact), the same moved up to
  // 300 mm and turned up to 0.5 rad (many postures out of reach), and pushed towards the
  // boundary of the reach (the closed form's clamp).
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    std::mt19937_64 rng(20261205);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int checked = 0, near_reach = 0, differ = 0;
    for (int n = 0; n < 3000; ++n) {
      const JointVector q = test::random_posture(cell, rng);
      Isometry T = tcp_pose(cell, q);
      if (n % 3 == 1) {
        T.translation() += 300.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
        T.linear() = T.linear() * Eigen::AngleAxisd(0.5 * u(rng), axis).toRotationMatrix();
      } else if (n % 3 == 2) {
        // Along the line from the arm's base to the target, to the last scale at which the
        // target's own posture exists (bisection to 1e-12 of the scale).
        KinematicsData data;
        forward_kinematics(cell, q, data);
        const Eigen::Vector3d base = data.p_B_joint[static_cast<size_t>(ik.arm_joints()[1])];
        const int mu = status_turn(cell, ik.status_model(), q).status;
        const Eigen::Vector3d d = T.translation() - base;
        double lo = 1.0, hi = 4.0;
        Isometry Tb = T;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          Tb.translation() = base + mid * d;
          (ik.solve(Tb, q, &q).exists[static_cast<size_t>(mu)] ? lo : hi) = mid;
        }
        Tb.translation() = base + hi * d;
        const bool beyond = !ik.solve(Tb, q, &q).exists[static_cast<size_t>(mu)];
        Tb.translation() = base + lo * d;
        T = Tb;
        near_reach += beyond && ik.solve(T, q, &q).exists[static_cast<size_t>(mu)] ? 1 : 0;
      }
      ArmBefore before;
      ArmAfter after;
      ik.before_arm(q, before);
      ik.after_arm(q, after);
      const ArmIkSolutions plain = ik.solve(T, q, &q);
      const ArmIkSolutions with = ik.solve(T, before, after, q, &q, -1, RoundTrip::check);
      const ArmIkSolutions skip = ik.solve(T, before, after, q, &q, -1, RoundTrip::skip);
      for (size_t s = 0; s < 8; ++s) {
        if (with.exists[s] != plain.exists[s] || with.valid[s] != plain.valid[s] ||
            skip.exists[s] != plain.exists[s] || skip.valid[s] != plain.valid[s])
          ++differ;
        else if (plain.exists[s] && (with.q[s] != plain.q[s] || skip.q[s] != plain.q[s]))
          ++differ;
        checked += plain.valid[s] ? 1 : 0;
      }
    }
    INFO(name << ": " << checked << " valid postures, " << near_reach << " targets at the reach");
    CHECK(checked > 5000);
    CHECK(near_reach > 500);
    CHECK(differ == 0);
  }
}

TEST_CASE("arm_ik: a folded pose of every shipped cell has eight distinct postures", "[arm_ik]") {
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    // A = (20, -120, 140, 30, 40, -20) deg: the wrist close to the A1 axis, within reach of
    // both shoulder branches; the other axes at home.
    AxisValues axes = to_controller_axes(cell, cell.home());
    const double a_deg[6] = {20.0, -120.0, 140.0, 30.0, 40.0, -20.0};
    for (int n = 1; n <= 6; ++n)
      axes.arm(n) = a_deg[n - 1];
    const JointVector home = from_controller_axes(cell, axes, cell.home());
    const Isometry T = tcp_pose(cell, home);
    const ArmIkSolutions sol = ik.solve(T, home);
    INFO(name);
    for (int s = 0; s < 8; ++s) {
      REQUIRE(sol.exists[static_cast<size_t>(s)]);
      const PoseError e = pose_error(cell, sol.q[static_cast<size_t>(s)], T);
      CHECK(e.position_mm < 1e-6);
      CHECK(e.rotation_rad < 1e-9);
      for (int t = 0; t < s; ++t) {
        double diff = 0.0;
        for (const int i : ik.arm_joints()) {
          diff = std::max(diff, std::abs(wrap_pi(sol.q[static_cast<size_t>(s)][i] -
                                                 sol.q[static_cast<size_t>(t)][i])));
        }
        CHECK(diff > 1e-3);
      }
    }
    // The pose's own posture returns it.
    const int mu = status_turn(cell, ik.status_model(), home).status;
    CHECK(sol.valid[static_cast<size_t>(mu)]);
    for (const int i : ik.arm_joints())
      CHECK(std::abs(sol.q[static_cast<size_t>(mu)][i] - home[i]) < 1e-9);
  }
}

TEST_CASE("arm_ik: a target far outside the reach has no posture", "[arm_ik]") {
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    const JointVector home = cell.home();
    Isometry T = tcp_pose(cell, home);
    T.translation() += Eigen::Vector3d(20000.0, -15000.0, 8000.0);
    const ArmIkSolutions sol = ik.solve(T, home);
    for (int s = 0; s < 8; ++s) {
      CHECK_FALSE(sol.exists[static_cast<size_t>(s)]);
      CHECK_FALSE(sol.valid[static_cast<size_t>(s)]);
    }
  }
}

TEST_CASE("arm_ik: a cell whose arm is not of the KUKA class is refused with the reason",
          "[arm_ik]") {
  struct Case {
    std::string from, to, reason;
  };
  const Case cases[] = {
      // A5 axis moved 40 mm along A4: A4 and A5 no longer meet.
      {R"(<dh alpha="-90" a="0" theta="0" d="0"/>)", R"(<dh alpha="-90" a="40" theta="0" d="0"/>)",
       "spherical wrist"},
      // A3 tilted by 5 deg against A2.
      {R"(<dh alpha="0" a="650" theta="0" d="0"/>)", R"(<dh alpha="5" a="650" theta="0" d="0"/>)",
       "not parallel"},
  };
  for (const Case& c : cases) {
    const Cell cell = parse_cell(kr15_with(c.from, c.to), "bent_kr15.xml");
    try {
      const ArmIk ik(cell);
      FAIL("no Error for a cell with " << c.reason);
    } catch (const Error& e) {
      INFO(e.message());
      CHECK(e.code() == ErrorCode::bad_input);
      CHECK(e.message().find(c.reason) != std::string::npos);
    }
  }
  // The unmodified text is accepted: the edits above are what is refused.
  CHECK_NOTHROW(ArmIk(parse_cell(kr15_with("<cell", "<cell"), "kr15.xml")));
}

TEST_CASE("arm_ik: at A5 = 0 the wrist-singular pose is reached with A4 kept at q_near",
          "[arm_ik]") {
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    const ArmIk ik(cell);
    const std::array<int, 6>& arm = ik.arm_joints();
    const int j4 = arm[3], j5 = arm[4];
    std::mt19937_64 rng(5);
    int checked = 0;
    for (int n = 0; n < 200; ++n) {
      JointVector q = test::random_posture(cell, rng);
      q[j5] = from_axis_value(cell.joint(j5), 0.0);
      const Isometry T = tcp_pose(cell, q);
      const JointVector home = cell.home();
      const ArmIkSolutions sol = ik.solve(T, q);
      const int mu = status_turn(cell, ik.status_model(), q).status;
      INFO(name << " pose " << n << " status " << mu);
      REQUIRE(sol.exists[static_cast<size_t>(mu)]);
      const JointVector& qs = sol.q[static_cast<size_t>(mu)];
      // A1..A3 and A5 as given; A4 the home value (as near as the limits allow); A6 takes the
      // rest of the rotation about the aligned A4/A6 axis.
      for (const int i : {arm[0], arm[1], arm[2], j5})
        CHECK(std::abs(wrap_pi(qs[i] - q[i])) < 1e-7);
      CHECK(std::abs(wrap_pi(qs[j4] - home[j4])) < 1e-12);
      const PoseError e = pose_error(cell, qs, T);
      CHECK(e.position_mm < 1e-6);
      CHECK(e.rotation_rad < 1e-9);
      for (int s = 0; s < 8; ++s) {
        if (sol.exists[static_cast<size_t>(s)])
          CHECK(status_turn(cell, ik.status_model(), sol.q[static_cast<size_t>(s)]).status == s);
      }
      ++checked;
    }
    CHECK(checked == 200);
  }
}

TEST_CASE("arm_ik: a wrist point on the A1 axis keeps A1 at q_near", "[arm_ik]") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const ArmIk ik(cell);
  const ArmStatusModel& model = ik.status_model();
  const std::array<int, 6>& arm = ik.arm_joints();
  // A2 = -100 deg; A3 by bisection so that the wrist x in the A1 frame is 0.
  JointVector q = cell.home();
  q[arm[0]] = deg_to_rad(20.0);
  q[arm[1]] = from_axis_value(cell.joint(arm[1]), -100.0);
  q[arm[3]] = 0.4, q[arm[4]] = from_axis_value(cell.joint(arm[4]), 35.0), q[arm[5]] = -0.8;
  double lo = 0.0, hi = 150.0;  // A3 (deg): wrist x changes sign between them
  auto wx = [&](double a3) {
    q[arm[2]] = from_axis_value(cell.joint(arm[2]), a3);
    return wrist_x_in_a1_frame_mm(cell, model, q);
  };
  REQUIRE((wx(lo) < 0.0) != (wx(hi) < 0.0));
  const bool lo_negative = wx(lo) < 0.0;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    ((wx(mid) < 0.0) == lo_negative ? lo : hi) = mid;
  }
  wx(0.5 * (lo + hi));
  REQUIRE(std::abs(wrist_x_in_a1_frame_mm(cell, model, q)) < 1e-9);
  const Isometry T = tcp_pose(cell, q);
  const JointVector near = q;
  const ArmIkSolutions sol = ik.solve(T, q, &near);
  int exists = 0;
  for (int s = 0; s < 8; ++s) {
    if (!sol.exists[static_cast<size_t>(s)])
      continue;
    ++exists;
    const JointVector& qs = sol.q[static_cast<size_t>(s)];
    CHECK(status_turn(cell, model, qs).status == s);
    const PoseError e = pose_error(cell, qs, T);
    CHECK(e.position_mm < 1e-6);
    CHECK(e.rotation_rad < 1e-9);
    // A1 is q_near's, or q_near's turned by pi (the other shoulder branch).
    const double d1 = std::abs(wrap_pi(qs[arm[0]] - near[arm[0]]));
    CHECK((d1 < 1e-9 || std::abs(d1 - kPi) < 1e-9));
  }
  CHECK(exists >= 4);
  // Status bit 0 is decided by the rounding of a wrist x of ~0 here, so the original posture
  // may sit in either shoulder slot; it is among the solutions.
  bool original_found = false;
  for (int s = 0; s < 8; ++s) {
    if (!sol.exists[static_cast<size_t>(s)])
      continue;
    bool same = true;
    for (const int i : arm)
      same = same && std::abs(wrap_pi(sol.q[static_cast<size_t>(s)][i] - q[i])) < 1e-6;
    original_found = original_found || same;
  }
  CHECK(original_found);
}
