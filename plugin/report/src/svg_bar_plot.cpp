// BarPlot as SVG (see svg_plot.hpp): one bar per named category, with the value written over
// each bar when there is room.
#include "redpost/report/svg_plot.hpp"

#include "escape.hpp"
#include "svg_draw.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace redpost::report {

using namespace svg;

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

}  // namespace redpost::report
