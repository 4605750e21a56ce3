// The 3D view's HTML and data (scene3d_html.hpp).
#include "scene3d_html.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "assets.hpp"
#include "escape.hpp"

namespace redpost::report {

namespace {

// A JSON string: quotes, backslashes and control characters escaped, and <, > and & as \u
// escapes so that no text from a cell file can end the <script> element it sits in.
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || c == '<' || c == '>' || c == '&') {
      out += fmt::format("\\u{:04x}", u);
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// Numbers: shortest text that reads back (fmt ignores the C locale); NaN and inf as null.
std::string json_number(double v) {
  return std::isfinite(v) ? fmt::format("{}", v) : "null";
}

std::string json_array(const double* v, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i)
    out += (i ? "," : "") + json_number(v[i]);
  return out + "]";
}

// Little-endian bytes of 32-bit values, base64: the page reads them with DataView.
class Base64 {
 public:
  void put_u32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k)
      put_byte(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void put_f32(float f) {
    std::uint32_t v;
    std::memcpy(&v, &f, sizeof v);
    put_u32(v);
  }
  void put_byte(std::uint8_t b) {
    group_ = (group_ << 8) | b;
    if (++count_ == 3) {
      flush(4);
      group_ = 0;
      count_ = 0;
    }
  }
  std::string finish() {
    if (count_ > 0) {
      group_ <<= 8 * (3 - count_);
      flush(count_ + 1);
      out_.append(static_cast<std::size_t>(3 - count_), '=');
    }
    return std::move(out_);
  }

 private:
  void flush(int chars) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int k = 0; k < chars; ++k)
      out_ += kAlphabet[(group_ >> (18 - 6 * k)) & 63];
  }
  std::string out_;
  std::uint32_t group_ = 0;
  int count_ = 0;
};

std::string b64_floats(const std::vector<float>& v) {
  Base64 b;
  for (const float f : v)
    b.put_f32(f);
  return "\"" + b.finish() + "\"";
}
std::string b64_uints(const std::vector<std::uint32_t>& v) {
  Base64 b;
  for (const std::uint32_t u : v)
    b.put_u32(u);
  return "\"" + b.finish() + "\"";
}
std::string b64_bytes(const std::vector<std::uint8_t>& v) {
  Base64 b;
  for (const std::uint8_t u : v)
    b.put_byte(u);
  return "\"" + b.finish() + "\"";
}

const char* type_name(SceneLink::Type t) {
  switch (t) {
    case SceneLink::Type::prismatic:
      return "prismatic";
    case SceneLink::Type::virtual_spin:
      return "virtual";
    case SceneLink::Type::revolute:
      break;
  }
  return "revolute";
}

std::string cell_json(const SceneCell& c) {
  std::string out = "{\"name\":" + json_string(c.name) + ",\"links\":[";
  for (std::size_t i = 0; i < c.links.size(); ++i) {
    const SceneLink& l = c.links[i];
    out += fmt::format(
        "{}{{\"name\":{},\"axis\":{},\"type\":\"{}\",\"modified\":{},\"alpha\":{},\"a\":{},"
        "\"theta\":{},\"d\":{},\"T_prev\":{},\"lower\":{},\"upper\":{},\"axis_sign\":{},"
        "\"axis_offset\":{}}}",
        i ? "," : "", json_string(l.name), json_string(l.axis), type_name(l.type),
        l.modified_dh ? "true" : "false", json_number(l.alpha_rad), json_number(l.a_mm),
        json_number(l.theta_rad), json_number(l.d_mm), json_array(l.T_prev_link.data(), 12),
        json_number(l.lower), json_number(l.upper), json_number(l.axis_sign),
        json_number(l.axis_offset));
  }
  out += fmt::format(
      "],\"T_B_0\":{},\"T_last_tcp\":{},\"T_B_part\":{},\"reference_tool_length_mm\":{},"
      "\"positioner_joints\":{}}}",
      json_array(c.T_B_0.data(), 12), json_array(c.T_last_tcp.data(), 12),
      json_array(c.T_B_part.data(), 12), json_number(c.reference_tool_length_mm),
      c.positioner_joints);
  return out;
}

std::string body_json(const SceneBody& b) {
  std::string out = fmt::format("{{\"name\":{},\"role\":{},\"frame\":{},\"shapes\":[",
                                json_string(b.name), json_string(b.role), b.frame);
  for (std::size_t i = 0; i < b.shapes.size(); ++i) {
    const SceneShape& s = b.shapes[i];
    out += fmt::format("{}{{\"kind\":{},\"T\":{},\"radius\":{},\"length\":{},\"size\":{}",
                       i ? "," : "", json_string(s.kind), json_array(s.T.data(), 12),
                       json_number(s.radius_mm), json_number(s.length_mm),
                       json_array(s.size_mm.data(), 3));
    if (s.kind == "mesh")
      out += ",\"vertices\":" + b64_floats(s.vertices) + ",\"triangles\":" + b64_uints(s.triangles);
    out += "}";
  }
  return out + "]}";
}

std::string scene_json(const Scene3d& s) {
  std::string out = "{\"cell\":" + cell_json(s.cell) + ",\"quantities\":[";
  for (std::size_t q = 0; q < s.quantities.size(); ++q) {
    const SceneQuantity& Q = s.quantities[q];
    out += fmt::format(
        "{}{{\"name\":{},\"unit\":{},\"higher_is_better\":{},\"categorical\":{},"
        "\"threshold\":{},\"threshold_name\":{},\"lo\":{},\"hi\":{}}}",
        q ? "," : "", json_string(Q.name), json_string(Q.unit),
        Q.higher_is_better ? "true" : "false", Q.categorical ? "true" : "false",
        json_number(Q.threshold), json_string(Q.threshold_name), json_number(s.value_range[q][0]),
        json_number(s.value_range[q][1]));
  }
  out += fmt::format(
      "],\"line_label\":{},\"motions\":{},\"frames\":{},\"frame_motion\":{},\"frame_line\":{},",
      json_string(s.line_label), s.motions, b64_floats(s.frame_data), b64_uints(s.frame_motion),
      b64_uints(s.frame_line));
  out += "\"path\":" + b64_floats(s.path_xyz) + ",\"path_motion\":" + b64_uints(s.path_motion) +
         ",\"path_values\":[";
  for (std::size_t q = 0; q < s.path_value_codes.size(); ++q)
    out += (q ? "," : "") + b64_bytes(s.path_value_codes[q]);
  out += fmt::format("],\"path_as_points\":{},\"rects\":[", s.path_as_points ? "true" : "false");
  for (std::size_t i = 0; i < s.rects.size(); ++i) {
    const SceneRect& r = s.rects[i];
    out += fmt::format("{}{{\"corner\":{},\"u\":{},\"v\":{},\"colour\":{},\"name\":{}}}",
                       i ? "," : "", json_array(r.corner.data(), 3), json_array(r.edge_u.data(), 3),
                       json_array(r.edge_v.data(), 3), json_string(r.colour), json_string(r.name));
  }
  out += "],\"bodies\":[";
  for (std::size_t i = 0; i < s.bodies.size(); ++i)
    out += (i ? "," : "") + body_json(s.bodies[i]);
  out += "]";
  if (s.closest.shown) {
    out += fmt::format(",\"closest\":{{\"a\":{},\"b\":{},\"label\":{}}}",
                       json_array(s.closest.a.data(), 3), json_array(s.closest.b.data(), 3),
                       json_string(s.closest.label));
  }
  return out + "}";
}

// What the reader is told about the decimation (the limits of Scene3dLimits).
std::string decimation_note(const Scene3d& s) {
  std::string note;
  if (s.frames() >= s.motions) {
    note = fmt::format("The slider steps through all {} motions.", s.motions);
  } else {
    note = fmt::format(
        "The program has {} motions; the slider steps through {} of them (one in every {} and "
        "the last), so that the page stays small: the view keeps at most {} motions.",
        s.motions, s.frames(), s.frame_stride, s.limits.max_frames);
  }
  if (s.path_tolerance_mm > 0.0015) {
    note += fmt::format(
        " The {} is drawn with {} points (at most {}): points closer than {:.3g} mm to the "
        "previous one are merged into it, keeping the worse value of each quantity.",
        s.path_name, s.path_points(), s.limits.max_path_points, s.path_tolerance_mm);
  }
  return note;
}

}  // namespace

std::string render_scene3d(const Scene3d& s, const std::string& id) {
  std::string options;
  for (std::size_t q = 0; q < s.quantities.size(); ++q) {
    const std::string unit = s.quantities[q].unit.empty() ? "" : " [" + s.quantities[q].unit + "]";
    options += fmt::format("<option value=\"{}\">{}</option>", q, esc(s.quantities[q].name + unit));
  }
  if (options.empty())
    options = "<option value=\"0\">(no quantity)</option>";
  std::string out = fmt::format("<div class=\"scene3d\" id=\"{0}\" data-scene=\"{0}-data\">\n", id);
  out += "<div class=\"s3-msg\"></div><canvas class=\"s3-canvas\"></canvas>\n";
  out += "<div class=\"s3-controls\"><button type=\"button\" class=\"s3-play\">Play</button>";
  out += fmt::format(
      "<input type=\"range\" class=\"s3-slider\" min=\"0\" max=\"{}\" value=\"0\" "
      "step=\"1\" aria-label=\"motion\"><span class=\"s3-readout\"></span></div>\n",
      s.frames() > 0 ? s.frames() - 1 : 0);
  std::string label = s.path_name;
  if (!label.empty())
    label[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(label[0])));
  out += "<div class=\"s3-colour\"><label>" + esc(label) +
         " coloured by <select class=\"s3-quantity\">" + options +
         "</select></label> <span class=\"s3-bar\"></span></div>\n</div>\n";
  std::string bodies;
  if (!s.bodies.empty()) {
    bodies =
        " Translucent: the bodies of the collision check (the cell's orange, the tool's grey, "
        "the fixtures brown, the part green).";
  }
  if (s.closest.shown)
    bodies += " The red line joins the closest approach's two points: " + s.closest.label + ".";
  out += "<p>" + esc(decimation_note(s)) +
         " Drag to turn the view, scroll to zoom, right-drag to pan. The red dot is the TCP at "
         "the motion shown." +
         esc(bodies) + "</p>\n";
  out += fmt::format("<script type=\"application/json\" id=\"{}-data\">{}</script>\n", id,
                     scene_json(s));
  return out;
}

std::string scene3d_scripts() {
  // The collector runs first, so that an error anywhere in the view's scripts is recorded.
  static constexpr const char* kCollector = R"(
window.__redpostErrors=[];
window.addEventListener('error',function(e){window.__redpostErrors.push(String(e.message||e));});
window.addEventListener('unhandledrejection',function(e){window.__redpostErrors.push('unhandled rejection: '+String(e.reason));});
['error','warn'].forEach(function(k){var f=console[k];console[k]=function(){window.__redpostErrors.push(k+': '+Array.prototype.join.call(arguments,' '));return f.apply(console,arguments);};});
)";
  std::string out = fmt::format("<script>{}</script>\n", kCollector);
  out += fmt::format(
      "<!-- three.js r111 and its OrbitControls (MIT licence, (c) 2010-2019 three.js authors), "
      "from Debian's libjs-three {} -->\n",
      assets::three_package_version);
  out += fmt::format("<script data-library=\"three.js\">{}</script>\n", assets::three_js);
  out += fmt::format("<script data-library=\"OrbitControls\">{}</script>\n",
                     assets::three_orbit_controls_js);
  out += fmt::format("<script>{}</script>\n", assets::scene3d_js);
  return out;
}

}  // namespace redpost::report
