// LinePlot as SVG (see svg_plot.hpp): series against an index or x value on one or two y axes,
// long series downsampled min/max, with shaded bands behind and horizontal lines in front.
#include "redpost/report/svg_plot.hpp"

#include "escape.hpp"
#include "svg_draw.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "redpost/report/plot_scale.hpp"

namespace redpost::report {

using namespace svg;

namespace {

// Reduce long series first: all later work is on at most ~3 * max_buckets points each.
std::vector<XYSeries> reduced_series(const LinePlot& p) {
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
  return data;
}

// The data ranges of the x axis and of the left and right y axes.
struct LineRanges {
  Range x, y, y2;
};

// The ranges over the (reduced) series, the horizontal lines and the bands.
LineRanges line_ranges(const LinePlot& p, const std::vector<XYSeries>& data) {
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
  return {rx, ry, ry2};
}

// The legend: the named series, then the bands, then the lines. colours receives the colour of
// every series, named or not.
std::vector<LegendItem> line_legend(const LinePlot& p, std::vector<std::string>& colours) {
  std::vector<LegendItem> legend;
  std::size_t next = 0;
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
  return legend;
}

// The ticks and scales of the x axis and of the left and right y axes.
struct LineAxes {
  Ticks tx, ty, ty2;
  Scale sx, sy, sy2;
};

// Ticks and scales in the plot area f, whose left and right ends (f.x0, f.x1) are set here to
// leave room for the tick labels of the y axes.
LineAxes line_axes(const LinePlot& p, const LineRanges& r, Frame& f) {
  LineAxes a;
  a.ty = make_y_ticks(p.y, r.y, f.y1 - f.y0, true);
  a.ty2 = p.has_y2 ? make_y_ticks(p.y2, r.y2, f.y1 - f.y0, true) : Ticks{};
  f.x0 = 26.0 + a.ty.max_label_width() + 10.0;
  f.x1 = f.W - (p.has_y2 ? 26.0 + a.ty2.max_label_width() + 10.0 : 20.0);
  a.tx = fit_x_ticks(p.x, r.x, f, true);
  a.sx = Scale{a.tx.lo, a.tx.hi, f.x0, f.x1, p.x.log};
  a.sy = Scale{a.ty.lo, a.ty.hi, f.y1, f.y0, p.y.log};
  a.sy2 = Scale{a.ty2.lo, a.ty2.hi, f.y1, f.y0, p.y2.log};
  return a;
}

void draw_bands(Svg& s, const LinePlot& p, const Frame& f, const Scale& sy, const std::string& id) {
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
}

// The series' lines and their markers (for series of at most kMaxMarkers points).
void draw_series(Svg& s, const LinePlot& p, const std::vector<XYSeries>& data,
                 const std::vector<std::string>& colours, const LineAxes& a) {
  const Scale& sx = a.sx;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const Series& se = p.series[k];
    const Scale& yk = p.has_y2 && se.right_axis ? a.sy2 : a.sy;
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
}

void draw_hlines(Svg& s, const LinePlot& p, const Frame& f, const LineAxes& a) {
  for (const HLine& h : p.hlines) {
    const Scale& yk = p.has_y2 && h.right_axis ? a.sy2 : a.sy;
    if (!yk.usable(h.y))
      continue;
    s.f("<path d=\"M{:.1f} {:.1f}H{:.1f}\" stroke=\"{}\" stroke-width=\"1.5\" "
        "stroke-dasharray=\"6 4\"/>",
        f.x0, yk(h.y), f.x1, esc(h.color));
  }
}

}  // namespace

std::string render_svg(const LinePlot& p) {
  const std::string id = plot_id(p.id);
  const std::vector<XYSeries> data = reduced_series(p);
  const LineRanges ranges = line_ranges(p, data);
  std::vector<std::string> colours;
  const std::vector<LegendItem> legend = line_legend(p, colours);

  Frame f;
  f.W = p.width;
  f.H = p.height;
  Svg s;
  const double top = open_plot(s, id, p.title, legend, f);
  const LineAxes a = line_axes(p, ranges, f);
  hover_attributes(s, f, a.tx, p.x.log, a.ty, p.y.log);

  draw_legend(s, legend, 20.0, top, f.W - 40.0, id);
  clip_def(s, id, f);
  draw_bands(s, p, f, a.sy, id);
  draw_x_axis(s, f, a.sx, a.tx, p.x, true);
  draw_y_axis(s, f, a.sy, a.ty, p.y, true, false, 14.0);
  if (p.has_y2)
    draw_y_axis(s, f, a.sy2, a.ty2, p.y2, false, true, f.W - 10.0);

  s.f("<g clip-path=\"url(#{}-c)\" fill=\"none\" stroke-linecap=\"round\" "
      "stroke-linejoin=\"round\">",
      esc(id));
  draw_series(s, p, data, colours, a);
  draw_hlines(s, p, f, a);
  s.f("</g>");
  draw_box_and_readout(s, f);
  s.f("</svg>");
  return std::move(s.s);
}

}  // namespace redpost::report
