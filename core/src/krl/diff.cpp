// Comparing two KRL programs motion by motion (docs/krl-diff.md): the targets made complete,
// the motions aligned (by keys, krl/diff_align.hpp) and each aligned pair compared; the main
// programs of a directory. The reports are written by diff_report.cpp.
#include "redpost/krl/diff.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "krl/diff_align.hpp"
#include "krl/diff_path.hpp"
#include "krl/reader_parse.hpp"
#include "krl/text.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost {

namespace fs = std::filesystem;

const char* krl_quantity_name(KrlQuantity q) {
  static const char* const names[kKrlQuantityCount] = {"position",     "orientation",
                                                       "aux_position", "A1",
                                                       "A2",           "A3",
                                                       "A4",           "A5",
                                                       "A6",           "E1",
                                                       "E2",           "E3",
                                                       "E4",           "E5",
                                                       "E6",           "status",
                                                       "turn",         "keyword",
                                                       "target_kind",  "vel_cp",
                                                       "apo_cdis",     "ptp_velocity",
                                                       "tool",         "base",
                                                       "path",         "path_orientation"};
  return names[static_cast<int>(q)];
}

bool krl_quantity_is_summarised(KrlQuantity q) {
  switch (q) {
    case KrlQuantity::keyword:
    case KrlQuantity::target_kind:
    case KrlQuantity::vel_cp:
    case KrlQuantity::apo_cdis:
    case KrlQuantity::ptp_velocity:
    case KrlQuantity::tool:
    case KrlQuantity::base:
    case KrlQuantity::path:
    case KrlQuantity::path_orientation:
      return true;
    default:
      return false;
  }
}

const char* krl_quantity_unit(KrlQuantity q) {
  switch (q) {
    case KrlQuantity::position:
    case KrlQuantity::aux_position:
    case KrlQuantity::apo_cdis:
    case KrlQuantity::path:
      return "mm";
    case KrlQuantity::orientation:
    case KrlQuantity::path_orientation:
      return "deg";
    case KrlQuantity::vel_cp:
      return "m/s";
    case KrlQuantity::ptp_velocity:
      return "%";
    case KrlQuantity::status:
    case KrlQuantity::turn:
    case KrlQuantity::keyword:
    case KrlQuantity::target_kind:
    case KrlQuantity::tool:
    case KrlQuantity::base:
      return "";
    default:
      return "axis";  // deg for rotary axes, mm for linear ones
  }
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Below this the orientation deviation is rounding noise of the rotation matrices (deg).
constexpr double kAngleNoiseDeg = 1e-9;

using krl::ident_char;
using krl::ident_start;
using krl::upper;

// A motion with its target made complete: fields a partial aggregate leaves out keep the value
// of the previous target of the same kind (KRL takes them from the current position).
struct Pose {
  const KrlMotionRecord* m = nullptr;
  size_t index = 0;  // in its program's motions
  std::string keyword;
  bool cartesian = false;  // X/Y/Z target
  bool axis = false;       // A1..A6 target
  std::array<double, 3> xyz{kNaN, kNaN, kNaN};
  std::array<double, 3> abc{kNaN, kNaN, kNaN};
  std::array<double, 12> axes;  // A1..A6 (axis targets only), E1..E6
  std::optional<int> status, turn;
  bool has_aux = false;
  std::array<double, 3> aux{kNaN, kNaN, kNaN};
  Pose() { axes.fill(kNaN); }
};

const char* const kCart[6] = {"X", "Y", "Z", "A", "B", "C"};
const char* const kAxes[12] = {"A1", "A2", "A3", "A4", "A5", "A6",
                               "E1", "E2", "E3", "E4", "E5", "E6"};

std::vector<Pose> complete_poses(const KrlProgram& p) {
  std::vector<Pose> out;
  out.reserve(p.motions.size());
  std::array<double, 6> cart;
  cart.fill(kNaN);
  std::array<double, 12> ax;
  ax.fill(kNaN);
  for (const KrlMotionRecord& m : p.motions) {
    Pose pose;
    pose.m = &m;
    pose.index = out.size();
    pose.keyword = upper(m.keyword);
    const auto& v = m.target.values;
    pose.cartesian = m.target.has("X") || m.target.has("Y") || m.target.has("Z") ||
                     m.target.has("A") || m.target.has("B") || m.target.has("C");
    pose.axis =
        !pose.cartesian && (m.target.has("A1") || m.target.has("A2") || m.target.has("A3") ||
                            m.target.has("A4") || m.target.has("A5") || m.target.has("A6"));
    if (m.relative) {
      // A relative motion is compared as written: its increments.
      for (int i = 0; i < 6; ++i) {
        auto it = v.find(kCart[i]);
        (i < 3 ? pose.xyz[i] : pose.abc[i - 3]) = it == v.end() ? 0.0 : it->second;
      }
      for (int i = 0; i < 12; ++i) {
        auto it = v.find(kAxes[i]);
        if (it != v.end())
          pose.axes[i] = it->second;
      }
    } else {
      if (pose.cartesian) {
        for (int i = 0; i < 6; ++i) {
          auto it = v.find(kCart[i]);
          if (it != v.end())
            cart[i] = it->second;
        }
        for (int i = 0; i < 3; ++i) {
          pose.xyz[i] = cart[i];
          pose.abc[i] = cart[i + 3];
        }
      }
      for (int i = 0; i < 12; ++i) {
        if (i < 6 && !pose.axis)
          continue;
        auto it = v.find(kAxes[i]);
        if (it != v.end())
          ax[i] = it->second;
        pose.axes[i] = ax[i];
      }
    }
    pose.status = m.target.status;
    pose.turn = m.target.turn;
    if (m.aux) {
      pose.has_aux = true;
      for (int i = 0; i < 3; ++i) {
        auto it = m.aux->values.find(kCart[i]);
        pose.aux[i] = it == m.aux->values.end() ? kNaN : it->second;
      }
    }
    out.push_back(std::move(pose));
  }
  return out;
}

// ---- alignment keys --------------------------------------------------------------------------

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  return h * 0xff51afd7ed558ccdULL;
}

uint64_t rounded(double v, double grid) {
  if (!std::isfinite(v))
    return 0x7ff8000000000001ULL;
  return static_cast<uint64_t>(std::llround(v / grid));
}

// Kind of target and position rounded to 0.1 mm (axis targets: axes rounded to 0.1), and with
// `with_cl` the CL line. The key only decides which motions are paired; every pair is then
// compared in full, and motions whose keys differ inside a run of mismatches are paired again.
uint64_t motion_key(const Pose& p, bool with_cl) {
  // The kind of target, not the keyword: a template that writes SLIN for LIN must pair each
  // motion with its partner (the keyword is then one summarised difference).
  uint64_t h = p.cartesian ? 1 : p.axis ? 2 : 3;
  if (with_cl)
    h = mix(h, static_cast<uint64_t>(p.m->cl_line));
  if (p.cartesian) {
    for (double c : p.xyz)
      h = mix(h, rounded(c, 0.1));
  } else {
    for (int i = 0; i < 6; ++i)
      h = mix(h, rounded(p.axes[i], 0.1));
  }
  return h;
}

// ---- comparison ------------------------------------------------------------------------------

double dist3(const std::array<double, 3>& p, const std::array<double, 3>& q) {
  return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                   (p[2] - q[2]) * (p[2] - q[2]));
}

bool finite3(const std::array<double, 3>& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

double orientation_deviation_deg(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  if (a == b)
    return 0.0;
  const Eigen::Matrix3d Ra = rotation_from_abc({a[0], a[1], a[2]});
  const Eigen::Matrix3d Rb = rotation_from_abc({b[0], b[1], b[2]});
  const Eigen::Matrix3d R = Ra.transpose() * Rb;
  const double angle = Eigen::AngleAxisd(R).angle() * 180.0 / kPi;
  return std::abs(angle) < kAngleNoiseDeg ? 0.0 : std::abs(angle);
}

std::string bits(int v) {
  std::string s;
  for (int b = 5; b >= 0; --b)
    s += ((v >> b) & 1) ? '1' : '0';
  return "'B" + s + "'";
}

// Text of a setting for a summary: its value, or "not set".
std::string setting_text(double v, const char* unit) {
  return v < 0.0 ? std::string("not set") : fmt::format("{:g} {}", v, unit);
}

class Comparer {
 public:
  // on_path_a/b: per motion, whether its point lies on the other program's path (as_curves).
  Comparer(const KrlDiffOptions& o, KrlDiffResult& r, const std::vector<char>& on_path_a,
           const std::vector<char>& on_path_b)
      : opt_(o), r_(r), on_path_a_(on_path_a), on_path_b_(on_path_b) {}

  void pair(const Pose& a, const Pose& b) {
    ++r_.compared;
    std::vector<KrlDeviation> over;
    auto measure = [&](KrlQuantity q, double value, double tol, std::string detail = {}) {
      KrlQuantityStats& s = r_.statistics[static_cast<size_t>(q)];
      ++s.compared;
      s.sum += value;
      s.max = std::max(s.max, value);
      if (value > tol) {
        ++s.over_tolerance;
        over.push_back({q, value, std::move(detail)});
      }
    };
    measure(KrlQuantity::keyword, a.keyword == b.keyword ? 0.0 : 1.0, 0.0,
            a.keyword == b.keyword ? "" : "A " + a.keyword + ", B " + b.keyword);
    if (a.cartesian != b.cartesian || a.axis != b.axis) {
      auto kind = [](const Pose& p) {
        return p.cartesian ? "Cartesian" : p.axis ? "axis" : "other";
      };
      measure(KrlQuantity::target_kind, 1.0, 0.0, std::string("A ") + kind(a) + ", B " + kind(b));
    }
    // As curves, the Cartesian geometry is the path comparison's (compare_paths).
    const bool geometry = !(opt_.as_curves && a.cartesian && b.cartesian);
    if (a.cartesian && b.cartesian && geometry) {
      if (finite3(a.xyz) && finite3(b.xyz))
        measure(KrlQuantity::position, dist3(a.xyz, b.xyz), opt_.pos_tol_mm);
      if (finite3(a.abc) && finite3(b.abc))
        measure(KrlQuantity::orientation, orientation_deviation_deg(a.abc, b.abc),
                opt_.ang_tol_deg);
    }
    if (geometry && a.has_aux && b.has_aux && finite3(a.aux) && finite3(b.aux))
      measure(KrlQuantity::aux_position, dist3(a.aux, b.aux), opt_.pos_tol_mm);
    measure_settings(*a.m, *b.m, measure);
    for (int i = 0; i < 12; ++i) {
      const double va = a.axes[static_cast<size_t>(i)], vb = b.axes[static_cast<size_t>(i)];
      if (std::isfinite(va) && std::isfinite(vb))
        measure(static_cast<KrlQuantity>(static_cast<int>(KrlQuantity::A1) + i), std::abs(va - vb),
                opt_.axis_tol);
    }
    if (a.status && b.status)
      measure(KrlQuantity::status, *a.status == *b.status ? 0.0 : 1.0, 0.0,
              *a.status == *b.status ? "" : "A " + bits(*a.status) + ", B " + bits(*b.status));
    if (a.turn && b.turn)
      measure(KrlQuantity::turn, *a.turn == *b.turn ? 0.0 : 1.0, 0.0,
              *a.turn == *b.turn ? "" : "A " + bits(*a.turn) + ", B " + bits(*b.turn));
    if (over.empty()) {
      last_ = KrlDifference::Kind::changed;
      run_open_ = false;
      return;
    }
    ++r_.changed;
    // Summarised quantities (a keyword, a setting) are said once for the program; the pair is
    // listed only for what else differs.
    bool per_motion = false;
    for (const KrlDeviation& d : over) {
      if (krl_quantity_is_summarised(d.quantity))
        summarise(d, a, b);
      else
        per_motion = true;
    }
    if (!per_motion) {
      last_ = KrlDifference::Kind::changed;
      run_open_ = false;
      return;
    }
    KrlDifference d;
    d.kind = KrlDifference::Kind::changed;
    d.file_a = a.m->file;
    d.line_a = d.last_line_a = a.m->line;
    d.file_b = b.m->file;
    d.line_b = d.last_line_b = b.m->line;
    d.keyword_a = a.keyword;
    d.keyword_b = b.keyword;
    d.deviations = std::move(over);
    add(std::move(d));
    run_open_ = false;
  }

  void only(const Pose& p, bool in_b) {
    // As curves, a point on the other program's path is the same path with other points.
    if (opt_.as_curves && p.cartesian && (in_b ? on_path_b_ : on_path_a_)[p.index])
      return;
    const auto kind = in_b ? KrlDifference::Kind::inserted : KrlDifference::Kind::removed;
    (in_b ? r_.inserted : r_.removed) += 1;
    if (run_open_ && last_ == kind) {
      if (run_shown_) {
        KrlDifference& d = r_.differences.back();
        ++d.count;
        (in_b ? d.last_line_b : d.last_line_a) = p.m->line;
      }
      return;
    }
    KrlDifference d;
    d.kind = kind;
    if (in_b) {
      d.file_b = p.m->file;
      d.line_b = d.last_line_b = p.m->line;
      d.keyword_b = p.keyword;
    } else {
      d.file_a = p.m->file;
      d.line_a = d.last_line_a = p.m->line;
      d.keyword_a = p.keyword;
    }
    run_shown_ = add(std::move(d));
    run_open_ = true;
    last_ = kind;
  }

  // A summarised difference found outside the pairs (the path comparison).
  void summarise(const KrlDeviation& d, const Pose* a, const Pose* b) {
    auto it = std::find_if(r_.summaries.begin(), r_.summaries.end(),
                           [&](const KrlSummaryDifference& s) { return s.quantity == d.quantity; });
    if (it == r_.summaries.end()) {
      ++r_.difference_count;
      KrlSummaryDifference s;
      s.quantity = d.quantity;
      if (a) {
        s.file_a = a->m->file;
        s.line_a = a->m->line;
      }
      if (b) {
        s.file_b = b->m->file;
        s.line_b = b->m->line;
      }
      s.detail = d.detail.empty() ? fmt::format("{:g} {}", d.value, krl_quantity_unit(d.quantity))
                                  : d.detail;
      r_.summaries.push_back(std::move(s));
      it = r_.summaries.end() - 1;
    }
    ++it->count;
  }

 private:
  void summarise(const KrlDeviation& d, const Pose& a, const Pose& b) { summarise(d, &a, &b); }

  // The settings in force at each motion: $VEL.CP, $APO.CDIS, the PTP velocity, $TOOL, $BASE.
  template <class Measure>
  void measure_settings(const KrlMotionRecord& a, const KrlMotionRecord& b, Measure& measure) {
    // The detail text is made only for a value over its tolerance (this runs at every pair).
    const auto m = [&](KrlQuantity q, double value, double tol, auto&& detail) {
      measure(q, value, tol, value > tol ? detail() : std::string());
    };
    m(KrlQuantity::vel_cp, std::abs(a.vel_cp_m_per_s - b.vel_cp_m_per_s), opt_.vel_tol_m_per_s,
      [&] { return fmt::format("A {:g} m/s, B {:g} m/s", a.vel_cp_m_per_s, b.vel_cp_m_per_s); });
    const bool apo_set = (a.apo_cdis_mm < 0.0) == (b.apo_cdis_mm < 0.0);
    m(KrlQuantity::apo_cdis, apo_set ? std::abs(a.apo_cdis_mm - b.apo_cdis_mm) : 1.0,
      apo_set ? opt_.pos_tol_mm : 0.0, [&] {
        return "A " + setting_text(a.apo_cdis_mm, "mm") + ", B " +
               setting_text(b.apo_cdis_mm, "mm");
      });
    const bool ptp_set = (a.ptp_velocity_percent < 0.0) == (b.ptp_velocity_percent < 0.0);
    m(KrlQuantity::ptp_velocity,
      ptp_set ? std::abs(a.ptp_velocity_percent - b.ptp_velocity_percent) : 1.0, 0.0, [&] {
        return "A " + setting_text(a.ptp_velocity_percent, "%") + ", B " +
               setting_text(b.ptp_velocity_percent, "%");
      });
    const auto shown = [](const std::string& t) { return t.empty() ? std::string("not set") : t; };
    m(KrlQuantity::tool, same_setting(a.tool, b.tool) ? 0.0 : 1.0, 0.0,
      [&] { return "A " + shown(a.tool) + ", B " + shown(b.tool); });
    m(KrlQuantity::base, same_setting(a.base, b.base) ? 0.0 : 1.0, 0.0,
      [&] { return "A " + shown(a.base) + ", B " + shown(b.base); });
  }

  // $TOOL and $BASE right-hand sides, compared without blanks and case.
  static bool same_setting(const std::string& x, const std::string& y) {
    if (x == y)
      return true;
    std::string u, v;
    for (char c : x)
      if (!std::isspace(static_cast<unsigned char>(c)))
        u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (char c : y)
      if (!std::isspace(static_cast<unsigned char>(c)))
        v += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return u == v;
  }

  bool add(KrlDifference d) {
    ++r_.difference_count;
    if (r_.differences.size() >= opt_.max_shown)
      return false;
    r_.differences.push_back(std::move(d));
    return true;
  }

  const KrlDiffOptions& opt_;
  KrlDiffResult& r_;
  const std::vector<char>& on_path_a_;
  const std::vector<char>& on_path_b_;
  KrlDifference::Kind last_ = KrlDifference::Kind::changed;
  bool run_open_ = false, run_shown_ = false;
};

double pose_distance(const Pose& a, const Pose& b) {
  if (a.cartesian && b.cartesian && finite3(a.xyz) && finite3(b.xyz))
    return dist3(a.xyz, b.xyz);
  double s = 0.0;
  for (int i = 0; i < 12; ++i) {
    const double d = a.axes[static_cast<size_t>(i)] - b.axes[static_cast<size_t>(i)];
    if (std::isfinite(d))
      s += d * d;
  }
  return std::sqrt(s) + (a.cartesian == b.cartesian ? 0.0 : 1e6);
}

// A run of unmatched motions (dels from A, ins into B) between two matches: motions are paired
// again (by CL line when aligning by CL lines, else in order, at the offset that keeps the
// paired positions closest); the rest are removals or insertions.
void flush_hunk(const std::vector<Pose>& pa, const std::vector<Pose>& pb,
                const std::vector<uint32_t>& dels, const std::vector<uint32_t>& ins, bool by_cl,
                Comparer& cmp) {
  if (by_cl) {
    size_t i = 0, j = 0;
    while (i < dels.size() || j < ins.size()) {
      if (j == ins.size()) {
        cmp.only(pa[dels[i++]], false);
      } else if (i == dels.size()) {
        cmp.only(pb[ins[j++]], true);
      } else {
        const int ca = pa[dels[i]].m->cl_line, cb = pb[ins[j]].m->cl_line;
        if (ca == cb) {
          // Same CL line: pair in order, the surplus of either side is inserted/removed.
          size_t ie = i, je = j;
          while (ie < dels.size() && pa[dels[ie]].m->cl_line == ca)
            ++ie;
          while (je < ins.size() && pb[ins[je]].m->cl_line == cb)
            ++je;
          std::vector<uint32_t> da(dels.begin() + static_cast<long>(i),
                                   dels.begin() + static_cast<long>(ie));
          std::vector<uint32_t> ib(ins.begin() + static_cast<long>(j),
                                   ins.begin() + static_cast<long>(je));
          flush_hunk(pa, pb, da, ib, false, cmp);
          i = ie;
          j = je;
        } else if (ca < cb) {
          cmp.only(pa[dels[i++]], false);
        } else {
          cmp.only(pb[ins[j++]], true);
        }
      }
    }
    return;
  }
  const size_t na = dels.size(), nb = ins.size(), k = std::min(na, nb);
  size_t best = 0;
  const size_t spread = std::max(na, nb) - k;
  if (k > 0 && spread > 0 && static_cast<double>(spread) * static_cast<double>(k) < 1e7) {
    double best_cost = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s <= spread; ++s) {
      double cost = 0.0;
      for (size_t t = 0; t < k; ++t)
        cost += na < nb ? pose_distance(pa[dels[t]], pb[ins[t + s]])
                        : pose_distance(pa[dels[t + s]], pb[ins[t]]);
      if (cost < best_cost) {
        best_cost = cost;
        best = s;
      }
    }
  }
  const bool b_longer = nb > na;
  for (size_t t = 0; t < best; ++t) {
    if (b_longer)
      cmp.only(pb[ins[t]], true);
    else
      cmp.only(pa[dels[t]], false);
  }
  for (size_t t = 0; t < k; ++t)
    cmp.pair(pa[dels[b_longer ? t : t + best]], pb[ins[b_longer ? t + best : t]]);
  for (size_t t = best + k; t < std::max(na, nb); ++t) {
    if (b_longer)
      cmp.only(pb[ins[t]], true);
    else
      cmp.only(pa[dels[t]], false);
  }
}

// The Cartesian points of a program as a polyline; a motion to an axis target (or a relative
// one) between two Cartesian motions breaks it.
std::vector<krl::PathPoint> path_of(const std::vector<Pose>& poses) {
  std::vector<krl::PathPoint> out;
  bool broken = true;
  for (const Pose& p : poses) {
    if (!p.cartesian || p.m->relative || !finite3(p.xyz)) {
      broken = true;
      continue;
    }
    out.push_back({p.xyz, p.abc, broken});
    broken = false;
  }
  return out;
}

// Every Cartesian point of `from` against the path of `to`: the path quantities' statistics,
// the largest distance, and per motion whether its point lies on the other path.
void compare_path(const std::vector<Pose>& from, const krl::PathIndex& to, const KrlDiffOptions& o,
                  KrlDiffResult& r, std::vector<char>& on_path, Comparer& cmp) {
  on_path.assign(from.size(), 0);
  if (to.empty())
    return;
  KrlQuantityStats& sp = r.statistics[static_cast<size_t>(KrlQuantity::path)];
  KrlQuantityStats& so = r.statistics[static_cast<size_t>(KrlQuantity::path_orientation)];
  for (const Pose& p : from) {
    if (!p.cartesian || p.m->relative || !finite3(p.xyz))
      continue;
    const krl::PathIndex::Nearest n = to.nearest({p.xyz, p.abc, false});
    ++sp.compared;
    sp.sum += n.distance_mm;
    if (n.distance_mm > r.path_distance_mm || (!n.exact && r.path_exact)) {
      r.path_distance_mm = std::max(r.path_distance_mm, n.distance_mm);
      r.path_exact = r.path_exact && n.exact;
      r.path_file = p.m->file;
      r.path_line = p.m->line;
    }
    sp.max = std::max(sp.max, n.distance_mm);
    on_path[p.index] = n.distance_mm <= o.path_tol_mm;
    if (n.distance_mm > o.path_tol_mm) {
      ++sp.over_tolerance;
      if (o.as_curves) {
        cmp.summarise({KrlQuantity::path, n.distance_mm,
                       fmt::format("{}{:.6g} mm from the other path", n.exact ? "" : "more than ",
                                   n.distance_mm)},
                      &p, nullptr);
      }
    }
    if (std::isfinite(n.orientation_deg)) {
      ++so.compared;
      so.sum += n.orientation_deg;
      so.max = std::max(so.max, n.orientation_deg);
      if (n.orientation_deg > o.ang_tol_deg) {
        ++so.over_tolerance;
        if (o.as_curves) {
          cmp.summarise({KrlQuantity::path_orientation, n.orientation_deg,
                         fmt::format("{:.6g} deg from the other path's orientation there",
                                     n.orientation_deg)},
                        &p, nullptr);
        }
      }
    }
  }
}

bool has_cl_lines(const KrlProgram& p) {
  return std::any_of(p.motions.begin(), p.motions.end(),
                     [](const KrlMotionRecord& m) { return m.cl_line > 0; });
}

}  // namespace

KrlDiffResult diff_krl_programs(const KrlProgram& a, const KrlProgram& b,
                                const KrlDiffOptions& options) {
  KrlDiffResult r;
  const std::vector<Pose> pa = complete_poses(a), pb = complete_poses(b);
  r.motions_a = pa.size();
  r.motions_b = pb.size();
  const bool by_cl = has_cl_lines(a) && has_cl_lines(b);
  r.aligned_by_cl_line = by_cl;
  std::vector<uint64_t> ka(pa.size()), kb(pb.size());
  for (size_t i = 0; i < pa.size(); ++i)
    ka[i] = motion_key(pa[i], by_cl);
  for (size_t j = 0; j < pb.size(); ++j)
    kb[j] = motion_key(pb[j], by_cl);
  std::vector<krl::Step> steps = krl::align_keys(ka, kb);
  ka = {};
  kb = {};

  // The paths as curves, both ways: A's points against B's polyline, then B's against A's.
  // The cell is the typical segment's length (at least 1 mm), so that a query looks at a few
  // cells.
  std::vector<char> on_path_a, on_path_b;
  Comparer cmp(options, r, on_path_a, on_path_b);
  {
    std::vector<krl::PathPoint> path_a = path_of(pa), path_b = path_of(pb);
    const auto cell = [](const std::vector<krl::PathPoint>& path) {
      std::vector<double> lengths;
      for (size_t i = 1; i < path.size(); ++i)
        if (!path[i].starts_piece)
          lengths.push_back(dist3(path[i - 1].xyz, path[i].xyz));
      if (lengths.empty())
        return 1.0;
      std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2),
                       lengths.end());
      return std::max(1.0, lengths[lengths.size() / 2]);
    };
    const double h = std::max(cell(path_a), cell(path_b));
    const krl::PathIndex index_a(std::move(path_a), h), index_b(std::move(path_b), h);
    compare_path(pa, index_b, options, r, on_path_a, cmp);
    compare_path(pb, index_a, options, r, on_path_b, cmp);
  }
  std::vector<uint32_t> dels, ins;
  for (const krl::Step& s : steps) {
    if (s.op == krl::Op::match) {
      if (!dels.empty() || !ins.empty()) {
        flush_hunk(pa, pb, dels, ins, by_cl, cmp);
        dels.clear();
        ins.clear();
      }
      cmp.pair(pa[s.i], pb[s.j]);
    } else if (s.op == krl::Op::del) {
      dels.push_back(s.i);
    } else {
      ins.push_back(s.j);
    }
  }
  if (!dels.empty() || !ins.empty())
    flush_hunk(pa, pb, dels, ins, by_cl, cmp);
  r.equal = r.difference_count == 0;
  return r;
}

}  // namespace redpost
