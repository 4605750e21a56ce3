// The SVG writer and what every plot kind draws with it (svg_*.cpp): the opening tag and title,
// the legend, the axes, the colour bar, polylines and dots, and the colours of series and
// colour-mapped values. Where things go is computed in svg_layout.hpp.
//
// The legend wraps into rows above the plot area, where it can never hide data.
#pragma once

#include <fmt/format.h>

#include <cstddef>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "svg_layout.hpp"

namespace redpost::report::svg {

constexpr double kLegendRow = 18.0;
constexpr int kColourBins = 64;
constexpr std::size_t kMaxMarkers = 600;

// The SVG text being written; f() appends formatted text.
struct Svg {
  std::string s;
  template <typename... A>
  void f(fmt::format_string<A...> format, A&&... args) {
    fmt::format_to(std::back_inserter(s), format, std::forward<A>(args)...);
  }
};

// --- colours ---------------------------------------------------------------------------------

// The colour bin (0 .. kColourBins - 1) of v on the colour scale lo..hi.
int colour_bin(double v, double lo, double hi);

// The colour-map colour at the centre of a bin.
std::string bin_colour(int bin);

// colour, or the next palette colour when it is empty.
std::string pick(const std::string& colour, std::size_t& next);

// --- legend ----------------------------------------------------------------------------------

enum class Swatch { line, dashed, dots, line_dots, patch, hatch };

struct LegendItem {
  std::string name;
  std::string colour;
  Swatch swatch = Swatch::line;
  double opacity = 1.0;
};

// The number of rows the legend wraps into within max_width.
int legend_rows(const std::vector<LegendItem>& items, double max_width);

void draw_legend(Svg& s, const std::vector<LegendItem>& items, double left, double top,
                 double max_width, const std::string& id);

// --- frame -----------------------------------------------------------------------------------

// Opens the <svg>, paints the background and the title, and returns the top of what follows.
double open_svg(Svg& s, const std::string& id, double W, double H, const std::string& title);

// Opens the <svg> of a plot of f.W x f.H with a legend above the plot area (open_svg), sets the
// top and bottom of the plot area (f.y0, f.y1) and returns the top of the legend.
double open_plot(Svg& s, const std::string& id, const std::string& title,
                 const std::vector<LegendItem>& legend, Frame& f);

// The hover read-out hook: the page script turns pointer positions into data values with these.
void hover_attributes(Svg& s, const Frame& f, const Ticks& tx, bool xlog, const Ticks& ty,
                      bool ylog);

void clip_def(Svg& s, const std::string& id, const Frame& f);

void draw_x_axis(Svg& s, const Frame& f, const Scale& sx, const Ticks& t, const Axis& ax,
                 bool grid);

// A y axis on the left (right = false) or on the right of the plot area.
void draw_y_axis(Svg& s, const Frame& f, const Scale& sy, const Ticks& t, const Axis& ax, bool grid,
                 bool right, double label_x);

void draw_box_and_readout(Svg& s, const Frame& f);

// The width right of the plot area that draw_colour_bar occupies.
double colour_bar_width(const Ticks& t);

// A vertical colour bar right of the plot area; returns nothing, occupies colour_bar_width().
void draw_colour_bar(Svg& s, const Frame& f, const Ticks& t, const Axis& ax, const std::string& id);

// --- paths -----------------------------------------------------------------------------------

// Appends a polyline through (x, y) with breaks at NaN; a lone point between gaps becomes a
// zero-length segment, which the round line cap shows as a dot. Points that land on the same
// 0.1 px as the previous one are dropped.
void append_polyline(std::string& d, const double* x, const double* y, std::size_t n,
                     const Scale& sx, const Scale& sy);

// Dots as zero-length round-capped segments: one path element for any number of points.
void append_dots(std::string& d, double px, double py);

// Throws std::invalid_argument when x is given but not one per y.
void check_xy(const std::vector<double>& x, const std::vector<double>& y, const std::string& what,
              const std::string& name);

// The plot's id, "plot" when empty.
std::string plot_id(const std::string& id);

}  // namespace redpost::report::svg
