// Text widths, scales, ticks and the frame of the SVG plots (see svg_layout.hpp).
#include "svg_layout.hpp"

#include <utility>

#include "redpost/report/plot_scale.hpp"

namespace redpost::report::svg {

double text_width(std::string_view s, double font) {
  std::size_t chars = 0;
  for (unsigned char c : s) {
    chars += (c & 0xC0) != 0x80;  // count UTF-8 code points, not bytes
  }
  return 0.6 * font * static_cast<double>(chars);
}

std::string axis_title(const Axis& a) {
  if (a.unit.empty()) {
    return a.label;
  }
  return a.label.empty() ? "[" + a.unit + "]" : a.label + " [" + a.unit + "]";
}

Ticks make_ticks(const Axis& ax, Range data, int intervals, bool expand) {
  const bool fixed_lo = std::isfinite(ax.min) && (!ax.log || ax.min > 0.0);
  const bool fixed_hi = std::isfinite(ax.max) && (!ax.log || ax.max > 0.0);
  if (fixed_lo)
    data.lo = ax.min;
  if (fixed_hi)
    data.hi = ax.max;
  if (data.empty()) {
    data.lo = ax.log ? 1.0 : 0.0;
    data.hi = ax.log ? 10.0 : 1.0;
  }
  Ticks t;
  if (ax.log) {
    LogTicks lt = nice_log_ticks(data.lo, data.hi, intervals);
    t.lo = fixed_lo ? data.lo : lt.lo;
    t.hi = fixed_hi ? data.hi : lt.hi;
    for (double v : lt.ticks) {
      if (v >= t.lo * (1 - 1e-12) && v <= t.hi * (1 + 1e-12)) {
        t.major.push_back(v);
        t.labels.push_back(format_log_tick(v));
      }
    }
    for (double v : lt.minor) {
      if (v >= t.lo && v <= t.hi)
        t.minor.push_back(v);
    }
    return t;
  }
  LinearTicks lt = nice_linear_ticks(data.lo, data.hi, intervals, expand && !fixed_lo && !fixed_hi);
  if (fixed_lo || fixed_hi) {
    // Expand only the free end, then place the ticks inside the final range.
    LinearTicks e = nice_linear_ticks(data.lo, data.hi, intervals, expand);
    const double lo = fixed_lo ? data.lo : e.lo;
    const double hi = fixed_hi ? data.hi : e.hi;
    lt = nice_linear_ticks(lo, hi, intervals, false);
    lt.lo = lo;
    lt.hi = hi;
  }
  t.lo = lt.lo;
  t.hi = lt.hi;
  t.major = lt.ticks;
  for (double v : t.major)
    t.labels.push_back(format_tick(v, lt.step));
  return t;
}

Ticks make_x_ticks(const Axis& ax, const Range& data, double length_px, bool expand) {
  auto fits = [&](const Ticks& t) {
    const double spacing = t.major.size() > 1 ? length_px / (t.major.size() - 1) : length_px;
    // On a fixed range the outer ticks need not sit on the ends: measure between ticks.
    double gap = spacing;
    if (t.major.size() > 1 && t.hi > t.lo && !ax.log) {
      gap = length_px * (t.major[1] - t.major[0]) / (t.hi - t.lo);
    }
    return t.max_label_width() + 12.0 <= std::min(spacing, gap);
  };
  int n = std::max(2, static_cast<int>(length_px / 90.0));
  Ticks t = make_ticks(ax, data, n, expand);
  while (n > 1 && !fits(t)) {
    t = make_ticks(ax, data, --n, expand);
  }
  for (int m = n + 1; t.major.size() < 3 && m <= std::max(2, static_cast<int>(length_px / 30.0));
       ++m) {
    Ticks more = make_ticks(ax, data, m, expand);
    if (!fits(more))
      break;
    t = std::move(more);
  }
  return t;
}

Ticks make_y_ticks(const Axis& ax, const Range& data, double length_px, bool expand) {
  int n = std::max(2, static_cast<int>(length_px / 45.0));
  Ticks t = make_ticks(ax, data, n, expand);
  if (ax.log && t.major.size() > 2 && length_px / (t.major.size() - 1) < 16.0) {
    t = make_ticks(ax, data, std::max(1, n / 2), expand);
  }
  for (int m = n + 1; t.major.size() < 3 && m <= static_cast<int>(length_px / 18.0); ++m) {
    t = make_ticks(ax, data, m, expand);
  }
  return t;
}

Ticks fit_x_ticks(const Axis& ax, const Range& data, Frame& f, bool expand) {
  Ticks t = make_x_ticks(ax, data, f.x1 - f.x0, expand);
  if (t.major.empty() || !(t.hi > t.lo))
    return t;
  const Scale sx{t.lo, t.hi, f.x0, f.x1, ax.log};
  const double over = sx(t.major.back()) + text_width(t.labels.back()) / 2.0 + 4.0 - f.W;
  if (over > 0.0) {
    f.x1 -= over;
    t = make_x_ticks(ax, data, f.x1 - f.x0, expand);
  }
  return t;
}

}  // namespace redpost::report::svg
