// The circle through three points (redpost/kinematics/circle.hpp) in closed form.
#include <cmath>

#include "catch_compat.hpp"
#include "redpost/kinematics/circle.hpp"

using namespace redpost;

TEST_CASE("circle: through three points, the sweep from the start through the middle point") {
  const double r = 10.0, s = r / std::sqrt(2.0);
  const Eigen::Vector3d a(r, 0, 5), quarter_mid(s, s, 5), top(0, r, 5), bottom(0, -r, 5);
  Circle c;
  REQUIRE(circle_through(a, quarter_mid, top, c));
  CHECK((c.centre - Eigen::Vector3d(0, 0, 5)).norm() < 1e-12);
  CHECK(c.radius == Approx(r).epsilon(1e-12));
  CHECK(c.length() == Approx(0.5 * M_PI * r).epsilon(1e-12));
  CHECK((c.at(0.0) - a).norm() < 1e-12);
  CHECK((c.at(0.5) - quarter_mid).norm() < 1e-9);
  CHECK((c.at(1.0) - top).norm() < 1e-9);
  // Through the top to the bottom: three quarters of the circle, the long way round.
  REQUIRE(circle_through(a, top, bottom, c));
  CHECK(c.length() == Approx(1.5 * M_PI * r).epsilon(1e-12));
  CHECK(c.normal.z() == Approx(1.0));
  // Points on one line have no circle.
  CHECK_FALSE(circle_through(a, Eigen::Vector3d(5, 0, 5), Eigen::Vector3d(-3, 0, 5), c));
}
