// Issue 47, item 2: the plan ranks its candidates as the time model does. On seeded random
// paths short enough for one window, the session times the plan that moves the external axes
// and the plan that holds them (PostOptions::on_plan_choice, estimate_plan_time). Each
// candidate is then converted on its own (the moving one with the choice off, the held one with
// the track and the table locked where it holds them), and the time model's cycle time
// of each written program is the reference: where the two programs differ by more than 2 %, the
// estimates must rank them the same way, and the program the session wrote with the choice on
// must be the one it chose; where one candidate's program keeps the arm's lowest 1/kappa_F at
// the plan's threshold and the other's does not, the one written must keep it.
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include <fmt/format.h>

#include "catch_compat.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

std::string goto_line(const Eigen::Vector3d& p, const Eigen::Vector3d& z) {
  return fmt::format("GOTO/{:.4f},{:.4f},{:.4f},{:.7f},{:.7f},{:.7f}\n", p.x(), p.y(), p.z(), z.x(),
                     z.y(), z.z());
}

// A raster or a straight pass on the Andres cell's table, as tests/cli/make_path_apt.py makes
// them, sized for one plan window (at most 2000 mm of cut).
std::string random_path(std::mt19937& rng, bool raster) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double angle = deg_to_rad(raster ? 90.0 * u01(rng) : -60.0 + 120.0 * u01(rng));
  const double tilt = deg_to_rad(25.0 * u01(rng));
  const Eigen::Vector3d dir(std::cos(angle), std::sin(angle), 0.0), side(-dir.y(), dir.x(), 0.0);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> points;
  if (raster) {
    const double width = 40.0 + 60.0 * u01(rng), spacing = 2.0 + 6.0 * u01(rng);
    const int lines =
        std::min(static_cast<int>(width / spacing) + 1, static_cast<int>(2000.0 / width));
    const int per_line = static_cast<int>(width / 0.5) + 1;
    const Eigen::Vector3d centre(-100.0, -450.0, 60.0);
    for (int l = 0; l < lines; ++l) {
      for (int k = 0; k < per_line; ++k) {
        const double a = -0.5 * width + (l % 2 == 0 ? k : per_line - 1 - k) * 0.5;
        const double b = -0.5 * width + l * spacing;
        // The tool tilts smoothly over the square, as the benchmark raster's does.
        const double ta = tilt * std::sin(kPi * a / width), tb = tilt * std::sin(kPi * b / width);
        const Eigen::Vector3d z = (std::sin(ta) * dir - std::sin(tb) * side +
                                   std::cos(ta) * std::cos(tb) * Eigen::Vector3d::UnitZ())
                                      .normalized();
        points.emplace_back(centre + a * dir + b * side, z);
      }
    }
  } else {
    const double length = 300.0 + 400.0 * u01(rng);
    const Eigen::Vector3d along(std::sin(angle), -std::cos(angle), 0.0);
    const Eigen::Vector3d across(-along.y(), along.x(), 0.0);
    const Eigen::Vector3d z = std::sin(tilt) * across + std::cos(tilt) * Eigen::Vector3d::UnitZ();
    for (double s = 0.0; s <= length + 1e-9; s += 2.0)
      points.emplace_back(Eigen::Vector3d(-100.0, -300.0, 60.0) + s * along, z);
  }
  std::string apt = "PARTNO/RANK\nUNITS/MM\nMULTAX/ON\nCUTTER/10.,5.\nLOADTL/1\n";
  apt += "SPINDL/15000,RPM,CLW\nRAPID\n";
  apt += goto_line(points.front().first + 80.0 * points.front().second, points.front().second);
  apt += "FEDRAT/MMPM,10000\n";
  for (const auto& [p, z] : points)
    apt += goto_line(p, z);
  apt += "RAPID\n" +
         goto_line(points.back().first + Eigen::Vector3d(0.0, 0.0, 80.0), Eigen::Vector3d::UnitZ());
  return apt + "FINI\n";
}

struct Run {
  PostSummary summary;
  std::vector<PlanChoice> choices;
};

Run convert(const Cell& cell, const KrlTemplateSet& krl, const std::string& apt, PostOptions o,
            const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("redpost_test_plan_choice_" + tag);
  fs::remove_all(dir);
  fs::create_directories(dir);
  test::remove_at_exit(dir);
  o.program.name = "P";
  o.program.output_dir = dir.string();
  o.source_name = "rank.apt";
  o.plan = RedundancyPlan::global;
  // The point reduction as the command line's default (--fit-tol 0.01, --fit-ang-tol 0.1).
  o.reduction.tolerance_mm = 0.01;
  o.reduction.axis_tolerance_deg = 0.1;
  Run run;
  o.on_plan_choice = [&run](const PlanChoice& c) { run.choices.push_back(c); };
  std::istringstream in(apt);
  ClReader reader(in, o.source_name);
  PostSession session(cell, krl, o);
  ClEvent e;
  while (reader.next(e))
    session.handle(e);
  run.summary = session.finish();
  return run;
}

}  // namespace

TEST_CASE(
    "the plan's time estimates rank moving and held axes as the written programs' cycle "
    "times do",
    "[post][plan][issue47]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet krl = load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  std::mt19937 rng(47);
  int compared = 0, ranked = 0, conditioned = 0;
  double worst_error = 0.0;
  std::string log;
  for (int n = 0; n < 16; ++n) {
    const bool raster = n % 2 == 0;
    const std::string apt = random_path(rng, raster);
    INFO("path " << n << (raster ? " (raster)" : " (pass)"));
    PostOptions o;
    const Run chosen = convert(cell, krl, apt, o, "chosen");
    // One window, one choice with both candidates timed: else nothing to compare here.
    if (chosen.summary.plan_windows != 1 || chosen.choices.size() != 1 ||
        std::isnan(chosen.choices[0].still_s) || std::isnan(chosen.choices[0].moving_s))
      continue;
    const PlanChoice& c = chosen.choices[0];
    REQUIRE(c.still_start.size() == cell.size());
    PostOptions free = o;
    free.plan_settings.hold_gain = -1.0;
    const Run moving = convert(cell, krl, apt, free, "moving");
    PostOptions locked = o;
    locked.plan_settings.lock_value =
        JointVector::Constant(cell.size(), std::numeric_limits<double>::quiet_NaN());
    for (int i = 0; i < cell.size(); ++i) {
      const Joint& j = cell.joint(i);
      if (j.axis.kind == AxisKind::external && j.type != JointType::virtual_spin) {
        locked.plan_settings.locked.set(static_cast<std::size_t>(i));
        // Where the held candidate holds them: where the moving plan starts, or another
        // place the first window's approach may put them (the faster).
        locked.plan_settings.lock_value[i] = c.still_start[i];
      }
    }
    const Run held = convert(cell, krl, apt, locked, "held");
    const double t_moving = moving.summary.cycle_time_s, t_held = held.summary.cycle_time_s;
    ++compared;
    log += fmt::format(
               "path {}: estimates moving {:.2f} s, held {:.2f} s; programs "
               "moving {:.2f} s, held {:.2f} s; chose {}",
               n, c.moving_s, c.still_s, t_moving, t_held, c.still ? "held" : "moving") +
           "\n";
    // The estimates time the cut of the window; the programs add the approach and the retract
    // (the same in both): their difference is what is compared.
    const double d_program = t_moving - t_held, d_estimate = c.moving_s - c.still_s;
    if (std::fabs(d_program) > 0.02 * std::min(t_moving, t_held)) {
      ++ranked;
      CHECK((d_program > 0.0) == (d_estimate > 0.0));
    }
    worst_error =
        std::max(worst_error, std::fabs(d_estimate - d_program) / std::min(t_moving, t_held));
    // The conditioning first (issue 47, step 4): where one candidate's program keeps the arm's
    // lowest 1/kappa_F at the plan's threshold and the other's does not, the one written does.
    const double threshold = o.plan_settings.condition_threshold;
    const double k_moving = moving.summary.lowest_inv_condition,
                 k_held = held.summary.lowest_inv_condition;
    log += fmt::format("  1/kappa_F: moving {:.3f}, held {:.3f}, written {:.3f}\n", k_moving,
                       k_held, chosen.summary.lowest_inv_condition);
    if ((k_moving >= threshold) != (k_held >= threshold)) {
      ++conditioned;
      CHECK(chosen.summary.lowest_inv_condition >= threshold);
    }
    // The program written with the choice on is the candidate chosen.
    const double t_chosen = c.still ? t_held : t_moving;
    CHECK(chosen.summary.cycle_time_s == Approx(t_chosen).epsilon(0.005));
  }
  INFO(log);
  INFO("compared " << compared << ", ranked " << ranked << ", on either side of the "
                   << "threshold " << conditioned << ", worst error of the "
                   << "difference " << worst_error);
  CHECK(compared >= 6);
  CHECK(ranked >= 3);
  CHECK(conditioned >= 2);  // 3 on these paths; step 3's choice by time alone wrote 0.234 on one
  // The estimates' difference is the programs' within 8 % of the cycle time (7.1 % measured on
  // these paths; 8.1 % while a rapid's inner keyframes were timed as points, 6.2 % while only
  // the windows whose plan moved an axis were compared: the
  // estimate joins LINs at the keyframes inside a move, where the track's rate changes, and the
  // program writes one LIN per move, so a moving plan's estimate runs high: path 2's by 12 %).
  // Timed without those joints, one pair ranked the wrong way; docs/redundancy.md.
  CHECK(worst_error < 0.08);
}

namespace {

// Square contours of 40 mm on the table, 80 to 160 mm apart along the track (4 to 6 of them, up
// to 800 mm), joined by rapids (up, across, down), as a job of several small pockets is.
// retract_mm: each pocket ends with a retract at feed along the tool axis, this high; the rapid
// to the next pocket starts at 50 mm or at the retract's end, whichever is higher.
std::string pockets_along_track(std::mt19937& rng, double retract_mm = 5.0) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::string apt = "PARTNO/POCKETS\nUNITS/MM\nMULTAX/ON\nCUTTER/10.,5.\nLOADTL/1\n";
  apt += "SPINDL/15000,RPM,CLW\n";
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const int pockets = 4 + static_cast<int>(3.0 * u01(rng));
  for (int k = 0; k < pockets; ++k) {
    const Eigen::Vector3d c(-160.0 + 120.0 * u01(rng), -300.0 - 120.0 * k - 40.0 * u01(rng), 60.0);
    const double half = 20.0;
    apt += "RAPID\n" + goto_line(c + Eigen::Vector3d(-half, -half, std::max(50.0, retract_mm)), z);
    apt += "RAPID\n" + goto_line(c + Eigen::Vector3d(-half, -half, 5.0), z);
    apt += "FEDRAT/MMPM,2000\n" + goto_line(c + Eigen::Vector3d(-half, -half, 0.0), z);
    for (int lap = 0; lap < 3; ++lap) {
      for (double s = 0.0; s < 4.0 * 2.0 * half - 1e-9; s += 2.0) {
        const int side = static_cast<int>(s / (2.0 * half));
        const double t = s - side * 2.0 * half - half;
        const Eigen::Vector3d p = side == 0   ? Eigen::Vector3d(t, -half, 0.0)
                                  : side == 1 ? Eigen::Vector3d(half, t, 0.0)
                                  : side == 2 ? Eigen::Vector3d(-t, half, 0.0)
                                              : Eigen::Vector3d(-half, -t, 0.0);
        apt += goto_line(c + p, z);
      }
    }
    apt += goto_line(c + Eigen::Vector3d(-half, -half, 0.0), z);
    apt += goto_line(c + Eigen::Vector3d(-half, -half, retract_mm), z);
  }
  apt += "RAPID\n" + goto_line(Eigen::Vector3d(-100.0, -300.0 - 120.0 * pockets, 140.0), z);
  return apt + "FINI\n";
}

struct ExternalTravel {
  // In the cut: in feed moves but retracts; in the air: in rapids, PTPs and retracts at feed.
  double track_cut_mm = 0.0, track_air_mm = 0.0;
  double table_cut_deg = 0.0, table_air_deg = 0.0;
  double track_retract_mm = 0.0;  // of track_air_mm, in retracts at feed
};

// The external axes' travel in the program `convert` writes, read motion by motion as written
// (PostOptions::on_motion), in the cut and in the air. A retract is a feed move up along +z (the
// pockets' tool axis) within 10 deg.
struct TravelCounter {
  const Cell& cell;
  ExternalTravel& travel;
  JointVector last;
  Eigen::Vector3d last_p = Eigen::Vector3d::Zero();

  void operator()(const MotionSample& m) {
    if (last.size() == m.q->size()) {
      const Eigen::Vector3d d = m.p_part_mm - last_p;
      const bool retract =
          !std::isnan(m.feed_mm_per_min) && d.z() > d.norm() * std::cos(deg_to_rad(10.0));
      const bool cut = !std::isnan(m.feed_mm_per_min) && !retract;
      for (int i = 0; i < cell.size(); ++i) {
        const Joint& j = cell.joint(i);
        if (j.axis.kind != AxisKind::external || j.type == JointType::virtual_spin)
          continue;
        const double step = std::fabs((*m.q)[i] - last[i]);
        if (j.type == JointType::prismatic) {
          (cut ? travel.track_cut_mm : travel.track_air_mm) += step;
          travel.track_retract_mm += retract ? step : 0.0;
        } else {
          (cut ? travel.table_cut_deg : travel.table_air_deg) += rad_to_deg(step);
        }
      }
    }
    last = *m.q;
    last_p = m.p_part_mm;
  }
};

}  // namespace

// Issue 47, item 1: the external axes change position in the rapids rather than in the cut
// where both would do (PathPlanSettings::w_travel_cut). The reference is the same plan without
// that term: the program's external axes, read motion by motion as written, move less in the
// feed moves, and the program is not 1 % slower.
TEST_CASE("the track and the table reposition in the rapids between pockets, not in the cut",
          "[post][plan][issue47]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet krl = load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  std::mt19937 rng(4747);
  const auto run = [&](const std::string& apt, double w_travel_cut, ExternalTravel& travel,
                       const std::string& tag) {
    PostOptions o;
    o.plan_settings.w_travel_cut = w_travel_cut;
    o.on_motion = TravelCounter{cell, travel, {}};
    return convert(cell, krl, apt, o, tag).summary;
  };
  ExternalTravel with_term, without_term;
  for (int n = 0; n < 3; ++n) {
    const std::string apt = pockets_along_track(rng);
    ExternalTravel a, b;
    const PostSummary s_with = run(apt, 5.0, a, "air");
    const PostSummary s_without = run(apt, 0.0, b, "cut");
    INFO("layout " << n << ": with the term track " << a.track_cut_mm << " mm in the cut, "
                   << a.track_air_mm << " in the air, table " << a.table_cut_deg << " / "
                   << a.table_air_deg << " deg, " << s_with.cycle_time_s << " s; without: track "
                   << b.track_cut_mm << " / " << b.track_air_mm << " mm, table " << b.table_cut_deg
                   << " / " << b.table_air_deg << " deg, " << s_without.cycle_time_s << " s");
    CHECK(s_with.cycle_time_s <= 1.01 * s_without.cycle_time_s);
    CHECK(s_with.lowest_inv_condition >= 0.3);
    with_term.track_cut_mm += a.track_cut_mm;
    with_term.table_cut_deg += a.table_cut_deg;
    without_term.track_cut_mm += b.track_cut_mm;
    without_term.table_cut_deg += b.table_cut_deg;
    CHECK(a.track_cut_mm + a.track_air_mm > 300.0);  // the track moves: 4 to 6 pockets
  }
  // Measured: the track 80 mm in the cut against 280 without the term, the table 9 deg against
  // 18 (a lattice step is 40 mm and 3 deg), the cycle times within 0.1 %.
  INFO("in the cut, with the term: track "
       << with_term.track_cut_mm << " mm, table " << with_term.table_cut_deg << " deg; without: "
       << without_term.track_cut_mm << " mm, " << without_term.table_cut_deg << " deg");
  CHECK(without_term.track_cut_mm >= 200.0);  // else the layouts test nothing
  CHECK(with_term.track_cut_mm <= 0.5 * without_term.track_cut_mm);
  CHECK(with_term.table_cut_deg <= without_term.table_cut_deg);
}

// Issue 47, item 1: a retract at feed along the tool axis is an air move too (the plan's
// keyframe walk, post/plan.cpp). Pockets that end with a 60 mm retract at feed (1.8 s at 2 m/min)
// and a rapid to the next: the track moves in the retracts too, and not in the cut. Measured: the
// track 40 mm in the cut, 1410 mm in the air of which 247 in the retracts, the table all in the
// air; with the retracts not taken as air, 78 mm in the cut, 42 in the retracts, 4.9 deg of table
// in the cut (cycle times within 0.03 s).
TEST_CASE("the track repositions in the retracts at feed, not in the cut",
          "[post][plan][issue47]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet krl = load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  std::mt19937 rng(4848);
  ExternalTravel all;
  for (int n = 0; n < 3; ++n) {
    ExternalTravel t;
    PostOptions o;
    o.on_motion = TravelCounter{cell, t, {}};
    const PostSummary s = convert(cell, krl, pockets_along_track(rng, 60.0), o, "retract").summary;
    INFO("layout " << n << ": track " << t.track_cut_mm << " mm in the cut, " << t.track_air_mm
                   << " in the air (" << t.track_retract_mm << " in retracts), table "
                   << t.table_cut_deg << " / " << t.table_air_deg << " deg, " << s.cycle_time_s
                   << " s");
    CHECK(s.lowest_inv_condition >= 0.3);
    CHECK(t.track_cut_mm + t.track_air_mm > 300.0);  // the track moves: 4 to 6 pockets
    CHECK(t.table_cut_deg < 1.0);
    all.track_cut_mm += t.track_cut_mm;
    all.track_air_mm += t.track_air_mm;
    all.track_retract_mm += t.track_retract_mm;
  }
  INFO("track " << all.track_cut_mm << " mm in the cut, " << all.track_air_mm << " in the air ("
                << all.track_retract_mm << " in retracts)");
  CHECK(all.track_retract_mm >= 0.1 * all.track_air_mm);
  CHECK(all.track_cut_mm <= 0.05 * all.track_air_mm);
}
