// The CL records that only set machine state (ClReader::Impl, cl/reader_impl.hpp): feed, spindle
// and coolant; tools (LOADTL, LOAD, SELECT, CUTTER, TLDATA, TOOL PATH); units, MULTAX, and the
// coordinate systems that are given out (MSYS) or only checked (CSYS, TRNTYP), and CUTCOM.
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

#include "cl/reader_impl.hpp"

namespace redpost {

// ===========================================================================================
// Feed, spindle, coolant

// A feed value with its unit word, in mm/min.
double ClReader::Impl::feed_value(const Field& value, std::string_view unit) const {
  double v = 0.0;
  if (iequals(unit, "MMPM")) {
    v = number(value);
  } else if (iequals(unit, "IPM")) {
    v = number(value, kMmPerInch);
  } else if (iequals(unit, "MMPR") || iequals(unit, "IPR")) {
    const double per_rev = number(value, iequals(unit, "IPR") ? kMmPerInch : 1.0);
    if (!(spindle_rpm > 0.0)) {
      fail_at(value.offset, word + "/..., " + std::string(unit) +
                                " is a feed per revolution, but the spindle speed is not "
                                "known (no SPINDL/n,RPM before it, or the spindle is off)");
    }
    v = per_rev * spindle_rpm;
  }
  if (!(v > 0.0))
    fail_at(value.offset, "the feed must be > 0, got " + std::string(value.text));
  if (v > kMaxMagnitude)
    fail_at(value.offset, "number out of range: the feed is beyond 1e7 mm/min");
  return v;
}

void ClReader::Impl::on_fedrat() {
  split_fields();
  expect_count(1, 2, "f, f,MMPM or MMPM,f (also IPM, MMPR, IPR)");
  const Field* value = &fields[0];
  std::string_view unit = unit_mm == 1.0 ? "MMPM" : "IPM";  // FEDRAT/f: per minute
  if (fields.size() == 2) {
    const bool unit_first = is_feed_unit(fields[0]);
    value = &fields[unit_first ? 1 : 0];
    const Field& u = fields[unit_first ? 0 : 1];
    if (!is_feed_unit(u))
      fail_at(u.offset,
              "FEDRAT: unknown feed unit " + std::string(u.text) + " (use MMPM, IPM, MMPR or IPR)");
    unit = u.text;
  }
  const double v = feed_value(*value, unit);
  feed_per_rev = iequals(unit, "MMPR") || iequals(unit, "IPR");
  feed_mm_per_rev = feed_per_rev ? v / spindle_rpm : 0.0;
  feed_mm_per_min = v;
  feed_known = true;
  push_feed(v, record_line);
}

void ClReader::Impl::on_spindl() {
  split_fields();
  if (fields.empty())
    fail_word("SPINDL/ needs a speed (SPINDL/n,RPM,CLW) or OFF");
  bool has_rpm = false, off = false, on = false;
  double rpm = 0.0;
  SpindleDirection dir = SpindleDirection::clockwise;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const Field& f = fields[i];
    if (is(f, "RPM")) {
    } else if (is(f, "CLW")) {
      dir = SpindleDirection::clockwise;
    } else if (is(f, "CCLW")) {
      dir = SpindleDirection::counter_clockwise;
    } else if (is(f, "OFF")) {
      off = true;
    } else if (is(f, "ON")) {
      on = true;
    } else if (is(f, "RANGE")) {
      ++i;  // the gearbox range: a robot spindle has none
      if (i >= fields.size())
        fail_at(f.offset, "SPINDL: RANGE needs a value after it");
      number(fields[i]);
    } else if (is(f, "SFM") || is(f, "SMM")) {
      fail_at(f.offset, "SPINDL: surface speed (" + std::string(f.text) +
                            ") is not supported; give the speed in RPM");
    } else if (is_letter(f.text.front())) {
      fail_at(f.offset, "SPINDL: unknown word " + std::string(f.text) +
                            " (known: RPM, CLW, CCLW, OFF, ON, RANGE)");
    } else {
      if (has_rpm)
        fail_at(f.offset, "SPINDL gives two speeds");
      rpm = number(f);
      if (rpm < 0.0)
        fail_at(f.offset, "the spindle speed must be >= 0 (CCLW gives the direction), got " +
                              std::string(f.text));
      has_rpm = true;
    }
  }
  if (off || (has_rpm && rpm == 0.0)) {
    spindle_rpm = 0.0;
    ClEvent& e = push(ClEventKind::spindle, record_line);
    e.value = 0.0;
    e.direction = SpindleDirection::off;
    return;
  }
  if (!has_rpm) {
    if (!on || !(last_spindle_rpm > 0.0))
      fail_word("SPINDL/ needs a speed in RPM (SPINDL/n,RPM,CLW)");
    rpm = last_spindle_rpm;
    dir = last_direction;
  }
  spindle_rpm = last_spindle_rpm = rpm;
  last_direction = dir;
  ClEvent& e = push(ClEventKind::spindle, record_line);
  e.value = rpm;
  e.direction = dir;
  if (feed_known && feed_per_rev) {  // a feed per revolution follows the spindle
    feed_mm_per_min = feed_mm_per_rev * rpm;
    push_feed(feed_mm_per_min, record_line);
  }
}

void ClReader::Impl::on_coolnt() {
  split_fields();
  expect_count(1, 2, "a mode: ON, OFF, FLOOD, MIST, THRU or TAP");
  bool flag = true;
  std::string_view mode;
  for (const Field& f : fields) {
    if (is(f, "OFF")) {
      flag = false;
    } else if (is(f, "ON")) {
    } else if (is(f, "FLOOD") || is(f, "MIST") || is(f, "THRU") || is(f, "TAP")) {
      mode = f.text;
    } else {
      fail_at(f.offset, "COOLNT: unknown mode " + std::string(f.text) +
                            " (use ON, OFF, FLOOD, MIST, THRU or TAP)");
    }
  }
  ClEvent& e = push(ClEventKind::coolant, record_line);
  e.flag = flag;
  if (mode.empty())
    mode = flag ? "ON" : "OFF";
  e.text.resize(mode.size());
  std::transform(mode.begin(), mode.end(), e.text.begin(), upper);
}

// ===========================================================================================
// Tools

void ClReader::Impl::push_tool_change(int number_) {
  cycle_on = false;  // the expander refuses the motion after it if no CYCLE/OFF came
  ClEvent& e = push(ClEventKind::tool_change, record_line);
  e.tool_number = number_;
  e.tool_diameter_mm = tool_diameter_mm;
  e.tool_length_mm = tool_length_mm;
  e.text = tool_name;
}

// Couplets after the tool number: ADJUST,m (length offset register) and LENGTH,l.
void ClReader::Impl::read_tool_couplets(std::size_t i) {
  for (; i < fields.size(); i += 2) {
    const Field& key = fields[i];
    if (i + 1 >= fields.size())
      fail_at(key.offset, word + ": " + std::string(key.text) + " needs a value after it");
    if (is(key, "ADJUST")) {
      tool_number(fields[i + 1]);
    } else if (is(key, "LENGTH")) {
      tool_length_mm = non_negative_length(fields[i + 1], "LENGTH");
    } else {
      fail_at(key.offset, word + ": unknown word " + std::string(key.text) +
                              " (known after the tool number: ADJUST, LENGTH)");
    }
  }
}

void ClReader::Impl::on_loadtl() {
  split_fields();
  if (fields.empty())
    fail_word("LOADTL/ needs a tool number");
  const int n = tool_number(fields[0]);
  read_tool_couplets(1);
  push_tool_change(n);
}

void ClReader::Impl::on_load_or_select(bool load) {
  split_fields();
  if (fields.size() < 2 || !is(fields[0], "TOOL")) {
    fail_at(fields.empty() ? word_offset : fields[0].offset,
            word + "/ is supported only as " + word + "/TOOL,n");
  }
  const int n = tool_number(fields[1]);
  read_tool_couplets(2);
  if (load || opt.select_tool_loads)
    push_tool_change(n);
  // Otherwise SELECT/TOOL is a preselect: the next tool to fetch, not a change (SolidWorks
  // CAM writes it right after LOAD/TOOL with the number of the following tool).
}

void ClReader::Impl::on_cutter() {
  split_fields();
  expect_count(1, 7, "1 to 7 values (d, r, e, f, a, b, h)");
  tool_diameter_mm = non_negative_length(fields[0], "the cutter diameter");
  for (std::size_t i = 1; i < fields.size(); ++i)
    length(fields[i]);
  tool_length_mm = fields.size() == 7 ? non_negative_length(fields[6], "the cutter height") : 0.0;
}

void ClReader::Impl::on_tldata() {
  split_fields();
  if (fields.empty())
    fail_word("TLDATA/ needs a tool type (TLDATA/MILL,d,r,length,...)");
  if (!is(fields[0], "MILL")) {
    warn_once("TLDATA " + std::string(fields[0].text), record_line,
              "TLDATA/" + std::string(fields[0].text) +
                  " not read: only TLDATA/MILL gives a diameter and length redpost knows");
    tool_diameter_mm = tool_length_mm = 0.0;
    return;
  }
  if (fields.size() < 4)
    fail_word("TLDATA/MILL takes at least 3 values (diameter, corner radius, length), got " +
              std::to_string(fields.size() - 1));
  tool_diameter_mm = non_negative_length(fields[1], "the tool diameter");
  non_negative_length(fields[2], "the corner radius");
  tool_length_mm = non_negative_length(fields[3], "the tool length");
  for (std::size_t i = 4; i < fields.size(); ++i)
    number(fields[i]);
}

void ClReader::Impl::on_tool_path() {
  split_fields();
  if (fields.empty())
    fail_word("TOOL PATH/ needs the operation's name");
  if (fields.size() >= 3 && is(fields[1], "TOOL"))
    tool_name.assign(fields[2].text.data(), fields[2].text.size());
  cycle_on = false;
  push_text(ClEventKind::operation_start, fields[0].text);
}

// ===========================================================================================
// Programme and coordinate systems

void ClReader::Impl::on_units() {
  units_given = true;
  split_fields();
  expect_count(1, 1, "MM or INCHES");
  const Field& f = fields[0];
  if (is(f, "MM")) {
    unit_mm = 1.0;
  } else if (is(f, "INCHES") || is(f, "INCH")) {
    unit_mm = kMmPerInch;
  } else {
    fail_at(f.offset, word + ": unknown unit " + std::string(f.text) + " (use MM or INCHES)");
  }
}

void ClReader::Impl::on_multax() {
  split_fields();
  expect_count(0, 1, "ON or OFF");
  if (fields.empty() || is(fields[0], "ON")) {
    multax = true;
  } else if (is(fields[0], "OFF")) {
    multax = false;
  } else {
    fail_at(fields[0].offset, "MULTAX: expected ON or OFF, got " + std::string(fields[0].text));
  }
}

// NX's machine coordinate system (MCS): origin and X, Y axes in NX's absolute frame, given out
// as written; the expander checks it and, under --msys apply, turns the data after it into that
// frame (cl/expander.cpp, docs/cl-format.md "MSYS").
void ClReader::Impl::on_msys() {
  split_fields();
  expect_count(9, 9, "9 values (origin x,y,z, X axis i,j,k, Y axis i,j,k)");
  ClEvent& e = push(ClEventKind::msys, record_line);
  e.p_mm = point(0);
  e.msys_x = Vector3d(number(fields[3]), number(fields[4]), number(fields[5]));
  e.msys_y = Vector3d(number(fields[6]), number(fields[7]), number(fields[8]));
}

// A 3 x 4 matrix [R | t]. redpost reads only the identity (both layouts in use: rows of
// [r r r t], or 9 rotation values then t); any other would put the points in another frame.
void ClReader::Impl::on_csys() {
  split_fields();
  expect_count(12, 12, "12 values (a 3 x 4 matrix)");
  static constexpr double kRows[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  static constexpr double kRotFirst[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  bool rows = true, rot_first = true;
  for (std::size_t i = 0; i < 12; ++i) {
    const double v = number(fields[i]);
    rows = rows && std::fabs(v - kRows[i]) <= 1e-9;
    rot_first = rot_first && std::fabs(v - kRotFirst[i]) <= 1e-9;
  }
  if (!rows && !rot_first) {
    fail_word(
        "CSYS/ with a matrix other than the identity is not supported: the points after "
        "it would be in another frame; output the CL data in the workpiece frame");
  }
}

void ClReader::Impl::on_trntyp() {
  split_fields();
  if (fields.empty())
    fail_word("TRNTYP/ needs values (TRNTYP/WORLD,0,0,0)");
  bool identity = is(fields[0], "WORLD");
  for (std::size_t i = 1; i < fields.size(); ++i)
    identity = number(fields[i]) == 0.0 && identity;
  if (!identity) {
    fail_word(
        "TRNTYP/ other than TRNTYP/WORLD,0,0,0 is not supported: it would move the "
        "points after it into another frame");
  }
}

void ClReader::Impl::on_cutcom() {
  split_fields();
  if (fields.empty())
    fail_word("CUTCOM/ needs LEFT, RIGHT or OFF");
  const Field& f = fields[0];
  const bool on = is(f, "LEFT") || is(f, "RIGHT");
  if (!on && !is(f, "OFF"))
    fail_at(f.offset, "CUTCOM: expected LEFT, RIGHT or OFF, got " + std::string(f.text));
  ClEvent& e = push(ClEventKind::cutcom, record_line);
  e.flag = on;
  e.text = on ? std::string(f.text) : "OFF";
}

}  // namespace redpost
