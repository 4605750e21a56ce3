// Plots as inline SVG for the HTML reports (issue 9).
//
// Each plot kind is a plain struct of data and labels; render_svg() turns it into one
// self-contained <svg class="plot"> element (no scripts, fonts or links outside it). Output is
// deterministic: the same plot gives the same bytes, numbers are written with fmt (never with
// the C locale), and colours come from a fixed palette in series order.
//
// Conventions shared by all kinds:
//   - NaN in the data is a gap (line plots break there, heat maps hatch the cell).
//   - Axis::unit is shown in brackets after the label: "feed [mm/min]".
//   - Axis::min/max fix the range; NaN (the default) takes it from the data with nice ticks.
//   - A colour is any SVG colour ("#1f77b4", "black"); empty picks the next palette colour.
//   - width/height are the SVG's natural size in CSS pixels; the defaults fit a 1366x768
//     screen at 1:1 with the fonts readable: wide plots (1240) one per row, small ones (620) two
//     side by side, three of 420 in a row. The page may scale plots down, never up, unless
//     the reader clicks one to enlarge it.
//   - id must be unique within one HTML page (it scopes clip paths and patterns); the
//     HtmlReport assigns one when it is left empty.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace redpost::report {

struct Axis {
  std::string label;  // what is plotted, "joint position"
  std::string unit;   // "mm", "deg", "1"; empty: no brackets
  bool log = false;   // base-10 logarithmic (non-positive values are then gaps)
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};

// An axis in one call (aggregate initialisation of Axis leaves min/max unnamed and warns).
inline Axis make_axis(std::string label, std::string unit, bool log = false) {
  Axis a;
  a.label = std::move(label);
  a.unit = std::move(unit);
  a.log = log;
  return a;
}

// One line of a LinePlot, or one polyline over a HeatMap.
struct Series {
  std::string name;       // legend text; empty: not in the legend
  std::vector<double> x;  // empty: the sample index 0, 1, 2, ...
  std::vector<double> y;  // NaN: a gap
  std::string color;
  bool markers = false;  // a dot at each point (drawn only up to 600 points)
  bool dashed = false;
  bool right_axis = false;  // against LinePlot::y2
  double line_width = 1.5;
};

// A horizontal line across the plot: a threshold, a limit.
struct HLine {
  double y = 0.0;
  std::string name;  // written at the right end of the line and in the legend
  std::string color = "#d62728";
  bool right_axis = false;
};

// A shaded horizontal band y_lo..y_hi: a forbidden zone, a limit margin.
struct HBand {
  double y_lo = 0.0;
  double y_hi = 0.0;
  std::string name;
  std::string color = "#d62728";
  double opacity = 0.12;
};

// Several series against an index or x value, on one or two y axes. Series longer than
// 2 * max_buckets points are downsampled min/max per bucket (MinMaxDecimator), so peaks stay.
struct LinePlot {
  std::string title;
  Axis x;
  Axis y;
  bool has_y2 = false;
  Axis y2;  // right-hand axis when has_y2
  std::vector<Series> series;
  std::vector<HLine> hlines;
  std::vector<HBand> bands;
  int max_buckets = 2000;
  int width = 1240;
  int height = 340;
  std::string id;
};

// Histograms of several data sets over the same bins, overlaid (before/after).
struct HistogramSet {
  std::string name;
  std::vector<double> values;  // NaN values are left out (and counted in the legend)
  std::string color;
};

struct Histogram {
  std::string title;
  Axis x;
  std::string y_label = "count";
  std::vector<HistogramSet> sets;
  int bins = 30;  // about this many; the bin width is a nice number
  int width = 620;
  int height = 320;
  std::string id;
};

// Bars over named categories (singular values, per-axis figures). y.log draws bars from the
// bottom of the log axis; non-positive values are then left out.
struct BarPlot {
  std::string title;
  std::string x_label;
  Axis y;
  std::vector<std::string> categories;
  std::vector<double> values;
  std::string color = "#1f77b4";
  int width = 620;
  int height = 320;
  std::string id;
};

// A matrix of values over two grids (path point x beta), coloured by value with a colour bar;
// NaN cells are hatched (unreachable). values(r, c) sits at (x_centres[c], y_centres[r]); the
// centres must increase. Wider matrices than max_columns are reduced by averaging groups of
// adjacent columns (a group with any NaN stays NaN, so unreachable points stay visible).
// overlays are polylines in the same (x, y) coordinates: best and worst plans.
struct HeatMap {
  std::string title;
  Axis x;
  Axis y;
  Axis value;                     // colour-bar label, unit and range (log not supported)
  std::vector<double> x_centres;  // empty: 0, 1, 2, ... (column index)
  std::vector<double> y_centres;  // empty: 0, 1, 2, ... (row index)
  Eigen::MatrixXd values;
  std::string nan_label = "unreachable";
  std::vector<Series> overlays;
  int max_columns = 600;
  int width = 1240;
  int height = 380;
  std::string id;
};

// Points or a polyline in a plane, optionally coloured by a scalar (then with a colour bar).
struct PointSet {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> value;  // empty, or one per point: colour by the colour scale
  std::string color;          // used when value is empty
  bool connect = false;       // draw as a polyline (coloured per segment when valued)
  bool markers = true;        // a dot at each point
  double marker_radius = 2.5;
};

// An axis-aligned rectangle: a work volume, a table, a reach limit.
struct Rect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  std::string name;
  std::string color = "#555555";
  double fill_opacity = 0.08;
};

// A 2D view (top view of a work volume, toolpath projections XY / XZ / YZ). With equal_scale
// one mm is as long on both axes (the ranges grow to fill the plot area). Each set is thinned
// in screen space (points closer than a pixel tolerance to the last kept one are dropped; the
// tolerance doubles until at most max_points_per_set remain), so a million-point toolpath
// stays small.
struct XYView {
  std::string title;
  Axis x;
  Axis y;
  bool equal_scale = true;  // ignores log on x and y
  Axis colour;              // the colour bar of valued sets: label, unit, range
  std::vector<PointSet> sets;
  std::vector<Rect> rects;
  int max_points_per_set = 20000;
  int width = 620;
  int height = 460;
  std::string id;
};

// One <svg class="plot" id=...> element. Throws std::invalid_argument when the data is
// inconsistent (x and y of different lengths, a heat-map grid that does not match the matrix).
std::string render_svg(const LinePlot& plot);
std::string render_svg(const Histogram& plot);
std::string render_svg(const BarPlot& plot);
std::string render_svg(const HeatMap& plot);
std::string render_svg(const XYView& plot);

// The palette colour of series number k (fixed order, distinguishable, 12 entries, repeating).
const char* palette_colour(std::size_t k);

// The colour map of heat maps and valued point sets at t in [0, 1] (viridis-like, dark blue to
// yellow, readable in greyscale), as "#rrggbb".
std::string colour_map(double t);

}  // namespace redpost::report
