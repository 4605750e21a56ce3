// The 3D view's data (issue 21): the recorder's decimation against a brute force over the same
// motions, and the page's data read back from the HTML (JSON and little-endian base64) equal to
// what was recorded. The drawing itself is checked in a browser (tests/report/scene_check.py).
#include "catch_compat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "redpost/report/html_report.hpp"
#include "redpost/report/scene3d.hpp"

namespace {

namespace rep = redpost::report;

rep::SceneCell two_link_cell() {
  rep::SceneCell c;
  c.name = "two </script><b>links";
  for (int i = 0; i < 2; ++i) {
    rep::SceneLink l;
    l.name = "j" + std::to_string(i + 1);
    l.axis = "A" + std::to_string(i + 1);
    l.a_mm = 400.0;
    l.lower = -3.0;
    l.upper = 3.0;
    c.links.push_back(l);
  }
  return c;
}

std::vector<rep::SceneQuantity> two_quantities() {
  return {{"1/kappa_F", "", true, 0.3, "threshold"}, {"speed", "%", false, 100.0, "limit"}};
}

// A random walk of the TCP with occasional tiny steps (to be merged) and spikes in the values.
struct Walk {
  std::vector<double> x, y, z, good, bad;
};
Walk random_walk(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Walk w;
  double x = 0, y = 0, z = 0;
  for (int i = 0; i < n; ++i) {
    const double step = u(rng) < 0.3 ? 1e-4 : 2.0 * u(rng);
    x += step * (u(rng) - 0.5);
    y += step * (u(rng) - 0.5);
    z += 0.1 * step * (u(rng) - 0.5);
    w.x.push_back(x);
    w.y.push_back(y);
    w.z.push_back(z);
    w.good.push_back(u(rng) < 0.001 ? 0.01 : 0.4 + 0.1 * u(rng));
    w.bad.push_back(u(rng) < 0.3 ? std::numeric_limits<double>::quiet_NaN() : 100.0 * u(rng));
  }
  return w;
}

rep::Scene3d record(const Walk& w, rep::Scene3dLimits limits) {
  rep::Scene3dRecorder rec(two_link_cell(), two_quantities(), limits);
  for (std::size_t i = 0; i < w.x.size(); ++i) {
    const double q[2] = {0.001 * static_cast<double>(i), -0.002 * static_cast<double>(i)};
    const double values[2] = {w.good[i], w.bad[i]};
    rep::SceneMotion m;
    m.index = static_cast<long>(i) + 1;
    m.cl_line = static_cast<int>(i) + 10;
    m.q = q;
    m.joint_count = 2;
    m.tool_length_mm = 100.0;
    m.tcp_part_mm[0] = w.x[i];
    m.tcp_part_mm[1] = w.y[i];
    m.tcp_part_mm[2] = w.z[i];
    m.values = values;
    rec.add(m);
  }
  return rec.scene();
}

std::vector<std::uint8_t> base64_decode(const std::string& s) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z')
      return c - 'A';
    if (c >= 'a' && c <= 'z')
      return c - 'a' + 26;
    if (c >= '0' && c <= '9')
      return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<std::uint8_t> out;
  unsigned bits = 0;
  int n = 0;
  for (char c : s) {
    const int v = value(c);
    if (v < 0)
      break;  // '=' padding
    bits = (bits << 6) | static_cast<unsigned>(v);
    n += 6;
    if (n >= 8) {
      n -= 8;
      out.push_back(static_cast<std::uint8_t>((bits >> n) & 0xff));
    }
  }
  return out;
}

// The base64 text of "key":"..." in the page's JSON.
std::string field(const std::string& html, const std::string& key) {
  const std::string tag = "\"" + key + "\":\"";
  const std::size_t at = html.find(tag);
  REQUIRE(at != std::string::npos);
  const std::size_t from = at + tag.size();
  return html.substr(from, html.find('"', from) - from);
}

float f32_le(const std::vector<std::uint8_t>& b, std::size_t i) {
  const std::uint32_t u = static_cast<std::uint32_t>(b[4 * i]) |
                          static_cast<std::uint32_t>(b[4 * i + 1]) << 8 |
                          static_cast<std::uint32_t>(b[4 * i + 2]) << 16 |
                          static_cast<std::uint32_t>(b[4 * i + 3]) << 24;
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

}  // namespace

TEST_CASE("scene3d: the kept frames are every stride-th motion and the last, stride minimal",
          "[report][scene3d]") {
  for (const int n : {1, 2, 49, 50, 51, 199, 1000, 4097}) {
    const Walk w = random_walk(n, 7u + static_cast<unsigned>(n));
    rep::Scene3dLimits limits;
    limits.max_frames = 50;
    const rep::Scene3d s = record(w, limits);
    // Brute force: the smallest power of two whose multiples fit in the limit.
    long stride = 1;
    while ((n - 1) / stride + 1 > limits.max_frames)
      stride *= 2;
    std::vector<std::uint32_t> expected;
    for (long i = 1; i <= n; i += stride)
      expected.push_back(static_cast<std::uint32_t>(i));
    if (expected.back() != static_cast<std::uint32_t>(n))
      expected.push_back(static_cast<std::uint32_t>(n));
    CAPTURE(n);
    CHECK(s.frame_stride == stride);
    CHECK(s.frame_motion == expected);
    REQUIRE(s.frame_data.size() == expected.size() * 7);
    for (std::size_t k = 0; k < expected.size(); ++k) {
      const std::size_t i = expected[k] - 1;
      CHECK(s.frame_data[k * 7 + 0] == static_cast<float>(0.001 * static_cast<double>(i)));
      CHECK(s.frame_data[k * 7 + 2] == 100.0f);  // tool length
      CHECK(s.frame_data[k * 7 + 4] == static_cast<float>(w.x[i]));
      CHECK(s.frame_line[k] == i + 10);
    }
  }
}

TEST_CASE("scene3d: the thinned toolpath keeps every extreme value and stays within its limit",
          "[report][scene3d]") {
  const int n = 30000;
  const Walk w = random_walk(n, 42);
  rep::Scene3dLimits limits;
  limits.max_path_points = 2000;
  const rep::Scene3d s = record(w, limits);
  CHECK(s.path_points() <= 2000);
  CHECK(s.path_points() > 500);
  CHECK(s.path_tolerance_mm > 0.001);
  // Consecutive kept points are at least the final tolerance apart.
  for (long i = 1; i < s.path_points(); ++i) {
    const auto* a = &s.path_xyz[3 * static_cast<std::size_t>(i - 1)];
    const auto* b = &s.path_xyz[3 * static_cast<std::size_t>(i)];
    CHECK(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) >= s.path_tolerance_mm * 0.999);
  }
  // The worst value of each quantity over all motions is the worst of the kept points: the
  // lowest 1/kappa_F (code 0) and the highest speed (code 254) survive the thinning.
  const double lowest = *std::min_element(w.good.begin(), w.good.end());
  double highest = 0.0;
  for (double v : w.bad)
    highest = std::isnan(v) ? highest : std::max(highest, v);
  REQUIRE(s.quantities.size() == 2);
  CHECK(s.value_range[0][0] == static_cast<double>(static_cast<float>(lowest)));
  CHECK(s.value_range[1][1] == static_cast<double>(static_cast<float>(highest)));
  CHECK(std::count(s.path_value_codes[0].begin(), s.path_value_codes[0].end(), 0) >= 1);
  CHECK(std::count(s.path_value_codes[1].begin(), s.path_value_codes[1].end(), 254) >= 1);
  // Motion indices increase along the path.
  CHECK(std::is_sorted(s.path_motion.begin(), s.path_motion.end()));
}

TEST_CASE("scene3d: a quantity without any value is left out", "[report][scene3d]") {
  Walk w = random_walk(100, 3);
  std::fill(w.bad.begin(), w.bad.end(), std::numeric_limits<double>::quiet_NaN());
  const rep::Scene3d s = record(w, {});
  REQUIRE(s.quantities.size() == 1);
  CHECK(s.quantities[0].name == "1/kappa_F");
}

TEST_CASE("scene3d: the page's data read back from the HTML equal the recorded ones",
          "[report][scene3d]") {
  const Walk w = random_walk(3000, 11);
  rep::Scene3dLimits limits;
  limits.max_frames = 100;
  const rep::Scene3d s = record(w, limits);
  rep::HtmlReport r("scene");
  r.add_section("3D");
  r.add_scene3d(s);
  const std::string html = r.html();
  CHECK(r.scene_count() == 1);
  // The cell's name cannot end the JSON's <script>: < and > are \u escapes there.
  CHECK(html.find("two </script>") == std::string::npos);
  CHECK(html.find("two \\u003c/script\\u003e\\u003cb\\u003elinks") != std::string::npos);
  // three.js is inlined once, from Debian's package, and nothing is loaded from outside.
  CHECK(html.find("data-library=\"three.js\"") != std::string::npos);
  CHECK(html.find(" src=") == std::string::npos);

  const std::vector<std::uint8_t> frames = base64_decode(field(html, "frames"));
  REQUIRE(frames.size() == s.frame_data.size() * 4);
  for (std::size_t i = 0; i < s.frame_data.size(); ++i)
    CHECK(f32_le(frames, i) == s.frame_data[i]);
  const std::vector<std::uint8_t> motion = base64_decode(field(html, "frame_motion"));
  REQUIRE(motion.size() == s.frame_motion.size() * 4);
  for (std::size_t i = 0; i < s.frame_motion.size(); ++i) {
    const std::uint32_t u = static_cast<std::uint32_t>(motion[4 * i]) |
                            static_cast<std::uint32_t>(motion[4 * i + 1]) << 8 |
                            static_cast<std::uint32_t>(motion[4 * i + 2]) << 16 |
                            static_cast<std::uint32_t>(motion[4 * i + 3]) << 24;
    CHECK(u == s.frame_motion[i]);
  }
  const std::vector<std::uint8_t> path = base64_decode(field(html, "path"));
  REQUIRE(path.size() == s.path_xyz.size() * 4);
  for (std::size_t i = 0; i < s.path_xyz.size(); ++i)
    CHECK(f32_le(path, i) == s.path_xyz[i]);
  // The same scene gives the same bytes.
  rep::HtmlReport again("scene");
  again.add_section("3D");
  again.add_scene3d(s);
  CHECK(again.html() == html);
}

TEST_CASE("scene3d: bad input is refused", "[report][scene3d]") {
  rep::SceneCell empty;
  CHECK_THROWS_AS(rep::Scene3dRecorder(empty, {}), std::invalid_argument);
  rep::Scene3dRecorder rec(two_link_cell(), two_quantities());
  const double q[3] = {0, 0, 0};
  rep::SceneMotion m;
  m.q = q;
  m.joint_count = 3;
  CHECK_THROWS_AS(rec.add(m), std::invalid_argument);
  std::vector<rep::SceneQuantity> seven(7);
  CHECK_THROWS_AS(rep::Scene3dRecorder(two_link_cell(), seven), std::invalid_argument);
}
