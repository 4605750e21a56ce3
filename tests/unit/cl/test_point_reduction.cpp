// The point reduction (cl/point_reduction.hpp) against a brute-force check of its promise: every
// dropped CL point within the tolerance of the merged line, its tool axis within half the angular
// tolerance of the great circle (recomputed here by Rodrigues' formula, not the library's slerp),
// the output a subset of the input in order, nothing merged across an event, each merge as long
// as the tolerance allows (greedy), and tolerance 0 the identity.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/cl/point_reduction.hpp"

using namespace redpost;

namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

ClEvent goto_at(int line, const Eigen::Vector3d& p, const Eigen::Vector3d& axis) {
  ClEvent e;
  e.kind = ClEventKind::move;
  e.line = line;
  e.p_mm = p;
  e.tool_axis = axis.normalized();
  return e;
}

ClEvent event_of(ClEventKind kind, int line, double value = 0.0) {
  ClEvent e;
  e.kind = kind;
  e.line = line;
  e.value = value;
  return e;
}

std::vector<ClEvent> reduce(const std::vector<ClEvent>& in, const PointReductionOptions& o,
                            long* moves_in = nullptr, long* moves_out = nullptr) {
  PointReducer r(o);
  std::vector<ClEvent> out;
  ClEvent e;
  for (const ClEvent& x : in) {
    r.push(x);
    while (r.next(e))
      out.push_back(e);
  }
  r.finish();
  while (r.next(e))
    out.push_back(e);
  if (moves_in)
    *moves_in = r.moves_in();
  if (moves_out)
    *moves_out = r.moves_out();
  return out;
}

// a turned towards b by the fraction t of the angle between them (Rodrigues).
Eigen::Vector3d rodrigues_axis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  const Eigen::Vector3d c = a.cross(b);
  if (c.norm() < 1e-15)
    return a;
  const Eigen::Vector3d k = c.normalized();
  const double angle = t * std::atan2(c.norm(), a.dot(b));
  return a * std::cos(angle) + k.cross(a) * std::sin(angle) + k * k.dot(a) * (1 - std::cos(angle));
}

// The worst deviation of the points strictly between a and b from the line a-b: distance (mm)
// and axis angle (rad) against the great circle at the nearest point's fraction.
std::pair<double, double> worst_between(const ClEvent& a, const ClEvent& b,
                                        const std::vector<ClEvent>& dropped) {
  double worst_mm = 0.0, worst_rad = 0.0;
  const Eigen::Vector3d d = b.p_mm - a.p_mm;
  for (const ClEvent& p : dropped) {
    const double t = std::clamp((p.p_mm - a.p_mm).dot(d) / d.squaredNorm(), 0.0, 1.0);
    worst_mm = std::max(worst_mm, (p.p_mm - (a.p_mm + t * d)).norm());
    const Eigen::Vector3d axis = rodrigues_axis(a.tool_axis, b.tool_axis, t);
    worst_rad = std::max(worst_rad, std::acos(std::clamp(axis.dot(p.tool_axis), -1.0, 1.0)));
  }
  return {worst_mm, worst_rad};
}

// A wavy 5-axis pass: points every `step` mm along x, y a sine of random amplitude and period,
// z a random walk, the tool tilted by a slowly varying angle with a little noise.
std::vector<ClEvent> wavy_pass(std::mt19937_64& rng, int n, int first_line) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double step = 0.2 + 2.0 * u(rng);
  const double amplitude = 5.0 * u(rng) * u(rng);
  const double period = 20.0 + 200.0 * u(rng);
  const double tilt_deg = 30.0 * u(rng);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<ClEvent> out;
  double z = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = i * step;
    z += 0.002 * noise(rng);
    const double tilt = tilt_deg * kDegToRad * std::sin(x / period) + 0.0005 * noise(rng);
    const Eigen::Vector3d axis(std::sin(tilt), 0.3 * std::sin(tilt), std::cos(tilt));
    out.push_back(goto_at(first_line + i, {x, amplitude * std::sin(x / period * 6.28), z}, axis));
  }
  return out;
}

}  // namespace

TEST_CASE("point reduction: the bounds of the options", "[cl][point_reduction]") {
  PointReductionOptions o;
  CHECK(point_reduction_problem(o).empty());  // off
  o.tolerance_mm = 0.01;
  CHECK(point_reduction_problem(o).empty());
  for (double bad : {-1.0, 1e-4, 1.5, std::nan("")}) {
    o.tolerance_mm = bad;
    CHECK_THAT(point_reduction_problem(o), Catch::Matchers::Contains("--fit-tol"));
  }
  o.tolerance_mm = 0.01;
  for (double bad : {0.0, -0.1, 6.0, std::nan("")}) {
    o.axis_tolerance_deg = bad;
    CHECK_THAT(point_reduction_problem(o), Catch::Matchers::Contains("--fit-ang-tol"));
  }
  o.axis_tolerance_deg = 0.1;
  o.max_points = 1;
  CHECK_FALSE(point_reduction_problem(o).empty());
}

TEST_CASE("point reduction: lin_deviation against closed forms", "[cl][point_reduction]") {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ(), x = Eigen::Vector3d::UnitX();
  // A point 3 mm off the middle of a 10 mm line whose axis turns by 90 deg: the middle's axis is
  // at 45 deg, so an axis along z misses it by 45 deg.
  LinDeviation d = lin_deviation({0, 0, 0}, z, {10, 0, 0}, x, {5, 3, 0}, z);
  CHECK(d.distance_mm == Approx(3.0).margin(1e-12));
  CHECK(d.axis_rad == Approx(45 * kDegToRad).margin(1e-12));
  // Beyond the end: the distance to the end point, the end's axis.
  d = lin_deviation({0, 0, 0}, z, {10, 0, 0}, x, {13, 4, 0}, x);
  CHECK(d.distance_mm == Approx(5.0).margin(1e-12));
  CHECK(d.axis_rad == Approx(0.0).margin(1e-12));
}

TEST_CASE("point reduction: tolerance 0 passes every event unchanged", "[cl][point_reduction]") {
  std::mt19937_64 rng(7);
  std::vector<ClEvent> in = wavy_pass(rng, 300, 10);
  in.insert(in.begin() + 100, event_of(ClEventKind::feed, 109, 2000.0));
  const std::vector<ClEvent> out = reduce(in, PointReductionOptions{});
  REQUIRE(out.size() == in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    CHECK(out[i].kind == in[i].kind);
    CHECK(out[i].line == in[i].line);
    CHECK(out[i].first_line == 0);
    CHECK(out[i].p_mm == in[i].p_mm);
  }
}

TEST_CASE("point reduction: collinear points, a closed form", "[cl][point_reduction]") {
  // 1001 points on a line with one tool axis: the first (an approach: no position before it)
  // and the move after it are kept, the other 999 become ceil(999 / max_points) moves of up to
  // max_points points each.
  std::vector<ClEvent> in;
  for (int i = 0; i <= 1000; ++i)
    in.push_back(goto_at(i + 1, {0.5 * i, 0, 0}, Eigen::Vector3d::UnitZ()));
  PointReductionOptions o;
  o.tolerance_mm = 0.01;
  long moves_in = 0, moves_out = 0;
  const std::vector<ClEvent> out = reduce(in, o, &moves_in, &moves_out);
  REQUIRE(out.size() == 12);
  CHECK(moves_in == 999);
  CHECK(moves_out == 10);
  CHECK(out[0].line == 1);
  CHECK(out[1].line == 2);
  for (int k = 1; k <= 10; ++k) {
    CHECK(out[k + 1].first_line == 100 * (k - 1) + 3);
    CHECK(out[k + 1].line == std::min(100 * k + 2, 1001));
  }
}

TEST_CASE("point reduction: seeded random passes, every dropped point within the tolerance",
          "[cl][point_reduction]") {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long total_in = 0, total_out = 0;
  for (int trial = 0; trial < 60; ++trial) {
    PointReductionOptions o;
    o.tolerance_mm = 0.002 + 0.05 * u(rng);
    o.axis_tolerance_deg = 0.02 + 0.5 * u(rng);
    o.max_points = 2 + static_cast<int>(200 * u(rng));
    const std::vector<ClEvent> in = wavy_pass(rng, 400, 1);
    const std::vector<ClEvent> out = reduce(in, o);
    INFO("trial " << trial << ", tolerance " << o.tolerance_mm << " mm, " << o.axis_tolerance_deg
                  << " deg, at most " << o.max_points << " points");
    // The output is a subset of the input in order, the first and last point kept.
    REQUIRE(out.front().line == in.front().line);
    REQUIRE(out.back().line == in.back().line);
    std::size_t prev = 0;
    for (std::size_t k = 1; k < out.size(); ++k) {
      const std::size_t i = static_cast<std::size_t>(out[k].line - 1);
      REQUIRE(i > prev);
      REQUIRE(out[k].p_mm == in[i].p_mm);
      // The merged move says which points it covers: the ones after the previous kept point.
      if (i - prev > 1)
        CHECK(out[k].first_line == in[prev + 1].line);
      else
        CHECK(out[k].first_line == 0);
      CHECK(static_cast<int>(i - prev) <= o.max_points);
      const std::vector<ClEvent> dropped(in.begin() + prev + 1, in.begin() + i);
      const auto [mm, rad] = worst_between(in[prev], in[i], dropped);
      CHECK(mm <= o.tolerance_mm + 1e-12);
      CHECK(rad <= 0.5 * o.axis_tolerance_deg * kDegToRad + 1e-9);
      // Greedy: one more point would break the tolerance, or the size bound (the move after the
      // first, an approach, is kept whatever the tolerance).
      if (k > 1 && i + 1 < in.size() && static_cast<int>(i - prev) < o.max_points) {
        const std::vector<ClEvent> longer(in.begin() + prev + 1, in.begin() + i + 1);
        const auto [mm2, rad2] = worst_between(in[prev], in[i + 1], longer);
        CHECK(
            (mm2 > o.tolerance_mm - 1e-12 || rad2 > 0.5 * o.axis_tolerance_deg * kDegToRad - 1e-9));
      }
      prev = i;
    }
    total_in += static_cast<long>(in.size());
    total_out += static_cast<long>(out.size());
  }
  // Not a toy: the passes are reduced (at these spacings and tolerances, well over 2x).
  CHECK(total_out * 2 < total_in);
}

TEST_CASE("point reduction: nothing is merged across an event, rapid, cycle or tool change",
          "[cl][point_reduction]") {
  PointReductionOptions o;
  o.tolerance_mm = 0.01;
  // A straight pass of 60 points, with an event at every tenth point.
  std::vector<ClEvent> line_pass;
  for (int i = 0; i < 60; ++i)
    line_pass.push_back(goto_at(i + 1, {1.0 * i, 0, 0}, Eigen::Vector3d::UnitZ()));
  const std::vector<ClEventKind> barriers = {
      ClEventKind::comment,       ClEventKind::literal,     ClEventKind::dwell,
      ClEventKind::coolant,       ClEventKind::spindle,     ClEventKind::operation_start,
      ClEventKind::operation_end, ClEventKind::tool_change, ClEventKind::rapid,
      ClEventKind::machine_frame, ClEventKind::feed};
  for (ClEventKind kind : barriers) {
    std::vector<ClEvent> in;
    in.push_back(event_of(ClEventKind::feed, 0, 1000.0));
    std::map<int, bool> barrier_before;  // line of a point -> an event right before it
    for (std::size_t i = 0; i < line_pass.size(); ++i) {
      if (i > 0 && i % 10 == 0) {
        in.push_back(event_of(kind, line_pass[i].line, kind == ClEventKind::feed ? 1000.0 + i : 0));
        barrier_before[line_pass[i].line] = true;
      }
      in.push_back(line_pass[i]);
    }
    const std::vector<ClEvent> out = reduce(in, o);
    INFO("barrier kind " << static_cast<int>(kind));
    // Every event comes out, in its place between the moves.
    int events = 0;
    for (const ClEvent& e : out)
      events += e.kind == kind;
    CHECK(events == (kind == ClEventKind::feed ? 6 : 5));
    int last_line = 0;
    for (const ClEvent& e : out) {
      if (e.kind != ClEventKind::move)
        continue;
      // A move never covers a point that follows an event: its first point is after the last.
      const int first = e.first_line > 0 ? e.first_line : e.line;
      for (int l = first + 1; l <= e.line; ++l)
        CHECK_FALSE(barrier_before.count(l));
      CHECK(first == last_line + 1);
      last_line = e.line;
    }
    CHECK(last_line == 60);
  }
  // A feed that repeats the feed in force changes nothing: the approach, the move after it, and
  // one run.
  std::vector<ClEvent> in = {event_of(ClEventKind::feed, 0, 1000.0)};
  for (std::size_t i = 0; i < line_pass.size(); ++i) {
    in.push_back(line_pass[i]);
    in.push_back(event_of(ClEventKind::feed, line_pass[i].line, 1000.0));
  }
  int moves = 0;
  for (const ClEvent& e : reduce(in, o))
    moves += e.kind == ClEventKind::move;
  CHECK(moves == 3);
}

TEST_CASE("point reduction: rapids, cycle moves, arcs and approaches are kept, and the move after",
          "[cl][point_reduction]") {
  PointReductionOptions o;
  o.tolerance_mm = 0.01;
  std::vector<ClEvent> in;
  int line = 1;
  auto add = [&](double x) {
    in.push_back(goto_at(line++, {x, 0, 0}, Eigen::Vector3d::UnitZ()));
    return &in.back();
  };
  add(0);                        // line 1: the approach (no known position before it): kept
  add(1);                        // 2: the move after it: kept
  add(2);                        // 3: mergeable, but the rapid after it ends its run
  add(3)->rapid = true;          // 4: a rapid: kept
  add(4);                        // 5: the move after a rapid: kept
  add(5);                        // 6: mergeable, alone before the cycle's move
  add(6)->has_clearance = true;  // 7: a cycle's move: kept
  add(7);                        // 8: after it: kept
  add(8);                        // 9: mergeable, alone before the FROM
  add(9)->origin = MoveOrigin::from_point;  // 10: kept
  add(10);                                  // 11: after it: kept
  add(11);                                  // 12: the last point
  std::vector<int> kept;
  for (const ClEvent& e : reduce(in, o)) {
    kept.push_back(e.line);
    CHECK(e.first_line == 0);
  }
  CHECK(kept == std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
  // Collinear plain points after those (lines 13 to 32): one move from line 12 on.
  for (int i = 0; i < 20; ++i)
    add(12 + i);
  const std::vector<ClEvent> out = reduce(in, o);
  CHECK(out.size() == 12);
  CHECK(out.back().line == 32);
  CHECK(out.back().first_line == 12);
}

namespace {

// Distance from p to the circle (centre c, unit normal n, radius r) in space: the closed form
// through the point's height over the plane and its distance from the axis.
double circle_distance(const Eigen::Vector3d& c, const Eigen::Vector3d& n, double r,
                       const Eigen::Vector3d& p) {
  const Eigen::Vector3d rel = p - c;
  const double h = rel.dot(n);
  return std::hypot(h, (rel - h * n).norm() - r);
}

// Points on a circle arc (centre c, in the plane with unit normal n, from direction u by `sweep`
// in `count` steps), each moved by up to `noise_mm`, one tool axis.
std::vector<ClEvent> arc_points(std::mt19937_64& rng, const Eigen::Vector3d& c,
                                const Eigen::Vector3d& n, const Eigen::Vector3d& u, double r,
                                double sweep, int count, double noise_mm, int first_line) {
  std::uniform_real_distribution<double> s(-1.0, 1.0);
  const Eigen::Vector3d v = n.cross(u);
  std::vector<ClEvent> out;
  for (int k = 0; k <= count; ++k) {
    const double phi = sweep * k / count;
    const Eigen::Vector3d jitter = noise_mm * Eigen::Vector3d(s(rng), s(rng), s(rng)) / 1.8;
    out.push_back(goto_at(
        first_line + k,
        c + r * (std::cos(phi) * u + std::sin(phi) * v) + (k ? jitter : Eigen::Vector3d::Zero()),
        Eigen::Vector3d(0.0, 0.0, 1.0)));
  }
  return out;
}

}  // namespace

TEST_CASE("point reduction: CL points on a circle become arcs that keep every point (brute force)",
          "[cl][point_reduction]") {
  std::mt19937_64 rng(3012);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long arcs = 0, points = 0;
  for (int trial = 0; trial < 60; ++trial) {
    PointReductionOptions o;
    o.tolerance_mm = 0.005 + 0.03 * u(rng);
    o.arcs = true;
    const double r = 0.5 + 40.0 * u(rng);
    const double sweep = 0.3 + 4.0 * u(rng);
    // Points closer than a line could merge: the chord a line covers is sqrt(8 r tol).
    const int count = 4 + static_cast<int>(sweep * r / (0.3 * std::sqrt(8.0 * r * o.tolerance_mm)));
    const Eigen::Vector3d n = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, 1.0).normalized();
    const Eigen::Vector3d axis_u = n.unitOrthogonal();
    const Eigen::Vector3d c(100.0 * u(rng), -50.0 * u(rng), 20.0 * u(rng));
    const std::vector<ClEvent> in =
        arc_points(rng, c, n, axis_u, r, sweep, count, 0.2 * o.tolerance_mm, 1);
    const std::vector<ClEvent> out = reduce(in, o);
    INFO("trial " << trial << ": r " << r << " mm, sweep " << sweep << " rad, " << count
                  << " points, tolerance " << o.tolerance_mm);
    REQUIRE(out.front().line == 1);
    REQUIRE(out.back().line == in.back().line);
    std::size_t prev = 0;
    for (std::size_t k = 1; k < out.size(); ++k) {
      const ClEvent& e = out[k];
      const std::size_t i = static_cast<std::size_t>(e.line - 1);
      REQUIRE(i > prev);
      REQUIRE(e.p_mm == in[i].p_mm);
      if (e.kind == ClEventKind::arc) {
        ++arcs;
        CHECK(e.origin == MoveOrigin::fitted_arc);
        CHECK(e.first_line == in[prev + 1].line);
        CHECK(static_cast<int>(i - prev) >= kMinArcPoints);
        // The arc event's circle: through its start (the point before) and end, and every point
        // it covers within half the tolerance; its axis the right-hand rule's of the travel.
        const double radius = e.value;
        CHECK(circle_distance(e.arc_centre_mm, e.arc_axis, radius, in[prev].p_mm) < 1e-9);
        CHECK(circle_distance(e.arc_centre_mm, e.arc_axis, radius, e.p_mm) < 1e-6);
        for (std::size_t j = prev + 1; j < i; ++j) {
          CHECK(circle_distance(e.arc_centre_mm, e.arc_axis, radius, in[j].p_mm) <=
                0.5 * o.tolerance_mm + 1e-12);
        }
        CHECK(e.arc_axis.dot(n) > 0.99);  // counter-clockwise about n, as the points go
        // Between the points: the arc, sampled finely from its start to its end, within the
        // tolerance of the CL polyline it replaces.
        const Eigen::Vector3d a0 = in[prev].p_mm - e.arc_centre_mm;
        const Eigen::Vector3d a1 = e.p_mm - e.arc_centre_mm;
        const Eigen::Vector3d av = e.arc_axis.cross(a0).normalized() * radius;
        double sweep_fit = std::atan2(a1.dot(av.normalized()), a1.dot(a0.normalized()));
        if (sweep_fit <= 0.0)
          sweep_fit += 2.0 * 3.14159265358979323846;
        double worst = 0.0;
        for (int k2 = 0; k2 <= 400; ++k2) {
          const double phi = sweep_fit * k2 / 400.0;
          const Eigen::Vector3d q = e.arc_centre_mm + std::cos(phi) * a0 + std::sin(phi) * av;
          double d = 1e9;
          for (std::size_t j = prev; j < i; ++j) {
            const Eigen::Vector3d seg = in[j + 1].p_mm - in[j].p_mm;
            const double t = std::clamp((q - in[j].p_mm).dot(seg) / seg.squaredNorm(), 0.0, 1.0);
            d = std::min(d, (q - in[j].p_mm - t * seg).norm());
          }
          worst = std::max(worst, d);
        }
        CHECK(worst <= o.tolerance_mm + 1e-9);
      } else {
        REQUIRE(e.kind == ClEventKind::move);
        const std::vector<ClEvent> dropped(in.begin() + prev + 1, in.begin() + i);
        CHECK(worst_between(in[prev], in[i], dropped).first <= o.tolerance_mm + 1e-12);
      }
      prev = i;
    }
    points += count;
  }
  // Not a toy: most of the points are in arcs, far fewer motions than points.
  CHECK(arcs >= 60);
  CHECK(arcs * 8 < points);
}

TEST_CASE("point reduction: a corner, a line and a short bend never become arcs",
          "[cl][point_reduction]") {
  PointReductionOptions o;
  o.tolerance_mm = 0.01;
  o.arcs = true;
  const Eigen::Vector3d z(0.0, 0.0, 1.0);
  // A square corner of 0.5 mm steps: two lines meeting at 90 deg.
  std::vector<ClEvent> corner;
  for (int k = 0; k <= 10; ++k)
    corner.push_back(goto_at(k + 1, {0.5 * k, 0.0, 0.0}, z));
  for (int k = 1; k <= 10; ++k)
    corner.push_back(goto_at(11 + k, {5.0, 0.5 * k, 0.0}, z));
  // The first move (an approach) and the one after it are kept; then a line to the corner and
  // one from it.
  std::vector<ClEvent> out = reduce(corner, o);
  REQUIRE(out.size() == 4);
  for (const ClEvent& e : out)
    CHECK(e.kind == ClEventKind::move);
  CHECK(out[2].line == 11);
  CHECK(out[3].line == 21);
  // Three points on a circle prove nothing: fewer than kMinArcPoints stay lines.
  const std::vector<ClEvent> bend = {goto_at(1, {0, 0, 0}, z), goto_at(2, {1, 0.2, 0}, z),
                                     goto_at(3, {2, 0.6, 0}, z), goto_at(4, {3, 1.2, 0}, z)};
  out = reduce(bend, o);
  for (const ClEvent& e : out)
    CHECK(e.kind == ClEventKind::move);
  CHECK(out.size() == 4);
  // A circle whose tool axis turns by more than half the angular tolerance (0.05 deg) from one
  // point to the next is no arc.
  std::mt19937_64 rng(1);
  std::vector<ClEvent> turning = arc_points(rng, {0, 0, 0}, z, {1, 0, 0}, 10.0, 1.0, 40, 0.0, 1);
  for (std::size_t k = 0; k < turning.size(); ++k) {
    const double t = 0.06 * static_cast<double>(k) * kDegToRad;
    turning[k].tool_axis = Eigen::Vector3d(std::sin(t), 0.0, std::cos(t));
  }
  out = reduce(turning, o);
  int arcs = 0;
  for (const ClEvent& e : out)
    arcs += e.kind == ClEventKind::arc ? 1 : 0;
  CHECK(arcs == 0);
  // Without `arcs` (a set with no CIRC) the circle is lines.
  o.arcs = false;
  out = reduce(arc_points(rng, {0, 0, 0}, z, {1, 0, 0}, 10.0, 1.0, 40, 0.0, 1), o);
  for (const ClEvent& e : out)
    CHECK(e.kind == ClEventKind::move);
  CHECK(out.size() > 5);
}
