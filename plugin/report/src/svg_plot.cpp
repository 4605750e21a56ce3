// SVG rendering of the report plots (see svg_plot.hpp).
//
// Layout is computed, not measured: text widths are estimated from the character count (0.6 em
// per character, a little wider than DejaVu Sans and Arial on average), margins are sized to
// the widest tick label, x ticks are thinned until their labels do not touch, and the legend
// wraps into rows above the plot area, where it can never hide data.
#include "redpost/report/svg_plot.hpp"

#include "escape.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "redpost/report/plot_scale.hpp"

namespace redpost::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFont = 12.0;
constexpr double kTitleFont = 15.0;
constexpr double kLegendRow = 18.0;
constexpr int kColourBins = 64;
constexpr std::size_t kMaxMarkers = 600;
constexpr const char* kFontFamily = "DejaVu Sans, Arial, Helvetica, sans-serif";

// --- text ------------------------------------------------------------------------------------

double text_width(std::string_view s, double font = kFont) {
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

struct Svg {
  std::string s;
  template <typename... A>
  void f(fmt::format_string<A...> format, A&&... args) {
    fmt::format_to(std::back_inserter(s), format, std::forward<A>(args)...);
  }
};

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

// Horizontal-axis ticks about 90 px apart whose labels do not touch: fewer intervals until
// they fit; then, on a fixed range (no expansion) that caught fewer than three ticks, more
// intervals while they still fit.
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

// Vertical-axis ticks about 45 px apart, at least three where the height allows.
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

// --- colours ---------------------------------------------------------------------------------

struct Rgb {
  double r, g, b;
};

// Anchors of a viridis-like map: perceptually ordered, dark to light, colour-blind safe.
constexpr Rgb kMap[] = {{68, 1, 84},    {72, 40, 120},  {62, 73, 137},
                        {49, 104, 142}, {38, 130, 142}, {31, 158, 137},
                        {53, 183, 121}, {110, 206, 88}, {253, 231, 37}};

int colour_bin(double v, double lo, double hi) {
  const double t = hi > lo ? (v - lo) / (hi - lo) : 0.5;
  return std::clamp(static_cast<int>(std::floor(t * kColourBins)), 0, kColourBins - 1);
}

std::string bin_colour(int bin) {
  return colour_map((bin + 0.5) / kColourBins);
}

std::string pick(const std::string& colour, std::size_t& next) {
  return colour.empty() ? std::string(palette_colour(next++)) : colour;
}

// --- frame -----------------------------------------------------------------------------------

// The plot area in pixels: x0 left, x1 right, y0 top, y1 bottom.
struct Frame {
  double W = 0.0, H = 0.0;
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
};

// x ticks for the plot area, whose right end moves left until the last tick label fits in the
// picture (a long label such as "1000000" under the right edge would be cut off).
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

enum class Swatch { line, dashed, dots, line_dots, patch, hatch };

struct LegendItem {
  std::string name;
  std::string colour;
  Swatch swatch = Swatch::line;
  double opacity = 1.0;
};

double legend_item_width(const LegendItem& it) {
  return 28.0 + text_width(it.name) + 16.0;
}

int legend_rows(const std::vector<LegendItem>& items, double max_width) {
  if (items.empty())
    return 0;
  int rows = 1;
  double x = 0.0;
  for (const auto& it : items) {
    const double w = legend_item_width(it);
    if (x > 0.0 && x + w > max_width) {
      ++rows;
      x = 0.0;
    }
    x += w;
  }
  return rows;
}

void draw_legend(Svg& s, const std::vector<LegendItem>& items, double left, double top,
                 double max_width, const std::string& id) {
  double x = 0.0, y = top + kLegendRow / 2.0;
  for (const auto& it : items) {
    const double w = legend_item_width(it);
    if (x > 0.0 && x + w > max_width) {
      x = 0.0;
      y += kLegendRow;
    }
    const double sx = left + x;
    const std::string c = esc(it.colour);
    switch (it.swatch) {
      case Swatch::line:
      case Swatch::dashed:
      case Swatch::line_dots:
        s.f("<path d=\"M{:.1f} {:.1f}h22\" stroke=\"{}\" stroke-width=\"2\"{}/>", sx, y, c,
            it.swatch == Swatch::dashed ? " stroke-dasharray=\"5 3\"" : "");
        if (it.swatch == Swatch::line_dots) {
          s.f("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"/>", sx + 11, y, c);
        }
        break;
      case Swatch::dots:
        s.f("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\"/>", sx + 11, y, c);
        break;
      case Swatch::patch:
        s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"22\" height=\"11\" fill=\"{}\" "
            "fill-opacity=\"{}\" stroke=\"{}\"/>",
            sx, y - 5.5, c, it.opacity, c);
        break;
      case Swatch::hatch:
        s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"22\" height=\"11\" fill=\"url(#{}-h)\" "
            "stroke=\"#999\"/>",
            sx, y - 5.5, id);
        break;
    }
    s.f("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>", sx + 28, y + 4, esc(it.name));
    x += w;
  }
}

// Opens the <svg>, paints the background and the title, and returns the top of what follows.
double open_svg(Svg& s, const std::string& id, double W, double H, const std::string& title) {
  s.f("<svg class=\"plot\" id=\"{}\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" "
      "height=\"{}\" viewBox=\"0 0 {} {}\" font-family=\"{}\" font-size=\"{}\" role=\"img\" "
      "aria-label=\"{}\">",
      esc(id), W, H, W, H, kFontFamily, kFont, esc(title));
  s.f("<rect width=\"{}\" height=\"{}\" fill=\"#fff\"/>", W, H);
  if (title.empty()) {
    return 10.0;
  }
  s.f("<text x=\"{:.1f}\" y=\"21\" text-anchor=\"middle\" font-size=\"{}\" "
      "font-weight=\"bold\">{}</text>",
      W / 2.0, kTitleFont, esc(title));
  return 32.0;
}

// The hover read-out hook: the page script turns pointer positions into data values with these.
void hover_attributes(Svg& s, const Frame& f, const Ticks& tx, bool xlog, const Ticks& ty,
                      bool ylog) {
  // Inserted into the already written <svg ...> tag, just before its '>'.
  const std::size_t at = s.s.find('>', s.s.rfind("<svg "));
  const std::string attrs =
      fmt::format(" data-px=\"{} {} {} {}\" data-x=\"{} {} {}\" data-y=\"{} {} {}\"", f.x0, f.x1,
                  f.y0, f.y1, tx.lo, tx.hi, xlog ? 1 : 0, ty.lo, ty.hi, ylog ? 1 : 0);
  s.s.insert(at, attrs);
}

void clip_def(Svg& s, const std::string& id, const Frame& f) {
  s.f("<defs><clipPath id=\"{}-c\"><rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" "
      "height=\"{:.1f}\"/></clipPath></defs>",
      esc(id), f.x0, f.y0, f.x1 - f.x0, f.y1 - f.y0);
}

void draw_x_axis(Svg& s, const Frame& f, const Scale& sx, const Ticks& t, const Axis& ax,
                 bool grid) {
  for (double v : t.minor) {
    const double p = sx(v);
    if (grid)
      s.f("<path d=\"M{:.1f} {:.1f}V{:.1f}\" stroke=\"#f0f0f0\"/>", p, f.y0, f.y1);
    s.f("<path d=\"M{:.1f} {:.1f}v3\" stroke=\"#333\"/>", p, f.y1);
  }
  for (std::size_t k = 0; k < t.major.size(); ++k) {
    const double p = sx(t.major[k]);
    if (grid)
      s.f("<path d=\"M{:.1f} {:.1f}V{:.1f}\" stroke=\"#e3e3e3\"/>", p, f.y0, f.y1);
    s.f("<path d=\"M{:.1f} {:.1f}v5\" stroke=\"#333\"/>", p, f.y1);
    s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>", p, f.y1 + 18,
        esc(t.labels[k]));
  }
  s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>", (f.x0 + f.x1) / 2,
      f.y1 + 37, esc(axis_title(ax)));
}

// A y axis on the left (right = false) or on the right of the plot area.
void draw_y_axis(Svg& s, const Frame& f, const Scale& sy, const Ticks& t, const Axis& ax, bool grid,
                 bool right, double label_x) {
  const double xa = right ? f.x1 : f.x0;
  const double dir = right ? 1.0 : -1.0;
  for (double v : t.minor) {
    const double p = sy(v);
    if (grid)
      s.f("<path d=\"M{:.1f} {:.1f}H{:.1f}\" stroke=\"#f0f0f0\"/>", f.x0, p, f.x1);
    s.f("<path d=\"M{:.1f} {:.1f}h{}\" stroke=\"#333\"/>", xa, p, 3 * dir);
  }
  for (std::size_t k = 0; k < t.major.size(); ++k) {
    const double p = sy(t.major[k]);
    if (grid)
      s.f("<path d=\"M{:.1f} {:.1f}H{:.1f}\" stroke=\"#e3e3e3\"/>", f.x0, p, f.x1);
    s.f("<path d=\"M{:.1f} {:.1f}h{}\" stroke=\"#333\"/>", xa, p, 5 * dir);
    s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"{}\">{}</text>", xa + 8 * dir, p + 4,
        right ? "start" : "end", esc(t.labels[k]));
  }
  // A label longer than the axis gets a smaller font, and squeezed if that is not enough, so
  // that it never runs into the title or off the picture.
  const double cy = (f.y0 + f.y1) / 2, room = f.y1 - f.y0;
  const std::string label = axis_title(ax);
  const double w = text_width(label);
  std::string fit;
  if (w > room && room > 0.0) {
    const double font = std::max(9.0, kFont * room / w);
    fit = fmt::format(" font-size=\"{:.1f}\"", font);
    if (text_width(label, font) > room) {
      fit += fmt::format(" textLength=\"{:.1f}\" lengthAdjust=\"spacingAndGlyphs\"", room);
    }
  }
  s.f("<text transform=\"translate({:.1f} {:.1f}) rotate(-90)\" text-anchor=\"middle\"{}>{}"
      "</text>",
      label_x, cy, fit, esc(label));
}

void draw_box_and_readout(Svg& s, const Frame& f) {
  s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" "
      "stroke=\"#333\"/>",
      f.x0, f.y0, f.x1 - f.x0, f.y1 - f.y0);
  s.f("<text class=\"ro\" x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"end\" stroke=\"#fff\" "
      "stroke-width=\"4\" paint-order=\"stroke\"></text>",
      f.x1 - 6, f.y0 + 16);
}

// A vertical colour bar right of the plot area; returns nothing, occupies colour_bar_width().
constexpr double kBarGap = 14.0, kBarWidth = 16.0;

double colour_bar_width(const Ticks& t) {
  return kBarGap + kBarWidth + 8.0 + t.max_label_width() + 26.0;
}

void draw_colour_bar(Svg& s, const Frame& f, const Ticks& t, const Axis& ax,
                     const std::string& id) {
  const double bx = f.x1 + kBarGap;
  s.f("<defs><linearGradient id=\"{}-g\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">", esc(id));
  for (int k = 0; k <= 16; ++k) {
    s.f("<stop offset=\"{}\" stop-color=\"{}\"/>", k / 16.0, colour_map(k / 16.0));
  }
  s.f("</linearGradient></defs>");
  s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{}\" height=\"{:.1f}\" fill=\"url(#{}-g)\" "
      "stroke=\"#333\"/>",
      bx, f.y0, kBarWidth, f.y1 - f.y0, esc(id));
  Frame bar = f;
  bar.x0 = bx;
  bar.x1 = bx + kBarWidth;
  const Scale sc{t.lo, t.hi, f.y1, f.y0, false};
  draw_y_axis(s, bar, sc, t, ax, false, true, f.W - 10);
}

// --- paths -----------------------------------------------------------------------------------

// Appends a polyline through (x, y) with breaks at NaN; a lone point between gaps becomes a
// zero-length segment, which the round line cap shows as a dot. Points that land on the same
// 0.1 px as the previous one are dropped.
void append_polyline(std::string& d, const double* x, const double* y, std::size_t n,
                     const Scale& sx, const Scale& sy) {
  bool pen = false;
  std::size_t in_run = 0;
  long last_qx = 0, last_qy = 0;
  auto out = std::back_inserter(d);
  for (std::size_t i = 0; i < n; ++i) {
    const double xv = x != nullptr ? x[i] : static_cast<double>(i);
    if (!sx.usable(xv) || !sy.usable(y[i])) {
      if (pen && in_run == 1)
        d += "h0";
      pen = false;
      continue;
    }
    const double px = sx(xv), py = sy(y[i]);
    const long qx = std::lround(px * 10), qy = std::lround(py * 10);
    if (!pen) {
      fmt::format_to(out, "M{:.1f} {:.1f}", px, py);
      pen = true;
      in_run = 1;
    } else if (qx != last_qx || qy != last_qy) {
      fmt::format_to(out, "{}{:.1f} {:.1f}", in_run == 1 ? "L" : " ", px, py);
      ++in_run;
    }
    last_qx = qx;
    last_qy = qy;
  }
  if (pen && in_run == 1)
    d += "h0";
}

// Dots as zero-length round-capped segments: one path element for any number of points.
void append_dots(std::string& d, double px, double py) {
  fmt::format_to(std::back_inserter(d), "M{:.1f} {:.1f}h0", px, py);
}

void check_xy(const std::vector<double>& x, const std::vector<double>& y, const std::string& what,
              const std::string& name) {
  if (!x.empty() && x.size() != y.size()) {
    throw std::invalid_argument(fmt::format(
        "{} '{}': x has {} values but y has {}; give one x per y, or no x at all (index)", what,
        name, x.size(), y.size()));
  }
}

std::string plot_id(const std::string& id) {
  return id.empty() ? std::string("plot") : id;
}

}  // namespace

// --- public helpers --------------------------------------------------------------------------

const char* palette_colour(std::size_t k) {
  static const char* const kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                         "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                         "#bcbd22", "#17becf", "#000000", "#aa40fc"};
  return kPalette[k % 12];
}

std::string colour_map(double t) {
  if (!std::isfinite(t))
    t = 0.0;
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int i = std::min(7, static_cast<int>(t));
  const double u = t - i;
  const Rgb& a = kMap[i];
  const Rgb& b = kMap[i + 1];
  auto mix = [u](double p, double q) { return static_cast<int>(std::lround(p + u * (q - p))); };
  return fmt::format("#{:02x}{:02x}{:02x}", mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b));
}

// --- LinePlot --------------------------------------------------------------------------------

std::string render_svg(const LinePlot& p) {
  const std::string id = plot_id(p.id);
  // Reduce long series first: all later work is on at most ~3 * max_buckets points each.
  std::vector<XYSeries> data;
  data.reserve(p.series.size());
  for (const Series& se : p.series) {
    check_xy(se.x, se.y, "line plot series", se.name);
    const double* x = se.x.empty() ? nullptr : se.x.data();
    if (se.y.size() > 2 * static_cast<std::size_t>(std::max(1, p.max_buckets))) {
      data.push_back(downsample_min_max(x, se.y.data(), se.y.size(), p.max_buckets));
    } else {
      XYSeries xy;
      xy.y = se.y;
      if (x != nullptr) {
        xy.x = se.x;
      } else {
        for (std::size_t i = 0; i < se.y.size(); ++i)
          xy.x.push_back(static_cast<double>(i));
      }
      data.push_back(std::move(xy));
    }
  }
  Range rx, ry, ry2;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const bool right = p.has_y2 && p.series[k].right_axis;
    for (std::size_t i = 0; i < data[k].y.size(); ++i) {
      if (!std::isfinite(data[k].y[i]) || !std::isfinite(data[k].x[i]))
        continue;
      if ((right ? p.y2.log : p.y.log) && data[k].y[i] <= 0.0)
        continue;
      if (p.x.log && data[k].x[i] <= 0.0)
        continue;
      rx.add(data[k].x[i], p.x.log);
      (right ? ry2 : ry).add(data[k].y[i], right ? p.y2.log : p.y.log);
    }
  }
  for (const HLine& h : p.hlines) {
    const bool right = p.has_y2 && h.right_axis;
    (right ? ry2 : ry).add(h.y, right ? p.y2.log : p.y.log);
  }
  for (const HBand& b : p.bands) {
    ry.add(b.y_lo, p.y.log);
    ry.add(b.y_hi, p.y.log);
  }

  std::vector<LegendItem> legend;
  std::size_t next = 0;
  std::vector<std::string> colours;
  for (const Series& se : p.series) {
    colours.push_back(pick(se.color, next));
    if (se.name.empty())
      continue;
    const Swatch sw = se.dashed ? Swatch::dashed : se.markers ? Swatch::line_dots : Swatch::line;
    legend.push_back(
        {p.has_y2 && se.right_axis ? se.name + " (right axis)" : se.name, colours.back(), sw});
  }
  for (const HBand& b : p.bands) {
    if (!b.name.empty())
      legend.push_back({b.name, b.color, Swatch::patch, b.opacity * 2});
  }
  for (const HLine& h : p.hlines) {
    if (!h.name.empty())
      legend.push_back({h.name, h.color, Swatch::dashed});
  }

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_svg(s, id, f.W, f.H, p.title);
  const double legend_w = f.W - 40.0;
  const int rows = legend_rows(legend, legend_w);
  f.y0 = top + rows * kLegendRow + (rows > 0 ? 8.0 : 0.0);
  f.y1 = f.H - 46.0;
  const Ticks ty = make_y_ticks(p.y, ry, f.y1 - f.y0, true);
  const Ticks ty2 = p.has_y2 ? make_y_ticks(p.y2, ry2, f.y1 - f.y0, true) : Ticks{};
  f.x0 = 26.0 + ty.max_label_width() + 10.0;
  f.x1 = f.W - (p.has_y2 ? 26.0 + ty2.max_label_width() + 10.0 : 20.0);
  const Ticks tx = fit_x_ticks(p.x, rx, f, true);
  const Scale sx{tx.lo, tx.hi, f.x0, f.x1, p.x.log};
  const Scale sy{ty.lo, ty.hi, f.y1, f.y0, p.y.log};
  const Scale sy2{ty2.lo, ty2.hi, f.y1, f.y0, p.y2.log};
  hover_attributes(s, f, tx, p.x.log, ty, p.y.log);

  draw_legend(s, legend, 20.0, top, legend_w, id);
  clip_def(s, id, f);
  s.f("<g clip-path=\"url(#{}-c)\">", esc(id));
  for (const HBand& b : p.bands) {
    if (!sy.usable(b.y_lo) || !sy.usable(b.y_hi))
      continue;
    const double ya = sy(std::max(b.y_lo, b.y_hi)), yb = sy(std::min(b.y_lo, b.y_hi));
    s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" "
        "fill-opacity=\"{}\"/>",
        f.x0, ya, f.x1 - f.x0, yb - ya, esc(b.color), b.opacity);
  }
  s.f("</g>");
  draw_x_axis(s, f, sx, tx, p.x, true);
  draw_y_axis(s, f, sy, ty, p.y, true, false, 14.0);
  if (p.has_y2)
    draw_y_axis(s, f, sy2, ty2, p.y2, false, true, f.W - 10.0);

  s.f("<g clip-path=\"url(#{}-c)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">",
      esc(id));
  for (std::size_t k = 0; k < data.size(); ++k) {
    const Series& se = p.series[k];
    const Scale& yk = p.has_y2 && se.right_axis ? sy2 : sy;
    std::string d;
    append_polyline(d, data[k].x.data(), data[k].y.data(), data[k].y.size(), sx, yk);
    if (!d.empty()) {
      s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"{}\"{}/>", d, esc(colours[k]), se.line_width,
          se.dashed ? " stroke-dasharray=\"6 4\"" : "");
    }
    if (se.markers && data[k].y.size() <= kMaxMarkers) {
      std::string m;
      for (std::size_t i = 0; i < data[k].y.size(); ++i) {
        if (sx.usable(data[k].x[i]) && yk.usable(data[k].y[i])) {
          append_dots(m, sx(data[k].x[i]), yk(data[k].y[i]));
        }
      }
      if (!m.empty()) {
        s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"6\"/>", m, esc(colours[k]));
      }
    }
  }
  for (const HLine& h : p.hlines) {
    const Scale& yk = p.has_y2 && h.right_axis ? sy2 : sy;
    if (!yk.usable(h.y))
      continue;
    s.f("<path d=\"M{:.1f} {:.1f}H{:.1f}\" stroke=\"{}\" stroke-width=\"1.5\" "
        "stroke-dasharray=\"6 4\"/>",
        f.x0, yk(h.y), f.x1, esc(h.color));
  }
  s.f("</g>");
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

// --- Histogram -------------------------------------------------------------------------------

std::string render_svg(const Histogram& p) {
  const std::string id = plot_id(p.id);
  Range r;
  for (const auto& set : p.sets) {
    for (double v : set.values)
      r.add(v, false);
  }
  if (std::isfinite(p.x.min))
    r.lo = p.x.min;
  if (std::isfinite(p.x.max))
    r.hi = p.x.max;
  if (r.empty()) {
    r.lo = 0.0;
    r.hi = 1.0;
  }
  LinearTicks edges_t = nice_linear_ticks(r.lo, r.hi, std::max(1, p.bins), true);
  const double step = edges_t.step;
  const double e0 = edges_t.lo;
  const int nb = std::max(1, static_cast<int>(std::lround((edges_t.hi - e0) / step)));
  std::vector<std::vector<double>> counts(p.sets.size(), std::vector<double>(nb, 0.0));
  double max_count = 0.0;
  std::vector<LegendItem> legend;
  std::size_t next = 0;
  std::vector<std::string> colours;
  for (std::size_t k = 0; k < p.sets.size(); ++k) {
    std::size_t n = 0, nan = 0, outside = 0;
    for (double v : p.sets[k].values) {
      if (!std::isfinite(v)) {
        ++nan;
        continue;
      }
      // A value on the top edge belongs to the last bin.
      const double b = std::floor((v - e0) / step);
      if (b < 0.0 || v > edges_t.hi) {
        ++outside;
        continue;
      }
      counts[k][std::min(nb - 1, static_cast<int>(b))] += 1.0;
      ++n;
    }
    for (double c : counts[k])
      max_count = std::max(max_count, c);
    colours.push_back(pick(p.sets[k].color, next));
    std::string name = fmt::format("{} (n = {}", p.sets[k].name, n);
    if (nan > 0)
      name += fmt::format(", {} NaN", nan);
    if (outside > 0)
      name += fmt::format(", {} outside", outside);
    legend.push_back({name + ")", colours.back(), Swatch::patch, 0.3});
  }

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_svg(s, id, f.W, f.H, p.title);
  const int rows = legend_rows(legend, f.W - 40.0);
  f.y0 = top + rows * kLegendRow + (rows > 0 ? 8.0 : 0.0);
  f.y1 = f.H - 46.0;
  Axis ya;
  ya.label = p.y_label;
  ya.min = 0.0;
  Range rc;
  rc.add(0.0, false);
  rc.add(std::max(1.0, max_count), false);
  const Ticks ty = make_y_ticks(ya, rc, f.y1 - f.y0, true);
  f.x0 = 26.0 + ty.max_label_width() + 10.0;
  f.x1 = f.W - 20.0;
  Range re;
  re.lo = e0;
  re.hi = edges_t.hi;
  Axis xa = p.x;
  xa.min = e0;
  xa.max = edges_t.hi;
  xa.log = false;
  const Ticks tx = fit_x_ticks(xa, re, f, false);
  const Scale sx{e0, edges_t.hi, f.x0, f.x1, false};
  const Scale sy{ty.lo, ty.hi, f.y1, f.y0, false};
  hover_attributes(s, f, tx, false, ty, false);
  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  draw_x_axis(s, f, sx, tx, p.x, true);
  draw_y_axis(s, f, sy, ty, ya, true, false, 14.0);
  for (std::size_t k = 0; k < counts.size(); ++k) {
    // The outline of the bars as one step path, filled translucent so that overlaps show.
    std::string d = fmt::format("M{:.1f} {:.1f}", sx(e0), sy(0.0));
    for (int b = 0; b < nb; ++b) {
      fmt::format_to(std::back_inserter(d), "V{:.1f}H{:.1f}", sy(counts[k][b]),
                     sx(e0 + (b + 1) * step));
    }
    fmt::format_to(std::back_inserter(d), "V{:.1f}Z", sy(0.0));
    s.f("<path d=\"{}\" fill=\"{}\" fill-opacity=\"0.3\" stroke=\"{}\" stroke-width=\"1.5\"/>", d,
        esc(colours[k]), esc(colours[k]));
  }
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

// --- BarPlot ---------------------------------------------------------------------------------

std::string render_svg(const BarPlot& p) {
  const std::string id = plot_id(p.id);
  if (!p.categories.empty() && p.categories.size() != p.values.size()) {
    throw std::invalid_argument(
        fmt::format("bar plot '{}': {} categories but {} values; give one name per value", p.title,
                    p.categories.size(), p.values.size()));
  }
  const std::size_t n = p.values.size();
  Range r;
  if (!p.y.log)
    r.add(0.0, false);
  for (double v : p.values)
    r.add(v, p.y.log);

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  f.y0 = open_svg(s, id, f.W, f.H, p.title) + 6.0;
  f.y1 = f.H - 46.0;
  const Ticks ty = make_y_ticks(p.y, r, f.y1 - f.y0, true);
  f.x0 = 26.0 + ty.max_label_width() + 10.0;
  f.x1 = f.W - 20.0;
  const Scale sy{ty.lo, ty.hi, f.y1, f.y0, p.y.log};
  s.s.insert(s.s.find('>', s.s.rfind("<svg ")),
             fmt::format(" data-px=\"{} {} {} {}\" data-y=\"{} {} {}\"", f.x0, f.x1, f.y0, f.y1,
                         ty.lo, ty.hi, p.y.log ? 1 : 0));
  draw_y_axis(s, f, sy, ty, p.y, true, false, 14.0);
  const double slot = n > 0 ? (f.x1 - f.x0) / n : 1.0;
  double widest = 0.0;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n; ++i) {
    names.push_back(p.categories.empty() ? fmt::format("{}", i + 1) : p.categories[i]);
    widest = std::max(widest, text_width(names.back()));
  }
  const std::size_t every =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil((widest + 8.0) / slot)));
  const double base = p.y.log ? f.y1 : std::clamp(sy(0.0), f.y0, f.y1);
  const bool value_labels = n <= 16 && slot >= 44.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double cx = f.x0 + (i + 0.5) * slot;
    if (i % every == 0) {
      s.f("<path d=\"M{:.1f} {:.1f}v5\" stroke=\"#333\"/>", cx, f.y1);
      s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>", cx, f.y1 + 18,
          esc(names[i]));
    }
    if (!sy.usable(p.values[i]))
      continue;
    const double yv = std::clamp(sy(p.values[i]), f.y0, f.y1);
    s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\"/>",
        cx - 0.35 * slot, std::min(yv, base), 0.7 * slot, std::abs(base - yv), esc(p.color));
    if (value_labels) {
      const bool up = p.values[i] >= 0.0 || p.y.log;
      s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\" font-size=\"11\">{:.3g}</text>",
          cx, up ? std::max(yv - 4.0, f.y0 + 11.0) : std::min(yv + 13.0, f.y1 - 2.0), p.values[i]);
    }
  }
  s.f("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">{}</text>", (f.x0 + f.x1) / 2,
      f.y1 + 37, esc(p.x_label));
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

// --- HeatMap ---------------------------------------------------------------------------------

namespace {

// Cell edges from increasing centres: midpoints inside, half a step beyond the ends.
std::vector<double> edges_from_centres(const std::vector<double>& c, Eigen::Index n,
                                       const std::string& what) {
  std::vector<double> centres = c;
  if (centres.empty()) {
    for (Eigen::Index i = 0; i < n; ++i)
      centres.push_back(static_cast<double>(i));
  }
  if (static_cast<Eigen::Index>(centres.size()) != n) {
    throw std::invalid_argument(
        fmt::format("heat map: {} has {} centres but the matrix has {}; give one centre per {}",
                    what, centres.size(), n, what == "x" ? "column" : "row"));
  }
  for (std::size_t i = 1; i < centres.size(); ++i) {
    if (!(centres[i] > centres[i - 1])) {
      throw std::invalid_argument(
          fmt::format("heat map: {} centres must increase (entry {} is {}, after {})", what, i,
                      centres[i], centres[i - 1]));
    }
  }
  std::vector<double> e(centres.size() + 1);
  if (centres.size() == 1) {
    e[0] = centres[0] - 0.5;
    e[1] = centres[0] + 0.5;
    return e;
  }
  for (std::size_t i = 1; i < centres.size(); ++i)
    e[i] = 0.5 * (centres[i - 1] + centres[i]);
  e.front() = centres.front() - (e[1] - centres.front());
  e.back() = centres.back() + (centres.back() - e[centres.size() - 1]);
  return e;
}

}  // namespace

std::string render_svg(const HeatMap& p) {
  const std::string id = plot_id(p.id);
  const Eigen::Index rows = p.values.rows(), cols0 = p.values.cols();
  std::vector<double> ye = edges_from_centres(p.y_centres, rows, "y");
  std::vector<double> xe0 = edges_from_centres(p.x_centres, cols0, "x");
  // Reduce the columns to at most max_columns by averaging groups.
  const Eigen::Index group = std::max<Eigen::Index>(
      1, (cols0 + std::max(1, p.max_columns) - 1) / std::max(1, p.max_columns));
  const Eigen::Index cols = (cols0 + group - 1) / group;
  Eigen::MatrixXd v(rows, cols);
  std::vector<double> xe;
  for (Eigen::Index c = 0; c < cols; ++c) {
    xe.push_back(xe0[c * group]);
    const Eigen::Index c1 = std::min(cols0, (c + 1) * group);
    for (Eigen::Index r = 0; r < rows; ++r) {
      double sum = 0.0;
      bool nan = false;
      for (Eigen::Index k = c * group; k < c1; ++k) {
        nan = nan || !std::isfinite(p.values(r, k));
        sum += p.values(r, k);
      }
      v(r, c) = nan ? kNaN : sum / static_cast<double>(c1 - c * group);
    }
  }
  xe.push_back(xe0.back());

  Range rv;
  bool any_nan = false;
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      rv.add(v(r, c), false);
      any_nan = any_nan || std::isnan(v(r, c));
    }
  }
  Axis va = p.value;
  va.log = false;

  std::vector<LegendItem> legend;
  std::size_t next = 0;
  std::vector<std::string> colours;
  for (const Series& o : p.overlays) {
    check_xy(o.x, o.y, "heat map overlay", o.name);
    // Overlays start at the palette's red so that they stand out on the blue-green-yellow map.
    colours.push_back(o.color.empty() ? std::string(palette_colour(3 + next++)) : o.color);
    if (!o.name.empty()) {
      legend.push_back({o.name, colours.back(),
                        o.dashed    ? Swatch::dashed
                        : o.markers ? Swatch::line_dots
                                    : Swatch::line});
    }
  }
  if (any_nan)
    legend.push_back({p.nan_label, "#999", Swatch::hatch});

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_svg(s, id, f.W, f.H, p.title);
  const int lrows = legend_rows(legend, f.W - 40.0);
  f.y0 = top + lrows * kLegendRow + (lrows > 0 ? 8.0 : 0.0);
  f.y1 = f.H - 46.0;
  Range ry;
  ry.lo = ye.front();
  ry.hi = ye.back();
  Axis yax = p.y;
  yax.log = false;
  const Ticks ty = make_y_ticks(yax, ry, f.y1 - f.y0, false);
  const Ticks tv = make_ticks(va, rv, std::max(2, static_cast<int>((f.y1 - f.y0) / 45.0)), false);
  f.x0 = 26.0 + ty.max_label_width() + 10.0;
  f.x1 = f.W - colour_bar_width(tv);
  Range rx;
  rx.lo = xe.front();
  rx.hi = xe.back();
  Axis xax = p.x;
  xax.log = false;
  const Ticks tx = make_x_ticks(xax, rx, f.x1 - f.x0, false);
  const Scale sx{tx.lo, tx.hi, f.x0, f.x1, false};
  const Scale sy{ty.lo, ty.hi, f.y1, f.y0, false};
  hover_attributes(s, f, tx, false, ty, false);
  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  s.f("<defs><pattern id=\"{}-h\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
      "patternTransform=\"rotate(45)\"><rect width=\"6\" height=\"6\" fill=\"#fff\"/>"
      "<path d=\"M0 0V6\" stroke=\"#999\" stroke-width=\"1.5\"/></pattern></defs>",
      esc(id));
  clip_def(s, id, f);

  // One path per colour bin (and one for NaN), cells merged along rows where the bin repeats.
  std::vector<std::string> d(kColourBins + 1);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const double ya = sy(ye[r + 1]), yb = sy(ye[r]);
    Eigen::Index c = 0;
    while (c < cols) {
      const int bin = std::isnan(v(r, c)) ? kColourBins : colour_bin(v(r, c), tv.lo, tv.hi);
      Eigen::Index c1 = c + 1;
      while (c1 < cols &&
             (std::isnan(v(r, c1)) ? kColourBins : colour_bin(v(r, c1), tv.lo, tv.hi)) == bin) {
        ++c1;
      }
      fmt::format_to(std::back_inserter(d[bin]), "M{:.1f} {:.1f}H{:.1f}V{:.1f}H{:.1f}z", sx(xe[c]),
                     ya, sx(xe[c1]), yb, sx(xe[c]));
      c = c1;
    }
  }
  s.f("<g clip-path=\"url(#{}-c)\" shape-rendering=\"crispEdges\">", esc(id));
  for (int b = 0; b < kColourBins; ++b) {
    if (!d[b].empty())
      s.f("<path d=\"{}\" fill=\"{}\"/>", d[b], bin_colour(b));
  }
  if (!d[kColourBins].empty()) {
    s.f("<path d=\"{}\" fill=\"url(#{}-h)\"/>", d[kColourBins], esc(id));
  }
  s.f("</g>");
  draw_x_axis(s, f, sx, tx, p.x, false);
  draw_y_axis(s, f, sy, ty, p.y, false, false, 14.0);
  draw_colour_bar(s, f, tv, va, id);

  s.f("<g clip-path=\"url(#{}-c)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">",
      esc(id));
  for (std::size_t k = 0; k < p.overlays.size(); ++k) {
    const Series& o = p.overlays[k];
    std::string dd;
    append_polyline(dd, o.x.empty() ? nullptr : o.x.data(), o.y.data(), o.y.size(), sx, sy);
    if (dd.empty())
      continue;
    // A white halo keeps the line visible over any colour of the map.
    s.f("<path d=\"{}\" stroke=\"#fff\" stroke-width=\"{}\"/>", dd, o.line_width + 3.0);
    s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"{}\"{}/>", dd, esc(colours[k]), o.line_width,
        o.dashed ? " stroke-dasharray=\"6 4\"" : "");
    if (o.markers && o.y.size() <= kMaxMarkers) {
      std::string m;
      for (std::size_t i = 0; i < o.y.size(); ++i) {
        const double xv = o.x.empty() ? static_cast<double>(i) : o.x[i];
        if (sx.usable(xv) && sy.usable(o.y[i]))
          append_dots(m, sx(xv), sy(o.y[i]));
      }
      s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"6\"/>", m, esc(colours[k]));
    }
  }
  s.f("</g>");
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

// --- XYView ----------------------------------------------------------------------------------

namespace {

// Indices of the points to draw: the first, then every point at least tol px from the last
// kept one, the last, and the points on either side of a gap. tol doubles until at most
// max_points remain.
std::vector<std::size_t> thin(const PointSet& set, const Scale& sx, const Scale& sy,
                              std::size_t max_points) {
  std::vector<std::size_t> kept;
  const std::size_t n = set.y.size();
  for (double tol = 0.75;; tol *= 2.0) {
    kept.clear();
    double lx = 0.0, ly = 0.0;
    bool have = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!sx.usable(set.x[i]) || !sy.usable(set.y[i])) {
        if (have)
          kept.push_back(i);  // keep the break
        have = false;
        continue;
      }
      const double px = sx(set.x[i]), py = sy(set.y[i]);
      const bool last = i + 1 == n || !sx.usable(set.x[i + 1]) || !sy.usable(set.y[i + 1]);
      if (!have || last || std::hypot(px - lx, py - ly) >= tol) {
        kept.push_back(i);
        lx = px;
        ly = py;
        have = true;
      }
    }
    if (kept.size() <= std::max<std::size_t>(2, max_points) || tol > 1e4) {
      return kept;
    }
  }
}

}  // namespace

std::string render_svg(const XYView& p) {
  const std::string id = plot_id(p.id);
  Range rx, ry, rv;
  bool valued = false;
  const bool xlog = p.x.log && !p.equal_scale, ylog = p.y.log && !p.equal_scale;
  for (const PointSet& set : p.sets) {
    if (set.x.size() != set.y.size()) {
      throw std::invalid_argument(
          fmt::format("2D view point set '{}': x has {} values but y has {}; give one x per y",
                      set.name, set.x.size(), set.y.size()));
    }
    if (!set.value.empty() && set.value.size() != set.y.size()) {
      throw std::invalid_argument(
          fmt::format("2D view point set '{}': {} values for {} points; give one per point or none",
                      set.name, set.value.size(), set.y.size()));
    }
    valued = valued || !set.value.empty();
    for (std::size_t i = 0; i < set.y.size(); ++i) {
      rx.add(set.x[i], xlog);
      ry.add(set.y[i], ylog);
    }
    for (double v : set.value)
      rv.add(v, false);
  }
  for (const Rect& r : p.rects) {
    rx.add(r.x0, xlog), rx.add(r.x1, xlog);
    ry.add(r.y0, ylog), ry.add(r.y1, ylog);
  }
  Axis va = p.colour;
  va.log = false;

  std::vector<LegendItem> legend;
  std::size_t next = 0;
  std::vector<std::string> colours;
  for (const Rect& r : p.rects) {
    if (!r.name.empty())
      legend.push_back({r.name, r.color, Swatch::patch, 0.3});
  }
  for (const PointSet& set : p.sets) {
    colours.push_back(set.value.empty() ? pick(set.color, next) : colour_map(0.5));
    if (set.name.empty())
      continue;
    const Swatch sw = set.connect ? (set.markers ? Swatch::line_dots : Swatch::line) : Swatch::dots;
    legend.push_back(
        {set.value.empty() ? set.name : set.name + " (coloured by " + axis_title(p.colour) + ")",
         colours.back(), sw});
  }

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_svg(s, id, f.W, f.H, p.title);
  const int lrows = legend_rows(legend, f.W - 40.0);
  f.y0 = top + lrows * kLegendRow + (lrows > 0 ? 8.0 : 0.0);
  f.y1 = f.H - 46.0;
  const Ticks tv =
      valued ? make_ticks(va, rv, std::max(2, static_cast<int>((f.y1 - f.y0) / 45.0)), false)
             : Ticks{};
  // The y tick labels depend on the y range, which with equal scales depends on the plot
  // width; estimate the left margin from a first pass and settle it in a second.
  Ticks tx, ty;
  double left = 60.0;
  for (int pass = 0; pass < 2; ++pass) {
    f.x0 = left;
    f.x1 = f.W - (valued ? colour_bar_width(tv) : 20.0);
    Axis ax = p.x, ay = p.y;
    ax.log = xlog;
    ay.log = ylog;
    if (p.equal_scale) {
      Range bx = rx, by = ry;
      if (std::isfinite(p.x.min))
        bx.lo = p.x.min;
      if (std::isfinite(p.x.max))
        bx.hi = p.x.max;
      if (std::isfinite(p.y.min))
        by.lo = p.y.min;
      if (std::isfinite(p.y.max))
        by.hi = p.y.max;
      if (bx.empty())
        bx.lo = 0.0, bx.hi = 1.0;
      if (by.empty())
        by.lo = 0.0, by.hi = 1.0;
      const double pad = 0.04 * std::max({bx.hi - bx.lo, by.hi - by.lo, 1e-9});
      double xs = bx.hi - bx.lo + 2 * pad, ys = by.hi - by.lo + 2 * pad;
      const double pw = f.x1 - f.x0, ph = f.y1 - f.y0;
      const double mm_per_px = std::max(xs / pw, ys / ph);
      xs = mm_per_px * pw;
      ys = mm_per_px * ph;
      const double cx = 0.5 * (bx.lo + bx.hi), cy = 0.5 * (by.lo + by.hi);
      ax.min = cx - xs / 2, ax.max = cx + xs / 2;
      ay.min = cy - ys / 2, ay.max = cy + ys / 2;
    }
    ty = make_y_ticks(ay, ry, f.y1 - f.y0, true);
    left = 26.0 + ty.max_label_width() + 10.0;
    tx = make_x_ticks(ax, rx, f.x1 - f.x0, true);
  }
  const Scale sx{tx.lo, tx.hi, f.x0, f.x1, xlog};
  const Scale sy{ty.lo, ty.hi, f.y1, f.y0, ylog};
  hover_attributes(s, f, tx, xlog, ty, ylog);
  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  clip_def(s, id, f);
  draw_x_axis(s, f, sx, tx, p.x, true);
  draw_y_axis(s, f, sy, ty, p.y, true, false, 14.0);
  if (valued)
    draw_colour_bar(s, f, tv, va, id);

  s.f("<g clip-path=\"url(#{}-c)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">",
      esc(id));
  for (const Rect& r : p.rects) {
    const double xa = sx(std::min(r.x0, r.x1)), xb = sx(std::max(r.x0, r.x1));
    const double ya = sy(std::max(r.y0, r.y1)), yb = sy(std::min(r.y0, r.y1));
    s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" "
        "fill-opacity=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>",
        xa, ya, xb - xa, yb - ya, esc(r.color), r.fill_opacity, esc(r.color));
  }
  for (std::size_t k = 0; k < p.sets.size(); ++k) {
    const PointSet& set = p.sets[k];
    const std::vector<std::size_t> idx =
        thin(set, sx, sy, static_cast<std::size_t>(std::max(2, p.max_points_per_set)));
    const bool by_value = !set.value.empty();
    auto usable = [&](std::size_t i) { return sx.usable(set.x[i]) && sy.usable(set.y[i]); };
    if (set.connect) {
      if (!by_value) {
        std::vector<double> xs, ys;
        for (std::size_t i : idx) {
          xs.push_back(usable(i) ? set.x[i] : kNaN);
          ys.push_back(usable(i) ? set.y[i] : kNaN);
        }
        std::string d;
        append_polyline(d, xs.data(), ys.data(), ys.size(), sx, sy);
        if (!d.empty())
          s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>", d, esc(colours[k]));
      } else {
        // Segments coloured by the mean value of their ends, one path per colour bin; runs of
        // the same bin continue one subpath.
        std::vector<std::string> d(kColourBins);
        int open_bin = -1;
        for (std::size_t j = 1; j < idx.size(); ++j) {
          const std::size_t a = idx[j - 1], b = idx[j];
          if (!usable(a) || !usable(b)) {
            open_bin = -1;
            continue;
          }
          const int bin = colour_bin(0.5 * (set.value[a] + set.value[b]), tv.lo, tv.hi);
          auto out = std::back_inserter(d[bin]);
          if (bin != open_bin) {
            fmt::format_to(out, "M{:.1f} {:.1f}", sx(set.x[a]), sy(set.y[a]));
          }
          fmt::format_to(out, "L{:.1f} {:.1f}", sx(set.x[b]), sy(set.y[b]));
          open_bin = bin;
        }
        for (int b = 0; b < kColourBins; ++b) {
          if (!d[b].empty()) {
            s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>", d[b], bin_colour(b));
          }
        }
      }
    }
    if (set.markers) {
      std::vector<std::string> d(by_value ? kColourBins : 1);
      for (std::size_t i : idx) {
        if (!usable(i))
          continue;
        const int bin = by_value ? colour_bin(set.value[i], tv.lo, tv.hi) : 0;
        append_dots(d[bin], sx(set.x[i]), sy(set.y[i]));
      }
      for (std::size_t b = 0; b < d.size(); ++b) {
        if (d[b].empty())
          continue;
        s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"{}\"/>", d[b],
            by_value ? bin_colour(static_cast<int>(b)) : esc(colours[k]), 2 * set.marker_radius);
      }
    }
  }
  s.f("</g>");
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

}  // namespace redpost::report
