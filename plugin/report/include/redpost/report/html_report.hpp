// A self-contained HTML report (issue 9): one file, inline CSS, inline SVG plots and a small
// inline script for hover read-outs and click-to-enlarge. Nothing is fetched from anywhere, so
// the file opens on an offline shop-floor PC.
//
// Build it top to bottom: a title, summary rows (the metadata table under the title), then
// sections with paragraphs, tables and plots. Plots are rendered when they are added, so the
// caller may drop its data right after. The same calls give the same bytes: there is no
// timestamp unless the caller puts one in a summary row.
#pragma once

#include <string>
#include <vector>

#include "redpost/report/scene3d.hpp"
#include "redpost/report/svg_plot.hpp"

namespace redpost::report {

// A table cell: text as given, numbers right-aligned.
struct TableCell {
  std::string text;
  bool numeric = false;
};

// A number with a fixed count of decimals (fmt, locale-independent); NaN and inf as "NaN",
// "inf", "-inf". Right-aligned.
TableCell num(double value, int decimals);
// An integer count. Right-aligned.
TableCell count(long long value);
// Text. Left-aligned.
TableCell text(std::string value);

struct Table {
  std::string caption;              // optional, shown above the table
  std::vector<std::string> header;  // column titles (with units: "E1 [mm]")
  std::vector<std::vector<TableCell>> rows;
};

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  // A key/value row of the summary table right under the title (input file, cell, counts).
  void add_summary(std::string key, std::string value);
  // Replaces the value of the summary row `key` (added if there is none): for a count known
  // only once the sections are made.
  void set_summary(const std::string& key, std::string value);
  // Starts a new section with an <h2> heading; what follows belongs to it.
  void add_section(std::string heading);
  void add_paragraph(std::string text);
  // A paragraph styled as a warning (red-brown border), for limits hit and the like.
  void add_warning(std::string text);
  void add_table(const Table& table);

  // Plots; an empty id becomes "plot-<n>" (n counts the plots of this report from 1).
  void add_plot(LinePlot plot);
  void add_plot(Histogram plot);
  void add_plot(BarPlot plot);
  void add_plot(HeatMap plot);
  void add_plot(XYView plot);
  // A pre-rendered <svg class="plot"> (its ids must not clash with the report's plot-<n>).
  void add_svg(std::string svg);

  // A 3D view of the cell running its program (scene3d.hpp), id "scene-<n>". The page then
  // inlines three.js and the view's script once, after the last view (about 650 KB).
  void add_scene3d(const Scene3d& scene);

  int plot_count() const { return plots_; }
  int scene_count() const { return scenes_; }
  int warning_count() const { return warnings_; }

  // The whole document. The host writes it (the CLI through redpost::write_text_file: a
  // temporary, fsync and a rename, so a reader never sees half a report); the report library
  // draws and never touches the disk.
  std::string html() const;

 private:
  std::string next_id();

  std::string title_;
  std::vector<std::pair<std::string, std::string>> summary_;
  std::string body_;
  bool in_section_ = false;
  int plots_ = 0;
  int scenes_ = 0;
  int warnings_ = 0;
};

}  // namespace redpost::report
