// HeatMap as SVG (see svg_plot.hpp): a matrix over two grids coloured by value with a colour
// bar, NaN cells hatched, wide matrices reduced by averaging columns, and polylines (plans)
// drawn over it with a white halo.
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

// The matrix drawn: at most max_columns columns, with their edges.
struct ReducedMap {
  Eigen::MatrixXd v;
  std::vector<double> xe;
};

// Reduce the columns to at most max_columns by averaging groups.
ReducedMap reduce_columns(const HeatMap& p, const std::vector<double>& xe0) {
  const Eigen::Index rows = p.values.rows(), cols0 = p.values.cols();
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
  return {std::move(v), std::move(xe)};
}

// The range of the values drawn; any_nan tells whether a cell is NaN (hatched).
Range value_range(const Eigen::MatrixXd& v, bool& any_nan) {
  Range rv;
  any_nan = false;
  for (Eigen::Index r = 0; r < v.rows(); ++r) {
    for (Eigen::Index c = 0; c < v.cols(); ++c) {
      rv.add(v(r, c), false);
      any_nan = any_nan || std::isnan(v(r, c));
    }
  }
  return rv;
}

// The legend: the named overlays, then the hatch when a cell is NaN. colours receives the colour
// of every overlay, named or not.
std::vector<LegendItem> heat_map_legend(const HeatMap& p, bool any_nan,
                                        std::vector<std::string>& colours) {
  std::vector<LegendItem> legend;
  std::size_t next = 0;
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
  return legend;
}

// The ticks of the x and y axes and of the colour bar (tv), and the scales of x and y.
struct HeatMapAxes {
  Ticks tx, ty, tv;
  Scale sx, sy;
};

// Ticks and scales in the plot area f, whose left and right ends (f.x0, f.x1) are set here to
// leave room for the y tick labels and the colour bar. The axes are linear whatever they say.
HeatMapAxes heat_map_axes(const HeatMap& p, const std::vector<double>& xe,
                          const std::vector<double>& ye, const Axis& va, const Range& rv,
                          Frame& f) {
  HeatMapAxes a;
  Range ry;
  ry.lo = ye.front();
  ry.hi = ye.back();
  Axis yax = p.y;
  yax.log = false;
  a.ty = make_y_ticks(yax, ry, f.y1 - f.y0, false);
  a.tv = make_ticks(va, rv, std::max(2, static_cast<int>((f.y1 - f.y0) / 45.0)), false);
  f.x0 = 26.0 + a.ty.max_label_width() + 10.0;
  f.x1 = f.W - colour_bar_width(a.tv);
  Range rx;
  rx.lo = xe.front();
  rx.hi = xe.back();
  Axis xax = p.x;
  xax.log = false;
  a.tx = make_x_ticks(xax, rx, f.x1 - f.x0, false);
  a.sx = Scale{a.tx.lo, a.tx.hi, f.x0, f.x1, false};
  a.sy = Scale{a.ty.lo, a.ty.hi, f.y1, f.y0, false};
  return a;
}

// The diagonal hatch of NaN cells (and of their legend swatch).
void hatch_def(Svg& s, const std::string& id) {
  s.f("<defs><pattern id=\"{}-h\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
      "patternTransform=\"rotate(45)\"><rect width=\"6\" height=\"6\" fill=\"#fff\"/>"
      "<path d=\"M0 0V6\" stroke=\"#999\" stroke-width=\"1.5\"/></pattern></defs>",
      esc(id));
}

void draw_cells(Svg& s, const ReducedMap& m, const std::vector<double>& ye, const HeatMapAxes& a,
                const std::string& id) {
  const Eigen::MatrixXd& v = m.v;
  const std::vector<double>& xe = m.xe;
  const Eigen::Index rows = v.rows(), cols = v.cols();
  const Scale &sx = a.sx, &sy = a.sy;
  const Ticks& tv = a.tv;
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
}

void draw_overlays(Svg& s, const HeatMap& p, const std::vector<std::string>& colours,
                   const Scale& sx, const Scale& sy, const std::string& id) {
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
}

}  // namespace

std::string render_svg(const HeatMap& p) {
  const std::string id = plot_id(p.id);
  std::vector<double> ye = edges_from_centres(p.y_centres, p.values.rows(), "y");
  std::vector<double> xe0 = edges_from_centres(p.x_centres, p.values.cols(), "x");
  const ReducedMap m = reduce_columns(p, xe0);
  bool any_nan = false;
  const Range rv = value_range(m.v, any_nan);
  Axis va = p.value;
  va.log = false;
  std::vector<std::string> colours;
  const std::vector<LegendItem> legend = heat_map_legend(p, any_nan, colours);

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_plot(s, id, p.title, legend, f);
  const HeatMapAxes a = heat_map_axes(p, m.xe, ye, va, rv, f);
  hover_attributes(s, f, a.tx, false, a.ty, false);
  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  hatch_def(s, id);
  clip_def(s, id, f);
  draw_cells(s, m, ye, a, id);
  draw_x_axis(s, f, a.sx, a.tx, p.x, false);
  draw_y_axis(s, f, a.sy, a.ty, p.y, false, false, 14.0);
  draw_colour_bar(s, f, a.tv, va, id);
  draw_overlays(s, p, colours, a.sx, a.sy, id);
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

}  // namespace redpost::report
