// The CL reader's drilling cycles: CYCLE/ and its parameters, and each GOTO under an active
// cycle expanded into the moves of a hole (ClReader::Impl, cl/reader_impl.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "cl/reader_impl.hpp"

namespace redpost {

namespace {
// A longer dwell is a typo (a value in milliseconds, or revolutions): the spindle would run for
// minutes at the hole bottom.
constexpr double kMaxDwellSeconds = 600.0;
}  // namespace

namespace {

// More pecks in one hole than a drill would ever make (a 100 mm hole in 10 um pecks): a typo in
// the peck depths, which would otherwise write millions of motions per hole.
constexpr double kMaxPecks = 10'000;

}  // namespace

void ClReader::Impl::on_cycle() {
  split_fields();
  if (fields.empty())
    fail_word("CYCLE/ needs a cycle type (DRILL, DEEP, OFF, ...)");
  const Field& type = fields[0];
  if (is(type, "OFF") || is(type, "INIT")) {
    // INIT: SolidWorks CAM opens a cycle block with it; the cycle itself follows.
    if (fields.size() > 1)
      fail_at(fields[1].offset, "CYCLE/" + std::string(type.text) + " takes no further values");
    if (is(type, "OFF")) {
      cycle.active = false;
      cycle.interrupted = false;
    }
    return;
  }
  if (is(type, "ON")) {
    if (!cycle.defined)
      fail_at(type.offset, "CYCLE/ON without a cycle defined before it");
    cycle.active = true;
    cycle.interrupted = false;
    return;
  }
  std::size_t i = 1;
  bool deep = false;
  if (is(type, "DRILL")) {
    if (fields.size() > 1 && (is(fields[1], "DEEP") || is(fields[1], "BRKCHP"))) {
      deep = true;
      i = 2;
    }
  } else if (type.text.size() >= 4 && iequals(type.text.substr(0, 4), "DEEP") &&
             std::all_of(type.text.begin() + 4, type.text.end(),
                         [](char c) { return c >= '0' && c <= '9'; })) {
    deep = true;  // DEEP, and SolidWorks CAM's DEEP2
  } else {
    fail_at(type.offset,
            "CYCLE/" + std::string(type.text) +
                " is not supported; redpost expands only drilling cycles (CYCLE/DRILL, "
                "CYCLE/DRILL,DEEP, CYCLE/DEEP) into moves: output this operation as GOTO "
                "points instead");
  }
  read_cycle_parameters(i, deep);
}

void ClReader::Impl::read_cycle_parameters(std::size_t i, bool deep) {
  DrillCycle c;
  c.deep = deep;
  c.line = record_line;
  bool has_depth = false, has_clearance = false, has_retract = false, has_feed = false;
  bool has_first = false, has_next = false;
  const std::string name = "CYCLE/" + std::string(fields[0].text);
  for (; i < fields.size(); i += 2) {
    const Field& key = fields[i];
    if (looks_numeric(key)) {
      fail_at(key.offset, name +
                              ": expected a keyword (FEDTO, RAPTO, RTRCTO, MMPM, ...) but "
                              "found the number " +
                              std::string(key.text) +
                              " (the positional ISO 4343:1978 form is not supported)");
    }
    if (i + 1 >= fields.size())
      fail_at(key.offset, name + ": " + std::string(key.text) + " needs a value after it");
    const Field& val = fields[i + 1];
    if (is(key, "FEDTO")) {
      c.depth_mm = non_negative_length(val, "FEDTO (the depth below the hole point)");
      has_depth = true;
    } else if (is(key, "RAPTO")) {
      c.clearance_mm = non_negative_length(val, "RAPTO (the clearance above the hole point)");
      has_clearance = true;
    } else if (is(key, "RTRCTO")) {
      c.retract_mm = non_negative_length(val, "RTRCTO (the retract height above the hole point)");
      has_retract = true;
    } else if (is_feed_unit(key)) {
      c.feed_mm_per_min = feed_value(val, key.text);
      has_feed = true;
    } else if (is(key, "DWELL")) {
      // Seconds at the hole bottom, written as the template set's dwell (WAIT SEC).
      c.dwell_s = number(val);
      if (c.dwell_s < 0.0 || c.dwell_s > kMaxDwellSeconds) {
        fail_at(val.offset, name + ": DWELL must be 0 to " +
                                std::to_string(static_cast<int>(kMaxDwellSeconds)) +
                                " seconds, got " + std::string(val.text));
      }
    } else if (is(key, "1STPECK")) {
      c.first_peck_mm = positive_length(val, "1STPECK");
      has_first = true;
    } else if (is(key, "SUBPECK")) {
      c.next_peck_mm = positive_length(val, "SUBPECK");
      has_next = true;
    } else {
      fail_at(key.offset, name + ": unknown parameter " + std::string(key.text) +
                              " (known: FEDTO, RAPTO, RTRCTO, MMPM, IPM, MMPR, IPR, DWELL, "
                              "1STPECK, SUBPECK); redpost will not guess what it means");
    }
  }
  if (!has_depth || !has_clearance)
    fail_word(name + " needs FEDTO (the depth) and RAPTO (the clearance) to be expanded safely");
  if (!has_feed) {
    if (!feed_known)
      fail_word(name + " gives no feed (MMPM, IPM, MMPR or IPR) and no FEDRAT came before it");
    c.feed_mm_per_min = feed_mm_per_min;
  }
  c.retract_mm = has_retract ? c.retract_mm : c.clearance_mm;
  if (deep) {
    if (!has_first && c.depth_mm > 0.0) {
      fail_word(name +
                " gives no peck depth (1STPECK, SUBPECK): redpost will not guess one for a "
                "pecking cycle");
    }
    c.next_peck_mm = has_next ? c.next_peck_mm : c.first_peck_mm;
    if (!has_first)  // FEDTO 0: a single touch, nothing to peck
      c.first_peck_mm = c.next_peck_mm = 1.0;
  }
  if (c.depth_mm == 0.0)
    warn_once("FEDTO0", record_line,
              name + " has FEDTO 0: its holes are only touched, not drilled");
  c.defined = true;
  c.active = true;
  cycle = c;
}

void ClReader::Impl::interrupt_cycle() {
  if (cycle.active) {
    cycle.active = false;
    cycle.interrupted = true;
    cycle.interrupted_line = record_line;
  }
}

// Motion after an interrupted cycle (see DrillCycle::interrupted) is refused.
void ClReader::Impl::check_cycle_not_interrupted() const {
  if (!cycle.interrupted)
    return;
  // Not "add CYCLE/OFF before the tool change": the points after it are usually the next
  // tool's holes (on the part's surface), and as plain moves the tool would be dragged across
  // the part between them.
  fail_word("the CYCLE of line " + std::to_string(cycle.line) +
            " was still on when the tool changed at line " +
            std::to_string(cycle.interrupted_line) +
            " (no CYCLE/OFF): redpost cannot tell whether this " + word +
            " is a hole of that cycle or a plain move, and will not guess. Fix it in the CAM "
            "system: end the cycle where its last hole is done (the tool retracts to RTRCTO), "
            "and give the next tool's holes a CYCLE/ of their own after its LOAD/TOOL. Do not "
            "only insert CYCLE/OFF before the tool change: points on the part's surface would "
            "then become plain moves between the holes, through the part");
}

// A hole at `p` (the GOTO point, on the surface): travel at the retract height, rapid to the
// clearance, feed down in one go or in pecks (rapid out to the clearance and back down to the
// clearance above the last peck's bottom between them), rapid out to the retract height.
void ClReader::Impl::start_hole(const Vector3d& p) {
  take_rapid();  // the cycle decides which of its moves are rapid
  hole_point = p;
  hole_pecks = 1;
  if (cycle.deep && cycle.depth_mm > cycle.first_peck_mm) {
    const double more =
        std::ceil((cycle.depth_mm - cycle.first_peck_mm) / cycle.next_peck_mm - 1e-9);
    if (more + 1.0 > kMaxPecks) {
      fail_line(cycle.line,
                fmt::format("this pecking cycle needs {:.0f} pecks per hole, more than the {:.0f} "
                            "redpost writes: check the peck depths of the CYCLE record "
                            "(1STPECK {:.6g} mm, SUBPECK {:.6g} mm, depth {:.6g} mm)",
                            std::min(more + 1.0, 1e15), kMaxPecks, cycle.first_peck_mm,
                            cycle.next_peck_mm, cycle.depth_mm));
    }
    hole_pecks = 1 + static_cast<long>(more);
  }
  hole_peck = 0;
  hole_phase = HolePhase::travel;
  gen_axis = axis;
  gen_line = record_line;
  generator = Generator::hole;
}

double ClReader::Impl::peck_depth(long k) const {
  if (!cycle.deep)
    return cycle.depth_mm;
  return std::min(cycle.depth_mm,
                  cycle.first_peck_mm + static_cast<double>(k) * cycle.next_peck_mm);
}

// A move of the cycle, left out when it would not move.
void ClReader::Impl::hole_move(double above_mm, bool rapid) {
  const Vector3d q = hole_point + above_mm * gen_axis;
  if (pos_known && (q - pos).norm() <= 1e-9)
    return;
  push_move(q, gen_axis, MoveOrigin::cycle, rapid, gen_line);
  ClEvent& e = queue.back();
  e.has_clearance = true;
  e.clearance_p_mm = hole_point + cycle.clearance_mm * gen_axis;
  pos = q;
  pos_known = true;
}

void ClReader::Impl::run_hole() {
  while (queue.size() < kBatch && hole_phase != HolePhase::done) {
    switch (hole_phase) {
      case HolePhase::travel:
        hole_move(cycle.retract_mm, true);
        hole_phase = HolePhase::approach;
        break;
      case HolePhase::approach:
        hole_move(cycle.clearance_mm, true);
        hole_phase = HolePhase::feed_on;
        break;
      case HolePhase::feed_on:
        push_feed(cycle.feed_mm_per_min, gen_line);
        hole_phase = HolePhase::cut;
        break;
      case HolePhase::reenter:
        hole_move(cycle.clearance_mm - peck_depth(hole_peck - 1), true);
        hole_phase = HolePhase::cut;
        break;
      case HolePhase::cut:
        hole_move(-peck_depth(hole_peck), false);
        hole_phase = hole_peck + 1 < hole_pecks ? HolePhase::peck_out : HolePhase::dwell;
        break;
      case HolePhase::dwell:
        if (cycle.dwell_s > 0.0)
          push(ClEventKind::dwell, gen_line).value = cycle.dwell_s;
        hole_phase = HolePhase::feed_off;
        break;
      case HolePhase::peck_out:
        hole_move(cycle.clearance_mm, true);
        ++hole_peck;
        hole_phase = HolePhase::reenter;
        break;
      case HolePhase::feed_off:
        if (feed_known)
          push_feed(feed_mm_per_min, gen_line);
        hole_phase = HolePhase::retract;
        break;
      case HolePhase::retract:
        hole_move(cycle.retract_mm, true);
        hole_phase = HolePhase::done;
        break;
      case HolePhase::done:
        break;
    }
  }
  if (hole_phase == HolePhase::done)
    generator = Generator::none;
}

}  // namespace redpost
