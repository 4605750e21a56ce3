// The clearance of a written program recomputed from its text alone (`redpost check --cell`,
// docs/collision.md, "check"): each motion's target turned into joints as the controller turns
// it (a PTP's E6AXIS through the axis mapping; a LIN's or CIRC's E6POS with its E1, E2 through
// the arm's closed-form IK in the posture of the motion before), and every motion's path checked
// against the cell's, the tool's and the set-up's bodies with the same proven bound as convert
// (collision/clearance.hpp), independently of convert's own figures.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "redpost/collision/cell_bodies.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/tool_table.hpp"
#include "redpost/krl/reader.hpp"

namespace redpost {

struct KrlClearanceOptions {
  const Cell* cell = nullptr;  // the cell with its chain TCP
  CellBodies cell_bodies;      // its <collision>
  std::vector<Body> setup;     // fixtures and part, placed in {B}
  ToolTable tools;             // TOOL_DATA index -> the tool's length and geometry
  double margin_mm = 5.0;
  // The frame E6POS targets are in ($BASE), in {B}: convert writes them in {B} (the coupled
  // table's frame for the reference cell); a program written in another base needs it.
  Isometry T_B_base = Isometry::Identity();
};

// One finding of the clearance check.
struct KrlClearanceFinding {
  std::string file;
  int line = 0;
  std::string message;
  bool warning = false;  // what could not be checked, not a collision
};

// The least clearance of a program, as check_krl reports it.
struct KrlClearanceTotals {
  long motions = 0;
  double least_mm = 0.0;  // the least distance computed (+inf: no pair came within reach)
  std::string least_file, least_pair;
  int least_line = 0;
  bool checked = false;  // some pair of bodies was checked
};

class KrlClearanceCheck {
 public:
  explicit KrlClearanceCheck(KrlClearanceOptions options);
  ~KrlClearanceCheck();
  // The motions in execution order.
  void add(const KrlMotionRecord& m);
  std::vector<KrlClearanceFinding> finish();
  const KrlClearanceTotals& totals() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace redpost
