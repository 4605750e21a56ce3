// The clearance of a written program from its text (krl/clearance_check.hpp).
#include "redpost/krl/clearance_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "redpost/collision/clearance.hpp"
#include "redpost/collision/tool_bodies.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/circle.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/status_turn.hpp"

namespace redpost {

struct KrlClearanceCheck::State {
  KrlClearanceOptions o;
  int tool_data = -1;  // the TOOL_DATA index of the scene (0: none known)
  std::unique_ptr<Cell> tool_cell;
  std::unique_ptr<ArmIk> ik;
  std::string ik_problem;
  std::unique_ptr<CollisionScene> scene;
  std::unique_ptr<ClearanceMonitor> monitor;
  bool have_prev = false;
  JointVector q_prev;
  Isometry T_prev = Isometry::Identity();
  std::string prev_approximation;
  double prev_apo_mm = 0.0;
  Eigen::Vector3d last_direction = Eigen::Vector3d::UnitX();
  double last_length = 0.0;
  std::vector<KrlClearanceFinding> findings;
  KrlClearanceTotals totals;
  long relative_skipped = 0;
  // Motions whose clearance could not be computed, said once per program (finish()).
  long unchecked = 0;
  KrlClearanceFinding first_unchecked;
  void not_checked(const KrlMotionRecord& m, const std::string& why);

  const Cell& cell() const { return tool_cell ? *tool_cell : *o.cell; }
  void use_tool(const KrlMotionRecord& m);
  bool joints(const KrlMotionRecord& m, JointVector& q, std::string& why);
  bool cp_beyond_limit(const KrlMotionRecord& m, const JointVector& q, std::string& why);
  void motion(const KrlMotionRecord& m);
  void note(const KrlMotionRecord& m, const MotionClearance& c);
};

namespace {

// "TOOL_DATA[3]" -> 3; 0 when the text names no TOOL_DATA entry.
int tool_data_index(const std::string& tool) {
  std::string u;
  for (char c : tool) {
    if (!std::isspace(static_cast<unsigned char>(c)))
      u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  const std::string prefix = "TOOL_DATA[";
  if (u.compare(0, prefix.size(), prefix) != 0 || u.back() != ']')
    return 0;
  const std::string digits = u.substr(prefix.size(), u.size() - prefix.size() - 1);
  if (digits.empty() || digits.size() > 3 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return 0;
  return std::stoi(digits);
}

// The motion's keyword in capitals (KRL is case-blind): "LIN", "PTP", "SPL".
std::string upper_keyword(const KrlMotionRecord& m) {
  std::string kw;
  for (char ch : m.keyword)
    kw += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return kw;
}

JointVector physical(const Cell& cell, JointVector q) {
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      q[i] = 0.0;
  }
  return q;
}

}  // namespace

// The tool in force: its TCP and its bodies, from the tool table's entry for its TOOL_DATA.
void KrlClearanceCheck::State::use_tool(const KrlMotionRecord& m) {
  const int k = tool_data_index(m.tool);
  if (scene && k == tool_data)
    return;
  tool_data = k;
  const ToolEntry* entry = nullptr;
  for (const ToolEntry& e : o.tools.tools) {
    if (e.tool_data == k)
      entry = &e;
  }
  tool_cell.reset();
  std::vector<Body> bodies = o.cell_bodies.bodies;
  bodies.insert(bodies.end(), o.setup.begin(), o.setup.end());
  if (entry) {
    if (o.cell->tools.has_reference())
      tool_cell = std::make_unique<Cell>(cell_for_tool(*o.cell, entry->length_mm));
    ToolGeometry g;
    g.name = fmt::format("tool {}", entry->number);
    g.length_mm = entry->length_mm;
    g.diameter_mm = entry->diameter_mm;
    g.flute_length_mm = entry->flute_length_mm;
    g.shank_diameter_mm = entry->shank_diameter_mm;
    g.holder_diameter_mm = entry->holder_diameter_mm;
    g.holder_length_mm = entry->holder_length_mm;
    for (Body& b : tool_bodies(g))
      bodies.push_back(std::move(b));
  }
  ik.reset();
  try {
    ik = std::make_unique<ArmIk>(cell());
  } catch (const Error& e) {
    ik_problem = e.message();
  }
  monitor.reset();
  scene = std::make_unique<CollisionScene>(cell(), std::move(bodies), o.cell_bodies.allowed);
  totals.checked = totals.checked || !scene->pairs().empty();
  if (scene->pairs().empty())
    return;
  ClearanceSettings settings;
  settings.margin_mm = o.margin_mm;
  monitor = std::make_unique<ClearanceMonitor>(*scene, settings);
  if (have_prev)
    monitor->start(q_prev);
}

// The joints the controller moves to: an E6AXIS through the axis mapping; an E6POS (in {B}: the
// coupled base turns with the table as {B} does) with its external axes, the arm in the posture
// of the motion before (or the target's own S).
bool KrlClearanceCheck::State::joints(const KrlMotionRecord& m, JointVector& q, std::string& why) {
  const Cell& c = cell();
  q = have_prev ? q_prev : physical(c, c.home());
  const KrlAggregate& t = m.target;
  for (int i = 0; i < c.size(); ++i) {
    const Joint& j = c.joint(i);
    if (!j.axis.mapped())
      continue;
    const std::string name = axis_name(j.axis);
    if (j.axis.kind == AxisKind::arm && !t.has("A1"))
      continue;  // a Cartesian target: the arm is solved below
    if (t.has(name))
      q[i] = from_axis_value(j, t.values.at(name));
  }
  if (t.has("A1"))
    return true;
  if (!(t.has("X") && t.has("Y") && t.has("Z"))) {
    why = "a target without X, Y, Z or A1..A6";
    return false;
  }
  if (!ik) {
    why = "the arm cannot be solved in closed form (" + ik_problem + ")";
    return false;
  }
  const auto value = [&](const char* f) { return t.has(f) ? t.values.at(f) : 0.0; };
  const Isometry T = o.T_B_base * frame_from_xyzabc(value("X"), value("Y"), value("Z"),
                                                    KukaAbc{value("A"), value("B"), value("C")});
  const int status = t.status ? *t.status & 7 : status_turn(c, ik->status_model(), q).status;
  const ArmIkSolutions sol = ik->solve(T, q, &q, status);
  if (!sol.valid[static_cast<std::size_t>(status)]) {
    why = fmt::format("the arm cannot reach this target in Status {} within its limits", status);
    return false;
  }
  q = sol.q[static_cast<std::size_t>(status)];
  return !cp_beyond_limit(m, q, why);
}

// A LIN, CIRC or SPL moves the axes on continuously from where the motion before left them:
// the solver's choice of A4's or A6's turn within the limits is then not the controller's when
// the continuous value lies beyond a limit (a pose printed a hair past it), and the controller
// stops at its software limit switch. A finding at the motion; `why` is left empty.
bool KrlClearanceCheck::State::cp_beyond_limit(const KrlMotionRecord& m, const JointVector& q,
                                               std::string& why) {
  const std::string kw = upper_keyword(m);
  if (!have_prev || kw == "PTP" || kw == "SPTP")
    return false;
  const Cell& c = cell();
  for (int i = 0; i < c.size(); ++i) {
    const Joint& j = c.joint(i);
    if (j.type != JointType::revolute || j.axis.kind != AxisKind::arm)
      continue;
    const double turns = std::round((q_prev[i] - q[i]) / (2.0 * kPi));
    const double continued = q[i] + 2.0 * kPi * turns;
    if (continued >= j.lower && continued <= j.upper)
      continue;
    why.clear();
    const double a = to_axis_value(j, j.lower), b = to_axis_value(j, j.upper);
    const double v = to_axis_value(j, continued);
    const double limit = v < std::min(a, b) ? std::min(a, b) : std::max(a, b);
    findings.push_back(
        {m.file, m.line,
         fmt::format("joint limit: {} would pass its limit of {:g} deg by {:.2g} deg on this {}, "
                     "going on from the motion before: the controller stops at its software "
                     "limit switch",
                     axis_name(j.axis), limit, std::abs(v - limit), m.keyword)});
    return true;
  }
  return false;
}

void KrlClearanceCheck::State::note(const KrlMotionRecord& m, const MotionClearance& c) {
  ++totals.motions;
  if (c.nearest_mm < totals.least_mm) {
    totals.least_mm = c.nearest_mm;
    totals.least_file = m.file;
    totals.least_line = m.line;
    totals.least_pair = scene->pair_name(c.nearest_pair);
  }
  if (c.clear)
    return;
  const std::string pair = c.pair >= 0 ? scene->pair_name(c.pair) : std::string("?");
  const char* unproven =
      "cannot be proven to stay apart (the bound of the motion did not close: a joint that jumps "
      "within it?)";
  const ClearanceShortfall why = shortfall(c);
  const std::string what =
      why == ClearanceShortfall::touching   ? std::string("touch or pass through each other")
      : why == ClearanceShortfall::unproven ? std::string(unproven)
                                            : fmt::format("come within {:.2f} mm", c.least_mm);
  findings.push_back({m.file, m.line,
                      fmt::format("collision: {} {} on this {} ({:g} mm must stay between them)",
                                  pair, what, m.keyword, o.margin_mm)});
}

void KrlClearanceCheck::State::motion(const KrlMotionRecord& m) {
  if (m.relative) {
    ++relative_skipped;
    return;
  }
  use_tool(m);
  JointVector q;
  std::string why;
  if (!joints(m, q, why)) {
    if (!why.empty())
      not_checked(m, why);
    return;
  }
  const Cell& c = cell();
  q = physical(c, q);
  const Isometry T = tcp_pose(c, q);
  if (monitor) {
    const std::string kw = upper_keyword(m);
    MotionClearance r;
    if (!have_prev || !monitor->started()) {
      r = monitor->start(q);
    } else if (kw == "PTP" || kw == "SPTP") {
      r = monitor->advance(JointLinePath(q_prev, q));
      last_length = 0.0;
    } else {
      std::unique_ptr<CartesianPath> path;
      Circle circle;
      const bool arc = (kw == "CIRC" || kw == "SCIRC") && m.aux;
      if (arc) {
        const auto v = [&](const char* f) { return m.aux->has(f) ? m.aux->values.at(f) : 0.0; };
        if (!circle_through(T_prev.translation(), Eigen::Vector3d(v("X"), v("Y"), v("Z")),
                            T.translation(), circle)) {
          not_checked(m, "the CIRC's points lie on a line");
          return;
        }
      }
      path = arc ? std::make_unique<CartesianPath>(*ik, c, q_prev, q, circle)
                 : std::make_unique<CartesianPath>(*ik, c, q_prev, q);
      // The blend at its start, where the motion before is approximated (as convert's check).
      const Eigen::Vector3d step = T.translation() - T_prev.translation();
      const double length = step.norm();
      double share = 0.0;
      if (prev_approximation == "C_DIS" && prev_apo_mm > 0.0 && last_length > 0.0 &&
          length > 1e-9) {
        const double cosine = std::clamp(last_direction.dot(step / length), -1.0, 1.0);
        share = std::sqrt(0.5 * (1.0 - cosine));
        path->blend_fraction = share * std::min(0.5, prev_apo_mm / length);
        path->blend_fraction_before = share * std::min(0.5, prev_apo_mm / last_length);
      }
      if (kw == "SPL")
        path->allowance_mm = 0.2;  // within the spline's tolerance of its chord, as convert
      r = monitor->advance(*path);
      if (length > 1e-9) {
        last_direction = step / length;
        last_length = length;
      }
    }
    if (r.path_lost)
      not_checked(m, "its path leaves the arm's reach in its posture");
    else
      note(m, r);
    if (!r.clear)
      monitor->start(q);  // the next motion checked from here, on its own
  }
  have_prev = true;
  q_prev = q;
  T_prev = T;
  prev_approximation = m.approximation;
  prev_apo_mm = m.apo_cdis_mm;
}

void KrlClearanceCheck::State::not_checked(const KrlMotionRecord& m, const std::string& why) {
  if (unchecked++ == 0)
    first_unchecked = {m.file, m.line, why, true};
}

KrlClearanceCheck::KrlClearanceCheck(KrlClearanceOptions options) : s_(std::make_unique<State>()) {
  s_->o = std::move(options);
  s_->totals.least_mm = std::numeric_limits<double>::infinity();
  if (!s_->o.cell)
    throw Error(ErrorCode::internal, "KrlClearanceCheck without a cell");
}

KrlClearanceCheck::~KrlClearanceCheck() = default;

void KrlClearanceCheck::add(const KrlMotionRecord& m) {
  s_->motion(m);
}

std::vector<KrlClearanceFinding> KrlClearanceCheck::finish() {
  if (s_->unchecked > 0) {
    KrlClearanceFinding f = s_->first_unchecked;
    f.message = fmt::format(
        "clearance not checked on {} motion(s), the first here: {} (are the E6POS targets in "
        "the cell's base frame? --base gives another)",
        s_->unchecked, f.message);
    s_->findings.push_back(std::move(f));
  }
  return std::move(s_->findings);
}

const KrlClearanceTotals& KrlClearanceCheck::totals() const {
  return s_->totals;
}

}  // namespace redpost
