// Reading numbers, units and frames of redpost's definition files (cells, their collision
// bodies): one reader, so that every definition file takes the same units ("0.684 m",
// "0.3564 rad") and reports the same way, "file:line: what".
//
// Internal to redpost::core; not installed.
#pragma once

#include <tinyxml2.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <system_error>

#include "io/strict_xml.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost::detail {

using tinyxml2::XMLElement;

// Largest magnitudes accepted, to catch typos such as 1e308 before they poison the maths.
inline constexpr double kMaxLengthMm = 1e7;  // 10 km
inline constexpr double kMaxAngleDeg = 1e5;  // about 280 turns

class DefinitionReader : public StrictXml {
 public:
  using StrictXml::fail;
  using StrictXml::StrictXml;

  // A number with an optional unit suffix. `units` maps suffix -> factor into internal units;
  // the first entry is the default unit (empty suffix).
  struct Unit {
    std::string_view suffix;
    double factor;
  };
  double number(const XMLElement* e, const char* attr, const char* text,
                std::initializer_list<Unit> units, double max_abs) const {
    std::string_view s(text);
    auto trim = [](std::string_view v) {
      while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front())))
        v.remove_prefix(1);
      while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back())))
        v.remove_suffix(1);
      return v;
    };
    s = trim(s);
    const char* first = s.data();
    const char* last = s.data() + s.size();
    // from_chars takes no '+'; take one, but not a second sign after it ("+-450").
    if (first != last && *first == '+' && first + 1 != last && first[1] != '-')
      ++first;
    double value = 0.0;
    auto [ptr, ec] = std::from_chars(first, last, value);
    const std::string where =
        std::string("<") + e->Name() + "> attribute '" + attr + "' = \"" + text + "\"";
    if (ec == std::errc::result_out_of_range)
      fail(e, where + ": number out of range");
    if (ec != std::errc() || s.empty())
      fail(e, where + ": not a number");
    // from_chars also reads "nan" and "inf"; neither has a place in a cell definition.
    if (!std::isfinite(value))
      fail(e, where + ": must be a finite number (NaN and inf are refused)");
    const std::string_view suffix = trim(std::string_view(ptr, static_cast<size_t>(last - ptr)));
    // A plain number takes no unit: "12a" is a typo, not an unknown unit.
    if (!suffix.empty() && units.size() == 1 && units.begin()->suffix.empty()) {
      fail(e, where + ": not a number");
    }
    double factor = 0.0;
    for (const Unit& u : units) {
      if (u.suffix == suffix || (suffix.empty() && &u == units.begin())) {
        factor = u.factor;
        break;
      }
    }
    if (factor == 0.0) {
      std::string list;
      for (const Unit& u : units)
        list += (list.empty() ? "" : ", ") + std::string(u.suffix);
      fail(e, where + ": unknown unit '" + std::string(suffix) + "' (use " + list + ")");
    }
    const double out = value * factor;
    if (std::fabs(out) > max_abs)
      fail(e, where + ": magnitude too large to be meant");
    return out;
  }

  double length_mm(const XMLElement* e, const char* attr, double fallback) const {
    const char* t = e->Attribute(attr);
    return t ? number(e, attr, t, {{"mm", 1.0}, {"m", 1000.0}}, kMaxLengthMm) : fallback;
  }
  double angle_rad(const XMLElement* e, const char* attr, double fallback) const {
    const char* t = e->Attribute(attr);
    return t ? number(e, attr, t, {{"deg", kPi / 180.0}, {"rad", 1.0}}, deg_to_rad(kMaxAngleDeg))
             : fallback;
  }
  double plain(const XMLElement* e, const char* attr, double max_abs) const {
    return number(e, attr, required(e, attr), {{"", 1.0}}, max_abs);
  }

  // x y z (mm) and a b c (deg, KUKA ZYX) of <base>, <fixed>, <tool>.
  Isometry frame(const XMLElement* e) const {
    only_attributes(e, {"name", "x", "y", "z", "a", "b", "c"});
    const KukaAbc abc{rad_to_deg(angle_rad(e, "a", 0.0)), rad_to_deg(angle_rad(e, "b", 0.0)),
                      rad_to_deg(angle_rad(e, "c", 0.0))};
    return frame_from_xyzabc(length_mm(e, "x", 0.0), length_mm(e, "y", 0.0), length_mm(e, "z", 0.0),
                             abc);
  }

  const XMLElement* child(const XMLElement* parent, const char* name, bool needed) const {
    const XMLElement* c = parent->FirstChildElement(name);
    if (!c && needed) {
      fail(parent, std::string("<") + parent->Name() + "> needs a <" + name + "> element");
    }
    if (c && c->NextSiblingElement(name)) {
      fail(c->NextSiblingElement(name),
           std::string("<") + name + "> given twice in <" + parent->Name() + ">");
    }
    return c;
  }
};

}  // namespace redpost::detail
