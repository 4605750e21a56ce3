// Aligned motions compared, one pair or one motion at a time (krl/diff_compare.hpp).
#include "krl/diff_compare.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost::krl {

namespace {

// Below this the orientation deviation is rounding noise of the rotation matrices (deg).
constexpr double kAngleNoiseDeg = 1e-9;

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

// $TOOL and $BASE right-hand sides, compared without blanks and case.
bool same_setting(const std::string* x, const std::string* y) {
  if (x == y || *x == *y)
    return true;
  std::string u, v;
  for (char c : *x)
    if (!std::isspace(static_cast<unsigned char>(c)))
      u += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (char c : *y)
    if (!std::isspace(static_cast<unsigned char>(c)))
      v += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u == v;
}

double pose_distance(const DiffPose& a, const DiffPose& b) {
  if (a.cartesian && b.cartesian && finite3(a.xyz) && finite3(b.xyz))
    return dist3(a.xyz, b.xyz);
  double s = 0.0;
  for (size_t i = 0; i < 12; ++i) {
    const double d = a.axes[i] - b.axes[i];
    if (std::isfinite(d))
      s += d * d;
  }
  return std::sqrt(s) + (a.cartesian == b.cartesian ? 0.0 : 1e6);
}

}  // namespace

void Comparer::pair(const DiffPose& a, const DiffPose& b) {
  measure_path(a, false);
  measure_path(b, true);
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
  const bool same_keyword = *a.keyword == *b.keyword;
  measure(KrlQuantity::keyword, same_keyword ? 0.0 : 1.0, 0.0,
          same_keyword ? "" : "A " + *a.keyword + ", B " + *b.keyword);
  if (a.cartesian != b.cartesian || a.axis != b.axis) {
    auto kind = [](const DiffPose& p) {
      return p.cartesian ? "Cartesian" : p.axis ? "axis" : "other";
    };
    measure(KrlQuantity::target_kind, 1.0, 0.0, std::string("A ") + kind(a) + ", B " + kind(b));
  }
  // As curves, the Cartesian geometry is the path comparison's (measure_path).
  const bool geometry = !(opt_.as_curves && a.cartesian && b.cartesian);
  if (a.cartesian && b.cartesian && geometry) {
    if (finite3(a.xyz) && finite3(b.xyz))
      measure(KrlQuantity::position, dist3(a.xyz, b.xyz), opt_.pos_tol_mm);
    if (finite3(a.abc) && finite3(b.abc))
      measure(KrlQuantity::orientation, orientation_deviation_deg(a.abc, b.abc), opt_.ang_tol_deg);
  }
  if (geometry && a.has_aux && b.has_aux && finite3(a.aux) && finite3(b.aux))
    measure(KrlQuantity::aux_position, dist3(a.aux, b.aux), opt_.pos_tol_mm);
  measure_settings(a, b, measure);
  for (size_t i = 0; i < 12; ++i) {
    const double va = a.axes[i], vb = b.axes[i];
    if (std::isfinite(va) && std::isfinite(vb))
      measure(static_cast<KrlQuantity>(static_cast<int>(KrlQuantity::A1) + static_cast<int>(i)),
              std::abs(va - vb), opt_.axis_tol);
  }
  if (a.status != kNoInt && b.status != kNoInt)
    measure(KrlQuantity::status, a.status == b.status ? 0.0 : 1.0, 0.0,
            a.status == b.status ? "" : "A " + bits(a.status) + ", B " + bits(b.status));
  if (a.turn != kNoInt && b.turn != kNoInt)
    measure(KrlQuantity::turn, a.turn == b.turn ? 0.0 : 1.0, 0.0,
            a.turn == b.turn ? "" : "A " + bits(a.turn) + ", B " + bits(b.turn));
  run_open_ = false;
  last_ = KrlDifference::Kind::changed;
  if (over.empty())
    return;
  ++r_.changed;
  // Summarised quantities (a keyword, a setting) are said once for the program; the pair is
  // listed only for what else differs.
  bool per_motion = false;
  for (const KrlDeviation& d : over) {
    if (krl_quantity_is_summarised(d.quantity))
      summarise(d, &a, &b);
    else
      per_motion = true;
  }
  if (!per_motion)
    return;
  KrlDifference d;
  d.kind = KrlDifference::Kind::changed;
  d.file_a = *a.file;
  d.line_a = d.last_line_a = a.line;
  d.file_b = *b.file;
  d.line_b = d.last_line_b = b.line;
  d.keyword_a = *a.keyword;
  d.keyword_b = *b.keyword;
  d.deviations = std::move(over);
  add(std::move(d));
}

void Comparer::only(const DiffPose& p, bool in_b) {
  const bool on_path = measure_path(p, in_b);
  // As curves, a point on the other program's path is the same path with other points.
  if (opt_.as_curves && p.cartesian && on_path)
    return;
  const auto kind = in_b ? KrlDifference::Kind::inserted : KrlDifference::Kind::removed;
  (in_b ? r_.inserted : r_.removed) += 1;
  if (run_open_ && last_ == kind) {
    if (run_shown_) {
      KrlDifference& d = r_.differences.back();
      ++d.count;
      (in_b ? d.last_line_b : d.last_line_a) = p.line;
    }
    return;
  }
  KrlDifference d;
  d.kind = kind;
  if (in_b) {
    d.file_b = *p.file;
    d.line_b = d.last_line_b = p.line;
    d.keyword_b = *p.keyword;
  } else {
    d.file_a = *p.file;
    d.line_a = d.last_line_a = p.line;
    d.keyword_a = *p.keyword;
  }
  run_shown_ = add(std::move(d));
  run_open_ = true;
  last_ = kind;
}

bool Comparer::measure_path(const DiffPose& p, bool in_b) {
  const PathWindow& to = *paths_[in_b ? 0 : 1];
  if (!p.on_cartesian_path() || to.empty())
    return false;
  // A segment within a tenth of the tolerance ends the search (PathWindow::nearest): the
  // distance is then at most that, which the tolerance does not tell from the least.
  const PathWindow::Nearest n = to.nearest({p.xyz, p.abc, false, p.seq}, 0.1 * opt_.path_tol_mm);
  KrlQuantityStats& sp = r_.statistics[static_cast<size_t>(KrlQuantity::path)];
  KrlQuantityStats& so = r_.statistics[static_cast<size_t>(KrlQuantity::path_orientation)];
  ++sp.compared;
  sp.sum += n.distance_mm;
  r_.path_capped += n.capped ? 1 : 0;
  r_.path_examined += n.examined;
  if (n.distance_mm > r_.path_distance_mm || (!n.exact && r_.path_exact)) {
    r_.path_distance_mm = std::max(r_.path_distance_mm, n.distance_mm);
    r_.path_exact = r_.path_exact && n.exact;
    r_.path_file = *p.file;
    r_.path_line = p.line;
  }
  sp.max = std::max(sp.max, n.distance_mm);
  const DiffPose* a = in_b ? nullptr : &p;
  const DiffPose* b = in_b ? &p : nullptr;
  if (n.distance_mm > opt_.path_tol_mm) {
    ++sp.over_tolerance;
    if (opt_.as_curves) {
      summarise({KrlQuantity::path, n.distance_mm,
                 fmt::format("{}{:.6g} mm from the other path",
                             !n.exact   ? "more than "
                             : n.capped ? "at most "
                                        : "",
                             n.distance_mm)},
                a, b);
    }
  }
  if (std::isfinite(n.orientation_deg)) {
    ++so.compared;
    so.sum += n.orientation_deg;
    so.max = std::max(so.max, n.orientation_deg);
    if (n.orientation_deg > opt_.ang_tol_deg) {
      ++so.over_tolerance;
      if (opt_.as_curves) {
        summarise(
            {KrlQuantity::path_orientation, n.orientation_deg,
             fmt::format("{:.6g} deg from the other path's orientation there", n.orientation_deg)},
            a, b);
      }
    }
  }
  return n.distance_mm <= opt_.path_tol_mm;
}

void Comparer::summarise(const KrlDeviation& d, const DiffPose* a, const DiffPose* b) {
  auto it = std::find_if(r_.summaries.begin(), r_.summaries.end(),
                         [&](const KrlSummaryDifference& s) { return s.quantity == d.quantity; });
  if (it == r_.summaries.end()) {
    ++r_.difference_count;
    KrlSummaryDifference s;
    s.quantity = d.quantity;
    if (a) {
      s.file_a = *a->file;
      s.line_a = a->line;
    }
    if (b) {
      s.file_b = *b->file;
      s.line_b = b->line;
    }
    s.detail = d.detail.empty() ? fmt::format("{:g} {}", d.value, krl_quantity_unit(d.quantity))
                                : d.detail;
    r_.summaries.push_back(std::move(s));
    it = r_.summaries.end() - 1;
  }
  ++it->count;
}

// The settings in force at each motion: $VEL.CP, $APO.CDIS, the PTP velocity, $TOOL, $BASE.
template <class Measure>
void Comparer::measure_settings(const DiffPose& a, const DiffPose& b, Measure& measure) {
  // The detail text is made only for a value over its tolerance (this runs at every pair).
  const auto m = [&](KrlQuantity q, double value, double tol, auto&& detail) {
    measure(q, value, tol, value > tol ? detail() : std::string());
  };
  m(KrlQuantity::vel_cp, std::abs(a.vel_cp_m_per_s - b.vel_cp_m_per_s), opt_.vel_tol_m_per_s,
    [&] { return fmt::format("A {:g} m/s, B {:g} m/s", a.vel_cp_m_per_s, b.vel_cp_m_per_s); });
  const bool apo_set = (a.apo_cdis_mm < 0.0) == (b.apo_cdis_mm < 0.0);
  m(KrlQuantity::apo_cdis, apo_set ? std::abs(a.apo_cdis_mm - b.apo_cdis_mm) : 1.0,
    apo_set ? opt_.pos_tol_mm : 0.0, [&] {
      return "A " + setting_text(a.apo_cdis_mm, "mm") + ", B " + setting_text(b.apo_cdis_mm, "mm");
    });
  const bool ptp_set = (a.ptp_velocity_percent < 0.0) == (b.ptp_velocity_percent < 0.0);
  m(KrlQuantity::ptp_velocity,
    ptp_set ? std::abs(a.ptp_velocity_percent - b.ptp_velocity_percent) : 1.0, 0.0, [&] {
      return "A " + setting_text(a.ptp_velocity_percent, "%") + ", B " +
             setting_text(b.ptp_velocity_percent, "%");
    });
  const auto shown = [](const std::string* t) { return t->empty() ? std::string("not set") : *t; };
  m(KrlQuantity::tool, same_setting(a.tool, b.tool) ? 0.0 : 1.0, 0.0,
    [&] { return "A " + shown(a.tool) + ", B " + shown(b.tool); });
  m(KrlQuantity::base, same_setting(a.base, b.base) ? 0.0 : 1.0, 0.0,
    [&] { return "A " + shown(a.base) + ", B " + shown(b.base); });
}

bool Comparer::add(KrlDifference d) {
  ++r_.difference_count;
  if (r_.differences.size() >= opt_.max_shown)
    return false;
  r_.differences.push_back(std::move(d));
  return true;
}

void flush_hunk(const std::vector<const DiffPose*>& dels, const std::vector<const DiffPose*>& ins,
                bool by_cl, Comparer& cmp) {
  if (by_cl) {
    size_t i = 0, j = 0;
    while (i < dels.size() || j < ins.size()) {
      if (j == ins.size()) {
        cmp.only(*dels[i++], false);
      } else if (i == dels.size()) {
        cmp.only(*ins[j++], true);
      } else {
        const int ca = dels[i]->cl_line, cb = ins[j]->cl_line;
        if (ca == cb) {
          // Same CL line: pair in order, the surplus of either side is inserted/removed.
          size_t ie = i, je = j;
          while (ie < dels.size() && dels[ie]->cl_line == ca)
            ++ie;
          while (je < ins.size() && ins[je]->cl_line == cb)
            ++je;
          const std::vector<const DiffPose*> da(dels.begin() + static_cast<long>(i),
                                                dels.begin() + static_cast<long>(ie));
          const std::vector<const DiffPose*> ib(ins.begin() + static_cast<long>(j),
                                                ins.begin() + static_cast<long>(je));
          flush_hunk(da, ib, false, cmp);
          i = ie;
          j = je;
        } else if (ca < cb) {
          cmp.only(*dels[i++], false);
        } else {
          cmp.only(*ins[j++], true);
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
        cost +=
            na < nb ? pose_distance(*dels[t], *ins[t + s]) : pose_distance(*dels[t + s], *ins[t]);
      if (cost < best_cost) {
        best_cost = cost;
        best = s;
      }
    }
  }
  const bool b_longer = nb > na;
  for (size_t t = 0; t < best; ++t) {
    if (b_longer)
      cmp.only(*ins[t], true);
    else
      cmp.only(*dels[t], false);
  }
  for (size_t t = 0; t < k; ++t)
    cmp.pair(*dels[b_longer ? t : t + best], *ins[b_longer ? t + best : t]);
  for (size_t t = best + k; t < std::max(na, nb); ++t) {
    if (b_longer)
      cmp.only(*ins[t], true);
    else
      cmp.only(*dels[t], false);
  }
}

}  // namespace redpost::krl
