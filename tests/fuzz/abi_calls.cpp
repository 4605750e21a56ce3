// Fuzz target: sequences of C ABI calls (redpost.h) on the Andres 2011 cell, with the writer's
// inputs drawn from the bytes: the program name, feeds (1e300, 1e-4, NaN and raw doubles),
// literals and comments with any bytes, tool names, coordinates, calls out of order, rp_prepare
// and rp_close at any point. Whatever the sequence, the ABI must return a status (never crash
// or throw), and the output folder must hold either nothing or, after an RP_OK from rp_close,
// the program's files with no temporary beside them: checked here, abort() otherwise.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include "fuzz_support.hpp"
#include "redpost.h"

namespace {

// Reads the input a piece at a time; past its end everything is 0.
struct Bytes {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;
  bool more() const { return at < size; }
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  double number() {
    static const double kValues[] = {0.0,
                                     1.0,
                                     -1.0,
                                     900.0,
                                     120000.0,
                                     120001.0,
                                     1e-4,
                                     1e300,
                                     -1e300,
                                     1e-300,
                                     0.03,
                                     7.5,
                                     std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::infinity()};
    const std::uint8_t k = byte();
    if (k < 200)
      return kValues[k % (sizeof kValues / sizeof kValues[0])] + (k / 14) * 0.5;
    // The next 8 bytes as a double, any bit pattern (what is left, zero-padded).
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i)
      bits |= static_cast<std::uint64_t>(byte()) << (8 * i);
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  std::string text() {
    const std::size_t n = byte() % 40;
    std::string s;
    for (std::size_t i = 0; i < n && more(); ++i)
      s += static_cast<char>(byte());
    return s;
  }
};

const char* const kNames[] = {"FUZZ", "end", "P",     "A_VERY_LONG_PROGRAM_NAME_X",
                              "1ABC", "LIN", "Part_7"};

// A point near the pocket example's, where the cell reaches.
void move(rp_session* s, Bytes& in, bool linear) {
  const double x = -120.0 + (in.byte() % 64), y = -470.0 + (in.byte() % 64);
  const double z = 40.0 + (in.byte() % 64);
  if (!linear) {
    rp_circular_move(s, x, y, z, 0, 0, 1, in.number(), x + 5, y, z, 0, 0, 1);
    return;
  }
  const std::uint8_t tilt = in.byte();
  rp_linear_move(s, x, y, z, (tilt & 7) * 0.05, ((tilt >> 3) & 7) * 0.05, 1.0);
}

// Each argument is read in its own statement: the order in which a call's arguments are
// evaluated is unspecified, and the corpus must mean the same to gcc's replay and clang's fuzzer.
void call(rp_session* s, Bytes& in) {
  switch (in.byte() % 24) {
    case 0:
      rp_feed(s, in.number());
      break;
    case 1:
    case 2:
      move(s, in, true);
      break;
    case 3:
      rp_rapid(s);
      break;
    case 4:
      rp_literal(s, in.text().c_str());
      break;
    case 5:
      rp_comment(s, in.text().c_str());
      break;
    case 6: {
      const double rpm = in.number();
      rp_spindle(s, rpm, static_cast<rp_spindle_direction>(in.byte() % 4));
      break;
    }
    case 7: {
      const int on = in.byte() & 1;
      rp_coolant(s, on, in.text().c_str());
      break;
    }
    case 8: {
      const int number = in.byte() % 20;
      const std::string name = in.text();
      const double diameter = in.number();
      rp_tool_change(s, number, name.c_str(), diameter, in.number());
      break;
    }
    case 9:
      rp_set_line(s, static_cast<int>(in.byte()) - 8);
      break;
    case 10:
      move(s, in, false);
      break;
    case 11:
      rp_operation_start(s, in.text().c_str());
      break;
    case 12:
      rp_operation_end(s);
      break;
    case 13:
      rp_prepare(s);
      break;
    case 14: {  // the toolpath calls of 0.6: cycles, NURBS, MSYS, texts, cutcom, dwell, warnings
      rp_cycle_params c;
      rp_cycle_params_init(&c);
      c.peck = in.byte() & 1;
      c.depth_mm = in.number();
      c.clearance_mm = in.number();
      c.retract_mm = in.byte() & 1 ? in.number() : c.retract_mm;
      c.feed_mm_per_min = in.byte() & 1 ? in.number() : c.feed_mm_per_min;
      c.dwell_s = in.byte() & 1 ? in.number() : 0.0;
      c.first_peck_mm = in.number();
      c.next_peck_mm = in.number();
      rp_cycle_define(s, &c);
      break;
    }
    case 15: {
      const double x = in.number(), y = in.number(), z = in.number();
      rp_cycle_hole(s, x, y, z, 0, 0, 1);
      break;
    }
    case 16:
      if (in.byte() & 1)
        rp_cycle_off(s);
      else
        rp_cycle_on(s);
      break;
    case 17: {
      double knots[12], points[48];
      const int nk = in.byte() % 13, np = in.byte() % 13;
      for (int k = 0; k < nk; ++k)
        knots[k] = in.byte() % 2 ? in.number() : (k + 1.0) / nk;
      for (int k = 0; k < 4 * np; ++k)
        points[k] = k % 4 == 3 ? 1.0 + (in.byte() % 3) : in.number();
      rp_nurbs_move(s, knots, nk, points, np, 0, 0, 1);
      break;
    }
    case 18: {
      const double o3[3] = {in.number(), in.number(), in.number()};
      const double x[3] = {1, 0, 0}, y[3] = {0, static_cast<double>(in.byte() % 3), 0};
      rp_machine_frame(s, o3, x, y);
      break;
    }
    case 19:
      rp_operator_text(s, static_cast<rp_text_kind>(in.byte() % 4), in.text().c_str());
      break;
    case 20:
      rp_cutcom(s, in.byte() & 1, in.text().c_str());
      break;
    case 21:
      rp_dwell(s, in.number());
      break;
    case 22:
      rp_warn(s, in.text().c_str());
      break;
    default:
      rp_close(s);
      break;
  }
}

bool has_temporaries(const std::filesystem::path& dir) {
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (!n.empty() && n.back() == '~')
      return true;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string cell =
      redpost::fuzz::source_path("definitions/cells/andres2011_kr15_track_table.xml");
  const std::filesystem::path dir = redpost::fuzz::fresh_scratch_dir();
  Bytes in{data, size};
  rp_options o;
  rp_options_init(&o);
  o.cell_path = cell.c_str();
  const std::string out = dir.string();
  o.output_dir = out.c_str();
  o.program_name = kNames[in.byte() % (sizeof kNames / sizeof kNames[0])];
  o.plan = (in.byte() & 1) ? RP_PLAN_LOCAL : RP_PLAN_GLOBAL;
  o.motions_per_file = in.byte() % 4 == 0 ? 5 : 0;
  o.apo_mm = in.byte() % 8 == 0 ? in.number() : 0.5;
  o.pipeline = in.byte() & 1;
  rp_session* s = nullptr;
  if (rp_open(&o, &s) != RP_OK) {
    if (s != nullptr || !std::filesystem::is_empty(dir))
      std::abort();  // a refused open leaves no session and no file
    return 0;
  }
  for (int k = 0; k < 64 && in.more(); ++k)
    call(s, in);
  const bool closed = rp_close(s) == RP_OK;
  static const bool verbose = std::getenv("REDPOST_FUZZ_VERBOSE") != nullptr;
  if (verbose)
    std::fprintf(stderr, "%s\n", closed ? "written" : rp_last_error(s));
  const char* first = rp_output_file(s, 0);
  const std::string main_src = first ? first : "";
  rp_free(s);
  if (has_temporaries(dir))
    std::abort();  // a temporary or the lock outlived the session
  if (closed && (main_src.empty() || !std::filesystem::exists(main_src)))
    std::abort();  // closed without its program
  if (!closed && rp_close(nullptr) == RP_OK)
    std::abort();
  return 0;
}
