// The motion checks of `redpost check` (krl/check_motions.hpp).
#include "krl/check_motions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "krl/text.hpp"
#include "redpost/kinematics/controller_axes.hpp"

namespace redpost {

namespace krl {

MotionChecks::MotionChecks(const KrlCheckOptions& options, std::string main_file)
    : options_(options), main_file_(std::move(main_file)), rate_(options.motion_rate) {
  if (options.clearance)
    clearance_ = std::make_unique<KrlClearanceCheck>(*options.clearance);
}

void MotionChecks::add(const KrlMotionRecord& m) {
  first_motion(m);
  first_cartesian_ptp(m);
  if (options_.motion_rate.interpolation_cycle_s > 0.0)
    rate_.add(m);
  if (options_.cell)
    limits(m);
  if (clearance_)
    clearance_->add(m);
}

std::vector<KrlFinding> MotionChecks::finish() {
  if (options_.motion_rate.interpolation_cycle_s > 0.0)
    motion_rate(rate_.finish());
  if (clearance_) {
    for (KrlClearanceFinding& f : clearance_->finish())
      out_.push_back({std::move(f.file), f.line, std::move(f.message), f.warning});
    if (options_.clearance_totals)
      options_.clearance_totals->emplace_back(main_file_, clearance_->totals());
  }
  return std::move(out_);
}

// The first motion of a program is the BCO run, from wherever the robot stands: only a PTP to
// every axis (A1..A6 and, with a cell, each external axis it maps) defines where it goes and
// how; a CP motion or a partial target leaves the posture or an axis to chance.
void MotionChecks::first_motion(const KrlMotionRecord& m) {
  if (motion_seen_)
    return;
  motion_seen_ = true;
  const std::string kw = upper(m.keyword);
  std::string missing;
  const auto need = [&](const std::string& axis) {
    if (!m.target.has(axis))
      missing += (missing.empty() ? "" : ", ") + axis;
  };
  for (int a = 1; a <= 6; ++a)
    need(fmt::format("A{}", a));
  for (int i = 0; options_.cell && i < options_.cell->size(); ++i) {
    const ControllerAxis& axis = options_.cell->joint(i).axis;
    if (axis.kind == AxisKind::external)
      need(fmt::format("E{}", axis.number));
  }
  const bool ptp = (kw == "PTP" || kw == "SPTP") && !m.relative;
  if (ptp && missing.empty())
    return;
  const std::string what =
      ptp ? fmt::format("a {} without {}", kw, missing) : fmt::format("a {}", kw);
  out_.push_back({m.file, m.line,
                  fmt::format("the program's first motion is {}: the BCO run from wherever the "
                              "robot stands needs a PTP to a full E6AXIS (A1..A6{}), so that the "
                              "posture and every axis are defined (docs/krl-diff.md)",
                              what, options_.cell ? " and every external axis of the cell" : "")});
}

// S and T on the first Cartesian PTP: without them the controller picks the posture from
// wherever the robot happens to be.
void MotionChecks::first_cartesian_ptp(const KrlMotionRecord& m) {
  const std::string kw = upper(m.keyword);
  if (ptp_seen_ || m.relative || (kw != "PTP" && kw != "SPTP"))
    return;
  const KrlAggregate& t = m.target;
  const bool cartesian =
      t.has("X") || t.has("Y") || t.has("Z") || t.has("A") || t.has("B") || t.has("C");
  if (!cartesian)
    return;
  ptp_seen_ = true;
  if (!t.status || !t.turn) {
    const std::string missing = !t.status && !t.turn ? "S and T" : !t.status ? "S" : "T";
    out_.push_back({m.file, m.line,
                    fmt::format("the first Cartesian {} has no {}: the posture is then left "
                                "to the robot's current one",
                                kw, missing)});
  }
}

void MotionChecks::motion_rate(KrlMotionRate rate) {
  const double cycle_ms = 1000.0 * options_.motion_rate.interpolation_cycle_s;
  for (std::size_t i = 0; i < rate.stretches.size(); ++i) {
    const KrlShortStretch& st = rate.stretches[i];
    if (i == kKrlMaxShortStretchWarnings) {
      out_.push_back({st.file, st.first_line,
                      fmt::format("{} more stretches of motions shorter than the {:g} ms "
                                  "interpolation cycle from here (not listed)",
                                  rate.stretch_count - static_cast<long>(i), cycle_ms),
                      true});
      break;
    }
    const std::string lines =
        st.first_line == st.last_line
            ? fmt::format("this motion")
            : fmt::format("{} CP motions to line {}", st.motions, st.last_line);
    out_.push_back(
        {st.file, st.first_line,
         fmt::format("{} last{} less than one {:g} ms interpolation cycle at the $VEL.CP in "
                     "force (shortest {:.1f} ms): the controller cannot run {} that fast "
                     "(docs/timing.md)",
                     lines, st.motions == 1 ? "s" : "", cycle_ms, 1000.0 * st.shortest_s,
                     st.motions == 1 ? "it" : "them"),
         true});
  }
  if (options_.motion_rates)
    options_.motion_rates->emplace_back(main_file_, std::move(rate));
}

void MotionChecks::limits(const KrlMotionRecord& m) {
  if (m.relative)
    return;
  const Cell& cell = *options_.cell;
  static const char* const names[12] = {"A1", "A2", "A3", "A4", "A5", "A6",
                                        "E1", "E2", "E3", "E4", "E5", "E6"};
  for (int a = 0; a < 12; ++a) {
    auto it = m.target.values.find(names[a]);
    if (it == m.target.values.end())
      continue;
    const AxisKind kind = a < 6 ? AxisKind::arm : AxisKind::external;
    const int number = a < 6 ? a + 1 : a - 5;
    bool mapped = false;
    for (int j = 0; j < cell.size(); ++j) {
      const Joint& joint = cell.joint(j);
      if (joint.axis.kind != kind || joint.axis.number != number)
        continue;
      mapped = true;
      const double q = from_axis_value(joint, it->second);
      const double slack = 1e-9 * std::max(1.0, std::abs(joint.upper - joint.lower));
      if (q < joint.lower - slack || q > joint.upper + slack) {
        double lo = to_axis_value(joint, joint.lower), hi = to_axis_value(joint, joint.upper);
        if (lo > hi)
          std::swap(lo, hi);
        out_.push_back({m.file, m.line,
                        fmt::format("{} {:g} is outside the limits [{:g}, {:g}] of joint '{}'",
                                    names[a], it->second, lo, hi, joint.name)});
      }
    }
    // A value for an axis the cell does not have: 0 is what posts write for axes that are
    // not there; anything else moves an axis the cell does not model (a program for
    // another cell?). Once per axis and file.
    if (!mapped && it->second != 0.0 && unmapped_reported_.insert(m.file + "#" + names[a]).second) {
      out_.push_back({m.file, m.line,
                      fmt::format("{} is {:g}, but the cell '{}' maps no joint to {}: is the "
                                  "program for this cell?",
                                  names[a], it->second, cell.name, names[a])});
    }
  }
}

}  // namespace krl

std::vector<KrlFinding> check_krl_motions(const KrlProgram& program,
                                          const KrlCheckOptions& options) {
  krl::MotionChecks checks(options, program.main_file);
  for (const KrlMotionRecord& m : program.motions)
    checks.add(m);
  return checks.finish();
}

}  // namespace redpost
