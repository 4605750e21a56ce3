// XYView as SVG (see svg_plot.hpp): point sets and rectangles in a plane, at equal scales when
// asked, thinned in screen space, optionally coloured by a value with a colour bar.
#include "redpost/report/svg_plot.hpp"

#include "escape.hpp"
#include "svg_draw.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace redpost::report {

using namespace svg;

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

// The data ranges of x, y and the colour value, and whether any set is coloured by value.
struct XYRanges {
  Range x, y, v;
  bool valued = false;
};

// The ranges over the point sets and the rectangles. Throws std::invalid_argument when a set's
// x, y and values do not match.
XYRanges xy_ranges(const XYView& p, bool xlog, bool ylog) {
  Range rx, ry, rv;
  bool valued = false;
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
  return {rx, ry, rv, valued};
}

// The legend: the named rectangles, then the named sets. colours receives the colour of every
// set, named or not (valued sets: the middle of the colour map).
std::vector<LegendItem> xy_legend(const XYView& p, std::vector<std::string>& colours) {
  std::vector<LegendItem> legend;
  std::size_t next = 0;
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
  return legend;
}

// Equal scales: fixes the ranges of ax and ay, centred on the data (or on Axis::min/max) with a
// little padding, so that one mm is as long on both axes of the plot area f.
void fix_equal_scale_ranges(const XYView& p, const XYRanges& r, const Frame& f, Axis& ax,
                            Axis& ay) {
  Range bx = r.x, by = r.y;
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

// The ticks of x, y and the colour bar (tv, valued views only), and the scales of x and y.
struct XYAxes {
  Ticks tx, ty, tv;
  Scale sx, sy;
};

// Ticks and scales in the plot area f, whose left and right ends (f.x0, f.x1) are set here to
// leave room for the y tick labels and the colour bar.
XYAxes xy_axes(const XYView& p, const XYRanges& r, const Axis& va, bool xlog, bool ylog, Frame& f) {
  XYAxes a;
  a.tv = r.valued ? make_ticks(va, r.v, std::max(2, static_cast<int>((f.y1 - f.y0) / 45.0)), false)
                  : Ticks{};
  // The y tick labels depend on the y range, which with equal scales depends on the plot
  // width; estimate the left margin from a first pass and settle it in a second.
  double left = 60.0;
  for (int pass = 0; pass < 2; ++pass) {
    f.x0 = left;
    f.x1 = f.W - (r.valued ? colour_bar_width(a.tv) : 20.0);
    Axis ax = p.x, ay = p.y;
    ax.log = xlog;
    ay.log = ylog;
    if (p.equal_scale)
      fix_equal_scale_ranges(p, r, f, ax, ay);
    a.ty = make_y_ticks(ay, r.y, f.y1 - f.y0, true);
    left = 26.0 + a.ty.max_label_width() + 10.0;
    a.tx = make_x_ticks(ax, r.x, f.x1 - f.x0, true);
  }
  a.sx = Scale{a.tx.lo, a.tx.hi, f.x0, f.x1, xlog};
  a.sy = Scale{a.ty.lo, a.ty.hi, f.y1, f.y0, ylog};
  return a;
}

void draw_rects(Svg& s, const XYView& p, const Scale& sx, const Scale& sy) {
  for (const Rect& r : p.rects) {
    const double xa = sx(std::min(r.x0, r.x1)), xb = sx(std::max(r.x0, r.x1));
    const double ya = sy(std::max(r.y0, r.y1)), yb = sy(std::min(r.y0, r.y1));
    s.f("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" "
        "fill-opacity=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>",
        xa, ya, xb - xa, yb - ya, esc(r.color), r.fill_opacity, esc(r.color));
  }
}

bool usable(const PointSet& set, std::size_t i, const XYAxes& a) {
  return a.sx.usable(set.x[i]) && a.sy.usable(set.y[i]);
}

// A set without values as one polyline through the kept points idx, broken at gaps.
void draw_polyline(Svg& s, const PointSet& set, const std::vector<std::size_t>& idx,
                   const std::string& colour, const XYAxes& a) {
  std::vector<double> xs, ys;
  for (std::size_t i : idx) {
    xs.push_back(usable(set, i, a) ? set.x[i] : kNaN);
    ys.push_back(usable(set, i, a) ? set.y[i] : kNaN);
  }
  std::string d;
  append_polyline(d, xs.data(), ys.data(), ys.size(), a.sx, a.sy);
  if (!d.empty())
    s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>", d, esc(colour));
}

// A valued set as segments between the kept points idx.
void draw_valued_segments(Svg& s, const PointSet& set, const std::vector<std::size_t>& idx,
                          const XYAxes& a) {
  // Segments coloured by the mean value of their ends, one path per colour bin; runs of
  // the same bin continue one subpath.
  std::vector<std::string> d(kColourBins);
  int open_bin = -1;
  for (std::size_t j = 1; j < idx.size(); ++j) {
    const std::size_t i0 = idx[j - 1], i1 = idx[j];
    if (!usable(set, i0, a) || !usable(set, i1, a)) {
      open_bin = -1;
      continue;
    }
    const int bin = colour_bin(0.5 * (set.value[i0] + set.value[i1]), a.tv.lo, a.tv.hi);
    auto out = std::back_inserter(d[bin]);
    if (bin != open_bin) {
      fmt::format_to(out, "M{:.1f} {:.1f}", a.sx(set.x[i0]), a.sy(set.y[i0]));
    }
    fmt::format_to(out, "L{:.1f} {:.1f}", a.sx(set.x[i1]), a.sy(set.y[i1]));
    open_bin = bin;
  }
  for (int b = 0; b < kColourBins; ++b) {
    if (!d[b].empty()) {
      s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"/>", d[b], bin_colour(b));
    }
  }
}

// A dot at each kept point idx: one path in the set's colour, or one per colour bin.
void draw_markers(Svg& s, const PointSet& set, const std::vector<std::size_t>& idx,
                  const std::string& colour, const XYAxes& a) {
  const bool by_value = !set.value.empty();
  std::vector<std::string> d(by_value ? kColourBins : 1);
  for (std::size_t i : idx) {
    if (!usable(set, i, a))
      continue;
    const int bin = by_value ? colour_bin(set.value[i], a.tv.lo, a.tv.hi) : 0;
    append_dots(d[bin], a.sx(set.x[i]), a.sy(set.y[i]));
  }
  for (std::size_t b = 0; b < d.size(); ++b) {
    if (d[b].empty())
      continue;
    s.f("<path d=\"{}\" stroke=\"{}\" stroke-width=\"{}\"/>", d[b],
        by_value ? bin_colour(static_cast<int>(b)) : esc(colour), 2 * set.marker_radius);
  }
}

void draw_point_set(Svg& s, const XYView& p, const PointSet& set, const std::string& colour,
                    const XYAxes& a) {
  const std::vector<std::size_t> idx =
      thin(set, a.sx, a.sy, static_cast<std::size_t>(std::max(2, p.max_points_per_set)));
  if (set.connect) {
    if (set.value.empty())
      draw_polyline(s, set, idx, colour, a);
    else
      draw_valued_segments(s, set, idx, a);
  }
  if (set.markers)
    draw_markers(s, set, idx, colour, a);
}

}  // namespace

std::string render_svg(const XYView& p) {
  const std::string id = plot_id(p.id);
  const bool xlog = p.x.log && !p.equal_scale, ylog = p.y.log && !p.equal_scale;
  const XYRanges ranges = xy_ranges(p, xlog, ylog);
  Axis va = p.colour;
  va.log = false;
  std::vector<std::string> colours;
  const std::vector<LegendItem> legend = xy_legend(p, colours);

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_plot(s, id, p.title, legend, f);
  const XYAxes a = xy_axes(p, ranges, va, xlog, ylog, f);
  hover_attributes(s, f, a.tx, xlog, a.ty, ylog);
  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  clip_def(s, id, f);
  draw_x_axis(s, f, a.sx, a.tx, p.x, true);
  draw_y_axis(s, f, a.sy, a.ty, p.y, true, false, 14.0);
  if (ranges.valued)
    draw_colour_bar(s, f, a.tv, va, id);

  s.f("<g clip-path=\"url(#{}-c)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">",
      esc(id));
  draw_rects(s, p, a.sx, a.sy);
  for (std::size_t k = 0; k < p.sets.size(); ++k)
    draw_point_set(s, p, p.sets[k], colours[k], a);
  s.f("</g>");
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

}  // namespace redpost::report
