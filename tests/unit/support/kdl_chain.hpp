// An Orocos KDL chain built from a redpost::Cell, to check redpost's kinematics against an
// independent implementation (tests) and to time both on the same chain (benchmarks).
//
// Header-only and free of Catch so the benchmark binary can include it too.
//
// A KDL segment is "joint motion, then the fixed tip frame f_tip". redpost's links map onto it:
//   standard DH : Rz(theta0 + q) Tz(d) Tx(a) Rx(alpha)
//                 = joint RotZ(q), f_tip = Frame::DH(a, alpha, d, theta0)
//   modified DH : Rx(alpha) Tx(a) Rz(theta0 + q) Tz(d)
//                 = [fixed Rx(alpha) Tx(a)], joint RotZ(q), f_tip = Rz(theta0) Tz(d)
//   prismatic   : as above with TransZ(q), d = d0 + q; Tz(q) commutes with Rz(theta0), so the
//                 same f_tip holds.
// Everything fixed between two joints (the modified-DH Rx Tx prefix, a <fixed> T_prev_link,
// T_B_0 and T_last_tcp) is either folded into the neighbouring segment's f_tip (`merged`, the
// chain a KDL user would write by hand, used for timing) or kept as separate Joint::None
// segments (`explicit_fixed`, which exercises KDL's handling of fixed segments, in particular a
// trailing one, in the Jacobian solver).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/joint.hpp>
#include <kdl/segment.hpp>

#include "redpost/kinematics/cell.hpp"

namespace redpost::test {

enum class KdlChainLayout { merged, explicit_fixed };

// The same transform as a KDL frame (element by element, no conversion conventions involved).
inline KDL::Frame kdl_frame(const Isometry& T) {
  const Eigen::Matrix3d& R = T.linear();
  const Eigen::Vector3d& p = T.translation();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0),
                                  R(2, 1), R(2, 2)),
                    KDL::Vector(p.x(), p.y(), p.z()));
}

inline Isometry isometry_from_kdl(const KDL::Frame& F) {
  Isometry T = Isometry::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      T.linear()(r, c) = F.M(r, c);
    }
    T.translation()[r] = F.p(r);
  }
  return T;
}

// Exact, unlike KDL::Equal, whose comparison is strict and so never holds with eps = 0.
inline bool is_exact_identity(const KDL::Frame& F) {
  for (int r = 0; r < 3; ++r) {
    if (F.p(r) != 0.0)
      return false;
    for (int c = 0; c < 3; ++c) {
      if (F.M(r, c) != (r == c ? 1.0 : 0.0))
        return false;
    }
  }
  return true;
}

inline KDL::Chain kdl_chain_from_cell(const Cell& cell,
                                      KdlChainLayout layout = KdlChainLayout::merged) {
  // Collected first so that a fixed frame can still be appended to the previous segment's tip.
  struct Piece {
    std::string name;
    KDL::Joint::JointType type;
    KDL::Frame f_tip;
  };
  std::vector<Piece> pieces;
  KDL::Frame pending = kdl_frame(cell.T_B_0);  // fixed motion not yet placed in a segment

  // In the merged layout a fixed frame goes into the previous segment's tip if there is one;
  // before the first joint it has to stay pending (a segment's joint acts before its tip).
  auto add_fixed = [&](const std::string& name, const KDL::Frame& F) {
    if (layout == KdlChainLayout::explicit_fixed) {
      pieces.push_back({name, KDL::Joint::None, F});
    } else {
      pending = pending * F;
    }
  };
  auto flush_pending = [&]() {
    if (layout == KdlChainLayout::explicit_fixed)
      return;
    if (pieces.empty()) {
      if (!is_exact_identity(pending)) {
        pieces.push_back({"base", KDL::Joint::None, pending});
      }
    } else {
      pieces.back().f_tip = pieces.back().f_tip * pending;
    }
    pending = KDL::Frame::Identity();
  };

  if (layout == KdlChainLayout::explicit_fixed) {
    pieces.push_back({"base", KDL::Joint::None, pending});
    pending = KDL::Frame::Identity();
  }

  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.has_fixed_before)
      add_fixed(j.name + "_fixed_before", kdl_frame(j.T_prev_link));
    KDL::Frame tip;
    if (j.convention == DhConvention::standard) {
      tip = KDL::Frame::DH(j.a_mm, j.alpha_rad, j.d_mm, j.theta_rad);
    } else {
      add_fixed(j.name + "_rx_tx",
                KDL::Frame(KDL::Rotation::RotX(j.alpha_rad), KDL::Vector(j.a_mm, 0.0, 0.0)));
      tip = KDL::Frame(KDL::Rotation::RotZ(j.theta_rad), KDL::Vector(0.0, 0.0, j.d_mm));
    }
    flush_pending();
    const KDL::Joint::JointType type =
        j.type == JointType::prismatic ? KDL::Joint::TransZ : KDL::Joint::RotZ;
    pieces.push_back({j.name, type, tip});
  }
  add_fixed("tcp", kdl_frame(cell.T_last_tcp));
  flush_pending();

  KDL::Chain chain;
  for (const Piece& p : pieces) {
    chain.addSegment(KDL::Segment(p.name, KDL::Joint(p.name, p.type), p.f_tip));
  }
  return chain;
}

}  // namespace redpost::test
