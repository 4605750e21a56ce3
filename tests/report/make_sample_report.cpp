// Writes a sample report that uses every plot kind of redpost::report, with data shaped like
// that of convert, calibrate and place (synthetic, deterministic). The browser check
// (render_check.sh) renders it headless. Usage: make_sample_report OUT.html
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <utility>

#include "redpost/io/durable_write.hpp"
#include "redpost/report/html_report.hpp"

using namespace redpost::report;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A small deterministic pseudo-random sequence (the same on every platform, unlike
// std::uniform_real_distribution).
struct Lcg {
  unsigned long long s = 12345;
  double next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  }
};

template <typename T>
T named(std::string name) {
  T t;
  t.name = std::move(name);
  return t;
}

HLine hline(double y, std::string name) {
  HLine h;
  h.y = y;
  h.name = std::move(name);
  return h;
}

HBand hband(double lo, double hi, std::string name) {
  HBand b;
  b.y_lo = lo;
  b.y_hi = hi;
  b.name = std::move(name);
  return b;
}

void convert_section(HtmlReport& r) {
  r.add_section("Convert: joints, conditioning, external axes");
  const int n = 20000;  // poses: long enough to be downsampled
  LinePlot joints;
  joints.title = "Joint positions, normalised to their limits";
  joints.x = make_axis("pose", "", false);
  joints.y = make_axis("position in range", "1", false);
  joints.y.min = 0.0;
  joints.y.max = 1.0;
  joints.bands.push_back(hband(0.0, 0.05, "within 5 % of a limit"));
  joints.bands.push_back(hband(0.95, 1.0, ""));
  const char* names[] = {"A1", "A2", "A3", "A4", "A5", "A6", "E1 track", "E2 table", "spin"};
  for (int j = 0; j < 9; ++j) {
    Series s;
    s.name = names[j];
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / n;
      double v = 0.5 + 0.35 * std::sin(2 * kPi * (j + 1) * 0.7 * t + j);
      if (j == 4 && i == 12345)
        v = 0.985;  // a one-pose peak: must survive downsampling
      if (j == 8 && i > 7000 && i < 7600)
        v = kNaN;  // a gap
      s.y.push_back(v);
    }
    joints.series.push_back(std::move(s));
  }
  r.add_plot(std::move(joints));

  LinePlot kappa;
  kappa.title = "Inverse condition number 1/kappa_F of the arm Jacobian";
  kappa.x = make_axis("pose", "", false);
  kappa.y = make_axis("1/kappa_F", "1", false);
  Series inv;
  inv.name = "1/kappa_F";
  for (int i = 0; i < n; ++i) {
    inv.y.push_back(0.18 + 0.1 * std::cos(i * 0.0011) + 0.04 * std::sin(i * 0.013));
  }
  kappa.series.push_back(std::move(inv));
  kappa.hlines.push_back(hline(0.1, "switch threshold 0.1"));
  r.add_plot(std::move(kappa));

  LinePlot ext;
  ext.title = "External axes";
  ext.x = make_axis("pose", "", false);
  ext.y = make_axis("track E1", "mm", false);
  ext.has_y2 = true;
  ext.y2 = make_axis("table E2", "deg", false);
  Series e1 = named<Series>("E1 track"), e2 = named<Series>("E2 table");
  e2.right_axis = true;
  e2.dashed = true;
  for (int i = 0; i < n; ++i) {
    e1.y.push_back(1200.0 + 850.0 * std::sin(i * 0.0004));
    e2.y.push_back(-90.0 + 170.0 * std::sin(i * 0.00023 + 1.0));
  }
  ext.series.push_back(std::move(e1));
  ext.series.push_back(std::move(e2));
  r.add_plot(std::move(ext));

  Table t;
  t.caption = "Joint usage";
  t.header = {"joint", "min [deg]", "max [deg]", "closest to a limit [deg]", "poses near a limit"};
  for (int j = 0; j < 6; ++j) {
    t.rows.push_back({text(names[j]), num(-120.0 + 13.3 * j, 2), num(95.5 - 7.1 * j, 2),
                      num(4.25 * (j + 1), 2), count(j * 17)});
  }
  r.add_table(t);
}

void calibrate_section(HtmlReport& r) {
  r.add_section("Calibrate: identification");
  LinePlot params;
  params.title = "Parameters per iteration";
  params.x = make_axis("iteration", "", false);
  params.y = make_axis("parameter change from nominal", "mm", false);
  const char* pn[] = {"track x0", "track y0", "table x", "table y"};
  for (int k = 0; k < 4; ++k) {
    Series s = named<Series>(pn[k]);
    s.markers = true;
    for (int it = 0; it < 8; ++it) {
      s.x.push_back(it);
      s.y.push_back((k + 1) * 0.8 * (1.0 - std::exp(-0.9 * it)) * (k % 2 == 0 ? 1.0 : -1.0));
    }
    params.series.push_back(std::move(s));
  }
  params.width = 620;
  params.height = 300;
  r.add_plot(std::move(params));

  LinePlot rms;
  rms.title = "Residual RMS per iteration";
  rms.x = make_axis("iteration", "", false);
  rms.y = make_axis("residual RMS", "mm", true);
  Series s = named<Series>("RMS");
  s.markers = true;
  for (int it = 0; it < 8; ++it) {
    s.x.push_back(it);
    s.y.push_back(2.5 * std::pow(0.12, it) + 0.004);
  }
  rms.series.push_back(std::move(s));
  rms.hlines.push_back(hline(0.01, "laser noise 0.01 mm"));
  rms.width = 620;
  rms.height = 300;
  r.add_plot(std::move(rms));

  Histogram h;
  h.title = "Residuals before and after calibration";
  h.x = make_axis("residual", "mm", false);
  Lcg g;
  HistogramSet before = named<HistogramSet>("before"), after = named<HistogramSet>("after");
  for (int i = 0; i < 600; ++i) {
    // Sums of uniforms: roughly normal, fixed across platforms.
    double a = 0, b = 0;
    for (int k = 0; k < 6; ++k)
      a += g.next() - 0.5, b += g.next() - 0.5;
    before.values.push_back(0.6 + 1.1 * a);
    after.values.push_back(0.05 * b);
  }
  after.values.push_back(kNaN);
  h.sets = {before, after};
  r.add_plot(std::move(h));

  BarPlot sv;
  sv.title = "Singular values of the identification Jacobian";
  sv.x_label = "singular value";
  sv.y = make_axis("sigma", "mm", true);
  for (int k = 0; k < 7; ++k) {
    sv.categories.push_back("s" + std::to_string(k + 1));
    sv.values.push_back(900.0 * std::pow(0.22, k));
  }
  r.add_plot(std::move(sv));
}

void place_section(HtmlReport& r) {
  r.add_section("Place: workpiece placement and tool spin");
  HeatMap hm;
  hm.title = "Deflection along the path over the tool spin beta";
  hm.x = make_axis("path point", "", false);
  hm.y = make_axis("beta", "deg", false);
  hm.value = make_axis("deflection", "mm", false);
  const int cols = 900, rows = 72;
  hm.values.resize(rows, cols);
  for (int b = 0; b < rows; ++b)
    hm.y_centres.push_back(-180.0 + 5.0 * b + 2.5);
  for (int c = 0; c < cols; ++c) {
    for (int b = 0; b < rows; ++b) {
      const double beta = hm.y_centres[b] * kPi / 180.0;
      double v = 0.05 + 0.03 * std::sin(beta + c * 0.01) + 0.02 * std::cos(2 * beta - c * 0.004);
      if (b > 50 && b < 60 && c > 300 && c < 420)
        v = kNaN;  // unreachable
      hm.values(b, c) = v;
    }
  }
  Series best = named<Series>("best plan"), worst = named<Series>("worst plan");
  for (int c = 0; c < cols; c += 10) {
    best.x.push_back(c);
    best.y.push_back(-120.0 + 40.0 * std::sin(c * 0.006));
    worst.x.push_back(c);
    worst.y.push_back(60.0 + 50.0 * std::cos(c * 0.005));
  }
  worst.dashed = true;
  hm.overlays = {best, worst};
  r.add_plot(std::move(hm));

  XYView top;
  top.title = "Top view: work volume and candidate placements";
  top.x = make_axis("x", "mm", false);
  top.y = make_axis("y", "mm", false);
  Rect volume;
  volume.x0 = 600.0, volume.y0 = -800.0, volume.x1 = 2200.0, volume.y1 = 900.0;
  volume.name = "work volume";
  top.rects.push_back(volume);
  PointSet cand = named<PointSet>("candidates"), chosen = named<PointSet>("chosen");
  Lcg g;
  for (int i = 0; i < 120; ++i) {
    cand.x.push_back(700.0 + 1400.0 * g.next());
    cand.y.push_back(-700.0 + 1500.0 * g.next());
  }
  chosen.x = {1450.0};
  chosen.y = {80.0};
  chosen.marker_radius = 6.0;
  top.sets = {cand, chosen};
  r.add_plot(std::move(top));

  // A helical toolpath seen from three sides, coloured by feed.
  const char* views[][3] = {{"XY", "x", "y"}, {"XZ", "x", "z"}, {"YZ", "y", "z"}};
  for (auto& v : views) {
    XYView tp;
    tp.title = std::string("Toolpath, ") + v[0] + " projection";
    tp.x = {v[1], "mm", false};
    tp.y = {v[2], "mm", false};
    tp.colour = make_axis("feed", "mm/min", false);
    PointSet path = named<PointSet>("toolpath");
    path.connect = true;
    path.markers = false;
    for (int i = 0; i < 50000; ++i) {
      const double t = i * 0.002;
      const double p[3] = {300.0 * std::cos(t), 180.0 * std::sin(t), -2.0 * t};
      path.x.push_back(p[v[1][0] - 'x']);
      path.y.push_back(p[v[2][0] - 'x']);
      path.value.push_back(1500.0 + 1000.0 * std::sin(3 * t));
    }
    tp.sets = {path};
    tp.width = 420;
    tp.height = 400;
    r.add_plot(std::move(tp));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_sample_report OUT.html\n");
    return 2;
  }
  try {
    HtmlReport r("redpost sample report");
    r.add_summary("input", "examples/sample.cls (synthetic data)");
    r.add_summary("cell", "definitions/cells/andres2011_track_table.xml");
    r.add_summary("poses", "20000");
    convert_section(r);
    calibrate_section(r);
    place_section(r);
    redpost::write_text_file(argv[1], r.html());
    std::printf("%d\n", r.plot_count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_sample_report: %s\n", e.what());
    return 1;
  }
  return 0;
}
