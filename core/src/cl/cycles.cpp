// The CL reader's drilling cycles: CYCLE/ and its parameters, read and checked value by value,
// and given out as the cycle's definition, CYCLE/ON or CYCLE/OFF (ClReader::Impl,
// cl/reader_impl.hpp). The expander turns every hole of the cycle (a GOTO while it is on) into
// the moves it stands for (cl/expander_curves.cpp), the same way for NX's MOM_drill_move.
#include <algorithm>
#include <cmath>
#include <string>

#include "cl/reader_impl.hpp"

namespace redpost {

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
      cycle_on = false;
      push(ClEventKind::cycle_off, record_line);
    }
    return;
  }
  if (is(type, "ON")) {
    if (!cycle_defined)
      fail_at(type.offset, "CYCLE/ON without a cycle defined before it");
    cycle_on = true;
    push(ClEventKind::cycle_on, record_line);
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

// The couplets of a cycle's definition, each value checked where it stands; what the cycle as a
// whole needs (a depth, a clearance, a feed, a peck) is the expander's check.
void ClReader::Impl::read_cycle_parameters(std::size_t i, bool deep) {
  ClEvent& e = push(ClEventKind::cycle, record_line);
  ClCycle& c = e.cycle;
  c.deep = deep;
  e.text = "CYCLE/" + std::string(fields[0].text);
  const std::string& name = e.text;
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
    } else if (is(key, "RAPTO")) {
      c.clearance_mm = non_negative_length(val, "RAPTO (the clearance above the hole point)");
    } else if (is(key, "RTRCTO")) {
      c.retract_mm = non_negative_length(val, "RTRCTO (the retract height above the hole point)");
    } else if (is_feed_unit(key)) {
      c.feed_mm_per_min = feed_value(val, key.text);
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
    } else if (is(key, "SUBPECK")) {
      c.next_peck_mm = positive_length(val, "SUBPECK");
    } else {
      fail_at(key.offset, name + ": unknown parameter " + std::string(key.text) +
                              " (known: FEDTO, RAPTO, RTRCTO, MMPM, IPM, MMPR, IPR, DWELL, "
                              "1STPECK, SUBPECK); redpost will not guess what it means");
    }
  }
  cycle_defined = true;
  cycle_on = true;
  cycle_retract_mm = !std::isnan(c.retract_mm)     ? c.retract_mm
                     : !std::isnan(c.clearance_mm) ? c.clearance_mm
                                                   : 0.0;
}

}  // namespace redpost
