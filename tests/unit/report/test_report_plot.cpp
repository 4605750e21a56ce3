// The report writer (issue 9): plot scaling (nice ticks, min/max downsampling) against brute
// force and closed forms, and properties of the SVG/HTML output read back from the text.
#include <algorithm>
#include <clocale>
#include <cmath>
#include <limits>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/report/html_report.hpp"
#include "redpost/report/plot_scale.hpp"
#include "redpost/report/svg_plot.hpp"

using namespace redpost::report;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The mantissa of a positive number in [1, 10).
double mantissa(double v) {
  return v / std::pow(10.0, std::floor(std::log10(v) + 1e-12));
}

bool is_nice(double step) {
  const double m = mantissa(step);
  return std::abs(m - 1.0) < 1e-9 || std::abs(m - 2.0) < 1e-9 || std::abs(m - 5.0) < 1e-9;
}

// Numbers of an SVG attribute, e.g. data-px="x0 x1 y0 y1".
// The text between the first `open` in `svg` and the next double quote. Found with find rather
// than std::regex: libstdc++ matches [^"]* recursively, a stack frame per character, which
// overflows the stack on a long path under AddressSanitizer.
std::string quoted_after(const std::string& svg, const std::string& open) {
  const std::size_t start = svg.find(open);
  REQUIRE(start != std::string::npos);
  const std::size_t from = start + open.size();
  const std::size_t end = svg.find('"', from);
  REQUIRE(end != std::string::npos);
  return svg.substr(from, end - from);
}

// The numbers in a text, every other character (SVG path commands, commas) read as a blank.
std::vector<double> numbers_in(std::string text) {
  for (char& c : text) {
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == 'e'))
      c = ' ';
  }
  std::vector<double> v;
  std::istringstream in(text);
  for (double x; in >> x;)
    v.push_back(x);
  return v;
}

std::vector<double> attr_numbers(const std::string& svg, const std::string& name) {
  return numbers_in(quoted_after(svg, name + "=\""));
}

}  // namespace

TEST_CASE("report: nice_step is the smallest 1, 2, 5 x 10^k step within the interval count",
          "[report]") {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> exponent(-8.0, 8.0);
  std::uniform_int_distribution<int> target(1, 12);
  for (int k = 0; k < 5000; ++k) {
    const double span = std::pow(10.0, exponent(rng));
    const int n = target(rng);
    const double step = nice_step(span, n);
    CHECK(is_nice(step));
    // Brute force over all candidates: the smallest nice step giving at most n intervals.
    double best = std::numeric_limits<double>::infinity();
    for (int e = -12; e <= 12; ++e) {
      for (double m : {1.0, 2.0, 5.0}) {
        const double c = m * std::pow(10.0, e);
        if (span / c <= n * (1 + 1e-9))
          best = std::min(best, c);
      }
    }
    CHECK(step == Approx(best).epsilon(1e-12));
  }
  CHECK(nice_step(0.0, 5) == 1.0);
  CHECK(nice_step(kNaN, 5) == 1.0);
}

TEST_CASE("report: linear ticks are multiples of a nice step and cover the data", "[report]") {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> centre(-1e4, 1e4), lexp(-6.0, 5.0);
  std::uniform_int_distribution<int> target(2, 10);
  for (int k = 0; k < 3000; ++k) {
    const double c = centre(rng), half = std::pow(10.0, lexp(rng));
    const double lo = c - half * 0.3, hi = c + half;
    const int n = target(rng);
    const LinearTicks t = nice_linear_ticks(lo, hi, n, true);
    CHECK(is_nice(t.step));
    CHECK(t.lo <= lo);
    CHECK(t.hi >= hi);
    REQUIRE(t.ticks.size() >= 2);
    CHECK(t.ticks.size() <= static_cast<std::size_t>(n) + 2);  // n intervals plus expansion
    CHECK(t.ticks.front() == Approx(t.lo).margin(1e-9 * t.step));
    CHECK(t.ticks.back() == Approx(t.hi).margin(1e-9 * t.step));
    std::set<std::string> labels;
    for (std::size_t i = 0; i < t.ticks.size(); ++i) {
      const double q = t.ticks[i] / t.step;
      CHECK(std::abs(q - std::round(q)) < 1e-6 + 1e-14 * std::abs(q));  // double rounding
      if (i > 0) {
        CHECK(t.ticks[i] - t.ticks[i - 1] ==
              Approx(t.step).margin(1e-12 * std::abs(t.ticks[i])).epsilon(1e-6));
      }
      // Labels are distinct and read back as the tick value.
      const std::string label = format_tick(t.ticks[i], t.step);
      labels.insert(label);
      CHECK(std::stod(label) ==
            Approx(t.ticks[i]).margin(1e-6 * t.step + 1e-12 * std::abs(t.ticks[i])));
    }
    CHECK(labels.size() == t.ticks.size());
  }
  // Without expansion the range is the data's and the ticks lie inside it.
  const LinearTicks t = nice_linear_ticks(-0.33, 0.71, 5, false);
  CHECK(t.lo == -0.33);
  CHECK(t.hi == 0.71);
  CHECK(t.ticks.front() >= -0.33);
  CHECK(t.ticks.back() <= 0.71);
  // A constant series still gets a usable range around its value.
  const LinearTicks flat = nice_linear_ticks(5.0, 5.0, 5, true);
  CHECK(flat.lo < 5.0);
  CHECK(flat.hi > 5.0);
}

TEST_CASE("report: tick labels have the decimals of the step, no -0, no locale", "[report]") {
  CHECK(format_tick(0.1 + 0.2, 0.1) == "0.3");
  CHECK(format_tick(-1e-17, 0.1) == "0.0");
  CHECK(format_tick(1200.0, 200.0) == "1200");
  CHECK(format_tick(2.5, 0.5) == "2.5");
  CHECK(format_tick(0.125, 0.025) == "0.125");
  CHECK(format_tick(-0.0, 1.0) == "0");
  CHECK(format_log_tick(0.01) == "0.01");
  CHECK(format_log_tick(1e-6) == "1e-6");
  CHECK(format_log_tick(2e8) == "2e8");
  CHECK(num(-0.0001, 2).text == "0.00");
  CHECK(num(1234.5678, 1).text == "1234.6");
  // A decimal comma locale must not leak into the output (only checked where installed).
  for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8"}) {
    if (std::setlocale(LC_ALL, name) != nullptr) {
      CHECK(format_tick(2.5, 0.5) == "2.5");
      CHECK(num(3.25, 2).text == "3.25");
      std::setlocale(LC_ALL, "C");
      break;
    }
  }
}

TEST_CASE("report: log ticks are decades (and 2, 5 on short ranges) covering the data",
          "[report]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> e(-9.0, 9.0);
  for (int k = 0; k < 2000; ++k) {
    double a = std::pow(10.0, e(rng)), b = std::pow(10.0, e(rng));
    if (a > b)
      std::swap(a, b);
    const LogTicks t = nice_log_ticks(a, b, 5);
    CHECK(t.lo <= a * (1 + 1e-12));
    CHECK(t.hi >= b * (1 - 1e-12));
    CHECK(std::abs(mantissa(t.lo) - 1.0) < 1e-9);
    CHECK(std::abs(mantissa(t.hi) - 1.0) < 1e-9);
    REQUIRE(t.ticks.size() >= 2);
    CHECK(t.ticks.size() <= 12);
    for (double v : t.ticks)
      CHECK(is_nice(v));
    CHECK(std::is_sorted(t.ticks.begin(), t.ticks.end()));
  }
}

TEST_CASE("report: min/max downsampling keeps every bucket's extremes and the NaN gaps",
          "[report]") {
  std::mt19937_64 rng(12);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_int_distribution<int> length(1, 200000);
  for (int trial = 0; trial < 20; ++trial) {
    const std::size_t n = trial == 0 ? 4000 : static_cast<std::size_t>(length(rng));
    const int buckets = 100 + trial * 37;
    std::vector<double> y(n);
    double walk = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      walk += noise(rng);
      y[i] = walk;
    }
    // Single-sample spikes and a few NaN runs.
    for (int s = 0; s < 5; ++s)
      y[rng() % n] = (s % 2 ? -1.0 : 1.0) * 1e6;
    for (int g = 0; g < 3; ++g) {
      const std::size_t at = rng() % n;
      for (std::size_t i = at; i < std::min(n, at + 50); ++i)
        y[i] = kNaN;
    }
    MinMaxDecimator d(buckets);
    for (double v : y)
      d.push(v);
    const XYSeries r = d.result();
    CHECK(r.y.size() <= 3 * static_cast<std::size_t>(buckets));
    if (n <= 2 * static_cast<std::size_t>(buckets)) {
      // Short series come back unchanged (NaN stays NaN).
      REQUIRE(r.y.size() == n);
      for (std::size_t i = 0; i < n; ++i) {
        CHECK((r.y[i] == y[i] || (std::isnan(r.y[i]) && std::isnan(y[i]))));
      }
      continue;
    }
    // Brute force over the buckets the decimator says it used.
    const std::size_t w = d.bucket_width();
    CHECK((n + w - 1) / w <= static_cast<std::size_t>(buckets));
    // Result positions of the finite points, in order; x is the sample index.
    std::vector<std::size_t> finite_at;
    for (std::size_t k = 0; k < r.x.size(); ++k) {
      if (!std::isnan(r.y[k]))
        finite_at.push_back(k);
    }
    for (std::size_t k = 1; k < finite_at.size(); ++k) {
      CHECK(r.x[finite_at[k]] > r.x[finite_at[k - 1]]);  // in pushing order
    }
    auto has_nan = [&r](std::size_t from, std::size_t to) {  // a break in r[from, to)
      for (std::size_t k = from; k < to; ++k) {
        if (std::isnan(r.y[k]))
          return true;
      }
      return false;
    };
    std::size_t f = 0;  // index into finite_at
    for (std::size_t b0 = 0; b0 < n; b0 += w) {
      const std::size_t b1 = std::min(n, b0 + w);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      std::size_t ilo = 0, ihi = 0;
      bool nan = false;
      for (std::size_t i = b0; i < b1; ++i) {
        if (std::isnan(y[i])) {
          nan = true;
          continue;
        }
        if (y[i] < lo)
          lo = y[i], ilo = i;
        if (y[i] > hi)
          hi = y[i], ihi = i;
      }
      // This bucket's points: the finite result points with x in [b0, b1).
      const std::size_t first = f;
      std::vector<std::pair<double, double>> got;
      while (f < finite_at.size() && r.x[finite_at[f]] < static_cast<double>(b1)) {
        got.emplace_back(r.x[finite_at[f]], r.y[finite_at[f]]);
        ++f;
      }
      if (std::isfinite(lo)) {
        CHECK(std::find(got.begin(), got.end(), std::make_pair(double(ilo), lo)) != got.end());
        CHECK(std::find(got.begin(), got.end(), std::make_pair(double(ihi), hi)) != got.end());
      }
      for (const auto& [x, v] : got)
        CHECK(y[static_cast<std::size_t>(x)] == v);  // real samples
      // A gap in the bucket shows as a break between the neighbours' points; a bucket without
      // one has no break between its own points.
      const std::size_t from = first > 0 ? finite_at[first - 1] + 1 : 0;
      const std::size_t to = f < finite_at.size() ? finite_at[f] : r.y.size();
      if (nan)
        CHECK(has_nan(from, to));
      if (!nan && got.size() > 1)
        CHECK_FALSE(has_nan(finite_at[first], finite_at[f - 1]));
    }
    // The batch function is the same reduction.
    const XYSeries batch = downsample_min_max(nullptr, y.data(), n, buckets);
    CHECK(batch.y.size() == r.y.size());
  }
}

TEST_CASE("report: a one-sample peak in a long line survives into the SVG", "[report]") {
  const std::size_t n = 300000;
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 3; ++trial) {
    LinePlot p;
    p.y = make_axis("y", "mm");
    p.y.min = 0.0;
    p.y.max = 1.0;
    Series s;
    s.color = "#123456";
    s.y.assign(n, 0.0);
    s.y[rng() % n] = 1.0;
    p.series.push_back(s);
    const std::string svg = render_svg(p);
    const std::vector<double> px = attr_numbers(svg, "data-px");  // x0 x1 y0 y1
    // The series' path: the last d="..." before its stroke colour.
    const std::size_t stroke = svg.find("\" stroke=\"#123456\"");
    REQUIRE(stroke != std::string::npos);
    const std::size_t d_at = svg.rfind("<path d=\"", stroke);
    REQUIRE(d_at != std::string::npos);
    const std::string d = quoted_after(svg.substr(d_at, stroke - d_at + 1), "<path d=\"");
    // The plot is y = 0 except at the peak, which must reach the top of the plot area (y0).
    const std::vector<double> v = numbers_in(d);
    REQUIRE(v.size() >= 4);
    REQUIRE(v.size() % 2 == 0);
    double top = 1e9;
    for (std::size_t i = 1; i < v.size(); i += 2)
      top = std::min(top, v[i]);
    CHECK(top == Approx(px[2]).margin(0.06));
    CHECK(svg.size() < 200000);  // 300 000 points, downsampled
  }
}

TEST_CASE("report: output is deterministic, escaped and self-contained", "[report]") {
  auto build = [] {
    HtmlReport r("Report <of> \"run\" & more");
    r.add_summary("poses", "3");
    r.add_section("A section");
    Table t;
    t.header = {"name", "value [mm]"};
    t.rows.push_back({text("a<b"), num(1.5, 3)});
    r.add_table(t);
    LinePlot lp;
    lp.title = "line";
    Series s;
    s.name = "s";
    s.y = {1.0, kNaN, 3.0, 2.0};
    lp.series.push_back(s);
    r.add_plot(lp);
    BarPlot bp;
    bp.values = {3.0, 0.5};
    bp.y.log = true;
    r.add_plot(bp);
    Histogram h;
    HistogramSet hs;
    hs.values = {1, 2, 2, 3};
    h.sets.push_back(hs);
    r.add_plot(h);
    return r;
  };
  const HtmlReport r = build();
  const std::string a = r.html();
  CHECK(a == build().html());
  CHECK(r.plot_count() == 3);
  CHECK(a.find("Report &lt;of&gt; &quot;run&quot; &amp; more") != std::string::npos);
  CHECK(a.find("<td>a&lt;b</td>") != std::string::npos);
  CHECK(a.find("<td class=\"n\">1.500</td>") != std::string::npos);
  for (const char* id : {"id=\"plot-1\"", "id=\"plot-2\"", "id=\"plot-3\""}) {
    CHECK(a.find(id) != std::string::npos);
  }
  // Nothing to fetch: the only URL is the SVG namespace.
  std::regex url("https?://[^\"]*");
  for (auto it = std::sregex_iterator(a.begin(), a.end(), url); it != std::sregex_iterator();
       ++it) {
    CHECK(it->str() == "http://www.w3.org/2000/svg");
  }
}

TEST_CASE("report: inconsistent plot data is refused with a message", "[report]") {
  LinePlot p;
  Series s;
  s.x = {1, 2, 3};
  s.y = {1, 2};
  p.series.push_back(s);
  CHECK_THROWS_AS(render_svg(p), std::invalid_argument);
  HeatMap h;
  h.values = Eigen::MatrixXd::Zero(3, 4);
  h.x_centres = {0, 1, 2};
  CHECK_THROWS_AS(render_svg(h), std::invalid_argument);
  h.x_centres = {0, 1, 1, 2};
  CHECK_THROWS_AS(render_svg(h), std::invalid_argument);
}

TEST_CASE("report: a 2D view with equal scales has as many pixels per mm on both axes",
          "[report]") {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    XYView v;
    v.width = 400 + static_cast<int>(200 * (u(rng) + 1));
    PointSet s;
    const double sx = std::pow(10.0, 2 * u(rng)), sy = std::pow(10.0, 2 * u(rng));
    for (int i = 0; i < 50; ++i) {
      s.x.push_back(sx * u(rng) + 1000);
      s.y.push_back(sy * u(rng));
    }
    v.sets.push_back(s);
    const std::string svg = render_svg(v);
    const auto px = attr_numbers(svg, "data-px"), x = attr_numbers(svg, "data-x"),
               y = attr_numbers(svg, "data-y");
    const double kx = (px[1] - px[0]) / (x[1] - x[0]), ky = (px[3] - px[2]) / (y[1] - y[0]);
    CHECK(kx == Approx(ky).epsilon(1e-9));
    // Every point inside the shown range.
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      CHECK(s.x[i] >= x[0]);
      CHECK(s.x[i] <= x[1]);
      CHECK(s.y[i] >= y[0]);
      CHECK(s.y[i] <= y[1]);
    }
  }
}

TEST_CASE("report: heat map hatches NaN cells and merges equal cells along a row", "[report]") {
  HeatMap h;
  const int rows = 5, cols = 40;
  h.values = Eigen::MatrixXd::Constant(rows, cols, 2.0);
  h.values(2, 7) = kNaN;
  const std::string svg = render_svg(h);
  CHECK(svg.find("url(#plot-h)") != std::string::npos);
  // A constant matrix: one run per row, except the row with the NaN, which splits into three.
  std::size_t cells = 0;
  for (std::size_t at = svg.find("<g clip-path"); (at = svg.find('z', at)) != std::string::npos &&
                                                  at < svg.find("</g>", svg.find("<g clip-path"));
       ++at) {
    ++cells;
  }
  CHECK(cells == static_cast<std::size_t>(rows + 2));
  // Reducing the columns keeps an unreachable cell visible.
  h.max_columns = 8;
  CHECK(render_svg(h).find("url(#plot-h)\"/>") != std::string::npos);
}
