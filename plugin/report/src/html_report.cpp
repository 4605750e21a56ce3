// The HTML page around the plots (see html_report.hpp).
#include "redpost/report/html_report.hpp"

#include "escape.hpp"
#include "scene3d_html.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace redpost::report {

namespace {

// Sized for a 1366x768 screen: the page is at most 1340 px wide, figures flow side by side and
// plots keep their natural size (readable at 1:1) unless the window is narrower.
constexpr const char* kStyle = R"(
body{margin:0;background:#f4f4f4;color:#111;font:14px/1.4 "DejaVu Sans",Arial,Helvetica,sans-serif}
main{max-width:1340px;margin:0 auto;padding:12px 16px 24px;background:#fff}
h1{font-size:22px;margin:6px 0 10px}
h2{font-size:18px;margin:22px 0 8px;padding-top:8px;border-top:1px solid #ccc}
p{margin:6px 0;max-width:1000px}
p.warn{border-left:4px solid #b35806;padding:4px 8px;background:#fdf1e6}
table{border-collapse:collapse;margin:8px 0 14px;font-size:13px}
caption{text-align:left;font-weight:bold;padding:2px 0 4px}
th,td{border:1px solid #ccc;padding:3px 8px;vertical-align:top}
th{background:#eee;text-align:left}
td.n{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
table.meta th{white-space:nowrap}
figure{display:inline-block;vertical-align:top;margin:8px 10px 10px 0}
svg.plot{display:block;max-width:100%;height:auto;cursor:crosshair;border:1px solid #ddd}
svg.plot.zoom{width:100%}
footer{margin-top:24px;color:#666;font-size:12px}
div.scene3d{max-width:1240px;margin:8px 0}
canvas.s3-canvas{display:block;border:1px solid #ddd;cursor:grab}
div.s3-controls{display:flex;align-items:center;gap:10px;margin:6px 0}
input.s3-slider{flex:1}
span.s3-readout{font-size:12px;font-variant-numeric:tabular-nums;min-width:520px}
div.s3-colour{font-size:13px}
span.s3-bar{display:inline-flex;align-items:center;gap:6px}
span.s3-bar span{position:relative;display:inline-block;width:220px;height:12px;border:1px solid #999}
span.s3-bar i{position:absolute;top:-3px;bottom:-3px;width:2px;background:#d62728}
div.s3-msg{color:#b35806}
)";

// Hover read-out (data coordinates under the pointer, from the data-px/x/y attributes of each
// plot) and click-to-enlarge. The last line marks the page as done, for the browser check.
constexpr const char* kScript = R"(
(function(){
function f(v){var a=Math.abs(v);if(a!==0&&(a<1e-3||a>=1e6))return v.toExponential(3);return String(+v.toPrecision(5));}
function inv(p,p0,p1,a,b,lg){var t=(p-p0)/(p1-p0);if(lg){var l=Math.log(a)+t*(Math.log(b)-Math.log(a));return Math.exp(l);}return a+t*(b-a);}
var plots=document.querySelectorAll('svg.plot');
for(var i=0;i<plots.length;i++){(function(s){
var ro=s.querySelector('text.ro');if(!ro||!s.dataset.px)return;
var px=s.dataset.px.split(' ').map(Number);
var ax=s.dataset.x?s.dataset.x.split(' ').map(Number):null;
var ay=s.dataset.y?s.dataset.y.split(' ').map(Number):null;
s.addEventListener('mousemove',function(e){
var m=s.getScreenCTM();if(!m)return;var pt=s.createSVGPoint();pt.x=e.clientX;pt.y=e.clientY;
var q=pt.matrixTransform(m.inverse());
if(q.x<px[0]||q.x>px[1]||q.y<px[2]||q.y>px[3]){ro.textContent='';return;}
var t=[];if(ax)t.push('x = '+f(inv(q.x,px[0],px[1],ax[0],ax[1],ax[2])));
if(ay)t.push('y = '+f(inv(q.y,px[3],px[2],ay[0],ay[1],ay[2])));
ro.textContent=t.join('   ');});
s.addEventListener('mouseleave',function(){ro.textContent='';});
s.addEventListener('click',function(){s.classList.toggle('zoom');});
})(plots[i]);}
document.documentElement.setAttribute('data-report-ready',String(plots.length));
})();
)";

}  // namespace

TableCell num(double value, int decimals) {
  if (std::isnan(value))
    return {"NaN", true};
  if (std::isinf(value))
    return {value > 0 ? "inf" : "-inf", true};
  std::string s = fmt::format("{:.{}f}", value, std::max(0, decimals));
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') {
    s.erase(0, 1);  // "-0.00" reads as a sign that is not there
  }
  return {std::move(s), true};
}

TableCell count(long long value) {
  return {fmt::format("{}", value), true};
}

TableCell text(std::string value) {
  return {std::move(value), false};
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::add_summary(std::string key, std::string value) {
  summary_.emplace_back(std::move(key), std::move(value));
}

void HtmlReport::set_summary(const std::string& key, std::string value) {
  for (auto& row : summary_) {
    if (row.first == key) {
      row.second = std::move(value);
      return;
    }
  }
  add_summary(key, std::move(value));
}

void HtmlReport::add_section(std::string heading) {
  if (in_section_)
    body_ += "</section>\n";
  body_ += fmt::format("<section>\n<h2>{}</h2>\n", esc(heading));
  in_section_ = true;
}

void HtmlReport::add_paragraph(std::string text) {
  body_ += fmt::format("<p>{}</p>\n", esc(text));
}

void HtmlReport::add_warning(std::string text) {
  ++warnings_;
  body_ += fmt::format("<p class=\"warn\">{}</p>\n", esc(text));
}

void HtmlReport::add_table(const Table& t) {
  body_ += "<table>";
  if (!t.caption.empty())
    body_ += fmt::format("<caption>{}</caption>", esc(t.caption));
  if (!t.header.empty()) {
    body_ += "<thead><tr>";
    for (const auto& h : t.header)
      body_ += fmt::format("<th>{}</th>", esc(h));
    body_ += "</tr></thead>";
  }
  body_ += "<tbody>\n";
  for (const auto& row : t.rows) {
    body_ += "<tr>";
    for (const auto& c : row) {
      body_ += fmt::format(c.numeric ? "<td class=\"n\">{}</td>" : "<td>{}</td>", esc(c.text));
    }
    body_ += "</tr>\n";
  }
  body_ += "</tbody></table>\n";
}

std::string HtmlReport::next_id() {
  return fmt::format("plot-{}", ++plots_);
}

namespace {
template <typename Plot>
void add_rendered(std::string& body, Plot& plot, std::string id) {
  if (plot.id.empty())
    plot.id = std::move(id);
  body += "<figure>";
  body += render_svg(plot);
  body += "</figure>\n";
}
}  // namespace

void HtmlReport::add_plot(LinePlot plot) {
  add_rendered(body_, plot, next_id());
}
void HtmlReport::add_plot(Histogram plot) {
  add_rendered(body_, plot, next_id());
}
void HtmlReport::add_plot(BarPlot plot) {
  add_rendered(body_, plot, next_id());
}
void HtmlReport::add_plot(HeatMap plot) {
  add_rendered(body_, plot, next_id());
}
void HtmlReport::add_plot(XYView plot) {
  add_rendered(body_, plot, next_id());
}

void HtmlReport::add_scene3d(const Scene3d& scene) {
  ++scenes_;
  body_ += render_scene3d(scene, "scene-" + std::to_string(scenes_));
}

void HtmlReport::add_svg(std::string svg) {
  ++plots_;
  body_ += "<figure>" + svg + "</figure>\n";
}

std::string HtmlReport::html() const {
  std::string out;
  out.reserve(body_.size() + 4096);
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  // An empty icon: the browser then asks for no favicon, not even a local one.
  out += "<link rel=\"icon\" href=\"data:,\">\n";
  out += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n<main>\n", esc(title_),
                     kStyle);
  out += fmt::format("<h1>{}</h1>\n", esc(title_));
  if (!summary_.empty()) {
    out += "<table class=\"meta\"><tbody>\n";
    for (const auto& [k, v] : summary_) {
      out += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", esc(k), esc(v));
    }
    out += "</tbody></table>\n";
  }
  out += body_;
  if (in_section_)
    out += "</section>\n";
  out +=
      "<footer>Written by redpost. Hover over a plot for values; click it to enlarge.</footer>\n";
  out += "</main>\n";
  if (scenes_ > 0)
    out += scene3d_scripts();
  out += fmt::format("<script>{}</script>\n</body>\n</html>\n", kScript);
  return out;
}

}  // namespace redpost::report
