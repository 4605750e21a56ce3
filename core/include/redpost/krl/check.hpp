// A static check of KRL programs (`redpost check`, docs/krl-diff.md).
//
// From the raw text of each .src/.dat: matched DEF/END (DEFFCT/ENDFCT, DEFDAT/ENDDAT) and
// FOLD/ENDFOLD, declarations before statements, identifiers of at most 24 characters, named
// motion targets declared in the .src or its .dat, $VEL.CP in (0, 2] m/s, the file size and
// (with max_program_bytes) the size of a program's files together.
// From the program read with read_krl_program: S and T on the first Cartesian PTP and, with a
// cell, axis values A1..A6/E1..E6 within the limits of the joints mapped to them; and, as
// warnings, the CP motions shorter than one interpolation cycle at their $VEL.CP
// (krl/motion_rate.hpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "redpost/kinematics/cell.hpp"
#include "redpost/krl/clearance_check.hpp"
#include "redpost/krl/motion_rate.hpp"
#include "redpost/krl/reader.hpp"

namespace redpost {

struct KrlFinding {
  std::string file;
  int line = 0;
  std::string message;
  // A warning: the controller runs the program, but not as written (the motion rate). It does
  // not make `check` fail unless --strict.
  bool warning = false;
};

inline constexpr size_t kKrlDefaultMaxBytes = 5u * 1000u * 1000u;  // 5 MB (docs/krl-diff.md)
inline constexpr int kKrlMaxIdentifierLength = 24;
inline constexpr double kKrlMaxVelCp = 2.0;  // m/s
// $APO.CDIS the writer accepts, mm: the controller blends over at most half a motion anyway, and a
// larger value is a slip of the keyboard (1e300 is not even a KRL REAL).
inline constexpr double kKrlMaxApoCdisMm = 1000.0;

// Stretches of short motions warned about per program; the rest are counted.
inline constexpr std::size_t kKrlMaxShortStretchWarnings = 50;

struct KrlCheckOptions {
  const Cell* cell = nullptr;  // limits of A1..A6/E1..E6; nullptr: not checked
  size_t max_bytes = kKrlDefaultMaxBytes;
  // The controller's program memory: a program whose files (the main .src, the parts it calls,
  // their .dat) take more is a finding, since it cannot be loaded at once. 0: not checked.
  size_t max_program_bytes = 0;
  // The motion rate (0: not checked); with `motion_rates`, each program's totals, by main file.
  KrlMotionRateOptions motion_rate;
  std::vector<std::pair<std::string, KrlMotionRate>>* motion_rates = nullptr;
  // The clearance of every motion recomputed from the text (krl/clearance_check.hpp): each
  // collision is a finding; with `clearance_totals`, each program's least clearance by main
  // file. nullptr: not checked.
  const KrlClearanceOptions* clearance = nullptr;
  std::vector<std::pair<std::string, KrlClearanceTotals>>* clearance_totals = nullptr;
};

// Checks a .src (and the files it calls, and the .dat files beside them) or every .src/.dat of
// a directory. Findings sorted by file and line. Throws Error(io) when a file cannot be read;
// a program the reader rejects is reported as a finding.
std::vector<KrlFinding> check_krl(const std::string& path, const KrlCheckOptions& options);

// The text checks of one file (`dat_declared`: names declared in the matching .dat).
std::vector<KrlFinding> check_krl_text(const std::string& file, const std::string& text,
                                       const std::vector<std::string>& dat_declared,
                                       const KrlCheckOptions& options);

// What the text checks find in `lines` (one statement or more, '\n'-separated) standing in a
// DEF: the first finding, its line counted within `lines` (1-based); line 0 and "" when none.
// For the text a template set or a host puts into every program (template.hpp, writer.hpp).
KrlFinding check_krl_statements(const std::string& lines);

// Names declared (DECL ... NAME, NAME2 = ...) in a .src or .dat text, upper case.
std::vector<std::string> krl_declared_names(const std::string& text);

// The checks on the motions of a program read: S/T on the first Cartesian PTP, cell limits.
std::vector<KrlFinding> check_krl_motions(const KrlProgram& program,
                                          const KrlCheckOptions& options);

}  // namespace redpost
