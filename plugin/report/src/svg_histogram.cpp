// Histogram as SVG (see svg_plot.hpp): several data sets counted over the same nice bins and
// drawn as overlaid translucent step outlines.
#include "redpost/report/svg_plot.hpp"

#include "escape.hpp"
#include "svg_draw.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "redpost/report/plot_scale.hpp"

namespace redpost::report {

using namespace svg;

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
  const double top = open_plot(s, id, p.title, legend, f);
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

}  // namespace redpost::report
