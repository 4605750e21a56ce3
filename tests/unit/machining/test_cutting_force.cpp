// The mean milling force of Caro eq. 3.3 against numerical quadrature of the per-tooth force,
// the engagement angles against the cut's geometry, and the input checks.
#include <cmath>
#include <limits>
#include <string>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/types.hpp"
#include "redpost/machining/cutting_force.hpp"

namespace {

using redpost::caro2014_milling_conditions;
using redpost::kPi;
using redpost::MillingConditions;
using redpost::MillingMode;

// Composite Simpson of tooth_force_N over [a, b] with n (even) intervals.
Eigen::Vector3d simpson(const MillingConditions& c, double a, double b, int n) {
  const double h = (b - a) / n;
  Eigen::Vector3d sum = redpost::tooth_force_N(c, a) + redpost::tooth_force_N(c, b);
  for (int k = 1; k < n; ++k)
    sum += (k % 2 == 1 ? 4.0 : 2.0) * redpost::tooth_force_N(c, a + k * h);
  return sum * (h / 3.0);
}

// The midpoint rule over the whole revolution: it needs no engagement angles, so it also checks
// that tooth_force_N is zero where the tooth is out of the material. The jumps at the ends of
// the engagement make it first-order only, hence the many points.
Eigen::Vector3d midpoint_revolution(const MillingConditions& c, int n) {
  const double h = 2.0 * kPi / n;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k)
    sum += redpost::tooth_force_N(c, (k + 0.5) * h);
  return sum * h;
}

std::string describe(const MillingConditions& c) {
  return "ae = " + std::to_string(c.ae_mm) + " mm, " + (c.mode == MillingMode::up ? "up" : "down") +
         "-milling, material_side = " + std::to_string(c.material_side);
}

}  // namespace

TEST_CASE("cutting force: closed-form mean force matches quadrature of the tooth force",
          "[cutting_force]") {
  for (const double ae : {0.5, 2.0, 5.0, 10.0, 15.0, 19.0, 20.0}) {
    for (const MillingMode mode : {MillingMode::up, MillingMode::down}) {
      for (const int side : {1, -1}) {
        const MillingConditions c = caro2014_milling_conditions(ae, mode, side);
        INFO(describe(c));
        const redpost::EngagementAngles e = redpost::engagement_angles(c);
        const double per_revolution = c.teeth / (2.0 * kPi);
        const Eigen::Vector3d F = redpost::mean_cutting_force_N(c);
        const Eigen::Vector3d F_simpson =
            per_revolution * simpson(c, e.phi_in_rad, e.phi_out_rad, 2000);
        const Eigen::Vector3d F_midpoint = per_revolution * midpoint_revolution(c, 400000);
        // Simpson on a smooth integrand with h ~ 1e-3 rad: error ~1e-12 of the ~200 N scale.
        CHECK((F - F_simpson).cwiseAbs().maxCoeff() < 1e-8);
        // Midpoint with jumps of up to Kt ap fz ~ 190 N: error ~ jump * h ~ 3e-3 N.
        CHECK((F - F_midpoint).cwiseAbs().maxCoeff() < 1e-2);
        CHECK(F.z() == 0.0);  // the model has no axial force
      }
    }
  }
}

TEST_CASE("cutting force: slotting gives the textbook closed form", "[cutting_force]") {
  // Over 0 -> pi: the integral of sin cos is 0 and that of sin^2 is pi/2, so per revolution
  // Fx = Kr Kt ap fz Z / 4 and |Fy| = Kt ap fz Z / 4, whatever the mode.
  for (const MillingMode mode : {MillingMode::up, MillingMode::down}) {
    const MillingConditions c = caro2014_milling_conditions(20.0, mode);
    const double base = c.Kt_N_per_mm2 * c.ap_mm * c.fz_mm * c.teeth / 4.0;
    const Eigen::Vector3d F = redpost::mean_cutting_force_N(c);
    CHECK(F.x() == Approx(c.Kr * base).epsilon(1e-12));
    CHECK(std::abs(F.y()) == Approx(base).epsilon(1e-12));
  }
}

TEST_CASE("cutting force: engagement angles follow the cut's geometry", "[cutting_force]") {
  // The tooth sits at R (sin phi, s cos phi) in F_P. Over the engagement it must be inside the
  // strip being removed: on the material's side, between the new wall (|y| = R) and the free
  // edge (|y| = R - ae), and ahead of the tool centre (x >= 0: the chip fz sin phi >= 0).
  for (const double ae : {1.0, 7.0, 10.0, 13.0, 20.0}) {
    for (const MillingMode mode : {MillingMode::up, MillingMode::down}) {
      for (const int side : {1, -1}) {
        const MillingConditions c = caro2014_milling_conditions(ae, mode, side);
        INFO(describe(c));
        const double R = 0.5 * c.tool_diameter_mm;
        const int s = redpost::spindle_sense(c);
        const redpost::EngagementAngles e = redpost::engagement_angles(c);
        REQUIRE(e.phi_in_rad < e.phi_out_rad);
        for (int k = 0; k <= 100; ++k) {
          const double phi = e.phi_in_rad + (e.phi_out_rad - e.phi_in_rad) * k / 100.0;
          const double x = R * std::sin(phi), y_material = side * s * R * std::cos(phi);
          CHECK(x >= -1e-12);
          CHECK(y_material >= R - ae - 1e-9);
        }
        // Up-milling starts at zero chip on the new wall, down-milling ends there.
        const double wall_phi = mode == MillingMode::up ? e.phi_in_rad : e.phi_out_rad;
        CHECK(std::sin(wall_phi) == Approx(0.0).margin(1e-12));
        if (ae < c.tool_diameter_mm) {
          const double edge_phi = mode == MillingMode::up ? e.phi_out_rad : e.phi_in_rad;
          CHECK(side * s * R * std::cos(edge_phi) == Approx(R - ae).margin(1e-9));
        }
      }
    }
  }
}

TEST_CASE("cutting force: mirroring the material side mirrors the force", "[cutting_force]") {
  // The other side of the feed is the mirror image through the xz plane of F_P, spindle sense
  // included: Fx stays, Fy changes sign.
  for (const MillingMode mode : {MillingMode::up, MillingMode::down}) {
    const Eigen::Vector3d Fp =
        redpost::mean_cutting_force_N(caro2014_milling_conditions(7.0, mode, 1));
    const Eigen::Vector3d Fm =
        redpost::mean_cutting_force_N(caro2014_milling_conditions(7.0, mode, -1));
    CHECK(Fm.x() == Approx(Fp.x()).epsilon(1e-14));
    CHECK(Fm.y() == Approx(-Fp.y()).epsilon(1e-14));
  }
  // Up-milling pulls the tool towards the material, down-milling pushes it away (the tool
  // receives -F): the well-known overcut / undercut of the two modes at small ae.
  const Eigen::Vector3d F_up =
      redpost::mean_cutting_force_N(caro2014_milling_conditions(5.0, MillingMode::up, 1));
  const Eigen::Vector3d F_down =
      redpost::mean_cutting_force_N(caro2014_milling_conditions(5.0, MillingMode::down, 1));
  CHECK(-F_up.y() > 0.0);
  CHECK(-F_down.y() < 0.0);
}

TEST_CASE("cutting force: validate rejects what makes no sense", "[cutting_force]") {
  const MillingConditions good = caro2014_milling_conditions(10.0);
  CHECK_NOTHROW(redpost::validate(good));
  const double nan = std::nan("");
  const auto rejects = [](const MillingConditions& c) {
    try {
      redpost::validate(c);
    } catch (const redpost::Error& e) {
      return e.code() == redpost::ErrorCode::bad_input;
    }
    return false;
  };
  MillingConditions c = good;
  c.tool_diameter_mm = 0.0;
  CHECK(rejects(c));
  c = good, c.tool_diameter_mm = nan;
  CHECK(rejects(c));
  c = good, c.teeth = 0;
  CHECK(rejects(c));
  c = good, c.fz_mm = -0.05;
  CHECK(rejects(c));
  c = good, c.ap_mm = 0.0;
  CHECK(rejects(c));
  c = good, c.ae_mm = 0.0;
  CHECK(rejects(c));
  c = good, c.ae_mm = 20.001;  // wider than the tool
  CHECK(rejects(c));
  c = good, c.ae_mm = 20.0;  // slotting is fine
  CHECK_FALSE(rejects(c));
  c = good, c.Kt_N_per_mm2 = std::numeric_limits<double>::infinity();
  CHECK(rejects(c));
  c = good, c.Kr = -0.1;
  CHECK(rejects(c));
  c = good, c.material_side = 0;
  CHECK(rejects(c));
  // A default MillingConditions has no material coefficients: the mean force refuses it.
  CHECK_THROWS_AS(redpost::mean_cutting_force_N(MillingConditions{}), redpost::Error);
}
