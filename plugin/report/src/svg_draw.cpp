// The SVG writer's shared drawing, and the palette and colour map (see svg_draw.hpp and
// svg_plot.hpp).
#include "svg_draw.hpp"

#include "escape.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace redpost::report::svg {

namespace {

constexpr double kTitleFont = 15.0;
constexpr const char* kFontFamily = "DejaVu Sans, Arial, Helvetica, sans-serif";

struct Rgb {
  double r, g, b;
};

// Anchors of a viridis-like map: perceptually ordered, dark to light, colour-blind safe.
constexpr Rgb kMap[] = {{68, 1, 84},    {72, 40, 120},  {62, 73, 137},
                        {49, 104, 142}, {38, 130, 142}, {31, 158, 137},
                        {53, 183, 121}, {110, 206, 88}, {253, 231, 37}};

double legend_item_width(const LegendItem& it) {
  return 28.0 + text_width(it.name) + 16.0;
}

constexpr double kBarGap = 14.0, kBarWidth = 16.0;

}  // namespace

// --- colours ---------------------------------------------------------------------------------

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

// --- legend ----------------------------------------------------------------------------------

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

// --- frame -----------------------------------------------------------------------------------

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

double open_plot(Svg& s, const std::string& id, const std::string& title,
                 const std::vector<LegendItem>& legend, Frame& f) {
  const double top = open_svg(s, id, f.W, f.H, title);
  const int rows = legend_rows(legend, f.W - 40.0);
  f.y0 = top + rows * kLegendRow + (rows > 0 ? 8.0 : 0.0);
  f.y1 = f.H - 46.0;
  return top;
}

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

}  // namespace redpost::report::svg

namespace redpost::report {

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
  const svg::Rgb& a = svg::kMap[i];
  const svg::Rgb& b = svg::kMap[i + 1];
  auto mix = [u](double p, double q) { return static_cast<int>(std::lround(p + u * (q - p))); };
  return fmt::format("#{:02x}{:02x}{:02x}", mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b));
}

}  // namespace redpost::report
