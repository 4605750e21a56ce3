// Strict reading of the machining concept's XML files (the placement job, the cutting
// conditions): numbers with units, bounded integers, booleans, children given once. On top of
// io's StrictXml, so that every file reports problems the same way, "file:line: what".
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
#include "redpost/io/error.hpp"
#include "redpost/kinematics/types.hpp"
#include "redpost/machining/cutting_force.hpp"

namespace redpost::detail {

using tinyxml2::XMLElement;

inline constexpr double kMaxLengthMm = 1e6;

class MachiningXml : public StrictXml {
 public:
  using StrictXml::fail;
  using StrictXml::StrictXml;

  struct Unit {
    std::string_view suffix;
    double factor;
  };

  // A finite number with an optional unit suffix; the first unit is the default.
  double number(const XMLElement* e, const char* attr, std::initializer_list<Unit> units) const {
    const char* text = required(e, attr);
    std::string_view s(text);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
      s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
      s.remove_suffix(1);
    const char* first = s.data();
    const char* last = s.data() + s.size();
    if (first != last && *first == '+' && first + 1 != last && first[1] != '-')
      ++first;
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, value);
    const std::string where =
        std::string("<") + e->Name() + "> attribute '" + attr + "' = \"" + text + "\"";
    if (ec != std::errc() || s.empty() || !std::isfinite(value))
      fail(e, where + ": not a finite number");
    const std::string_view suffix(ptr, static_cast<size_t>(last - ptr));
    for (const Unit& u : units) {
      if (u.suffix == suffix || (suffix.empty() && &u == units.begin())) {
        const double out = value * u.factor;
        if (std::fabs(out) > kMaxLengthMm)
          fail(e, where + ": magnitude too large to be meant");
        return out;
      }
    }
    std::string list;
    for (const Unit& u : units)
      list += (list.empty() ? "" : ", ") + std::string(u.suffix.empty() ? "no unit" : u.suffix);
    fail(e, where + ": unknown unit '" + std::string(suffix) + "' (use " + list + ")");
  }

  double length_mm(const XMLElement* e, const char* attr) const {
    return number(e, attr, {{"mm", 1.0}, {"m", 1000.0}});
  }
  double length_mm(const XMLElement* e, const char* attr, double fallback) const {
    return e->Attribute(attr) ? length_mm(e, attr) : fallback;
  }
  double angle_rad(const XMLElement* e, const char* attr, double fallback) const {
    return e->Attribute(attr) ? number(e, attr, {{"deg", kPi / 180.0}, {"rad", 1.0}}) : fallback;
  }
  double plain(const XMLElement* e, const char* attr, double fallback) const {
    return e->Attribute(attr) ? number(e, attr, {{"", 1.0}}) : fallback;
  }
  double positive(const XMLElement* e, const char* attr, double value) const {
    if (!(value > 0.0))
      fail(e, std::string("<") + e->Name() + "> attribute '" + attr + "' must be positive");
    return value;
  }
  int integer(const XMLElement* e, const char* attr, int fallback, int lo, int hi) const {
    if (!e->Attribute(attr))
      return fallback;
    const double v = number(e, attr, {{"", 1.0}});
    if (v != std::floor(v) || v < lo || v > hi) {
      fail(e, std::string("<") + e->Name() + "> attribute '" + attr + "' must be an integer in [" +
                  std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<int>(v);
  }
  bool boolean(const XMLElement* e, const char* attr, bool fallback) const {
    const char* t = e->Attribute(attr);
    if (!t)
      return fallback;
    const std::string v = t;
    if (v == "true" || v == "1")
      return true;
    if (v == "false" || v == "0")
      return false;
    fail(e, std::string("<") + e->Name() + "> attribute '" + attr + "' must be true or false");
  }

  const XMLElement* child(const XMLElement* parent, const char* name, bool needed) const {
    const XMLElement* c = parent->FirstChildElement(name);
    if (!c && needed)
      fail(parent, std::string("<") + parent->Name() + "> needs a <" + name + "> element");
    if (c && c->NextSiblingElement(name)) {
      fail(c->NextSiblingElement(name),
           std::string("<") + name + "> given twice in <" + parent->Name() + ">");
    }
    return c;
  }

  void only_children(const XMLElement* parent,
                     std::initializer_list<std::string_view> known) const {
    for (const XMLElement* c = parent->FirstChildElement(); c; c = c->NextSiblingElement()) {
      bool ok = false;
      for (auto k : known)
        ok = ok || k == c->Name();
      if (!ok) {
        std::string list;
        for (auto k : known)
          list += (list.empty() ? "" : ", ") + std::string("<") + std::string(k) + ">";
        fail(c, std::string("unknown element <") + c->Name() + "> in <" + parent->Name() +
                    "> (known: " + list + ")");
      }
    }
  }
};

inline MillingMode parse_mode(const MachiningXml& r, const XMLElement* e, MillingMode fallback) {
  const char* t = e->Attribute("mode");
  if (!t)
    return fallback;
  const std::string v = t;
  if (v == "down")
    return MillingMode::down;
  if (v == "up")
    return MillingMode::up;
  r.fail(e, "unknown milling mode '" + v + "' (use up or down)");
}

}  // namespace redpost::detail
