// Closed-form inverse kinematics of a KUKA-class 6R arm (arm_ik.hpp; derivation in
// docs/placement.md, "Inverse kinematics of the arm").
//
// The geometry is not read off the DH numbers but off the cell's own forward kinematics at a
// reference posture (arm DH values 0, A5 = 0): the joint axes as lines, written as a product of
// exponentials T_a0_6(q) = exp(S1 d1) ... exp(S6 d6) M0 with d = q - q_ref. This serves standard
// and modified DH, any joint signs and offsets and fixed frames between the arm joints alike.
// In the canonical frame {C} (origin on the A1 axis, z along A1, x forward) the problem splits:
//   position of the wrist point  -> A1 (atan2), A2 and A3 (a planar 2R problem, law of cosines);
//   orientation                  -> A4, A5, A6 (Z-Y-Z Euler angles about the wrist axes).
#include "redpost/kinematics/arm_ik.hpp"

#include <atomic>
#include <cmath>
#include <string>

#include "kinematics/sincos.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

namespace redpost {

namespace {

constexpr double kTwoPi = 2.0 * kPi;
// Assumption checks on the extracted geometry (exact in the model; FK rounding is ~1e-13).
constexpr double kAngleTol = 1e-9;     // rad: parallel / perpendicular axes
constexpr double kDistanceTol = 1e-6;  // mm: axes meeting in a point
// Solve-time thresholds.
constexpr double kReachTol = 1e-10;        // on cos(psi): ~1e-7 mm of reach at KUKA sizes
constexpr double kOnA1AxisMm = 1e-9;       // wrist point on the A1 axis: A1 is free
constexpr double kStatusBit0TieMm = 1e-6;  // below this, bit 0 is taken from status_turn itself
constexpr double kWristSingular = 1e-12;   // sin(A5) below this: A4 and A6 only in sum
// Round trip (arm_ik.hpp).
constexpr double kRoundTripMm = 1e-6;
constexpr double kRoundTripRad = 1e-9;

[[noreturn]] void not_of_class(const Cell& cell, const std::string& reason) {
  throw Error(ErrorCode::bad_input,
              "cell '" + cell.name +
                  "': the arm A1..A6 is not of the KUKA class the closed-form inverse "
                  "kinematics solves (" +
                  reason + "); use the numerical tracker for this cell",
              SourceLocation{cell.source_file, 0, 0});
}

// Closest points o1 + s w1 and o2 + t w2 of two non-parallel lines (unit directions).
void closest_points(const Eigen::Vector3d& o1, const Eigen::Vector3d& w1, const Eigen::Vector3d& o2,
                    const Eigen::Vector3d& w2, double& s, double& t) {
  const double b = w1.dot(w2);
  const double denom = 1.0 - b * b;
  const Eigen::Vector3d w0 = o1 - o2;
  const double d = w1.dot(w0), e = w2.dot(w0);
  s = (b * e - d) / denom;
  t = (e - b * d) / denom;
}

double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& o,
                        const Eigen::Vector3d& w) {
  const Eigen::Vector3d r = p - o;
  return (r - r.dot(w) * w).norm();
}

// Checks the KUKA-class assumptions on the axes of one posture (all in {B}) and returns the
// wrist point. Throws on the first one that fails.
Eigen::Vector3d check_arm_class(const Cell& cell, const KinematicsData& data,
                                const std::array<int, 6>& j, bool check_a4_a6_aligned) {
  Eigen::Vector3d w[6], p[6];
  for (int k = 0; k < 6; ++k) {
    w[k] = data.z_B_joint[static_cast<size_t>(j[static_cast<size_t>(k)])].normalized();
    p[k] = data.p_B_joint[static_cast<size_t>(j[static_cast<size_t>(k)])];
  }
  if (std::abs(w[0].dot(w[1])) > kAngleTol)
    not_of_class(cell, "the A2 axis is not perpendicular to the A1 axis");
  if (w[1].cross(w[2]).norm() > kAngleTol)
    not_of_class(cell, "the A3 axis is not parallel to the A2 axis");
  if (w[1].cross(w[3]).norm() < kAngleTol)
    not_of_class(cell, "the A4 axis is parallel to the A2 axis");
  if (std::abs(w[3].dot(w[4])) > kAngleTol || std::abs(w[4].dot(w[5])) > kAngleTol)
    not_of_class(cell, "the wrist axes A4, A5, A6 are not mutually perpendicular in turn");
  double s = 0.0, t = 0.0;
  closest_points(p[3], w[3], p[4], w[4], s, t);
  const Eigen::Vector3d on4 = p[3] + s * w[3], on5 = p[4] + t * w[4];
  if ((on4 - on5).norm() > kDistanceTol)
    not_of_class(cell, "the A4 and A5 axes do not meet (no spherical wrist)");
  const Eigen::Vector3d wrist = 0.5 * (on4 + on5);
  if (distance_to_line(wrist, p[5], w[5]) > kDistanceTol)
    not_of_class(cell, "the A6 axis misses the point where A4 and A5 meet (no spherical wrist)");
  // Rotations about A2 and A3 keep the component along A2; so does the A1 axis (perpendicular
  // to A2). A lateral shoulder offset would put the wrist beside the A1 axis at every posture.
  double s12 = 0.0, t12 = 0.0;
  closest_points(p[0], w[0], p[1], w[1], s12, t12);
  if (std::abs((wrist - (p[0] + s12 * w[0])).dot(w[1])) > kDistanceTol)
    not_of_class(cell, "the wrist point lies off the plane of A1 normal to A2 (lateral offset)");
  if (check_a4_a6_aligned && w[3].cross(w[5]).norm() > kAngleTol)
    not_of_class(cell,
                 "A4 and A6 are not aligned at A5 = 0, so Status bit 2 (A5 < 0) would not "
                 "mark the wrist flip");
  // status_turn() reads the wrist at the origin of the A5 joint frame.
  if ((p[4] - wrist).norm() > kDistanceTol)
    not_of_class(cell,
                 "the frame of A5 does not sit at the wrist point, where status_turn() "
                 "reads it");
  return wrist;
}

// Rounding without libm calls (SSE2 has no round instruction): adding 1.5 * 2^52 rounds to the
// nearest integer. Exact for |x| < 2^51, far beyond any turn count here.
inline double round_nearest(double x) {
  constexpr double kShift = 6755399441055744.0;
  return (x + kShift) - kShift;  // not folded: the compiler keeps IEEE semantics
}
inline double floor_fast(double x) {
  const double r = round_nearest(x);
  return r > x ? r - 1.0 : r;
}
inline double ceil_fast(double x) {
  const double r = round_nearest(x);
  return r < x ? r + 1.0 : r;
}

constexpr double kInvTwoPi = 1.0 / kTwoPi;

// The 2*pi-equivalent of q within [lo, hi] nearest to `near`; `in_limits` false (and q
// returned as given) when no equivalent lies within the limits.
double nearest_equivalent(double q, double lo, double hi, double near, bool& in_limits) {
  // The equivalent nearest to `near` overall, when within the limits, is the answer.
  const double k_near = round_nearest((near - q) * kInvTwoPi);
  const double v = q + kTwoPi * k_near;
  if (v >= lo && v <= hi) {
    in_limits = true;
    return v;
  }
  const double k_min = ceil_fast((lo - q) * kInvTwoPi), k_max = floor_fast((hi - q) * kInvTwoPi);
  in_limits = k_min <= k_max;
  if (!in_limits)
    return q;
  // |q + 2 pi k - near| is convex in k: clamp the unconstrained optimum.
  const double k = k_near < k_min ? k_min : (k_near > k_max ? k_max : k_near);
  const double out = q + kTwoPi * k;
  in_limits = out >= lo && out <= hi;  // guard the rounding of q + 2 pi k at a limit
  return out;
}

// One link of the chain, composed onto the running frame (R, p) exactly as forward_kinematics()
// does (fixed frame first, then standard or modified DH). solve() walks only the links it needs:
// those before and after the arm once, and for the round trip the arm's links, sharing the
// A1..A3 part between the two wrist flips.
void compose_link(const Cell& cell, int i, double q, Eigen::Matrix3d& R, Eigen::Vector3d& p) {
  const Joint& j = cell.joint(i);
  const Cell::LinkConstants& k = cell.link[static_cast<size_t>(i)];
  if (j.has_fixed_before) {
    p += R * j.T_prev_link.translation();
    R = R * j.T_prev_link.linear();
  }
  const bool prismatic = j.type == JointType::prismatic;
  const double d_mm = prismatic ? j.d_mm + q : j.d_mm;
  double st = 0.0, ct = 1.0;
  detail::sincos_one(prismatic ? j.theta_rad : j.theta_rad + q, st, ct);
  auto rot_z = [&] {
    const Eigen::Vector3d x = ct * R.col(0) + st * R.col(1);
    R.col(1) = ct * R.col(1) - st * R.col(0);
    R.col(0) = x;
  };
  auto rot_x = [&] {
    const Eigen::Vector3d y = k.cos_alpha * R.col(1) + k.sin_alpha * R.col(2);
    R.col(2) = k.cos_alpha * R.col(2) - k.sin_alpha * R.col(1);
    R.col(1) = y;
  };
  if (j.convention == DhConvention::standard) {
    rot_z();
    p += d_mm * R.col(2) + j.a_mm * R.col(0);
    rot_x();
  } else {
    rot_x();
    p += j.a_mm * R.col(0);
    rot_z();
    p += d_mm * R.col(2);
  }
}

// A2, A3: the wrist (ux, uy) in the arm plane from the A2 axis, D = l2 + l3 exp(i psi) rotated.
// psi: the fold at A3; eta: the angle from l2 to the A2 -> wrist line; both for elbow 0 (they
// change sign with the elbow). False when the wrist is beyond reach (or within the inner dead
// zone).
struct ArmPlaneAngles {
  double arg_d = 0.0;  // direction of the A2 -> wrist line
  double psi_abs = 0.0;
  double eta_abs = 0.0;
};

bool arm_plane_angles(double ux, double uy, double l2, double l3, ArmPlaneAngles& out) {
  double cpsi = (ux * ux + uy * uy - l2 * l2 - l3 * l3) / (2.0 * l2 * l3);
  if (cpsi > 1.0 + kReachTol || cpsi < -1.0 - kReachTol)
    return false;
  cpsi = cpsi > 1.0 ? 1.0 : (cpsi < -1.0 ? -1.0 : cpsi);
  const double spsi_abs = std::sqrt(1.0 - cpsi * cpsi);
  out.arg_d = std::atan2(uy, ux);
  out.psi_abs = std::atan2(spsi_abs, cpsi);
  out.eta_abs = std::atan2(l3 * spsi_abs, l2 + l3 * cpsi);
  return true;
}

// A4..A6 as Rw = Rz(alpha) Ry(beta) Rz(gamma), Rw the wrist rotation in the wrist basis E.
struct WristAngles {
  double alpha = 0.0, beta = 0.0, gamma = 0.0;
};

// alpha_near: the alpha of q_near, kept where A5 = 0 leaves only A4 + A6 defined.
WristAngles wrist_angles(const Eigen::Matrix3d& Rw, double alpha_near) {
  const double h = std::sqrt(Rw(0, 2) * Rw(0, 2) + Rw(1, 2) * Rw(1, 2));
  double alpha = 0.0, ca = 1.0, sa = 0.0;
  if (h > kWristSingular) {
    alpha = std::atan2(Rw(1, 2), Rw(0, 2));
    ca = Rw(0, 2) / h, sa = Rw(1, 2) / h;
  } else {  // A5 = 0: only A4 + A6 is defined; A4 keeps its q_near value
    alpha = alpha_near;
    detail::sincos_one(alpha, sa, ca);
  }
  // Rz(-alpha) Rw = Ry(beta) Rz(gamma): beta and gamma from it, consistent with alpha even
  // where alpha itself is ill-conditioned (near A5 = 0). At the singularity beta is set to
  // exactly 0, so that A5 is the reference value (A5 = 0) and the flip below duplicates
  // the same posture instead of landing in a slot decided by rounding.
  const double beta =
      h > kWristSingular ? std::atan2(ca * Rw(0, 2) + sa * Rw(1, 2), Rw(2, 2)) : 0.0;
  const double gamma = std::atan2(-sa * Rw(0, 0) + ca * Rw(1, 0), -sa * Rw(0, 1) + ca * Rw(1, 1));
  return {alpha, beta, gamma};
}

// Arm joint k's value for the displacement d from the reference posture; in_limits false when
// it has no 2*pi-equivalent within its limits.
double arm_joint_value(const Cell& cell, const std::array<int, 6>& j, const ArmStatusModel& model,
                       const std::array<double, 6>& q_arm_ref, const JointVector& near, int k,
                       double d, bool& in_limits) {
  const int i = j[static_cast<size_t>(k)];
  const Joint& joint = cell.joint(i);
  double v = q_arm_ref[static_cast<size_t>(k)] + d;
  // Status-bearing joints first in a canonical range: A3 within 180 deg of phi (its
  // elbow bit), A5 in (-180, 180] (its flip bit); the others near q_near.
  if (k == 2) {
    const double a_deg = to_axis_value(joint, v) - (model.phi_deg - 180.0);
    v -= joint.axis.sign * kTwoPi * floor_fast(a_deg / 360.0);
  } else if (k == 4) {
    const double a_deg = to_axis_value(joint, v);
    v -= joint.axis.sign * kTwoPi * ceil_fast((a_deg - 180.0) / 360.0);
  }
  return nearest_equivalent(v, joint.lower, joint.upper, near[i], in_limits);
}

// The arm joint values qa for the displacements d from the reference posture q_arm_ref;
// false when some joint has no 2*pi-equivalent within its limits.
bool arm_joint_values(const Cell& cell, const std::array<int, 6>& j, const ArmStatusModel& model,
                      const std::array<double, 6>& q_arm_ref, const JointVector& near,
                      const double (&d)[6], double (&qa)[6]) {
  bool within = true;
  for (int k = 0; k < 6; ++k) {
    bool in_limits = false;
    qa[k] = arm_joint_value(cell, j, model, q_arm_ref, near, k, d[k], in_limits);
    within = within && in_limits;
  }
  return within;
}

// The slot is the Status that status_turn() gives the returned q; rho is the signed distance
// of the wrist from the A1 axis (negative: overhead area).
int posture_status(const Cell& cell, const std::array<int, 6>& j, const ArmStatusModel& model,
                   const JointVector& q_other, const double (&qa)[6], double rho) {
  int bits = 0;
  if (to_axis_value(cell.joint(j[2]), qa[2]) >= model.phi_deg)
    bits |= 2;
  if (to_axis_value(cell.joint(j[4]), qa[4]) < 0.0)
    bits |= 4;
  if (std::abs(rho) > kStatusBit0TieMm) {
    bits |= rho < 0.0 ? 1 : 0;
  } else {
    JointVector qc = q_other;
    for (int k = 0; k < 6; ++k)
      qc[j[static_cast<size_t>(k)]] = qa[k];
    bits |= wrist_x_in_a1_frame_mm(cell, model, qc) < 0.0 ? 1 : 0;
  }
  return bits;
}

// The frame after A3 in {B}, for the round trip: shared by both wrist flips.
struct FrameAfterA3 {
  bool have = false;
  Eigen::Matrix3d R;
  Eigen::Vector3d p;
};

// Round trip through the cell's own links (not the product of exponentials of solve()).
bool round_trip_ok(const Cell& cell, const std::array<int, 6>& j, const Isometry& T_B_pre,
                   const Isometry& T_6_tcp, const Isometry& T_B_tcp, const double (&qa)[6],
                   FrameAfterA3& after_a3) {
  if (!after_a3.have) {
    after_a3.R = T_B_pre.linear();
    after_a3.p = T_B_pre.translation();
    for (int k = 0; k < 3; ++k)
      compose_link(cell, j[static_cast<size_t>(k)], qa[k], after_a3.R, after_a3.p);
    after_a3.have = true;
  }
  Eigen::Matrix3d R = after_a3.R;
  Eigen::Vector3d p = after_a3.p;
  for (int k = 3; k < 6; ++k)
    compose_link(cell, j[static_cast<size_t>(k)], qa[k], R, p);
  p += R * T_6_tcp.translation();
  R = R * T_6_tcp.linear();
  const double dp = (p - T_B_tcp.translation()).norm();
  // ||R1 - R2||_F = 2 sqrt(2) |sin(angle / 2)|
  const double dr = (R - T_B_tcp.linear()).norm() * (1.0 / std::sqrt(2.0));
  return dp < kRoundTripMm && dr < kRoundTripRad;
}

}  // namespace

ArmIk::ArmIk(const Cell& cell) : cell_(&cell), status_model_(make_arm_status_model(cell)) {
  static std::atomic<std::uint64_t> next_instance{1};
  instance_ = next_instance.fetch_add(1, std::memory_order_relaxed);
  for (int k = 0; k < 6; ++k)
    arm_joints_[static_cast<size_t>(k)] = status_model_.joint_of_axis[k];
  const std::array<int, 6>& j = arm_joints_;
  for (int k = 1; k < 6; ++k) {
    if (j[static_cast<size_t>(k)] != j[0] + k)
      not_of_class(cell, "A1..A6 are not consecutive joints of the chain");
  }

  // Reference posture: every arm DH value 0 except A5, which is set to 0 as a controller value
  // so that A4 and A6 are aligned (the Z-Y-Z wrist below needs it).
  g_.q_home = cell.home();
  g_.q_ref = g_.q_home;
  for (int k = 0; k < 6; ++k) {
    const int i = j[static_cast<size_t>(k)];
    g_.q_ref[i] = k == 4 ? from_axis_value(cell.joint(i), 0.0) : 0.0;
    g_.q_arm_ref[static_cast<size_t>(k)] = g_.q_ref[i];
  }

  // The assumptions hold for a rigid arm at every posture if they hold at one; checking three
  // more catches a chain that is not what its frames at one posture suggest.
  KinematicsData data;
  const double trial[3][6] = {{0.4, -0.9, 1.3, -2.1, 0.7, 2.9},
                              {-2.5, 0.3, -1.1, 1.7, -1.2, -0.6},
                              {1.9, 1.4, 2.6, 0.2, 2.4, -2.2}};
  for (const auto& t : trial) {
    JointVector q = g_.q_ref;
    for (int k = 0; k < 6; ++k)
      q[j[static_cast<size_t>(k)]] += t[k];
    forward_kinematics(cell, q, data);
    check_arm_class(cell, data, j, false);
  }
  forward_kinematics(cell, g_.q_ref, data);
  const Eigen::Vector3d wrist_B = check_arm_class(cell, data, j, true);

  // Everything below in a0, the link frame of A1 at the reference (rigid with the arm's base).
  const Isometry& P0 = data.T_B_link[static_cast<size_t>(j[0])];
  const Isometry P0_inv = P0.inverse(Eigen::Isometry);
  Eigen::Vector3d w[6], p[6];
  for (int k = 0; k < 6; ++k) {
    const size_t i = static_cast<size_t>(j[static_cast<size_t>(k)]);
    w[k] = (P0_inv.linear() * data.z_B_joint[i]).normalized();
    p[k] = P0_inv * data.p_B_joint[i];
  }
  const Eigen::Vector3d wrist = P0_inv * wrist_B;
  const Isometry M0 = P0_inv * data.T_B_link[static_cast<size_t>(j[5])];

  // Origin and forward direction of {C}, as status_turn() defines "forward" (bit 0).
  double s12 = 0.0, t12 = 0.0;
  closest_points(p[0], w[0], p[1], w[1], s12, t12);
  const Eigen::Vector3d origin = p[0] + s12 * w[0];
  Eigen::Vector3d forward = (p[1] + t12 * w[1]) - origin;
  if (!status_model_.forward_from_a2_offset) {
    // A2 meets A1: forward points to the wrist of the stretched-up posture A2 = -90, A3 = 90.
    JointVector q = g_.q_ref;
    q[j[1]] = from_axis_value(cell.joint(j[1]), -90.0);
    q[j[2]] = from_axis_value(cell.joint(j[2]), 90.0);
    KinematicsData up;
    forward_kinematics(cell, q, up);
    forward = P0_inv * up.p_B_joint[static_cast<size_t>(j[4])] - origin;
  }
  forward -= forward.dot(w[0]) * w[0];
  if (forward.norm() < 1e-3)
    not_of_class(cell, "the forward direction of the A1 frame is undefined");
  forward.normalize();
  Isometry T_a0_C = Isometry::Identity();
  T_a0_C.linear().col(0) = forward;
  T_a0_C.linear().col(1) = w[0].cross(forward);
  T_a0_C.linear().col(2) = w[0];
  T_a0_C.translation() = origin;
  g_.T_C_a0 = T_a0_C.inverse(Eigen::Isometry);
  g_.T_6ref_inv_C = M0.inverse(Eigen::Isometry) * T_a0_C;
  const Isometry& T_B_pre = j[0] > 0 ? data.T_B_link[static_cast<size_t>(j[0] - 1)] : cell.T_B_0;
  g_.T_pre_C = T_B_pre.inverse(Eigen::Isometry) * P0 * T_a0_C;

  const Eigen::Matrix3d R_C_a0 = g_.T_C_a0.linear();
  const Eigen::Vector3d w2 = R_C_a0 * w[1];
  g_.sigma2 = w2.y() > 0.0 ? 1.0 : -1.0;
  g_.sigma3 = w[1].dot(w[2]) > 0.0 ? 1.0 : -1.0;
  g_.a1_mm = (R_C_a0 * (p[1] - origin)).x();  // the A2 axis crosses the x axis of {C} here
  g_.wrist_C = g_.T_C_a0 * wrist;

  // The arm plane y_C = 0 in coordinates (x_C, -sigma2 z_C): there a rotation by +d about A2 is
  // a multiplication by exp(i d) (basis e1 = x_C, e2 = w2 x e1).
  auto plane = [&](const Eigen::Vector3d& p_C) {
    return Eigen::Vector2d(p_C.x(), -g_.sigma2 * p_C.z());
  };
  const Eigen::Vector2d u3 = plane(g_.T_C_a0 * p[2]), uw = plane(g_.wrist_C);
  const Eigen::Vector2d l2 = u3 - Eigen::Vector2d(g_.a1_mm, 0.0), l3 = uw - u3;
  g_.l2_mm = l2.norm();
  g_.l3_mm = l3.norm();
  if (g_.l2_mm < kDistanceTol || g_.l3_mm < kDistanceTol)
    not_of_class(cell, "the A2-A3 link or the A3-wrist distance is zero");
  g_.arg_l2 = std::atan2(l2.y(), l2.x());
  g_.arg_l3 = std::atan2(l3.y(), l3.x());

  const Eigen::Vector3d w4 = R_C_a0 * w[3], w5 = R_C_a0 * w[4], w6 = R_C_a0 * w[5];
  g_.E_wrist.col(0) = w5.cross(w4);
  g_.E_wrist.col(1) = w5;
  g_.E_wrist.col(2) = w4;
  g_.epsilon6 = w4.dot(w6) > 0.0 ? 1.0 : -1.0;
}

// The links before the arm ({B} -> the frame the A1 link starts from), at q_other.
void ArmIk::before_arm(const JointVector& q_other, ArmBefore& around) const {
  const Cell& cell = *cell_;
  Eigen::Matrix3d R = cell.T_B_0.linear();
  Eigen::Vector3d p = cell.T_B_0.translation();
  for (int i = 0; i < arm_joints_[0]; ++i)
    compose_link(cell, i, q_other[i], R, p);
  around.T_B_pre = Isometry::Identity();
  around.T_B_pre.linear() = R;
  around.T_B_pre.translation() = p;
  around.T_C_B = (around.T_B_pre * g_.T_pre_C).inverse(Eigen::Isometry);
}

// The links after it (the last arm frame -> TCP: fixed frames, the virtual spin), at q_other.
void ArmIk::after_arm(const JointVector& q_other, ArmAfter& around) const {
  const Cell& cell = *cell_;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = arm_joints_[5] + 1; i < cell.size(); ++i)
    compose_link(cell, i, q_other[i], R, p);
  around.T_6_tcp = Isometry::Identity();
  around.T_6_tcp.linear() = R;
  around.T_6_tcp.translation() = p;
  if (cell.has_tcp_frame)
    around.T_6_tcp = around.T_6_tcp * cell.T_last_tcp;
  around.T_tcp_C6 = around.T_6_tcp.inverse(Eigen::Isometry) * g_.T_6ref_inv_C;
}

ArmIkSolutions ArmIk::solve(const Isometry& T_B_tcp, const JointVector& q_other,
                            const JointVector* q_near, int only_status) const {
  ArmBefore before;
  ArmAfter after;
  before_arm(q_other, before);
  after_arm(q_other, after);
  return solve(T_B_tcp, before, after, q_other, q_near, only_status, RoundTrip::check);
}

ArmIkSolutions ArmIk::solve(const Isometry& T_B_tcp, const ArmBefore& before, const ArmAfter& after,
                            const JointVector& q_other, const JointVector* q_near, int only_status,
                            RoundTrip round_trip) const {
  const Cell& cell = *cell_;
  const Geometry& g = g_;
  const std::array<int, 6>& j = arm_joints_;
  const JointVector& near = q_near != nullptr ? *q_near : g.q_home;
  ArmIkSolutions out;

  // exp(S1 d1) ... exp(S6 d6) in {C}: T_C_a0 P^-1 T_B_tcp T_6_tcp^-1 M0^-1 T_a0_C, with
  // P = T_B_pre T_pre_a0 the frame a0 at q_other.
  const Isometry H = before.T_C_B * T_B_tcp * after.T_tcp_C6;
  const Eigen::Matrix3d R_H = H.linear();
  const Eigen::Vector3d w = R_H * g.wrist_C + H.translation();  // target wrist point in {C}

  // A1: the wrist lies in the arm plane, which contains the A1 axis.
  const double r = std::sqrt(w.x() * w.x() + w.y() * w.y());
  double c1 = 1.0, s1 = 0.0, phi1 = 0.0;
  if (r > kOnA1AxisMm) {
    c1 = w.x() / r, s1 = w.y() / r, phi1 = std::atan2(w.y(), w.x());
  } else {  // on the A1 axis every A1 reaches it: keep the one of q_near
    phi1 = near[j[0]] - g.q_arm_ref[0];
    detail::sincos_one(phi1, s1, c1);
  }

  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    // shoulder 1: A1 turned by pi, the wrist behind the A1 axis (overhead area).
    const double rho = shoulder == 0 ? r : -r;
    const double d1 = shoulder == 0 ? phi1 : phi1 + kPi;
    const double cd1 = shoulder == 0 ? c1 : -c1, sd1 = shoulder == 0 ? s1 : -s1;
    // One posture asked: its Status bit 0 is the shoulder's wherever the wrist is off the A1
    // axis (posture_status), so the other shoulder cannot give it.
    if (only_status >= 0 && r > kStatusBit0TieMm && ((only_status & 1) != 0) != (shoulder == 1))
      continue;
    ArmPlaneAngles a23;
    if (!arm_plane_angles(rho - g.a1_mm, -g.sigma2 * w.z(), g.l2_mm, g.l3_mm, a23))
      continue;  // beyond reach (or within the inner dead zone) for this shoulder
    for (int elbow = 0; elbow < 2; ++elbow) {
      const double psi = elbow == 0 ? a23.psi_abs : -a23.psi_abs;
      const double d2 = a23.arg_d - g.arg_l2 - (elbow == 0 ? a23.eta_abs : -a23.eta_abs);
      const double d3 = g.sigma3 * (psi - g.arg_l3 + g.arg_l2);
      if (only_status >= 0) {
        // Bit 1 (the elbow) is A3's alone, the same for both wrist flips (posture_status).
        bool unused = false;
        const double a3 = arm_joint_value(cell, j, status_model_, g.q_arm_ref, near, 2, d3, unused);
        if ((to_axis_value(cell.joint(j[2]), a3) >= status_model_.phi_deg) !=
            ((only_status & 2) != 0))
          continue;
      }
      // Rotation of A1..A3: Rz(d1) * Ry(sigma2 * (d2 + sigma3 d3)) in {C}.
      double s23 = 0.0, c23 = 1.0;
      detail::sincos_one(g.sigma2 * (d2 + g.sigma3 * d3), s23, c23);
      Eigen::Matrix3d R123;
      R123 << cd1 * c23, -sd1, cd1 * s23,  //
          sd1 * c23, cd1, sd1 * s23,       //
          -s23, 0.0, c23;
      // A4..A6: Rz(d4) Ry(d5) Rz(eps6 d6) in the wrist basis E.
      const Eigen::Matrix3d Rw = g.E_wrist.transpose() * (R123.transpose() * R_H) * g.E_wrist;
      const WristAngles a = wrist_angles(Rw, near[j[3]] - g.q_arm_ref[3]);

      FrameAfterA3 after_a3;
      for (int flip = 0; flip < 2; ++flip) {
        // The wrist flip: (alpha + pi, -beta, gamma + pi) gives the same rotation.
        const double d[6] = {d1,
                             d2,
                             d3,
                             flip == 0 ? a.alpha : a.alpha + kPi,
                             flip == 0 ? a.beta : -a.beta,
                             g.epsilon6 * (flip == 0 ? a.gamma : a.gamma + kPi)};
        if (only_status >= 0) {
          // Bit 2 is A5's sign alone (posture_status): the other flip cannot give it.
          bool unused = false;
          const double a5 =
              arm_joint_value(cell, j, status_model_, g.q_arm_ref, near, 4, d[4], unused);
          if ((to_axis_value(cell.joint(j[4]), a5) < 0.0) != ((only_status & 4) != 0))
            continue;
        }
        double qa[6];
        const bool within = arm_joint_values(cell, j, status_model_, g.q_arm_ref, near, d, qa);
        const size_t slot =
            static_cast<size_t>(posture_status(cell, j, status_model_, q_other, qa, rho));
        if (out.exists[slot])
          continue;  // a degenerate posture met twice (A5 = 0, stretched arm): keep the first
        out.exists[slot] = true;
        if (only_status >= 0 && static_cast<int>(slot) != only_status)
          continue;  // the planner asks for one posture: no copy, no round trip for the others
        JointVector& qs = out.q[slot];
        qs = q_other;
        for (int k = 0; k < 6; ++k)
          qs[j[static_cast<size_t>(k)]] = qa[k];
        if (!within)
          continue;
        out.valid[slot] =
            round_trip == RoundTrip::skip ||
            round_trip_ok(cell, j, before.T_B_pre, after.T_6_tcp, T_B_tcp, qa, after_a3);
      }
    }
  }
  return out;
}

}  // namespace redpost
