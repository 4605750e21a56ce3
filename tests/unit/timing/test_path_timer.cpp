// The time model (redpost/timing/path_timer.hpp) against closed forms and against a brute-force
// integration of the fastest profile on a fine grid of the path, with its own corner formula.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/timing/path_timer.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

struct Timed {
  TimedMotion m;
  MotionTiming t;
};

// The reference cell with its <speed> data (A1..A6, track, table).
Cell timing_cell() {
  return test::shipped_cell("andres2011_kr15_track_table");
}

TimedMotion cp(double length_mm, double speed_mm_s, const JointVector& chord_rate,
               const Eigen::Vector3d& tangent, double blend_mm) {
  TimedMotion m;
  m.kind = TimedMotion::Kind::cp;
  m.length_mm = m.tcp_length_mm = length_mm;
  m.asked_mm_s = m.command_mm_s = speed_mm_s;
  m.chord_rate = chord_rate;
  m.peak_rate = chord_rate.cwiseAbs();
  m.tangent = tangent;
  m.blend_mm = blend_mm;
  m.at_feed = true;
  return m;
}

std::vector<Timed> run(const Cell& cell, const ControllerTiming& c,
                       const std::vector<TimedMotion>& motions,
                       std::size_t* most_buffered = nullptr) {
  std::vector<Timed> out;
  PathTimer timer(cell, c, [&](const TimedMotion& m, const MotionTiming& t) {
    out.push_back({m, t});
  });
  long index = 0;
  for (TimedMotion m : motions) {
    m.index = ++index;
    timer.push(m);
    if (most_buffered)
      *most_buffered = std::max(*most_buffered, timer.buffered());
  }
  timer.finish();
  return out;
}

// The time model without the controller's clock: no interpolation cycle, unlimited look-ahead
// (the profile alone, as the tests before the cycle was modelled).
ControllerTiming unclocked() {
  ControllerTiming c;
  c.interpolation_cycle_s = 0.0;
  c.lookahead_motions = -1;
  return c;
}

double total(const std::vector<Timed>& v) {
  return v.empty() ? 0.0 : v.back().t.start_s + v.back().t.duration_s + v.back().m.dwell_after_s;
}

}  // namespace

TEST_CASE("path_timer: stop-to-stop trapezoids and triangles in closed form", "[timing]") {
  // 1000 mm at 100 mm/s and 2000 mm/s^2: 10 s cruising plus 2 x 0.05 s ramps at half speed.
  CHECK(PathTimer::stop_to_stop_s(1000.0, 100.0, 2000.0) == Approx(10.05).epsilon(1e-12));
  // 1 mm: the peak is sqrt(a d) = 44.7 mm/s < 100: a triangle of 2 sqrt(d / a).
  CHECK(PathTimer::stop_to_stop_s(1.0, 100.0, 2000.0) ==
        Approx(2.0 * std::sqrt(1.0 / 2000.0)).epsilon(1e-12));
  CHECK(PathTimer::stop_to_stop_s(-1.0, 100.0, 2000.0) ==
        Approx(2.0 * std::sqrt(1.0 / 2000.0)).epsilon(1e-12));
  // Exactly at the boundary the two forms agree: d = v^2 / a.
  CHECK(PathTimer::stop_to_stop_s(5.0, 100.0, 2000.0) == Approx(2.0 * 100.0 / 2000.0));
  // A segment entered and left at speed.
  CHECK(PathTimer::segment_s(100.0, 100.0, 100.0, 100.0, 2000.0) == Approx(1.0));
  CHECK(PathTimer::segment_s(100.0, 0.0, 100.0, 100.0, 2000.0) == Approx(1.0 + 0.025));
}

TEST_CASE("path_timer: one motion from rest to rest, and the same path in 1000 blended pieces",
          "[timing]") {
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.path_acceleration_mm_s2 = 2000.0;
  JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const std::vector<Timed> one = run(cell, c, {cp(1000.0, 100.0, rate, x, 0.5)});
  REQUIRE(one.size() == 1);
  CHECK(total(one) == Approx(10.05).epsilon(1e-12));
  CHECK(one[0].t.peak_mm_s == Approx(100.0));
  CHECK(one[0].t.limit == TimingLimit::none);

  std::vector<TimedMotion> pieces(1000, cp(1.0, 100.0, rate, x, 0.5));
  std::size_t most = 0;
  const std::vector<Timed> many = run(cell, c, pieces, &most);
  REQUIRE(many.size() == 1000);
  CHECK(total(many) == Approx(10.05).epsilon(1e-9));
  // The look-ahead holds what it takes to stop from 100 mm/s (2.5 mm), not the whole path.
  CHECK(most <= 2 * 64 + 8);
  // Without blending every piece stops: 1000 triangles of 1 mm.
  std::vector<TimedMotion> exact(1000, cp(1.0, 100.0, rate, x, 0.0));
  CHECK(total(run(cell, c, exact)) == Approx(1000 * 2.0 * std::sqrt(1.0 / 2000.0)).epsilon(1e-9));
}

TEST_CASE("path_timer: an axis's velocity and acceleration limits cap the path speed", "[timing]") {
  const Cell cell = timing_cell();
  const int track = cell.find_joint("d_L");
  REQUIRE(track >= 0);
  ControllerTiming c = unclocked();
  JointVector rate = JointVector::Zero(cell.size());
  rate[track] = 2.0;  // the track moves 2 mm per mm of path: at most 500 mm/s of path
  int joint = -1;
  CHECK(PathTimer::velocity_cap(cell, rate, &joint) == Approx(500.0));
  CHECK(joint == track);
  CHECK(PathTimer::acceleration_cap(cell, rate, &joint) == Approx(1000.0));
  const std::vector<Timed> r =
      run(cell, c, {cp(2000.0, 1000.0, rate, Eigen::Vector3d::UnitX(), 0.5)});
  // 2000 mm at 500 mm/s with 1000 mm/s^2 (the track's 2000 / 2): 4 s + 0.5 s.
  CHECK(total(r) == Approx(4.5).epsilon(1e-12));
  CHECK(r[0].t.limit == TimingLimit::axis_velocity);
  CHECK(r[0].t.joint == track);
  CHECK(r[0].t.axis_fraction == Approx(1.0));
  CHECK(r[0].t.axis_fraction_joint == track);
}

TEST_CASE("path_timer: PTPs, stops and dwells end the blending", "[timing]") {
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  TimedMotion ptp;
  ptp.kind = TimedMotion::Kind::ptp;
  ptp.ptp_time_s = 2.0;
  ptp.chord_rate = rate;
  ptp.peak_rate = rate;
  std::vector<Timed> out;
  PathTimer timer(cell, c, [&](const TimedMotion& m, const MotionTiming& t) {
    out.push_back({m, t});
  });
  std::vector<TimedMotion> seq = {cp(100.0, 100.0, rate, x, 0.5), ptp,
                                  cp(100.0, 100.0, rate, x, 0.5), cp(100.0, 100.0, rate, x, 0.5)};
  long i = 0;
  for (TimedMotion& m : seq) {
    m.index = ++i;
    timer.push(m);
    if (i == 3)
      timer.stop(1.5);  // WAIT SEC 1.5 after the third
  }
  timer.finish();
  REQUIRE(out.size() == 4);
  const double leg = PathTimer::stop_to_stop_s(100.0, 100.0, 2000.0);
  CHECK(out[1].t.start_s == Approx(leg));
  CHECK(out[2].t.start_s == Approx(leg + 2.0));
  CHECK(out[3].t.start_s == Approx(leg + 2.0 + leg + 1.5));
  CHECK(total(out) == Approx(3 * leg + 2.0 + 1.5));
  CHECK(out[0].t.exit_mm_s == 0.0);
  CHECK(out[2].t.exit_mm_s == 0.0);
}

TEST_CASE("path_timer: random paths against a brute-force profile on a fine grid", "[timing]") {
  const Cell cell = timing_cell();
  // Without the clock, and with a KR C4's (12 ms, $ADVANCE 3) and a tighter one (1 motion).
  const int clocked = GENERATE(0, 1, 2);
  ControllerTiming c = unclocked();
  if (clocked) {
    c.interpolation_cycle_s = 0.012;
    c.lookahead_motions = clocked == 1 ? 3 : 1;
  }
  c.path_acceleration_mm_s2 = 1500.0;
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    const int count = 40;
    std::vector<TimedMotion> motions;
    Eigen::Vector3d dir = Eigen::Vector3d::UnitX();
    JointVector rate = JointVector::Zero(cell.size());
    for (int k = 0; k < count; ++k) {
      const double length = 0.2 + 20.0 * u(rng) * u(rng);
      const double speed = 20.0 + 300.0 * u(rng);
      // Joint rates wander (the corners), sometimes steeply (the axis caps).
      for (int i = 0; i < cell.size(); ++i) {
        if (cell.joint(i).has_speed())
          rate[i] += (u(rng) - 0.5) * (cell.joint(i).type == JointType::prismatic ? 0.6 : 0.004);
      }
      dir = (dir + 0.3 * Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)).normalized();
      if (u(rng) < 0.15)  // a sharp turn (over 120 deg: the arc's room) or a reversal
        dir = u(rng) < 0.3 ? Eigen::Vector3d(-dir)
                           : Eigen::Vector3d(-dir + 0.4 * dir.unitOrthogonal()).normalized();
      TimedMotion m = cp(length, speed, rate, dir, u(rng) < 0.1 ? 0.0 : 0.5 + u(rng));
      if (u(rng) < 0.05)
        m.stop_after = true;
      motions.push_back(m);
    }
    const std::vector<Timed> timed = run(cell, c, motions);
    REQUIRE(timed.size() == motions.size());

    // Brute force: the fastest speed at every point of a fine grid under the same limits.
    std::vector<double> s_at, cap, accel;
    std::vector<std::size_t> owner;
    for (std::size_t k = 0; k < motions.size(); ++k) {
      const TimedMotion& m = motions[k];
      double cruise = std::min(m.command_mm_s, PathTimer::velocity_cap(cell, m.peak_rate, nullptr));
      if (c.interpolation_cycle_s > 0.0)
        cruise = std::min(cruise, m.length_mm / c.interpolation_cycle_s);
      const double a = std::min(c.path_acceleration_mm_s2,
                                PathTimer::acceleration_cap(cell, m.peak_rate, nullptr));
      const int steps = std::max(200, static_cast<int>(m.length_mm / 0.002));
      for (int q = 0; q < steps; ++q) {
        cap.push_back(cruise);
        accel.push_back(a);
        owner.push_back(k);
        s_at.push_back(m.length_mm / steps);
      }
      // The junction at its end: the corner formula, written again here.
      double j = 0.0;
      if (k + 1 < motions.size() && !m.stop_after && m.blend_mm > 0.0) {
        const TimedMotion& nx = motions[k + 1];
        const double d = std::min({m.blend_mm, 0.5 * m.length_mm, 0.5 * nx.length_mm});
        double next_cruise =
            std::min(nx.command_mm_s, PathTimer::velocity_cap(cell, nx.peak_rate, nullptr));
        if (c.interpolation_cycle_s > 0.0)
          next_cruise = std::min(next_cruise, nx.length_mm / c.interpolation_cycle_s);
        j = std::min(cruise, next_cruise);
        for (int i = 0; i < cell.size(); ++i) {
          const double dr = std::fabs(nx.chord_rate[i] - m.chord_rate[i]);
          if (cell.joint(i).has_speed() && dr > 0.0)
            j = std::min(j, std::sqrt(cell.joint(i).max_acceleration * d / dr));
        }
        // The TCP's turn by its angle: the velocity turns by 2 v sin(turn / 2) over d, and the
        // widest arc tangent to both legs d from the corner has the radius d / tan(turn / 2).
        const double turn = std::acos(std::clamp(nx.tangent.dot(m.tangent), -1.0, 1.0));
        if (turn > 0.0) {
          const double room = std::max(2.0 * std::sin(0.5 * turn), std::tan(0.5 * turn));
          j = std::min(j, room > 1e12 ? 0.0 : std::sqrt(c.path_acceleration_mm_s2 * d / room));
        }
      }
      cap.back() = std::min(cap.back(), j);  // the grid point at the motion's end
    }
    // The look-ahead: at each motion's end, the speed from which the grid can still stop by the
    // end of the motion `lookahead_motions` later (a backward pass at rest from there).
    if (c.lookahead_motions > 0) {
      std::vector<std::size_t> end_of(motions.size());
      for (std::size_t i = 0; i < owner.size(); ++i)
        end_of[owner[i]] = i;
      for (std::size_t k = 0; k + 1 < motions.size(); ++k) {
        const std::size_t last =
            std::min(motions.size() - 1, k + static_cast<std::size_t>(c.lookahead_motions));
        double w = 0.0;
        for (std::size_t i = end_of[last]; i > end_of[k]; --i)
          w = std::sqrt(w * w + 2.0 * accel[i] * s_at[i]);
        cap[end_of[k]] = std::min(cap[end_of[k]], w);
      }
    }
    // Forward and backward passes on the grid (v^2 grows by at most 2 a ds per step).
    const std::size_t n = cap.size();
    std::vector<double> v(n);
    double prev = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      v[i] = std::min(cap[i], std::sqrt(prev * prev + 2.0 * accel[i] * s_at[i]));
      prev = v[i];
    }
    double next = 0.0;
    for (std::size_t i = n; i-- > 0;) {
      v[i] = std::min(v[i], next);
      next = std::sqrt(v[i] * v[i] + 2.0 * accel[i] * s_at[i]);
    }
    double brute = 0.0;
    double before = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double mean = 0.5 * (before + v[i]);
      brute += mean > 0.0 ? s_at[i] / mean : 0.0;
      before = v[i];
    }
    INFO("trial " << trial << ", clock " << clocked);
    CHECK(total(timed) == Approx(brute).epsilon(0.01));
  }
}

TEST_CASE("path_timer: motions shorter than the interpolation cycle cost a cycle each",
          "[timing]") {
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.interpolation_cycle_s = 0.012;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // 1000 blended pieces of 1 mm asked at 100 mm/s last 10 ms each: below the 12 ms cycle, so
  // the path runs at 1 mm / 12 ms = 83.3 mm/s: 12 s plus the ramp from rest, v / (2 a) more.
  std::vector<TimedMotion> pieces(1000, cp(1.0, 100.0, rate, x, 0.5));
  const std::vector<Timed> many = run(cell, c, pieces);
  const double v = 1.0 / 0.012;
  CHECK(total(many) == Approx(1000.0 / v + v / 2000.0).epsilon(1e-9));
  CHECK(many[500].t.limit == TimingLimit::motion_rate);
  CHECK(many[500].t.peak_mm_s == Approx(v));
  CHECK(many[500].t.duration_s == Approx(0.012));
  CHECK(many[500].t.below_cycle);
  // 2 mm pieces at the same feed last 20 ms: the cycle changes nothing.
  std::vector<TimedMotion> longer(500, cp(2.0, 100.0, rate, x, 0.5));
  const std::vector<Timed> fine = run(cell, c, longer);
  CHECK(total(fine) == Approx(10.05).epsilon(1e-9));
  CHECK(fine[250].t.limit == TimingLimit::none);
  CHECK_FALSE(fine[250].t.below_cycle);
}

TEST_CASE("path_timer: SPLINE segments joined smoothly are one path, with no cycle each",
          "[timing]") {
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.interpolation_cycle_s = 0.012;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // The same 1000 pieces of 1 mm at 100 mm/s as above, but each after the first joined to the
  // one before it (SPL knots, straight: no turn), and no blend of their own: the whole path runs
  // at 100 mm/s, rest to rest, 10.05 s, as one 1000 mm motion would.
  std::vector<TimedMotion> pieces(1000, cp(1.0, 100.0, rate, x, 0.0));
  for (std::size_t i = 1; i < pieces.size(); ++i)
    pieces[i].entry_smooth = true;
  const std::vector<Timed> joined = run(cell, c, pieces);
  CHECK(total(joined) == Approx(10.05).epsilon(1e-9));
  for (const std::size_t k : {std::size_t{0}, std::size_t{500}, std::size_t{999}}) {
    CHECK(joined[k].t.spline_joined);
    CHECK_FALSE(joined[k].t.below_cycle);
  }
  CHECK(joined[500].t.limit == TimingLimit::none);
  // A turn of 10 deg at each knot: spread over half a piece (0.5 mm), the corner rule caps the
  // speed at sqrt(a d / |dt|) (the TCP's direction changes by 2 sin(5 deg)): 75.7 mm/s.
  std::vector<TimedMotion> bent = pieces;
  for (std::size_t i = 0; i < bent.size(); ++i) {
    const double phi = (10.0 * 3.14159265358979323846 / 180.0) * static_cast<double>(i);
    bent[i].tangent = Eigen::Vector3d(std::cos(phi), std::sin(phi), 0.0);
  }
  const std::vector<Timed> curved = run(cell, c, bent);
  const double cap =
      std::sqrt(2000.0 * 0.5 / (2.0 * std::sin(5.0 * 3.14159265358979323846 / 180.0)));
  CHECK(cap < 100.0);
  CHECK(curved[500].t.entry_mm_s == Approx(cap).epsilon(1e-9));
  CHECK(curved[500].t.limit == TimingLimit::corner);
  // A piece alone (no knot on either side): a motion of its own, so a cycle at least.
  std::vector<TimedMotion> alone(1, cp(1.0, 100.0, rate, x, 0.0));
  const std::vector<Timed> one = run(cell, c, alone);
  CHECK_FALSE(one[0].t.spline_joined);
  CHECK(one[0].t.below_cycle);
  CHECK(one[0].t.duration_s >= 0.012);
}

TEST_CASE("path_timer: the look-ahead of $ADVANCE motions bounds the speed in closed form",
          "[timing]") {
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.lookahead_motions = 3;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // 100 pieces of 1 mm asked at 1000 mm/s: at each junction the planner must be able to stop
  // within the 3 mm it sees, so the path passes every junction at B = sqrt(2 a 3 mm) =
  // 109.5 mm/s. Inside a piece the planner already sees one piece more: it speeds up from B at
  // a to sqrt(B^2 + a L) and brakes back to B (the braking is the look-ahead's own bound). It
  // reaches B after 3 mm from rest and leaves it 3 mm before the end: 2 B / a for the ramps,
  // 2 (sqrt(B^2 + a L) - B) / a for each of the 94 pieces between.
  std::vector<TimedMotion> pieces(100, cp(1.0, 1000.0, rate, x, 0.5));
  const std::vector<Timed> out = run(cell, c, pieces);
  const double a = 2000.0, b = std::sqrt(2.0 * a * 3.0);
  const double piece = 2.0 * (std::sqrt(b * b + a * 1.0) - b) / a;
  CHECK(total(out) == Approx(2.0 * b / a + 94.0 * piece).epsilon(1e-9));
  CHECK(out[50].t.limit == TimingLimit::lookahead);
  CHECK(out[50].t.exit_mm_s == Approx(b));
  // $ADVANCE 0: no blending, every piece stops (1000 mm/s is never reached on 1 mm).
  c.lookahead_motions = 0;
  CHECK(total(run(cell, c, pieces)) == Approx(100 * 2.0 * std::sqrt(1.0 / 2000.0)).epsilon(1e-9));
  // A long look-ahead leaves the profile alone: 1 m at 100 mm/s in 1000 pieces.
  c.lookahead_motions = 100;
  std::vector<TimedMotion> slow(1000, cp(1.0, 100.0, rate, x, 0.5));
  CHECK(total(run(cell, c, slow)) == Approx(10.05).epsilon(1e-9));
}

TEST_CASE("path_timer: a corner is judged by the motions' directions at their ends, not chords",
          "[timing]") {
  // A LIN along x into a quarter circle of 10 mm that leaves tangentially: the circle's chord
  // turns by 45 deg, its start does not. Given the circle's own ends, the junction is not a
  // corner (the speed is kept); judged by the chord it is one (the speed drops to the path
  // acceleration's sqrt(a d / |t1 - t0|), the closed form of the corner rule).
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.path_acceleration_mm_s2 = 2000.0;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d chord = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  const double arc_mm = 0.5 * 3.14159265358979323846 * 10.0;
  TimedMotion arc = cp(arc_mm, 100.0, rate, chord, 0.5);
  const std::vector<Timed> by_chord = run(cell, c, {cp(100.0, 100.0, rate, x, 0.5), arc});
  REQUIRE(by_chord.size() == 2);
  const double corner = std::sqrt(2000.0 * 0.5 / (x - chord).norm());
  CHECK(by_chord[0].t.exit_mm_s == Approx(corner).epsilon(1e-9));
  arc.entry_rate = rate;
  arc.exit_rate = rate;
  arc.tangent = x;  // the circle's direction where it starts
  arc.exit_tangent = Eigen::Vector3d::UnitY();
  const std::vector<Timed> by_ends = run(cell, c, {cp(100.0, 100.0, rate, x, 0.5), arc});
  REQUIRE(by_ends.size() == 2);
  CHECK(by_ends[0].t.exit_mm_s == Approx(100.0));
  CHECK(total(by_ends) < total(by_chord));
}

TEST_CASE("path_timer: a sharp turn is capped by the widest arc, a reversal stops", "[timing]") {
  // Two blended 10 mm LINs at 166.7 mm/s with $APO.CDIS 0.5 mm. At 90 deg the velocity turns by
  // v sqrt(2) over the blend: sqrt(a d / sqrt(2)). At 150 deg the widest arc tangent to both legs
  // 0.5 mm from the corner has the radius 0.5 / tan(75 deg) = 0.134 mm: sqrt(a r). Reversed (a
  // peck's bottom), the path stops, and the pair takes two stop-to-stop profiles.
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.path_acceleration_mm_s2 = 2000.0;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const double pi = 3.14159265358979323846;
  for (const double turn_deg : {90.0, 150.0, 180.0}) {
    const double turn = turn_deg * pi / 180.0;
    const Eigen::Vector3d out(std::cos(turn), std::sin(turn), 0.0);
    const std::vector<Timed> t =
        run(cell, c,
            {cp(10.0, 10000.0 / 60.0, rate, x, 0.5), cp(10.0, 10000.0 / 60.0, rate, out, 0.5)});
    REQUIRE(t.size() == 2);
    const double expected = turn_deg == 90.0    ? std::sqrt(2000.0 * 0.5 / std::sqrt(2.0))
                            : turn_deg == 150.0 ? std::sqrt(2000.0 * 0.5 / std::tan(0.5 * turn))
                                                : 0.0;
    CHECK(t[0].t.exit_mm_s == Approx(expected).margin(1e-6));
    if (turn_deg == 180.0)
      CHECK(total(t) == Approx(2.0 * PathTimer::stop_to_stop_s(10.0, 10000.0 / 60.0, 2000.0)));
  }
}

TEST_CASE("path_timer: a circle's radius caps its speed at sqrt(a r), its normal acceleration",
          "[timing]") {
  // A 1.5 mm circle asked at 10 000 mm/min (166.7 mm/s): at $ACC.CP 2000 mm/s^2 the TCP can go
  // round it at sqrt(2000 x 1.5) = 54.8 mm/s only (v^2 / r = a); a 500 mm circle keeps the feed.
  const Cell cell = timing_cell();
  ControllerTiming c = unclocked();
  c.path_acceleration_mm_s2 = 2000.0;
  const JointVector rate = JointVector::Zero(cell.size());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  for (const double r : {1.5, 500.0}) {
    TimedMotion circ = cp(2.0 * 3.14159265358979323846 * r, 10000.0 / 60.0, rate, x, 0.5);
    circ.curvature_per_mm = 1.0 / r;
    const std::vector<Timed> t = run(cell, c, {circ});
    REQUIRE(t.size() == 1);
    const double cap = std::min(10000.0 / 60.0, std::sqrt(2000.0 * r));
    CHECK(t[0].t.peak_mm_s == Approx(cap).epsilon(1e-9));
    CHECK(total(t) == Approx(PathTimer::stop_to_stop_s(circ.length_mm, cap, 2000.0)));
    CHECK(t[0].t.limit == (r < 10.0 ? TimingLimit::curvature : TimingLimit::none));
  }
}
