// The inline sin/cos of the kinematics against libm.
#include <cmath>
#include <random>

#include "catch_compat.hpp"
#include "kinematics/sincos.hpp"

TEST_CASE("sincos: within 2.3e-16 of libm over the joint range and beyond") {
  std::mt19937_64 rng(61);
  for (double range : {0.8, 4.0, 30.0, 1e3, 9e4}) {
    std::uniform_real_distribution<double> u(-range, range);
    double x[16], s[16], c[16];
    double worst = 0.0;
    for (int k = 0; k < 20000; ++k) {
      const int n = 1 + k % 16;  // odd and even counts: the SSE2 pairs and the scalar tail
      for (int i = 0; i < n; ++i)
        x[i] = u(rng);
      redpost::detail::sincos_batch(x, s, c, n);
      for (int i = 0; i < n; ++i) {
        worst = std::max(worst, std::abs(s[i] - std::sin(x[i])));
        worst = std::max(worst, std::abs(c[i] - std::cos(x[i])));
      }
    }
    INFO("range +-" << range);
    CHECK(worst <= 2.3e-16);
  }
}

TEST_CASE("sincos: exact values, quadrant boundaries and the libm fallback") {
  const double pi = 3.141592653589793;
  double x[] = {0.0, -0.0, pi / 2, pi, -pi / 2, 3 * pi / 2, 2 * pi, 1e6, -3e7, NAN};
  double s[10], c[10];
  redpost::detail::sincos_batch(x, s, c, 10);
  for (int i = 0; i < 9; ++i) {
    CHECK(s[i] == Approx(std::sin(x[i])).margin(2.3e-16));
    CHECK(c[i] == Approx(std::cos(x[i])).margin(2.3e-16));
  }
  CHECK(s[0] == 0.0);
  CHECK(c[0] == 1.0);
  CHECK(std::isnan(s[9]));
  CHECK(std::isnan(c[9]));
}
