// redpost's forward kinematics and Jacobian against Orocos KDL, an independent implementation,
// on the shipped cells and on a hand-built cell that uses every branch of the chain converter.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "catch_compat.hpp"
#include "kdl_chain.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "test_support.hpp"

namespace {

using redpost::Cell;
using redpost::Isometry;
using redpost::JointVector;
using redpost::test::KdlChainLayout;

constexpr int kPostures = 1000;
// FK: positions are up to ~3 m, so 1e-9 mm is ~2000 ulp of the largest coordinate, still far
// below any modelling error (a wrong sign or offset moves the TCP by millimetres).
constexpr double kPositionTol = 1e-9;   // mm
constexpr double kRotationTol = 1e-12;  // per matrix element
// Jacobian: angular rows are unit vectors; linear rows reach ~3000 mm/rad.
constexpr double kAngularTol = 1e-12;
constexpr double kLinearRelTol = 1e-9;  // relative to the largest linear entry (>= 1 mm)

KDL::JntArray to_kdl(const JointVector& q) {
  KDL::JntArray out(static_cast<unsigned>(q.size()));
  for (int i = 0; i < q.size(); ++i) {
    out(static_cast<unsigned>(i)) = q[i];
  }
  return out;
}

std::string describe(const JointVector& q) {
  std::ostringstream os;
  os.precision(17);
  os << "q = [" << q.transpose() << "]";
  return os.str();
}

// The postures of a test: home first (a readable failure if the model is off everywhere), then
// seeded uniform draws within the limits.
template <class Fn>
void for_postures(const Cell& cell, std::uint64_t seed, Fn fn) {
  fn(cell.home());
  std::mt19937_64 rng(seed);
  for (int k = 0; k < kPostures; ++k) {
    fn(redpost::test::random_posture(cell, rng));
  }
}

struct FkError {
  double position = 0.0;
  double rotation = 0.0;
  JointVector worst_q;
};

FkError compare_fk(const Cell& cell, KdlChainLayout layout, std::uint64_t seed) {
  const KDL::Chain chain = redpost::test::kdl_chain_from_cell(cell, layout);
  REQUIRE(static_cast<int>(chain.getNrOfJoints()) == cell.size());
  KDL::ChainFkSolverPos_recursive fk(chain);
  redpost::KinematicsData data;
  FkError err;
  for_postures(cell, seed, [&](const JointVector& q) {
    redpost::forward_kinematics(cell, q, data);
    KDL::Frame F;
    REQUIRE(fk.JntToCart(to_kdl(q), F) >= 0);
    const Isometry T_kdl = redpost::test::isometry_from_kdl(F);
    const double dp = (data.T_B_tcp.translation() - T_kdl.translation()).cwiseAbs().maxCoeff();
    const double dr = (data.T_B_tcp.linear() - T_kdl.linear()).cwiseAbs().maxCoeff();
    if (dp > err.position || dr > err.rotation)
      err.worst_q = q;
    err.position = std::max(err.position, dp);
    err.rotation = std::max(err.rotation, dr);
  });
  return err;
}

struct JacobianError {
  double angular = 0.0;
  double linear_rel = 0.0;
  JointVector worst_q;
};

JacobianError compare_jacobian(const Cell& cell, KdlChainLayout layout, std::uint64_t seed) {
  const KDL::Chain chain = redpost::test::kdl_chain_from_cell(cell, layout);
  KDL::ChainJntToJacSolver jac_solver(chain);
  KDL::Jacobian J_kdl(chain.getNrOfJoints());
  redpost::KinematicsData data;
  redpost::Jacobian J;
  JacobianError err;
  for_postures(cell, seed, [&](const JointVector& q) {
    redpost::forward_kinematics(cell, q, data);
    redpost::tcp_jacobian(cell, data, J);
    REQUIRE(jac_solver.JntToJac(to_kdl(q), J_kdl) >= 0);
    // KDL's rows are [v; omega] (reference point at the chain's end, base frame); ours are
    // [omega; v].
    const Eigen::Matrix<double, 6, Eigen::Dynamic> K = J_kdl.data;
    const double da = (J.topRows<3>() - K.bottomRows(3)).cwiseAbs().maxCoeff();
    const double scale = std::max(1.0, J.bottomRows<3>().cwiseAbs().maxCoeff());
    const double dl = (J.bottomRows<3>() - K.topRows(3)).cwiseAbs().maxCoeff() / scale;
    if (da > err.angular || dl > err.linear_rel)
      err.worst_q = q;
    err.angular = std::max(err.angular, da);
    err.linear_rel = std::max(err.linear_rel, dl);
  });
  return err;
}

// A cell that the shipped ones do not cover: modified DH with a prismatic joint, non-zero
// theta offsets, fixed frames between joints, a base and a tool frame, and mixed conventions.
Cell hand_built_cell() {
  using redpost::DhConvention;
  using redpost::JointType;
  return redpost::test::hand_built_cell(
      "kdl_hand_built", redpost::frame_from_xyzabc(120.0, -40.0, 300.0, {30.0, -10.0, 5.0}),
      redpost::frame_from_xyzabc(5.0, 10.0, 150.0, {0.0, 20.0, 45.0}),
      {
          {JointType::prismatic, DhConvention::modified, 30, 100, 15, 50, -400, 900},
          {JointType::revolute, DhConvention::modified, 90, 250, -20, 80, -3, 3},
          {JointType::revolute, DhConvention::standard, -90, 400, 10, -60, -3, 3},
          {JointType::prismatic, DhConvention::standard, 45, 30, 25, 10, 0, 500},
          {JointType::revolute, DhConvention::modified, -60, 0, 0, 200, -3, 3},
          {JointType::virtual_spin, DhConvention::standard, 0, 0, 5, -90, -3.2, 3.2},
      },
      // Fixed frames before a prismatic and before a modified-DH joint.
      {{1, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0}, {3, -15.0, 0.0, 70.0, 0.0, 90.0, 0.0}});
}

}  // namespace

TEST_CASE("kdl: chain layouts have the cell's joints and the expected segments") {
  const Cell andres = redpost::test::shipped_cell("andres2011_kr15_track_table");
  const KDL::Chain merged = redpost::test::kdl_chain_from_cell(andres, KdlChainLayout::merged);
  const KDL::Chain expl =
      redpost::test::kdl_chain_from_cell(andres, KdlChainLayout::explicit_fixed);
  CHECK(merged.getNrOfJoints() == 9);
  // No base and no tool frame: one segment per joint, which is what the benchmark times.
  CHECK(merged.getNrOfSegments() == 9);
  CHECK(expl.getNrOfJoints() == 9);
  CHECK(expl.getNrOfSegments() == 11);  // + base + tcp
  // d_L is the one prismatic joint.
  CHECK(merged.getSegment(1).getJoint().getType() == KDL::Joint::TransZ);
  CHECK(merged.getSegment(0).getJoint().getType() == KDL::Joint::RotZ);
}

TEST_CASE("kdl: FK of andres2011_kr15_track_table matches ChainFkSolverPos_recursive") {
  const Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  for (KdlChainLayout layout : {KdlChainLayout::merged, KdlChainLayout::explicit_fixed}) {
    const FkError e = compare_fk(cell, layout, 20110101);
    INFO("layout " << static_cast<int>(layout) << ", worst at " << describe(e.worst_q));
    CHECK(e.position <= kPositionTol);
    CHECK(e.rotation <= kRotationTol);
  }
}

TEST_CASE("kdl: FK of kr15_2 and caro2014_kr270_table matches ChainFkSolverPos_recursive") {
  for (const char* name : {"kr15_2", "caro2014_kr270_table"}) {
    const Cell cell = redpost::test::shipped_cell(name);
    for (KdlChainLayout layout : {KdlChainLayout::merged, KdlChainLayout::explicit_fixed}) {
      const FkError e = compare_fk(cell, layout, 42);
      INFO(name << ", layout " << static_cast<int>(layout) << ", worst at " << describe(e.worst_q));
      CHECK(e.position <= kPositionTol);
      CHECK(e.rotation <= kRotationTol);
    }
  }
}

TEST_CASE("kdl: FK of a hand-built modified/prismatic/fixed-frame cell matches KDL") {
  const Cell cell = hand_built_cell();
  for (KdlChainLayout layout : {KdlChainLayout::merged, KdlChainLayout::explicit_fixed}) {
    const FkError e = compare_fk(cell, layout, 7);
    INFO("layout " << static_cast<int>(layout) << ", worst at " << describe(e.worst_q));
    CHECK(e.position <= kPositionTol);
    CHECK(e.rotation <= kRotationTol);
  }
}

TEST_CASE("kdl: Jacobian matches ChainJntToJacSolver on every shipped cell") {
  // The explicit layout ends in a fixed "tcp" segment. ChainJntToJacSolver walks fixed
  // segments too, moving the reference point across each, so its Jacobian refers to the end of
  // the whole chain and needs no changeRefPoint. The shipped tool frames have no translation
  // (identity, or kr15_2's pure rotation), so the hand-built cell below, whose tool frame is
  // offset by ~150 mm, is the case that would expose a solver ignoring a trailing segment.
  for (const char* name : redpost::test::kShippedCells) {
    const Cell cell = redpost::test::shipped_cell(name);
    for (KdlChainLayout layout : {KdlChainLayout::merged, KdlChainLayout::explicit_fixed}) {
      const JacobianError e = compare_jacobian(cell, layout, 1234);
      INFO(name << ", layout " << static_cast<int>(layout) << ", worst at " << describe(e.worst_q));
      CHECK(e.angular <= kAngularTol);
      CHECK(e.linear_rel <= kLinearRelTol);
    }
  }
}

TEST_CASE("kdl: Jacobian of a hand-built modified/prismatic/fixed-frame cell matches KDL") {
  // In the explicit layout the last KDL segment is the fixed, translated tool frame.
  const Cell cell = hand_built_cell();
  for (KdlChainLayout layout : {KdlChainLayout::merged, KdlChainLayout::explicit_fixed}) {
    const JacobianError e = compare_jacobian(cell, layout, 99);
    INFO("layout " << static_cast<int>(layout) << ", worst at " << describe(e.worst_q));
    CHECK(e.angular <= kAngularTol);
    CHECK(e.linear_rel <= kLinearRelTol);
  }
}

TEST_CASE("kdl: the comparison notices a 1 micrometre change of one link") {
  // Guards the guard: if the tolerances were too loose or the chains were built from the same
  // numbers in a way that hid differences, this would pass silently.
  const Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  Cell perturbed = cell;
  perturbed.joints[4].a_mm += 1e-3;
  redpost::finalize_cell(perturbed);
  const KDL::Chain chain = redpost::test::kdl_chain_from_cell(perturbed);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::Frame F;
  const JointVector q = cell.home();
  REQUIRE(fk.JntToCart(to_kdl(q), F) >= 0);
  const Isometry T = redpost::tcp_pose(cell, q);
  const double dp =
      (T.translation() - redpost::test::isometry_from_kdl(F).translation()).cwiseAbs().maxCoeff();
  CHECK(dp > 1e3 * kPositionTol);
}
