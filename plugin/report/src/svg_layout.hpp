// Where things go in an SVG plot, shared by every plot kind (svg_*.cpp): text widths, data
// ranges, scales from data to pixels, axis ticks and the plot-area frame. Nothing here writes
// SVG; svg_draw.hpp does.
//
// Layout is computed, not measured: text widths are estimated from the character count (0.6 em
// per character, a little wider than DejaVu Sans and Arial on average), margins are sized to
// the widest tick label, and x ticks are thinned until their labels do not touch.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "redpost/report/svg_plot.hpp"

namespace redpost::report::svg {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFont = 12.0;

// --- text ------------------------------------------------------------------------------------

// The estimated width in px of s in the given font size.
double text_width(std::string_view s, double font = kFont);

// "label [unit]", "label" or "[unit]".
std::string axis_title(const Axis& a);

// --- scales and ticks ------------------------------------------------------------------------

// Data value to pixel. Far-off values are clamped so that coordinates stay printable; the clip
// path hides everything outside the plot area anyway.
struct Scale {
  double d0 = 0.0, d1 = 1.0;  // data range
  double p0 = 0.0, p1 = 1.0;  // pixel range (p1 < p0 for y)
  bool log = false;
  double operator()(double v) const {
    double t;
    if (log) {
      t = (std::log10(v) - std::log10(d0)) / (std::log10(d1) - std::log10(d0));
    } else {
      t = (v - d0) / (d1 - d0);
    }
    return std::clamp(p0 + t * (p1 - p0), -1e6, 1e6);
  }
  bool usable(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
};

struct Range {
  double lo = kNaN, hi = kNaN;
  void add(double v, bool log) {
    if (!std::isfinite(v) || (log && v <= 0.0)) {
      return;
    }
    if (!(lo <= v))
      lo = v;
    if (!(hi >= v))
      hi = v;
  }
  bool empty() const { return std::isnan(lo); }
};

struct Ticks {
  double lo = 0.0, hi = 1.0;
  std::vector<double> major;
  std::vector<std::string> labels;
  std::vector<double> minor;
  double max_label_width() const {
    double w = 0.0;
    for (const auto& l : labels)
      w = std::max(w, text_width(l));
    return w;
  }
};

// Ticks for one axis. intervals is the wanted number of tick intervals; a fixed Axis::min or
// ::max replaces the data end and the ticks then stay inside the fixed range.
Ticks make_ticks(const Axis& ax, Range data, int intervals, bool expand);

// Horizontal-axis ticks about 90 px apart whose labels do not touch: fewer intervals until
// they fit; then, on a fixed range (no expansion) that caught fewer than three ticks, more
// intervals while they still fit.
Ticks make_x_ticks(const Axis& ax, const Range& data, double length_px, bool expand);

// Vertical-axis ticks about 45 px apart, at least three where the height allows.
Ticks make_y_ticks(const Axis& ax, const Range& data, double length_px, bool expand);

// --- frame -----------------------------------------------------------------------------------

// The plot area in pixels: x0 left, x1 right, y0 top, y1 bottom.
struct Frame {
  double W = 0.0, H = 0.0;
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
};

// x ticks for the plot area, whose right end moves left until the last tick label fits in the
// picture (a long label such as "1000000" under the right edge would be cut off).
Ticks fit_x_ticks(const Axis& ax, const Range& data, Frame& f, bool expand);

}  // namespace redpost::report::svg
