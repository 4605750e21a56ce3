// Reading KRL programs (.src with their .dat): what redpost writes and the usual hand-written
// forms, for `redpost diff` and `redpost check` (docs/krl-diff.md).
//
// The reader follows a program through the subprograms it calls (a split program's parts) and
// returns its motions in execution order, each with the file and line it came from, the target
// resolved (named points from the .dat), and the state in force ($VEL.CP, $APO.CDIS, the PTP
// velocity of BAS (#VEL_PTP, n), $BASE, $TOOL, the last "CL line" comment). Errors name file:line.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace redpost {

// The largest .src or .dat the reader, check and diff take: far beyond what a controller loads
// (a few MB; programs are split below that), so that an oversized program is reported rather
// than refused, and bounded so that a hostile input cannot take any amount of memory.
inline constexpr std::size_t kMaxKrlFileBytes = std::size_t{512} << 20;  // 512 MiB

// An aggregate such as {X 1, Y 2, Z 3, A 0, B 90, C 0, S 6, T 27, E1 0} or {A1 0, ..., E1 0},
// with any subset of fields. Field names upper case; S and T kept as integers.
struct KrlAggregate {
  std::string type;                      // "E6POS", "E6AXIS", "POS", "AXIS", "FRAME" or ""
  std::map<std::string, double> values;  // X Y Z A B C A1..A6 E1..E6
  std::optional<int> status, turn;       // S, T (from 'B010' or decimal)
  bool has(const std::string& field) const { return values.count(field) != 0; }
};

struct KrlMotionRecord {
  std::string keyword;              // PTP LIN CIRC SPTP SLIN SCIRC SPL LIN_REL PTP_REL ...
  KrlAggregate target;              // resolved (a named point is looked up in the .dat)
  std::optional<KrlAggregate> aux;  // CIRC's auxiliary point
  std::string approximation;        // "", "C_DIS", "C_VEL", "C_PTP", "C_ORI", "C_SPL"
  bool relative = false;            // LIN_REL, PTP_REL
  std::string file;                 // the .src it is in
  int line = 0;
  int cl_line = 0;                     // from the last "; CL line N" comment before it (0: none)
  double vel_cp_m_per_s = 0.0;         // $VEL.CP in force, or the motion's own (WITH $VEL.CP)
                                       // (0: never set)
  int spline_block = 0;                // the SPLINE block it is in, 1, 2, ... in order (0: none)
  double apo_cdis_mm = -1.0;           // $APO.CDIS in force (-1: never set)
  double ptp_velocity_percent = -1.0;  // BAS (#VEL_PTP, n) in force (-1: never set)
  std::string base, tool;              // right-hand sides of the $BASE / $TOOL in force
};

struct KrlProgram {
  std::string main_file;
  std::vector<std::string> files;        // every .src read, in the order first entered
  std::vector<KrlMotionRecord> motions;  // in execution order, through calls
  std::vector<std::string> warnings;     // "file:line: ..." for constructs skipped
};

// Reads the program in `src_path` (and its .dat, and the .src/.dat of the subprograms it calls
// that are found in the same directory). Throws Error(bad_input / io) with file:line.
KrlProgram read_krl_program(const std::string& src_path);

// The same, streamed: each motion goes to `motion` once the statement after it is read (an
// ENDSPLINE's approximation belongs to its last motion), and none is kept (`motions` stays
// empty). A part is dropped once its call returns, so memory is bounded by the largest file
// and the calls in progress, not by the program's length (`redpost check`, docs/krl-diff.md).
using KrlMotionSink = std::function<void(const KrlMotionRecord&)>;
KrlProgram read_krl_program(const std::string& src_path, const KrlMotionSink& motion);

// And each file's text as the reader first loads it, before it is parsed: a module's .dat, then
// its .src. `redpost check` runs its text checks on it, so that each file is read once.
using KrlTextSink = std::function<void(const std::string& path, const std::string& text)>;
KrlProgram read_krl_program(const std::string& src_path, const KrlMotionSink& motion,
                            const KrlTextSink& text);

}  // namespace redpost
